//! `checkpoint.bin` on disk (the format lives in `bounce_scenario::checkpoint`).

use std::path::Path;

use anyhow::{Result, anyhow};
use bounce::World;
use bounce_scenario::checkpoint::{Checkpoint, RunState};

/// Writes the world and the run's output totals to `path` atomically.
pub fn save(world: &World, run: Option<&RunState>, path: &Path) -> Result<()> {
    bounce_scenario::checkpoint::save(world, run, path).map_err(|e| anyhow!(e))
}

/// Reads a checkpoint written by [`save`]; every problem names the file.
pub fn load(path: &Path) -> Result<Checkpoint> {
    bounce_scenario::checkpoint::load(path).map_err(|e| anyhow!(e))
}

/// The bytes of a checkpoint, kept in memory.
pub fn encode(world: &World, run: Option<&RunState>) -> Result<Vec<u8>> {
    bounce_scenario::checkpoint::encode(world, run).map_err(|e| anyhow!(e))
}
