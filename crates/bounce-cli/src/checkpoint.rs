//! `checkpoint.bin`: a tagged, versioned postcard encoding of the whole world.

use std::path::Path;

use anyhow::{Context, Result, bail};
use bounce::World;

const MAGIC: &[u8; 18] = b"BOUNCE-CHECKPOINT\n";
const VERSION: u32 = 1;

/// Writes the world to `path` atomically.
pub fn save(world: &World, path: &Path) -> Result<()> {
    let mut bytes = MAGIC.to_vec();
    bytes.extend_from_slice(&VERSION.to_le_bytes());
    let body = postcard::to_stdvec(world).context("cannot encode the checkpoint")?;
    bytes.extend_from_slice(&body);
    crate::atomic::write(path, &bytes)
}

/// Reads a world written by [`save`]; every problem names the file.
pub fn load(path: &Path) -> Result<World> {
    let bytes = std::fs::read(path)
        .with_context(|| format!("cannot read checkpoint {}", path.display()))?;
    let Some(rest) = bytes.strip_prefix(MAGIC.as_slice()) else {
        bail!(
            "{} is not a bounce checkpoint (no checkpoint header)",
            path.display()
        );
    };
    if rest.len() < 4 {
        bail!("{}: checkpoint is truncated", path.display());
    }
    let version = u32::from_le_bytes(rest[..4].try_into().expect("4 bytes"));
    if version != VERSION {
        bail!(
            "{}: checkpoint version {version}, this bounce reads version {VERSION}",
            path.display()
        );
    }
    postcard::from_bytes(&rest[4..])
        .map_err(|e| anyhow::anyhow!("{}: corrupt checkpoint: {e}", path.display()))
}
