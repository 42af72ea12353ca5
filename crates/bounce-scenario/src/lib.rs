//! Scenario files: what a bounce run simulates and writes, as TOML.
//!
//! [`load`] parses a file and validates everything it can, collecting *every* problem with
//! its line instead of stopping at the first; [`Scenario::build`] then places the particles
//! and returns a ready [`bounce::World`] and the discs' colours. [`Session`] wraps that into
//! what every front end runs (the CLI, the desktop viewer, the web page): world, colours,
//! time step, view and output plan, the run loop and checkpoints.
//!
//! The format, with every default, is documented in the user guide
//! (`docs/src/reference/scenario.md`) and by `bounce new gas`.

use std::path::Path;

pub mod analysis;
#[cfg(not(target_arch = "wasm32"))]
pub mod atomic;
pub mod checkpoint;
mod colour;
mod diagnose;
pub mod files;
pub mod observables;
pub mod obstacles;
pub use obstacles::{ObstacleGroup, ObstacleSpec};
#[cfg(not(target_arch = "wasm32"))]
pub mod gsd;
pub mod headline;
pub mod json;
pub mod palette;
mod session;
#[cfg(not(target_arch = "wasm32"))]
pub mod start;
pub mod structure;
pub mod support;
#[cfg(not(target_arch = "wasm32"))]
pub mod trajectory;
pub use colour::{Rgb, parse_colour, ramp, spin_ramp};
pub use session::{OBSTACLE_GREY, Piston, Session, TimeStepReport, note_emitted, view_bounds};
mod build;
mod limits;
mod lines;
pub mod overrides;
mod problems;
mod schema;
pub use build::Built;
pub use limits::{BYTES_PER_OBSTACLE, BYTES_PER_PARTICLE, Estimate, Limits};
pub use problems::{Problem, ScenarioError};
pub use schema::*;

/// The shipped scenarios, by name: `bounce new NAME` writes them out.
pub const TEMPLATES: [(&str, &str); 14] = [
    ("gas", include_str!("../../../scenarios/gas.toml")),
    ("pile", include_str!("../../../scenarios/pile.toml")),
    (
        "newtons-cradle",
        include_str!("../../../scenarios/newtons-cradle.toml"),
    ),
    ("brownian", include_str!("../../../scenarios/brownian.toml")),
    ("mixing", include_str!("../../../scenarios/mixing.toml")),
    ("million", include_str!("../../../scenarios/million.toml")),
    (
        "galton-board",
        include_str!("../../../scenarios/galton-board.toml"),
    ),
    (
        "hourglass",
        include_str!("../../../scenarios/hourglass.toml"),
    ),
    (
        "angle-of-repose",
        include_str!("../../../scenarios/angle-of-repose.toml"),
    ),
    ("piston", include_str!("../../../scenarios/piston.toml")),
    ("effusion", include_str!("../../../scenarios/effusion.toml")),
    (
        "hard-discs",
        include_str!("../../../scenarios/hard-discs.toml"),
    ),
    (
        "driven-granular",
        include_str!("../../../scenarios/driven-granular.toml"),
    ),
    ("shear", include_str!("../../../scenarios/shear.toml")),
];

/// Reads and validates a scenario file.
pub fn load(path: &Path) -> Result<Scenario, ScenarioError> {
    let file = path.display().to_string();
    let source = files::read_to_string(path).map_err(|e| ScenarioError {
        file: file.clone(),
        problems: vec![Problem {
            line: None,
            message: format!("cannot read the file: {e}"),
        }],
    })?;
    parse(&source, &file)
}

/// Parses and validates scenario text; `file` names it in messages. Every problem reading
/// can find is listed, in line order: type errors past the first, and the semantic problems
/// of the rest (the placement of the discs adds its own: [`Session::from_text_in`]).
pub fn parse(source: &str, file: &str) -> Result<Scenario, ScenarioError> {
    let examined = diagnose::examine(source);
    match examined.scenario {
        Some(scenario) if examined.problems.is_empty() => Ok(scenario),
        _ => Err(ScenarioError {
            file: file.to_string(),
            problems: examined.problems,
        }),
    }
}

/// The text of a shipped template.
pub fn template(name: &str) -> Option<&'static str> {
    TEMPLATES.iter().find(|(n, _)| *n == name).map(|(_, t)| *t)
}
