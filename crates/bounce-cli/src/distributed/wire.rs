//! What travels between ranks, word by word: a ghost's state, a contact sighting, the step's
//! exact sums as integer limbs, and the all-to-all that carries a word list to each rank.

use bounce::{ContactEvent, ContactKind, ExactSum, ParticleId, Party, StepSums, WallSide};
use mpi::Count;
use mpi::collective::SystemOperation;
use mpi::datatype::{Partition, PartitionMut};
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;

/// Exact sums a step reduces: the virial, the four walls and the energy friction removed.
pub(super) const SUMS: usize = 6;
/// Words of a ghost's state: x, y, vx, vy, ω.
pub(super) const GHOST_WORDS: usize = 5;

/// Words a contact sighting travels as.
pub(super) const SIGHTING_WORDS: usize = 11;

/// A part's contact sighting as words: the substep, the disc, the other party (its kind:
/// 0 a disc, 1 a wall, 2 an obstacle; and which), the point, the normal, the impulses and
/// the approach speed (ids and small integers are exact in an `f64`).
pub(super) fn sighting_words(substep: u32, e: &ContactEvent) -> [f64; SIGHTING_WORDS] {
    let (kind, which) = match e.b {
        Party::Disc(id) => (0.0, id.0),
        Party::Wall(side) => (1.0, side as u32),
        Party::Obstacle(k) => (2.0, k),
    };
    let mut words = [0.0; SIGHTING_WORDS];
    words[..4].copy_from_slice(&[f64::from(substep), f64::from(e.a.0), kind, f64::from(which)]);
    words[4..].copy_from_slice(&e.numbers());
    words
}

/// The sighting [`sighting_words`] wrote.
pub(super) fn sighting_of(w: &[f64]) -> (u32, ContactEvent) {
    let which = w[3] as u32;
    let b = match w[2] as u32 {
        0 => Party::Disc(ParticleId(which)),
        1 => Party::Wall(WallSide::ALL[which as usize % 4]),
        _ => Party::Obstacle(which),
    };
    let event = ContactEvent {
        kind: ContactKind::Begin,
        substep: w[0] as u32,
        a: ParticleId(w[1] as u32),
        b,
        point: [w[4], w[5]],
        normal: [w[6], w[7]],
        normal_impulse: w[8],
        tangent_impulse: w[9],
        approach_speed: w[10],
    };
    (event.substep, event)
}

/// The whole step's contact and collision counts and exact sums (virial, the four walls,
/// friction), from every part's,
/// and the bytes this rank sent: the counts and the sums' limbs are integers added by
/// one reduction, the non-finite parts by another (their sum does not depend on order either).
pub(super) fn add_sums(
    comm: &SimpleCommunicator,
    counts: [usize; 2],
    sums: &StepSums,
) -> ([usize; 2], [f64; SUMS], u64) {
    // Friction at pairs and obstacles and at the walls as one sum, as one process takes it.
    let mut friction = sums.friction.clone();
    friction.merge(&sums.walls.friction);
    let exact = [
        &sums.virial,
        &sums.walls.walls[0],
        &sums.walls.walls[1],
        &sums.walls.walls[2],
        &sums.walls.walls[3],
        &friction,
    ];
    let limbs_per_sum = ExactSum::WORDS - 1;
    let mut limbs = vec![counts[0] as i64, counts[1] as i64];
    let mut special = [0.0; SUMS];
    for (k, sum) in exact.iter().enumerate() {
        let words = sum.to_words();
        limbs.extend_from_slice(&words[..limbs_per_sum]);
        special[k] = f64::from_bits(words[limbs_per_sum] as u64);
    }
    let mut limbs_all = vec![0i64; limbs.len()];
    comm.all_reduce_into(&limbs[..], &mut limbs_all[..], SystemOperation::sum());
    let mut special_all = [0.0; SUMS];
    comm.all_reduce_into(&special[..], &mut special_all[..], SystemOperation::sum());
    let bytes = ((limbs.len() + special.len()) * 8) as u64;
    let value = |k: usize| {
        let at = 2 + k * limbs_per_sum;
        ExactSum::from_words(&limbs_all[at..at + limbs_per_sum], special_all[k]).value()
    };
    (
        [limbs_all[0] as usize, limbs_all[1] as usize],
        [0, 1, 2, 3, 4, 5].map(value),
        bytes,
    )
}

pub(super) fn displacements(counts: &[Count]) -> Vec<Count> {
    counts
        .iter()
        .scan(0, |acc, &c| {
            let at = *acc;
            *acc += c;
            Some(at)
        })
        .collect()
}

/// Sends `outgoing[k]` to rank `k`; returns what each rank sent here.
pub(super) fn exchange(comm: &SimpleCommunicator, outgoing: &[Vec<f64>]) -> Vec<Vec<f64>> {
    let send_counts: Vec<Count> = outgoing.iter().map(|w| w.len() as Count).collect();
    let mut recv_counts = vec![0 as Count; outgoing.len()];
    comm.all_to_all_into(&send_counts[..], &mut recv_counts[..]);
    let send: Vec<f64> = outgoing.concat();
    let (send_displs, recv_displs) = (displacements(&send_counts), displacements(&recv_counts));
    let mut recv = vec![0.0; recv_counts.iter().map(|&c| c as usize).sum()];
    {
        let partition = Partition::new(&send[..], &send_counts[..], &send_displs[..]);
        let mut into = PartitionMut::new(&mut recv[..], &recv_counts[..], &recv_displs[..]);
        comm.all_to_all_varcount_into(&partition, &mut into);
    }
    recv_displs
        .iter()
        .zip(&recv_counts)
        .map(|(&at, &n)| recv[at as usize..(at + n) as usize].to_vec())
        .collect()
}
