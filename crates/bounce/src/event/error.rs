//! Why the event-driven engine refuses a world or stops: its errors, and the events a step
//! may take.

use thiserror::Error;

/// Why an event-driven world was refused or stopped.
///
/// ```
/// use bounce::event::{EventDriven, EventError};
/// use bounce::{Config, Method, Particle};
/// let config = Config { method: Method::EventDriven, ..Config::default() };
/// let overlapping = [
///     Particle::new([0.0, 0.0], [0.0, 0.0], 1.0),
///     Particle::new([1.5, 0.0], [0.0, 0.0], 1.0),
/// ];
/// let error = EventDriven::new(&config, &overlapping).unwrap_err();
/// assert_eq!(error, EventError::Overlap(0, 1));
/// assert!(error.to_string().contains("needs every pair apart"));
/// ```
#[derive(Clone, Debug, PartialEq, Error)]
pub enum EventError {
    /// The configuration asks for what the event-driven engine does not do.
    #[error("the event-driven method {0}")]
    Unsupported(&'static str),
    /// A disc is invalid or placed where it cannot be.
    #[error("disc {0}: {1}")]
    Disc(usize, String),
    /// Two discs overlap: an event-driven world starts with every pair apart.
    #[error("discs {0} and {1} overlap: the event-driven method needs every pair apart")]
    Overlap(usize, usize),
    /// Events kept coming without the clock moving (inelastic collapse, or a disc resting
    /// on a wall or an obstacle under gravity).
    #[error(
        "the run cannot advance past t = {time}: discs {discs:?} collide endlessly there \
         (inelastic collapse or a resting contact); set contact_duration (the TC model) or \
         raise the restitution"
    )]
    Stalled {
        /// Where the clock stuck.
        time: f64,
        /// The discs of the last events.
        discs: Vec<usize>,
    },
    /// One interval took more events than it was allowed.
    #[error(
        "more than {events} events before t = {time} in one step: the world is observed too \
         rarely for its collision rate (lower dt)"
    )]
    TooManyEvents {
        /// The events processed.
        events: u64,
        /// Where it had got to.
        time: f64,
    },
    /// The interrupt flag was set during the interval.
    #[error("interrupted at t = {time}")]
    Interrupted {
        /// Where it had got to.
        time: f64,
    },
}

/// Events per disc one step (of [`crate::World::step`]) may take before it is refused with
/// [`EventError::TooManyEvents`]: far beyond a useful observation interval, well before a
/// run that looks hung. [`crate::World::step`] then stops with [`EventError::TooManyEvents`],
/// naming the time reached. See [`EventError`] for an example.
pub const MAX_EVENTS_PER_DISC: u64 = 10_000;
