//! `checkpoint.bin` on disk (the format lives in `bounce_scenario::checkpoint`).

use std::path::Path;

use anyhow::{Context, Result, anyhow};
use bounce::World;

/// Writes the world to `path` atomically.
pub fn save(world: &World, path: &Path) -> Result<()> {
    let bytes = bounce_scenario::checkpoint::encode(world).map_err(|e| anyhow!(e))?;
    crate::atomic::write(path, &bytes)
}

/// Reads a world written by [`save`]; every problem names the file.
pub fn load(path: &Path) -> Result<World> {
    let bytes = std::fs::read(path)
        .with_context(|| format!("cannot read checkpoint {}", path.display()))?;
    bounce_scenario::checkpoint::decode(&bytes, &path.display().to_string()).map_err(|e| anyhow!(e))
}
