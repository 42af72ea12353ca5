//! The checkpoint format shared by the CLI and the viewer: a tag, a version, and the world
//! encoded with postcard. Decoding validates everything (see `bounce::World`'s serde).

use bounce::World;

const MAGIC: &[u8; 18] = b"BOUNCE-CHECKPOINT\n";
/// Version 2 added the broadphase's reference positions (they decide when the candidate
/// list is rebuilt, and so the last bits of the energy sums).
const VERSION: u32 = 2;

/// The bytes of a checkpoint of `world`.
pub fn encode(world: &World) -> Result<Vec<u8>, String> {
    let mut bytes = MAGIC.to_vec();
    bytes.extend_from_slice(&VERSION.to_le_bytes());
    let body =
        postcard::to_stdvec(world).map_err(|e| format!("cannot encode the checkpoint: {e}"))?;
    bytes.extend_from_slice(&body);
    Ok(bytes)
}

/// A world from checkpoint bytes; `name` (the file) starts every error message.
pub fn decode(bytes: &[u8], name: &str) -> Result<World, String> {
    let Some(rest) = bytes.strip_prefix(MAGIC.as_slice()) else {
        return Err(format!(
            "{name} is not a bounce checkpoint (no checkpoint header)"
        ));
    };
    if rest.len() < 4 {
        return Err(format!("{name}: checkpoint is truncated"));
    }
    let version = u32::from_le_bytes(rest[..4].try_into().expect("4 bytes"));
    if version != VERSION {
        return Err(format!(
            "{name}: checkpoint version {version}, this bounce reads version {VERSION} \
             (re-run the scenario with this bounce to make a new one)"
        ));
    }
    postcard::from_bytes(&rest[4..]).map_err(|e| format!("{name}: corrupt checkpoint: {e}"))
}

/// Writes a checkpoint of `world` to `path` atomically (whole or not at all).
#[cfg(not(target_arch = "wasm32"))]
pub fn save(world: &World, path: &std::path::Path) -> Result<(), String> {
    let bytes = encode(world)?;
    crate::atomic::write(path, &bytes).map_err(|e| e.to_string())
}

/// Reads a checkpoint written by [`save`]; every problem names the file.
pub fn load(path: &std::path::Path) -> Result<World, String> {
    let bytes = std::fs::read(path)
        .map_err(|e| format!("cannot read checkpoint {}: {e}", path.display()))?;
    decode(&bytes, &path.display().to_string())
}

#[cfg(test)]
mod tests {
    use super::*;
    use bounce::{Config, Particle};

    #[test]
    fn round_trip_and_refusals() {
        let mut world = World::new(Config::default()).unwrap();
        world
            .add_particle(Particle::new([1.0, 2.0], [3.0, 4.0], 0.5))
            .unwrap();
        let bytes = encode(&world).unwrap();
        assert_eq!(
            decode(&bytes, "c").unwrap().state_hash(),
            world.state_hash()
        );
        assert!(
            decode(b"junk", "c")
                .unwrap_err()
                .contains("not a bounce checkpoint")
        );
        assert!(
            decode(&bytes[..bytes.len() - 3], "c")
                .unwrap_err()
                .contains("corrupt")
        );
        let mut other = bytes.clone();
        other[18] = 9;
        assert!(decode(&other, "c").unwrap_err().contains("version 9"));
    }
}
