//! What a front end cannot run yet, with the reason: the refusals that are not the core's own
//! (the core refuses what a `Config` cannot do at all, `Config::validate`). The user guide's
//! compatibility table (`docs/src/reference/compatibility.md`) is tested against these.

use bounce::{Config, Method};

/// What in `config` a run across MPI ranks does not support yet (`None`: everything), named
/// as the scenario file names it.
///
/// ```
/// use bounce::{Config, Obstacle};
/// use bounce_scenario::support::across_ranks_unsupported;
/// assert_eq!(across_ranks_unsupported(&Config::default()), None);
/// let pegs = Config { obstacles: vec![Obstacle::peg([0.0, 0.0], 1.0)], ..Config::default() };
/// assert_eq!(across_ranks_unsupported(&pegs), Some("[[obstacle]]"));
/// ```
pub fn across_ranks_unsupported(config: &Config) -> Option<&'static str> {
    let refused = [
        (!config.obstacles.is_empty(), "[[obstacle]]"),
        (!config.emitters.is_empty(), "[[emitter]]"),
        (!config.sinks.is_empty(), "[[sink]]"),
        (
            config.method == Method::EventDriven,
            "time.method = \"event_driven\"",
        ),
        (config.thermostat.is_some(), "world.thermostat"),
        (config.pressure_tensor, "output.pressure_tensor"),
        (config.collision_counts, "output.collision_counts"),
    ];
    refused
        .into_iter()
        .find_map(|(present, what)| present.then_some(what))
}
