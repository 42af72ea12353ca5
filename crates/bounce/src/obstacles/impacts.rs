//! What the obstacles received: each disc's collision with one ([`Impact`]), a pass's
//! impacts, and the books of a step ([`Met`]): the momentum of each obstacle, summed
//! exactly so it does not depend on the storage order, the work moving ones did, and what a
//! driven one's velocity takes from them.

use crate::config::{Config, Motion, ObstacleState};
use crate::context::StepContext;
use crate::particles::Particles;
use crate::sum::ExactSum;

use super::{Obstacles, Trail, resolve_obstacles};

/// A disc's collision with an obstacle.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Impact {
    /// The obstacle's index.
    pub obstacle: u32,
    /// The disc's storage index.
    pub disc: u32,
    /// The momentum the obstacle received.
    pub momentum: [f64; 2],
}

/// Where a disc met an obstacle and how fast it came (kept only for contact events).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Approach {
    /// The disc's centre.
    pub position: [f64; 2],
    /// Its velocity before.
    pub velocity: [f64; 2],
}

/// What one pass of [`resolve_obstacles`] gave the obstacles.
#[derive(Debug, Default)]
pub(crate) struct Impacts {
    /// Every collision, in chunk order, then disc order.
    pub list: Vec<Impact>,
    /// Each collision's approach, when asked for (contact events), else empty.
    pub approaches: Vec<Approach>,
    /// Work done on the discs by moving obstacles, `Σ J_disc · u`, summed exactly.
    pub work: ExactSum,
    /// The energy friction at the obstacles removed (rough discs), summed exactly.
    pub friction: ExactSum,
}

/// What the obstacles received over a step: the momentum of each, and the work moving ones
/// did on the discs.
#[derive(Debug)]
pub(crate) struct Met {
    pub impulses: Vec<[f64; 2]>,
    pub work: f64,
    /// The energy their friction removed.
    pub friction: ExactSum,
}

impl Met {
    /// Nothing yet, for `count` obstacles.
    pub(crate) fn new(count: usize) -> Met {
        Met {
            impulses: vec![[0.0; 2]; count],
            work: 0.0,
            friction: ExactSum::new(),
        }
    }
}

/// One obstacle pass ([`resolve_obstacles`]) and its bookkeeping: the momentum each obstacle
/// received and the work of moving ones go into `met`, and a driven obstacle takes the
/// discs' momentum into its velocity at once (for the next pass). Each obstacle's impulses
/// of the pass are summed exactly, so its velocity does not depend on the order the discs
/// are stored in (which changes when the candidates are listed anew).
pub(crate) fn meet(
    p: &mut Particles,
    trail: Option<&mut Trail>,
    obstacles: &Obstacles,
    states: &mut [ObstacleState],
    config: &Config,
    ctx: &StepContext,
    met: &mut Met,
) {
    let impacts = resolve_obstacles(p, trail, obstacles, states, ctx, false);
    take_impacts(impacts, config, states, met);
}

/// The bookkeeping of one obstacle pass's `impacts` (see [`meet`]).
pub(crate) fn take_impacts(
    mut impacts: Impacts,
    config: &Config,
    states: &mut [ObstacleState],
    met: &mut Met,
) {
    met.work += impacts.work.value();
    met.friction.merge(&impacts.friction);
    impacts.list.sort_by_key(|hit| hit.obstacle);
    for hits in impacts.list.chunk_by(|a, b| a.obstacle == b.obstacle) {
        let k = hits[0].obstacle as usize;
        let j = [0, 1].map(|axis| {
            let mut sum = ExactSum::new();
            for hit in hits {
                sum.add(hit.momentum[axis]);
            }
            sum.value()
        });
        met.impulses[k][0] += j[0];
        met.impulses[k][1] += j[1];
        if let Motion::Driven { mass, .. } = config.obstacles[k].motion {
            states[k].velocity[0] += j[0] / mass;
            states[k].velocity[1] += j[1] / mass;
        }
    }
}
