//! Tags: the user's number on each disc follows it through the reordering of the steps,
//! removals, a save and load and the records of distributed runs, and changes no bit of
//! the physics.

use bounce::scene::Bench;
use bounce::{Particle, ParticleId, World};

fn gas(tagged: bool) -> World {
    let (config, discs) = Bench::Gas.build(3000).unwrap();
    let mut world = World::new(config).unwrap();
    world.set_threads(2).unwrap();
    world.set_parallel_min_work(1);
    let discs: Vec<Particle> = (discs.into_iter().enumerate())
        .map(|(k, d)| {
            if tagged {
                d.with_tag(1_000_003 * k as u64 + 11)
            } else {
                d
            }
        })
        .collect();
    world.add_particles(discs).unwrap();
    world
}

#[test]
fn tags_follow_their_discs_and_change_nothing() {
    let (mut tagged, mut plain) = (gas(true), gas(false));
    assert!(
        plain.particles().tag().is_empty(),
        "untagged worlds keep no tags"
    );
    for _ in 0..150 {
        tagged.step(Bench::DT).unwrap();
        plain.step(Bench::DT).unwrap();
    }
    assert_eq!(tagged.state_hash(), plain.state_hash());
    assert!(tagged.stats().pairs > 0);
    // The discs were reordered many times; each id still has its tag.
    let check = |world: &World| {
        for (id, disc) in world.particles_by_id() {
            assert_eq!(disc.tag, 1_000_003 * id.0 as u64 + 11, "disc {}", id.0);
        }
    };
    check(&tagged);
    // Removing some, saving and loading, and a distributed run's records keep them.
    let gone: Vec<ParticleId> = (0..3000).step_by(7).map(ParticleId).collect();
    tagged.remove_particles(&gone);
    tagged.step(Bench::DT).unwrap();
    check(&tagged);
    let loaded: World = postcard::from_bytes(&postcard::to_allocvec(&tagged).unwrap()).unwrap();
    check(&loaded);
    let records: Vec<_> = (0..tagged.len()).map(|i| tagged.record(i)).collect();
    let words: Vec<f64> = records.iter().flat_map(|r| r.to_words()).collect();
    let back: Vec<_> = words
        .chunks(bounce::DiscRecord::WORDS)
        .map(bounce::DiscRecord::from_words)
        .collect();
    check(&tagged.part(&back).unwrap());
    // A tag set later, on a world that had none, starts the list.
    plain.set_tag(ParticleId(5), u64::MAX).unwrap();
    plain.step(Bench::DT).unwrap();
    assert_eq!(plain.particle(ParticleId(5)).unwrap().tag, u64::MAX);
    assert_eq!(plain.particle(ParticleId(6)).unwrap().tag, 0);
    assert!(plain.set_tag(ParticleId(99_999), 1).is_err());
}
