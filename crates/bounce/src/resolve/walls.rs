//! Walls as contacts of a solver pass.

use crate::context::StepContext;
use crate::geometry::Geometry;
use crate::law::{rub_walls, touch_walls};
use crate::parallel::CHUNK;
use crate::particles::Particles;
use crate::sum::WallSums;

/// Walls as contacts of a solver pass: every disc touching a wall (its centre at most its
/// radius from it, as [`Geometry::hold`] leaves pushed discs) and moving into it leaves with
/// its normal velocity reversed and scaled by the walls' restitution, like a reflection in
/// integration. Returns the momentum given to each wall by the discs the tally counts.
pub(crate) fn resolve_walls(p: &mut Particles, ctx: &StepContext) -> WallSums {
    let Geometry::Walls {
        min,
        max,
        restitution: e,
    } = ctx.geometry
    else {
        return WallSums::default();
    };
    let law = &ctx.law;
    let e = law.restitution_of(e);
    let tally = ctx.tally;
    let rubbing = law.rough.filter(|rough| rough.rubs_walls());
    let (x, y, radius, mass) = (&p.x, &p.y, &p.radius, &p.mass);
    // (The angular velocities' chunks are empty for smooth discs.)
    let mut omega_chunks: Vec<&mut [f64]> = p.omega.chunks_mut(CHUNK).collect();
    omega_chunks.resize_with(p.vx.len().div_ceil(CHUNK), || &mut []);
    type Chunk<'a> = (usize, &'a mut [f64], &'a mut [f64], &'a mut [f64]);
    let mut chunks: Vec<Chunk> =
        p.vx.chunks_mut(CHUNK)
            .zip(p.vy.chunks_mut(CHUNK))
            .zip(omega_chunks)
            .enumerate()
            .map(|(c, ((vx, vy), omega))| (c * CHUNK, vx, vy, omega))
            .collect();
    // One axis: the impulse on the low and the high wall.
    let partial = ctx
        .exec
        .map_mut(p.x.len(), &mut chunks, |_, (base, vx, vy, omega)| {
            let mut impulse = WallSums::default();
            for (k, (vx, vy)) in vx.iter_mut().zip(vy.iter_mut()).enumerate() {
                let i = *base + k;
                let r = radius[i];
                let m = law.mass(r, mass[i]);
                let [left, right] = touch_walls(x[i], vx, r, m, min[0], max[0], e);
                let [bottom, top] = touch_walls(y[i], vy, r, m, min[1], max[1], e);
                let hits = [left, right, bottom, top];
                let counted = tally.is_none_or(|t| t.counts(x[i], y[i]));
                if counted {
                    impulse.add(hits);
                }
                if let Some(rough) = &rubbing
                    && hits != [0.0; 4]
                {
                    let mut velocity = [*vx, *vy];
                    let work = rub_walls(hits, &mut velocity, &mut omega[k], r, m, rough);
                    [*vx, *vy] = velocity;
                    if counted {
                        impulse.friction.add(work);
                    }
                }
            }
            impulse
        });
    let mut total = WallSums::default();
    for impulse in &partial {
        total.merge(impulse);
    }
    total
}
