//! Thermostats and drives as the configuration describes them (applied by
//! `crate::thermostat` at the end of every step).

use serde::{Deserialize, Serialize};

/// A heat bath or a random drive acting on the discs' velocities at the end of every step,
/// after the collisions ([`crate::Config::thermostat`]). Off by default: a gas keeps
/// its energy. Random numbers come from `(seed, step, disc id)` alone, so a run gives the
/// same bits on any thread count, in any storage order and across a resume.
///
/// ```
/// use bounce::{Config, Thermostat, ThermostatKind};
/// let config = Config {
///     thermostat: Some(Thermostat::new(ThermostatKind::Andersen, 1.0, 0.5)),
///     ..Config::default()
/// };
/// assert!(config.validate().is_ok());
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Thermostat {
    /// What it does (see [`ThermostatKind`]).
    pub kind: ThermostatKind,
    /// The bath's temperature `T` (kT, energy units; the 2D kinetic energy per disc in the
    /// centre-of-mass frame). Finite and `>= 0`.
    pub temperature: f64,
    /// How strongly it acts, per unit time (see each kind). Finite and `> 0`.
    pub rate: f64,
    /// The random numbers' seed (the Andersen and white-noise kinds). Default 0.
    #[serde(default)]
    pub seed: u64,
}

impl Thermostat {
    /// A thermostat of `kind` at `temperature` acting at `rate`, seed 0. See [`Thermostat`]
    /// for an example.
    pub fn new(kind: ThermostatKind, temperature: f64, rate: f64) -> Self {
        Thermostat {
            kind,
            temperature,
            rate,
            seed: 0,
        }
    }

    /// What is wrong with it, if anything: the value and what it must be.
    pub(crate) fn problem(&self) -> Option<(String, &'static str)> {
        if !(self.temperature.is_finite() && self.temperature >= 0.0) {
            Some((
                format!("temperature {}", self.temperature),
                "the temperature must be finite and >= 0",
            ))
        } else if !(self.rate.is_finite() && self.rate > 0.0) {
            Some((
                format!("rate {}", self.rate),
                "the rate must be finite and > 0",
            ))
        } else {
            None
        }
    }
}

/// How a [`Thermostat`] acts, at the end of a step of `dt`, on discs of mass `m` (the mass
/// model's). See [`Thermostat`] and [`crate::World::thermostat_work`] for examples.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ThermostatKind {
    /// Velocity rescaling towards `T` (Berendsen's weak coupling): the velocities relative
    /// to the centre of mass are scaled by `λ = √(1 + min(rate dt, 1) (T/T_now − 1))`, so the
    /// temperature relaxes as `T_now += min(rate dt, 1) (T − T_now)` each step (exactly `T`
    /// when `rate dt >= 1`). Momentum is kept; a gas at rest (`T_now = 0`) is left alone.
    Rescale,
    /// Andersen's collisions with a heat bath: each disc, with probability
    /// `min(rate dt, 1)`, gets a new velocity drawn from the Maxwell–Boltzmann distribution
    /// at `T` (each component normal with variance `T/m`). Gives the canonical distribution;
    /// does not keep momentum.
    Andersen,
    /// Random kicks (white noise, the driven granular gas of Williams & MacKintosh and van
    /// Noije & Ernst): each disc's velocity changes by a normal `Δv` with variance
    /// `2 rate T dt / m` per component, less the kicks' mass-weighted mean (so momentum is
    /// kept): the noise of a Langevin bath at `T` with friction `rate`, without the
    /// friction. It puts in energy at `2 rate T (1 − 1/N)` per disc per unit time; an
    /// elastic gas heats without end, an inelastic one settles where collisions take out
    /// as much.
    WhiteNoise,
}
