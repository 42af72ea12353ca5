//! How pictures colour discs, shared by the CLI's frames and the viewer.

use bounce::World;

use crate::{ColorBy, Rgb, ramp, spin_ramp};

/// Grey for discs the scenario gives no colour.
pub const NO_COLOUR: Rgb = [150, 150, 150];

/// A colouring rule with its scales fixed when it is made (so colours keep their meaning
/// while a run cools or heats).
#[derive(Clone, Debug, PartialEq)]
pub struct Palette {
    /// The rule.
    pub colour_by: ColorBy,
    /// Scenario colours by particle id.
    pub colours: Vec<Option<Rgb>>,
    /// Speed at the top of the ramp: 2.5 times the root-mean-square speed.
    pub speed_scale: f64,
    /// Radii at the ends of the ramp.
    pub radius_range: [f64; 2],
    /// Angular velocity at either end of the spin ramp: 2.5 times the root-mean-square one.
    pub spin_scale: f64,
}

impl Palette {
    /// A palette whose scales come from the world as it is now.
    pub fn for_world(world: &World, colour_by: ColorBy, colours: Vec<Option<Rgb>>) -> Self {
        let p = world.particles();
        let n = p.len().max(1) as f64;
        let mean_v2 = p
            .vx()
            .iter()
            .zip(p.vy())
            .map(|(x, y)| x * x + y * y)
            .sum::<f64>()
            / n;
        let max_speed = p
            .vx()
            .iter()
            .zip(p.vy())
            .map(|(x, y)| x.hypot(*y))
            .fold(0.0, f64::max);
        let speed_scale = if mean_v2 > 0.0 {
            2.5 * mean_v2.sqrt()
        } else {
            max_speed.max(1.0)
        };
        let radius_range = [
            p.radius().iter().copied().fold(f64::INFINITY, f64::min),
            p.radius().iter().copied().fold(0.0, f64::max),
        ];
        let spin = p.angular_velocity();
        let mean_w2 = spin.iter().map(|w| w * w).sum::<f64>() / n;
        let spin_scale = if mean_w2 > 0.0 {
            2.5 * mean_w2.sqrt()
        } else {
            1.0
        };
        Palette {
            colour_by,
            colours,
            speed_scale,
            radius_range,
            spin_scale,
        }
    }

    /// The colour of particle `id` moving at `speed`, turning at `spin`, with `radius`.
    pub fn colour(&self, id: usize, speed: f64, radius: f64, spin: f64) -> Rgb {
        match self.colour_by {
            ColorBy::Spin => spin_ramp(spin / self.spin_scale),
            ColorBy::Speed => ramp(speed / self.speed_scale),
            ColorBy::Radius => {
                let [lo, hi] = self.radius_range;
                ramp(if hi > lo {
                    (radius - lo) / (hi - lo)
                } else {
                    0.5
                })
            }
            ColorBy::Color => self.colours.get(id).copied().flatten().unwrap_or(NO_COLOUR),
        }
    }
}
