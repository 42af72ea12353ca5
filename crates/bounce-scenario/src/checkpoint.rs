//! The checkpoint format shared by the CLI and the viewer.
//!
//! ```text
//! "BOUNCE-CHECKPOINT\n"   18 bytes
//! version                u32 LE (3)
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

use bounce::{Config, World};
use serde::{Deserialize, Serialize};

const MAGIC: &[u8; 18] = b"BOUNCE-CHECKPOINT\n";
/// Version 2 added the broadphase's reference positions; version 3 the checksum, the
/// fingerprint and the run's output state.
const VERSION: u32 = 3;
/// Bytes before the payload.
const HEADER: usize = 18 + 4 + 8 + 8 + 8;

/// What a run's outputs had accumulated since their last `stats.csv` row when the checkpoint
/// was written, so a resumed run continues the same rows.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct RunState {
    /// Colliding pairs since the last row.
    pub collisions: u64,
    /// Wall impulse since the last row.
    pub wall_impulse: f64,
    /// Largest overlap since the last row.
    pub max_overlap: f64,
    /// Simulated time since the last row.
    pub elapsed: f64,
    /// Momentum each obstacle received since the last row (empty without obstacles).
    pub obstacle_impulse: Vec<[f64; 2]>,
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
    world: World,
    run: Option<RunState>,
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
    let body: OwnedBody =
        postcard::from_bytes(payload).map_err(|e| format!("{name}: corrupt checkpoint: {e}"))?;
    if fingerprint(&body.world) != u64_of(fingerprint_read) {
        return Err(format!(
            "{name}: corrupt checkpoint: its fingerprint does not match its configuration"
        ));
    }
    Ok(Checkpoint {
        world: body.world,
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
        obstacles,
        emitters,
        sinks,
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
    differ("emitters", f(emitters), f(&b.emitters));
    differ("sinks", f(sinks), f(&b.sinks));
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
    let bytes = std::fs::read(path)
        .map_err(|e| format!("cannot read checkpoint {}: {e}", path.display()))?;
    decode(&bytes, &path.display().to_string())
}

#[cfg(test)]
mod tests {
    use super::*;
    use bounce::{Boundary, Particle};

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
            wall_impulse: 0.25,
            max_overlap: 0.0,
            elapsed: 0.5,
            obstacle_impulse: vec![[1.0, -2.0]],
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
        other[18] = 9;
        assert!(decode(&other, "c").unwrap_err().contains("version 9"));
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
