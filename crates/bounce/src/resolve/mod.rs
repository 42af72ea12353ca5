//! Resolution: the law's pair resolution applied to every contact, in the canonical order.
//!
//! Pairs are resolved one after another on the current state (Gauss–Seidel style, as the
//! seed's loop does): a disc pushed by one pair is seen at its new place by the next. The
//! order is the wave order of `contacts` (the canonical order's bits in one sweep); the pieces
//! of one phase touch disjoint discs, so they run in parallel and still give the serial
//! result bit for bit.
//!
//! With more than one solver pass, walls are contacts too: after each pass's pairs,
//! [`resolve_walls`] bounces every disc that touches a wall and moves into it. Without it
//! only integration meets the walls, once per substep, and the floor can hold up a stack
//! only by the bounce of its bottom row: in a momentum-conserving model the whole pile then
//! sinks at a steady speed that the pushes undo (measured: mean vy ≈ -0.6 in the settled
//! shipped pile under `relative_normal_velocity`, a kinetic energy near 150).

mod in_order;
mod side_by_side;
mod walls;

pub(crate) use in_order::{PairResolved, resolve_in_order, solver_order};
pub(crate) use side_by_side::resolve_all;
pub(crate) use walls::resolve_walls;

use crate::sum::ExactSum;

/// What resolving the contacts of a substep adds up.
#[derive(Clone, Debug)]
pub(crate) struct Resolved {
    /// The collision virial `Σ r_ij · Δp_ij`, summed exactly (so in no particular order).
    pub virial: ExactSum,
    /// The pairs that met as impacts ([`is_impact`]), not resting contacts.
    pub impacts: usize,
    /// The energy friction and rolling resistance removed (rough discs), summed exactly.
    pub friction: ExactSum,
    /// With [`Recording::tensor`]: the collision virial's tensor terms
    /// ([`virial_terms`]), summed exactly; empty otherwise.
    pub tensor: [ExactSum; 3],
    /// With [`Recording::impacts`]: the ids of the two discs of each impact, in no
    /// particular order; empty otherwise.
    pub collided: Vec<u32>,
}

impl Resolved {
    pub(crate) fn new() -> Self {
        Resolved {
            virial: ExactSum::new(),
            impacts: 0,
            friction: ExactSum::new(),
            tensor: [ExactSum::new(), ExactSum::new(), ExactSum::new()],
            collided: Vec::new(),
        }
    }

    fn merge(&mut self, other: &Resolved) {
        self.virial.merge(&other.virial);
        self.impacts += other.impacts;
        self.friction.merge(&other.friction);
        for (mine, theirs) in self.tensor.iter_mut().zip(&other.tensor) {
            mine.merge(theirs);
        }
        self.collided.extend_from_slice(&other.collided);
    }
}

/// What the solver records of each pair besides what every step sums (the virial, the
/// impacts, friction's work): compile-time absent when neither is asked for.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Recording {
    /// The virial tensor's terms ([`crate::Config::pressure_tensor`]).
    pub tensor: bool,
    /// The discs of each impact ([`crate::Config::collision_counts`]; a substep's first pass
    /// only, where the step counts its collisions).
    pub impacts: bool,
}

impl Recording {
    fn any(self) -> bool {
        self.tensor || self.impacts
    }
}
