//! The checkpoint format shared by the CLI and the viewer.
//!
//! ```text
//! "BOUNCE-CHECKPOINT\n"   18 bytes
//! version                u32 LE (8)
//! payload length         u64 LE
//! checksum               u64 LE: FNV-1a 64 of the payload
//! fingerprint            u64 LE: FNV-1a 64 of the configuration and the particle count
//! payload                postcard: the world, then the run's output state (optional)
//! ```
//!
//! FNV-1a changes its state bijectively with every byte, so any single changed byte of the
//! payload changes the checksum: corruption is an error, never a different state. Decoding
//! then validates every invariant of the world (see `bounce::World`'s serde) before anything
//! is allocated by a value read from the file.

use bounce::{Config, SavedWorld, World};
use serde::{Deserialize, Serialize};

const MAGIC: &[u8; 18] = b"BOUNCE-CHECKPOINT\n";
/// Version 2 added the broadphase's reference positions; version 3 the checksum, the
/// fingerprint and the run's output state; version 4 the contacts beside the collisions in it;
/// version 5 the configuration's `resting_contacts`; version 6 rough discs (friction in the
/// configuration, the discs' angular velocities and orientations, the friction work);
/// version 7 the configuration's `method` and `contact_duration` (event-driven runs);
/// version 8 contact events (the configuration's switch and threshold, the world's last
/// substep's contacts) and sensors (their regions, the discs each holds, their counts);
/// version 9 the configuration's thermostat and pressure-tensor switch, the step's
/// thermostat work and virial tensor, the run's thermostat work and its origin for `msd.csv`;
/// version 10 the configuration's collision-count switch and each disc's collisions;
/// version 11 the time the broadphase listed its candidates at (a Lees–Edwards box keeps its
/// list while its copies slide).
const VERSION: u32 = 11;
/// Bytes before the payload.
const HEADER: usize = 18 + 4 + 8 + 8 + 8;

/// What a run's outputs had accumulated since their last `stats.csv` row when the checkpoint
/// was written, so a resumed run continues the same rows.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct RunState {
    /// Collisions (impacts) since the last row.
    pub collisions: u64,
    /// Contacts (colliding pairs, resting ones in every substep) since the last row.
    pub contacts: u64,
    /// Wall impulse since the last row.
    pub wall_impulse: f64,
    /// Largest overlap since the last row.
    pub max_overlap: f64,
    /// Simulated time since the last row.
    pub elapsed: f64,
    /// Momentum each obstacle received since the last row (empty without obstacles).
    pub obstacle_impulse: Vec<[f64; 2]>,
    /// The discs each sensor saw enter and leave since the last row (empty without
    /// sensors).
    pub sensor_crossings: Vec<[u64; 2]>,
    /// The kinetic energy the thermostat added since the last row (0 without one).
    pub thermostat_work: f64,
    /// The state `msd.csv` measures from (with `[output] msd`).
    pub origin: Option<crate::observables::Origin>,
    /// The work moving obstacles did on the discs since the last row.
    pub obstacle_work: f64,
    /// The discs' energy (kinetic, rotational, potential) at the last row, which
    /// `dissipated` is measured from (`None` before the first row).
    pub row_energy: Option<f64>,
}

/// A decoded checkpoint.
#[derive(Debug)]
pub struct Checkpoint {
    /// The world.
    pub world: World,
    /// The run's output state, when a run wrote it.
    pub run: Option<RunState>,
}

#[derive(Serialize)]
struct Body<'a> {
    world: &'a World,
    run: Option<RunState>,
}

#[derive(Deserialize)]
struct OwnedBody {
    world: SavedWorld,
    run: Option<RunState>,
}

impl RunState {
    /// What is wrong with it, if anything, for a world with `obstacles` obstacles.
    fn problem(&self, obstacles: usize) -> Option<String> {
        let sane = |v: f64| v.is_finite() && v >= 0.0;
        if !sane(self.wall_impulse) {
            Some(format!(
                "wall_impulse = {} must be finite and >= 0",
                self.wall_impulse
            ))
        } else if !sane(self.max_overlap) {
            Some(format!(
                "max_overlap = {} must be finite and >= 0",
                self.max_overlap
            ))
        } else if let Some(origin) = self.origin.as_ref().filter(|o| {
            o.ids.len() != o.state.len()
                || o.ids.windows(2).any(|w| w[0] >= w[1])
                || o.state.iter().flatten().any(|v| !v.is_finite())
        }) {
            Some(format!(
                "the msd origin's {} ids and {} states must match, ids ascending, values finite",
                origin.ids.len(),
                origin.state.len()
            ))
        } else if !(self.obstacle_work.is_finite() && self.row_energy.is_none_or(f64::is_finite)) {
            Some(format!(
                "obstacle_work = {}, row_energy = {:?} must be finite",
                self.obstacle_work, self.row_energy
            ))
        } else if !self.thermostat_work.is_finite() {
            Some(format!(
                "thermostat_work = {} must be finite",
                self.thermostat_work
            ))
        } else if !sane(self.elapsed) {
            Some(format!(
                "elapsed = {} must be finite and >= 0",
                self.elapsed
            ))
        } else if !self.obstacle_impulse.is_empty() && self.obstacle_impulse.len() != obstacles {
            Some(format!(
                "{} obstacle impulses for {obstacles} obstacles",
                self.obstacle_impulse.len()
            ))
        } else {
            self.obstacle_impulse
                .iter()
                .position(|j| !(j[0].is_finite() && j[1].is_finite()))
                .map(|k| {
                    format!(
                        "obstacle {k}: impulse {:?} is not finite",
                        self.obstacle_impulse[k]
                    )
                })
        }
    }
}

/// FNV-1a, 64 bits.
fn fnv1a(bytes: &[u8], mut hash: u64) -> u64 {
    for &b in bytes {
        hash = (hash ^ b as u64).wrapping_mul(0x0100_0000_01b3);
    }
    hash
}
const FNV_START: u64 = 0xcbf2_9ce4_8422_2325;

/// The fingerprint of a world's physics: its configuration and particle count.
pub fn fingerprint(world: &World) -> u64 {
    let config = postcard::to_stdvec(world.config()).expect("a config always encodes");
    fnv1a(
        &(world.len() as u64).to_le_bytes(),
        fnv1a(&config, FNV_START),
    )
}

/// The bytes of a checkpoint of `world` (and of the run's output state, if any).
pub fn encode(world: &World, run: Option<&RunState>) -> Result<Vec<u8>, String> {
    let payload = postcard::to_stdvec(&Body {
        world,
        run: run.cloned(),
    })
    .map_err(|e| format!("cannot encode the checkpoint: {e}"))?;
    let mut bytes = Vec::with_capacity(HEADER + payload.len());
    bytes.extend_from_slice(MAGIC);
    bytes.extend_from_slice(&VERSION.to_le_bytes());
    bytes.extend_from_slice(&(payload.len() as u64).to_le_bytes());
    bytes.extend_from_slice(&fnv1a(&payload, FNV_START).to_le_bytes());
    bytes.extend_from_slice(&fingerprint(world).to_le_bytes());
    bytes.extend_from_slice(&payload);
    Ok(bytes)
}

/// A checkpoint from its bytes; `name` (the file) starts every error message.
pub fn decode(bytes: &[u8], name: &str) -> Result<Checkpoint, String> {
    let Some(rest) = bytes.strip_prefix(MAGIC.as_slice()) else {
        return Err(format!(
            "{name} is not a bounce checkpoint (no checkpoint header)"
        ));
    };
    let word = |at: usize, len: usize| -> Option<&[u8]> { rest.get(at..at + len) };
    let Some(version) = word(0, 4) else {
        return Err(format!("{name}: checkpoint is truncated"));
    };
    let version = u32::from_le_bytes(version.try_into().expect("4 bytes"));
    if version != VERSION {
        return Err(format!(
            "{name}: checkpoint version {version}, this bounce reads version {VERSION} \
             (re-run the scenario with this bounce to make a new one)"
        ));
    }
    let (Some(length), Some(checksum), Some(fingerprint_read)) =
        (word(4, 8), word(12, 8), word(20, 8))
    else {
        return Err(format!("{name}: checkpoint is truncated"));
    };
    let u64_of = |b: &[u8]| u64::from_le_bytes(b.try_into().expect("8 bytes"));
    let payload = &rest[28..];
    if u64_of(length) != payload.len() as u64 {
        return Err(format!(
            "{name}: corrupt checkpoint: the header says {} payload bytes, the file has {} \
             (truncated or appended to)",
            u64_of(length),
            payload.len()
        ));
    }
    if u64_of(checksum) != fnv1a(payload, FNV_START) {
        return Err(format!(
            "{name}: corrupt checkpoint: the checksum does not match its contents"
        ));
    }
    let (body, after): (OwnedBody, &[u8]) = postcard::take_from_bytes(payload)
        .map_err(|e| format!("{name}: corrupt checkpoint: cannot read its contents ({e})"))?;
    if !after.is_empty() {
        return Err(format!(
            "{name}: corrupt checkpoint: {} bytes after its contents",
            after.len()
        ));
    }
    // Validated like a scenario's discs: the error names the disc and the field.
    let world = World::try_from(body.world).map_err(|e| format!("{name}: {e}"))?;
    if fingerprint(&world) != u64_of(fingerprint_read) {
        return Err(format!(
            "{name}: corrupt checkpoint: its fingerprint does not match its configuration"
        ));
    }
    if let Some(problem) = body
        .run
        .as_ref()
        .and_then(|run| run.problem(world.config().obstacles.len()))
    {
        return Err(format!("{name}: the run's totals: {problem}"));
    }
    Ok(Checkpoint {
        world,
        run: body.run,
    })
}

/// Where two configurations differ, one `field: a vs b` line each (empty when equal).
pub fn config_differences(a: &Config, b: &Config) -> Vec<String> {
    // Destructured, so a new field of `Config` cannot be forgotten here.
    let Config {
        collision_radius_scale,
        coefficient_of_restitution,
        gravity,
        substeps,
        solver_iterations,
        max_travel,
        boundary,
        mass_model,
        restitution_model,
        velocity_update,
        resting_contacts,
        friction,
        wall_friction,
        tangential_restitution,
        rolling_resistance,
        inertia_factor,
        method,
        contact_duration,
        contact_events,
        contact_event_threshold,
        obstacles,
        emitters,
        sinks,
        sensors,
        pressure_tensor,
        collision_counts,
        thermostat,
    } = a;
    let mut out = Vec::new();
    let mut differ = |field: &str, x: String, y: String| {
        if x != y {
            out.push(format!("{field}: {x} vs {y}"));
        }
    };
    let f = |v: &dyn std::fmt::Debug| format!("{v:?}");
    differ(
        "collision_radius_scale",
        f(collision_radius_scale),
        f(&b.collision_radius_scale),
    );
    differ(
        "coefficient_of_restitution",
        f(coefficient_of_restitution),
        f(&b.coefficient_of_restitution),
    );
    differ("gravity", f(gravity), f(&b.gravity));
    differ("substeps", f(substeps), f(&b.substeps));
    differ(
        "solver_iterations",
        f(solver_iterations),
        f(&b.solver_iterations),
    );
    differ("max_travel", f(max_travel), f(&b.max_travel));
    differ("boundary", f(boundary), f(&b.boundary));
    differ("mass_model", f(mass_model), f(&b.mass_model));
    differ(
        "restitution_model",
        f(restitution_model),
        f(&b.restitution_model),
    );
    differ("velocity_update", f(velocity_update), f(&b.velocity_update));
    differ(
        "resting_contacts",
        f(resting_contacts),
        f(&b.resting_contacts),
    );
    differ("friction", f(friction), f(&b.friction));
    differ("wall_friction", f(wall_friction), f(&b.wall_friction));
    differ("method", f(method), f(&b.method));
    differ(
        "contact_duration",
        f(contact_duration),
        f(&b.contact_duration),
    );
    differ(
        "tangential_restitution",
        f(tangential_restitution),
        f(&b.tangential_restitution),
    );
    differ(
        "rolling_resistance",
        f(rolling_resistance),
        f(&b.rolling_resistance),
    );
    differ("inertia_factor", f(inertia_factor), f(&b.inertia_factor));
    differ("contact_events", f(contact_events), f(&b.contact_events));
    differ(
        "contact_event_threshold",
        f(contact_event_threshold),
        f(&b.contact_event_threshold),
    );
    differ("emitters", f(emitters), f(&b.emitters));
    differ("sinks", f(sinks), f(&b.sinks));
    differ("sensors", f(sensors), f(&b.sensors));
    differ("thermostat", f(thermostat), f(&b.thermostat));
    differ("pressure_tensor", f(pressure_tensor), f(&b.pressure_tensor));
    differ(
        "collision_counts",
        f(collision_counts),
        f(&b.collision_counts),
    );
    if obstacles != &b.obstacles {
        differ(
            "obstacles",
            format!("{} obstacles", obstacles.len()),
            format!("{} obstacles (or different ones)", b.obstacles.len()),
        );
        if out.is_empty() {
            out.push("obstacles: the same count, different shapes or motions".into());
        }
    }
    out
}

/// Writes a checkpoint of `world` to `path` atomically (whole or not at all).
#[cfg(not(target_arch = "wasm32"))]
pub fn save(world: &World, run: Option<&RunState>, path: &std::path::Path) -> Result<(), String> {
    let bytes = encode(world, run)?;
    crate::atomic::write(path, &bytes).map_err(|e| e.to_string())
}

/// Reads a checkpoint written by [`save`]; every problem names the file.
pub fn load(path: &std::path::Path) -> Result<Checkpoint, String> {
    let bytes = crate::files::read(path)
        .map_err(|e| format!("cannot read checkpoint {}: {e}", path.display()))?;
    decode(&bytes, &path.display().to_string())
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use bounce::{Boundary, Particle};

    /// `world` as a forged checkpoint says it is at `time`.
    pub(crate) fn with_time(world: &World, time: f64) -> World {
        let bytes = encode(world, None).unwrap();
        decode(&forge(&bytes, world.time(), time), "c")
            .unwrap()
            .world
    }

    fn small_world() -> World {
        let mut world = World::new(Config {
            boundary: Boundary::walls([0.0, 0.0], [10.0, 10.0]),
            gravity: [0.0, -1.0],
            ..Config::default()
        })
        .unwrap();
        for k in 0..3 {
            world
                .add_particle(Particle::new([2.0 + 2.5 * k as f64, 3.0], [1.0, 0.5], 0.5))
                .unwrap();
        }
        world.step(0.05).unwrap();
        world
    }

    #[test]
    fn round_trip_and_refusals() {
        let world = small_world();
        let run = RunState {
            collisions: 3,
            contacts: 40,
            wall_impulse: 0.25,
            max_overlap: 0.0,
            elapsed: 0.5,
            obstacle_impulse: Vec::new(),
            sensor_crossings: Vec::new(),
            thermostat_work: -1.5,
            obstacle_work: 0.25,
            row_energy: Some(12.5),
            origin: Some(crate::observables::Origin {
                ids: vec![0, 2],
                state: vec![[1.0, 2.0, 3.0, 4.0], [-1.0, 0.5, 0.0, 2.0]],
            }),
        };
        let bytes = encode(&world, Some(&run)).unwrap();
        let back = decode(&bytes, "c").unwrap();
        assert_eq!(back.world.state_hash(), world.state_hash());
        assert_eq!(back.run, Some(run));
        assert!(
            decode(b"junk", "c")
                .unwrap_err()
                .contains("not a bounce checkpoint")
        );
        assert!(
            decode(&bytes[..bytes.len() - 3], "c")
                .unwrap_err()
                .contains("truncated or appended")
        );
        let mut other = bytes.clone();
        other[18] = 12;
        assert!(decode(&other, "c").unwrap_err().contains("version 12"));
    }

    /// Three discs of distinct radii, masses and velocities after two steps: every value
    /// forged below has bits found once in the payload.
    fn forgeable() -> World {
        let mut world = World::new(Config {
            boundary: Boundary::walls([0.0, 0.0], [40.0, 40.0]),
            ..Config::default()
        })
        .unwrap();
        for k in 0..3 {
            let r = 0.5 + 0.125 * k as f64;
            let particle = Particle {
                mass: Some(2.0 + 1.5 * k as f64),
                ..Particle::new([3.0 + 7.0 * k as f64, 11.0], [1.25 + k as f64, 0.75], r)
            };
            world.add_particle(particle).unwrap();
        }
        world.step(0.0625).unwrap();
        world.step(0.0625).unwrap();
        world
    }

    /// `bytes` with the one place holding `from`'s bits in the payload set to `to`, and the
    /// checksum made to match: an edit a checksum does not catch.
    fn forge(bytes: &[u8], from: f64, to: f64) -> Vec<u8> {
        let (from, to) = (from.to_le_bytes(), to.to_le_bytes());
        let places: Vec<usize> = (HEADER..=bytes.len() - 8)
            .filter(|&k| bytes[k..k + 8] == from)
            .collect();
        assert_eq!(
            places.len(),
            1,
            "the forged value is not unique in the payload"
        );
        let mut out = bytes.to_vec();
        out[places[0]..places[0] + 8].copy_from_slice(&to);
        reseal(&mut out);
        out
    }

    /// Recomputes the header's payload length and checksum.
    fn reseal(bytes: &mut [u8]) {
        let payload_len = (bytes.len() - HEADER) as u64;
        let checksum = fnv1a(&bytes[HEADER..], FNV_START);
        bytes[22..30].copy_from_slice(&payload_len.to_le_bytes());
        bytes[30..38].copy_from_slice(&checksum.to_le_bytes());
    }

    #[test]
    fn forged_checkpoints_are_refused_naming_the_disc_and_the_field() {
        let world = forgeable();
        let p = world.particles();
        let bytes = encode(&world, Some(&RunState::default())).unwrap();
        let (x, vx, radius, mass) = (p.x()[1], p.vx()[1], p.radius()[1], p.per_particle_mass()[1]);
        let id = p.ids()[1].0;
        let cases: Vec<(f64, f64, String)> = vec![
            (x, 1e6, format!("c: disc {id}: centre [1000000.0")),
            (x, 1e300, format!("c: disc {id}: centre [1e300")),
            (x, -0.5, "outside the box [0.0, 0.0]..[40.0, 40.0]".into()),
            (vx, f64::NAN, format!("c: disc {id}: velocity [NaN")),
            (vx, 1e200, "gives a kinetic energy beyond f64".into()),
            (
                radius,
                0.0,
                format!("c: disc {id}: radius 0 must be finite and > 0"),
            ),
            (radius, 25.0, "is too large for the box".into()),
            (
                mass,
                -1.0,
                format!("c: disc {id}: mass -1 must be finite and > 0"),
            ),
            (world.time(), -5.0, "time -5 after 2 steps".into()),
            (world.time(), 1e308, "".into()),
            (world.time(), f64::INFINITY, "time inf after 2 steps".into()),
        ];
        for (from, to, expected) in cases {
            let error = decode(&forge(&bytes, from, to), "c").err();
            let Some(error) = error else {
                // A time far off the step count is the session's to refuse (its dt).
                assert_eq!(to, 1e308, "{from} -> {to} was accepted");
                continue;
            };
            assert!(error.contains(&expected), "{from} -> {to}: {error}");
            assert!(!error.contains("Serde"), "{error}");
        }
        // The run's totals.
        let run = RunState {
            wall_impulse: 0.375,
            ..RunState::default()
        };
        let with_run = encode(&world, Some(&run)).unwrap();
        let error = decode(&forge(&with_run, 0.375, f64::NAN), "c").unwrap_err();
        assert!(
            error.contains("c: the run's totals: wall_impulse = NaN"),
            "{error}"
        );
        // Bytes after the contents, with the header made to match.
        let mut appended = bytes.clone();
        appended.extend_from_slice(&[0, 1, 2]);
        reseal(&mut appended);
        let error = decode(&appended, "c").unwrap_err();
        assert!(error.contains("3 bytes after its contents"), "{error}");
        // The forgeries are refused for what they are: the untouched bytes decode.
        assert_eq!(
            decode(&bytes, "c").unwrap().world.state_hash(),
            world.state_hash()
        );
    }

    #[test]
    fn every_single_byte_flip_is_refused_or_harmless() {
        let world = small_world();
        let bytes = encode(&world, None).unwrap();
        let mut refused = 0;
        for at in 0..bytes.len() {
            for flip in [0x01u8, 0x80, 0xff] {
                let mut bad = bytes.clone();
                bad[at] ^= flip;
                match decode(&bad, "c") {
                    Err(e) => {
                        assert!(e.starts_with("c"), "{e}");
                        refused += 1;
                    }
                    // Only a byte that does not matter may pass, and then nothing changed.
                    Ok(back) => assert_eq!(
                        (back.world.state_hash(), fingerprint(&back.world)),
                        (world.state_hash(), fingerprint(&world)),
                        "byte {at} ^ {flip:#x} gave another world"
                    ),
                }
            }
        }
        assert_eq!(refused, 3 * bytes.len(), "every flip is caught");
    }

    #[test]
    fn differences_name_the_fields() {
        let a = Config::default();
        let b = Config {
            gravity: [0.0, -9.8],
            substeps: 4,
            ..Config::default()
        };
        let d = config_differences(&a, &b);
        assert_eq!(d.len(), 2, "{d:?}");
        assert!(
            d[0].starts_with("gravity: [0.0, 0.0] vs [0.0, -9.8]"),
            "{d:?}"
        );
        assert!(d[1].starts_with("substeps: 1 vs 4"), "{d:?}");
        assert!(config_differences(&a, &a).is_empty());
    }
}
