//! How a world is advanced: the time-stepped step (the default) or exact event-driven hard
//! discs, and what the event-driven method does not combine with.

use serde::{Deserialize, Serialize};

use super::{Boundary, Config, Motion, RestingContacts};

/// How [`crate::World::step`] advances the world.
///
/// ```
/// use bounce::{Config, Method};
/// let exact = Config { method: Method::EventDriven, ..Config::default() };
/// assert_eq!(exact.method.name(), "event_driven");
/// assert_eq!(exact.event_driven_unsupported(), None);
/// let stepped = Config { substeps: 4, ..exact };
/// assert_eq!(
///     stepped.event_driven_unsupported(),
///     Some("cannot be combined with substeps > 1 (events are exact)")
/// );
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Method {
    /// The time-stepped loop: move every disc by `dt`, then find the overlapping
    /// pairs and resolve them (push apart, velocity update). The default.
    #[default]
    TimeStepped,
    /// Exact hard discs ([`crate::event`]): discs fly freely between collisions, and every
    /// collision (with a disc, a wall, an obstacle) is resolved at the exact moment of
    /// contact with the collision law's velocity update; no overlap, so no push, and no time-step
    /// bias. `dt` is then the interval at which the world is observed: a step processes
    /// every event up to exactly `t + dt`.
    EventDriven,
}

impl Method {
    /// The name scenario files and Python use: `time_stepped` or `event_driven`. See
    /// [`Method`] for an example.
    pub fn name(self) -> &'static str {
        match self {
            Method::TimeStepped => "time_stepped",
            Method::EventDriven => "event_driven",
        }
    }
}

impl Config {
    /// What in this configuration the event-driven method cannot do (`None`: it can do it
    /// all), as the end of a sentence that starts "the event-driven method". See [`Method`]
    /// for an example.
    pub fn event_driven_unsupported(&self) -> Option<&'static str> {
        if self.substeps != 1 {
            return Some("cannot be combined with substeps > 1 (events are exact)");
        }
        if self.solver_iterations != 1 {
            return Some("cannot be combined with solver_iterations > 1 (events are exact)");
        }
        if self.max_travel.is_some() {
            return Some("cannot be combined with max_travel (events are exact)");
        }
        if self.resting_contacts == RestingContacts::Rest {
            return Some(
                "cannot be combined with resting_contacts = \"rest\" (use contact_duration, the TC model)",
            );
        }
        if self.is_rough() {
            return Some("cannot be combined with rough discs (friction, rolling_resistance) yet");
        }
        if self.contact_events {
            return Some("cannot record contact events yet ([output] events, contact_events)");
        }
        if !self.emitters.is_empty() || !self.sinks.is_empty() {
            return Some("cannot be combined with emitters or sinks");
        }
        if self.obstacles.iter().any(|o| o.motion != Motion::Fixed) {
            return Some("cannot be combined with moving obstacles");
        }
        if matches!(self.boundary, Boundary::LeesEdwards { .. }) {
            return Some("cannot be combined with a Lees–Edwards boundary yet");
        }
        if matches!(self.boundary, Boundary::Periodic { .. }) && !self.obstacles.is_empty() {
            return Some("cannot be combined with obstacles in a periodic box");
        }
        None
    }
}
