//! `checkpoint.bin` on disk (the format lives in `bounce_scenario::checkpoint`).

use std::path::Path;

use anyhow::{Result, anyhow};
use bounce::World;

/// Writes the world to `path` atomically.
pub fn save(world: &World, path: &Path) -> Result<()> {
    bounce_scenario::checkpoint::save(world, path).map_err(|e| anyhow!(e))
}

/// Reads a world written by [`save`]; every problem names the file.
pub fn load(path: &Path) -> Result<World> {
    bounce_scenario::checkpoint::load(path).map_err(|e| anyhow!(e))
}
