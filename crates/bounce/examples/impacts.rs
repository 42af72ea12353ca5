//! Impacts as a game hears them: discs fall into a box with a peg, and every contact that
//! begins with a normal impulse above a threshold is printed, as a game would play a sound
//! whose volume follows the impulse.
//!
//! `cargo run --release -p bounce --example impacts [THRESHOLD]` (default 1.0).

use bounce::{Boundary, Config, ContactKind, Obstacle, Particle, Party, World};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let threshold: f64 = std::env::args()
        .nth(1)
        .map(|a| a.parse())
        .transpose()?
        .unwrap_or(1.0);
    let config = Config {
        boundary: Boundary::walls([0.0, 0.0], [40.0, 30.0]),
        gravity: [0.0, -9.81],
        coefficient_of_restitution: 0.8,
        substeps: 4,
        obstacles: vec![Obstacle::peg([20.0, 8.0], 3.0)],
        // Only contacts that begin with at least this normal impulse are reported.
        contact_events: true,
        contact_event_threshold: threshold,
        ..Config::default()
    };
    let mut world = World::new(config)?;
    // Twelve rows of twenty discs, high in the box, drifting sideways.
    for row in 0..12 {
        for column in 0..20 {
            let position = [1.5 + 1.9 * column as f64, 14.0 + 1.2 * row as f64];
            let velocity = [if row % 2 == 0 { 1.0 } else { -1.0 }, 0.0];
            world.add_particle(Particle::new(position, velocity, 0.5))?;
        }
    }
    let (mut loudest, mut heard) = (0.0f64, [0usize; 3]);
    for _ in 0..300 {
        world.step(1.0 / 60.0)?;
        for event in world.contact_events() {
            if event.kind != ContactKind::Begin {
                continue;
            }
            let (what, kind) = match event.b {
                Party::Disc(id) => (format!("disc {}", id.0), 0),
                Party::Wall(side) => (format!("the {} wall", side.name()), 1),
                Party::Obstacle(k) => (format!("obstacle {k}"), 2),
            };
            heard[kind] += 1;
            if event.normal_impulse > loudest {
                loudest = event.normal_impulse;
                println!(
                    "t = {:6.3}  disc {:>3} hit {what:<16} at ({:5.2}, {:5.2}): impulse {:6.3}, \
                     speed {:6.3}",
                    world.time(),
                    event.a.0,
                    event.point[0],
                    event.point[1],
                    event.normal_impulse,
                    event.approach_speed
                );
            }
        }
    }
    println!(
        "impacts over {threshold}: {} between discs, {} on walls, {} on the peg (loudest {loudest:.3})",
        heard[0], heard[1], heard[2]
    );
    // The falling rows reach the floor and the peg hard: each kind is heard.
    if heard.contains(&0) || loudest < threshold {
        return Err("expected impacts of every kind above the threshold".into());
    }
    Ok(())
}
