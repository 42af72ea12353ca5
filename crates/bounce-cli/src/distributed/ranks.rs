//! The run's ranks, seen from one of them: its part of the world, the step with its one
//! exchange of ghost states, the redistribution of discs, the gathers for outputs.

use std::time::Instant;

use anyhow::{Context, Result, anyhow, bail};
use bounce::{
    Boundary, ContactLog, DiscRecord, ParticleId, SensorState, StepStats, Tally, WallImpulse, World,
};
use mpi::Count;
use mpi::collective::SystemOperation;
use mpi::datatype::PartitionMut;
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;

use super::decomposition::{BINS, Cuts, Domains, cuts_by_count, grid_shape};
use super::wire::{
    GHOST_WORDS, SIGHTING_WORDS, add_sums, displacements, exchange, sighting_of, sighting_words,
};
use super::{Failure, agree};

/// Order cells the discs may drift before they are redistributed. More means fewer
/// redistributions (each rebuilds every part: measured ~0.3 s at 10^6 discs on 2 ranks) and
/// thicker ghost layers (each ghost is stepped on two ranks).
pub(super) const DRIFT_CELLS: f64 = 4.0;

/// This rank's part of the world and who it exchanges with.
pub(super) struct Part {
    pub(super) world: World,
    /// How many discs this rank owned when they were distributed.
    owned: usize,
    /// Which events this part counts (`None` with one rank).
    tally: Option<Tally>,
    /// Per rank: the owned discs it holds as ghosts (ascending ids).
    send: Vec<Vec<ParticleId>>,
    /// Per rank: its discs held here as ghosts (ascending ids).
    recv: Vec<Vec<ParticleId>>,
    /// Discs within this of a domain are held by its rank.
    ghost_width: f64,
}

/// The run's ranks, seen from one of them.
pub(super) struct Ranks<'c> {
    comm: &'c SimpleCommunicator,
    pub(super) part: Part,
    threads: usize,
    dt: f64,
    /// The largest radius anywhere: every part's order grid is sized for it.
    max_radius: f64,
    /// The whole world's fastest disc (squared speed) and smallest radius after the last
    /// step: what adaptive substeps need.
    max_speed2: f64,
    min_radius: f64,
    /// The largest distance an owned disc moved in the last step, over all ranks.
    stride: f64,
    /// The signal any rank was stopped by (0: none).
    pub(super) stop: usize,
    pub(super) last_stats: StepStats,
    /// The energy friction has removed since the start, the merged steps' summed in order
    /// (what one process's world adds up).
    friction_work: f64,
    /// Bytes this rank sent: ghost states, redistributions, reductions, gathers; steps.
    sent: [u64; 4],
    steps: u64,
    redistributions: u64,
    /// Seconds in the part's own step, the reductions, ghost refreshes, redistributions.
    clock: [f64; 4],
    /// Each step's wall time, all of it.
    step_times: Vec<f64>,
    /// With contact events, on rank 0: the whole world's log, fed with every part's
    /// sightings after each step.
    pub(super) contact_log: Option<ContactLog>,
    /// With sensors, on rank 0: the whole world's sensors, fed with the discs every part
    /// sees in them after each step.
    pub(super) sensors: Option<SensorState>,
}

impl<'c> Ranks<'c> {
    /// Every rank starts from the whole world (built from the scenario or a checkpoint)
    /// and keeps its part.
    pub(super) fn new(
        comm: &'c SimpleCommunicator,
        whole: &World,
        threads: usize,
        dt: f64,
    ) -> Result<Self> {
        let p = whole.particles();
        let max_radius = p.radius().iter().copied().fold(0.0, f64::max);
        let max_speed2 = (0..p.len())
            .map(|i| p.vx()[i] * p.vx()[i] + p.vy()[i] * p.vy()[i])
            .fold(0.0, f64::max);
        let min_radius = p.radius().iter().copied().fold(f64::INFINITY, f64::min);
        let mut ranks = Ranks {
            comm,
            part: Part {
                world: whole.part(&[])?,
                owned: 0,
                tally: None,
                send: Vec::new(),
                recv: Vec::new(),
                ghost_width: 0.0,
            },
            threads,
            dt,
            max_radius,
            max_speed2,
            min_radius,
            stride: 0.0,
            stop: 0,
            last_stats: *whole.stats(),
            friction_work: whole.friction_work(),
            sent: [0; 4],
            steps: 0,
            redistributions: 0,
            clock: [0.0; 4],
            step_times: Vec::new(),
            contact_log: (whole.config().contact_events && comm.rank() == 0)
                .then(|| whole.contact_log().clone()),
            sensors: (!whole.config().sensors.is_empty() && comm.rank() == 0)
                .then(|| whole.sensor_state().clone()),
        };
        // Every rank holds every disc now: each takes its own share without messages.
        let all: Vec<DiscRecord> = whole
            .in_id_order()
            .into_iter()
            .map(|(_, i)| whole.record(i))
            .collect();
        let places: Vec<[f64; 2]> = all.iter().map(|r| r.position).collect();
        let domains = ranks.cut(&places, true);
        ranks.part = ranks.build(whole, domains, &all)?;
        Ok(ranks)
    }

    pub(super) fn size(&self) -> usize {
        self.comm.size() as usize
    }

    /// The reach of one step's chains of contacts (see the module docs), with the distance a
    /// disc may move in it.
    pub(super) fn reach(&self) -> f64 {
        let config = self.part.world.config();
        let cell = bounce::order_cell_width(config, self.max_radius);
        let substeps = self.substeps() as f64;
        let passes = f64::from(config.solver_iterations);
        let [gx, gy] = config.gravity;
        let fall = (gx * gx + gy * gy).sqrt() * self.dt;
        let step = 2.0 * (self.stride.max((self.max_speed2.sqrt() + fall) * self.dt)) + cell;
        substeps * passes * (bounce::order_pass_reach(config, self.max_radius) + 2.0 * step)
            + 2.0 * step
    }

    pub(super) fn substeps(&self) -> u32 {
        self.part
            .world
            .substeps_for_extremes(self.dt, self.max_speed2, self.min_radius)
    }

    /// Domains with about as many of `places` (this rank's discs; with `everyone`, every
    /// disc, which every rank holds) in each, cut on the order grid's block edges (each
    /// block's contacts are one rank's).
    pub(super) fn cut(&self, places: &[[f64; 2]], everyone: bool) -> Domains {
        let config = self.part.world.config();
        let period = |axis: usize| match config.boundary {
            Boundary::Periodic { min, max } | Boundary::LeesEdwards { min, max, .. } => {
                Some((min[axis], max[axis] - min[axis]))
            }
            _ => None,
        };
        // A Lees–Edwards box is cut in rows only: a disc through the top or bottom comes back
        // slid along x, and the copies across slide past each other, so a row's neighbours
        // across the edge may be anywhere along it.
        let (rows, columns) = match config.boundary.is_sheared() {
            true => (self.size(), 1),
            false => grid_shape(self.size()),
        };
        let whole = |axis: usize, parts: usize| Cuts {
            cuts: {
                let mut c = vec![f64::NEG_INFINITY; parts + 1];
                c[parts] = f64::INFINITY;
                c
            },
            period: period(axis),
        };
        let mut domains = Domains {
            rows: whole(1, rows),
            columns: vec![whole(0, columns); rows],
        };
        if self.size() == 1 {
            return domains;
        }
        let wrapped: Vec<[f64; 2]> = places
            .iter()
            .map(|&[x, y]| [domains.columns[0].wrapped(x), domains.rows.wrapped(y)])
            .collect();
        // The histograms' range: the box, or where the discs are.
        let (lo, hi) = match config.boundary.bounds() {
            Some((min, max)) => (min, max),
            None => {
                let mut ends = [f64::NEG_INFINITY; 4];
                for p in &wrapped {
                    for axis in 0..2 {
                        ends[axis] = ends[axis].max(-p[axis]);
                        ends[2 + axis] = ends[2 + axis].max(p[axis]);
                    }
                }
                if !everyone {
                    let mine = ends;
                    self.comm
                        .all_reduce_into(&mine[..], &mut ends[..], SystemOperation::max());
                }
                ([-ends[0], -ends[1]], [ends[2], ends[3]])
            }
        };
        let width = [0, 1].map(|axis| ((hi[axis] - lo[axis]) / BINS as f64).max(f64::MIN_POSITIVE));
        let bin = |axis: usize, v: f64| {
            let b = ((v - lo[axis]) / width[axis]).floor();
            (b.max(0.0) as usize).min(BINS - 1)
        };
        let sum = |counts: &mut Vec<u64>| {
            if !everyone {
                let mine = counts.clone();
                self.comm
                    .all_reduce_into(&mine[..], &mut counts[..], SystemOperation::sum());
            }
        };
        let snap = |axis: usize, cuts: &mut [f64]| {
            let n = cuts.len() - 1;
            for cut in &mut cuts[1..n] {
                *cut = bounce::order_block_start(config, self.max_radius, axis, *cut);
            }
        };
        // Rows by the heights, then each row's columns by the x of its discs.
        let mut counts = vec![0u64; BINS];
        for p in &wrapped {
            counts[bin(1, p[1])] += 1;
        }
        sum(&mut counts);
        domains.rows.cuts = cuts_by_count(&counts, lo[1], width[1], rows);
        snap(1, &mut domains.rows.cuts);
        if columns > 1 {
            let mut counts = vec![0u64; rows * BINS];
            for p in &wrapped {
                counts[domains.rows.part_of(p[1]) * BINS + bin(0, p[0])] += 1;
            }
            sum(&mut counts);
            for (row, cuts) in domains.columns.iter_mut().enumerate() {
                cuts.cuts = cuts_by_count(
                    &counts[row * BINS..(row + 1) * BINS],
                    lo[0],
                    width[0],
                    columns,
                );
                snap(0, &mut cuts.cuts);
            }
        }
        domains
    }

    /// This rank's part from `records` (every disc it must hold, and perhaps more), cut by
    /// `domains`, with clock and statistics from `clock`.
    pub(super) fn build(
        &self,
        clock: &World,
        domains: Domains,
        records: &[DiscRecord],
    ) -> Result<Part> {
        let me = self.comm.rank() as usize;
        let ghost_width = if self.size() == 1 {
            0.0
        } else {
            self.ghost_width()
        };
        let held: Vec<DiscRecord> = records
            .iter()
            .filter(|r| {
                let [x, y] = r.position;
                domains.gap(x, y, me) < ghost_width || domains.owner(x, y) == me
            })
            .copied()
            .collect();
        let mut world = clock.part(&held)?;
        world.set_threads(self.threads)?;
        world.set_order_radius(self.max_radius);
        Ok(self.plan(world, domains, ghost_width))
    }

    /// Who owns and who holds each of `world`'s discs under `domains`, from where they are.
    pub(super) fn plan(&self, mut world: World, domains: Domains, ghost_width: f64) -> Part {
        let me = self.comm.rank() as usize;
        let size = self.size();
        let mut owned = 0;
        let mut send = vec![Vec::new(); size];
        let mut recv = vec![Vec::new(); size];
        let p = world.particles();
        for ((&id, &x), &y) in p.ids().iter().zip(p.x()).zip(p.y()) {
            let owner = domains.owner(x, y);
            if owner == me {
                owned += 1;
                for (k, list) in send.iter_mut().enumerate() {
                    if k != me && domains.gap(x, y, k) < ghost_width {
                        list.push(id);
                    }
                }
            } else {
                recv[owner].push(id);
            }
        }
        for list in send.iter_mut().chain(recv.iter_mut()) {
            list.sort_unstable();
        }
        let tally = (size > 1).then(|| domains.tally(me));
        world.set_tally(tally);
        Part {
            world,
            owned,
            tally,
            send,
            recv,
            ghost_width,
        }
    }

    /// Discs within this of a domain are held by its rank: the reach, and room for the owners
    /// to drift `DRIFT_CELLS` order cells each way before a redistribution.
    pub(super) fn ghost_width(&self) -> f64 {
        let cell = bounce::order_cell_width(self.part.world.config(), self.max_radius);
        self.reach() + 2.0 * DRIFT_CELLS * cell
    }

    /// One step of the whole world; returns its statistics (the same on every rank).
    /// `stop` is the signal this rank received (0: none); `self.stop` becomes the largest
    /// any rank received.
    pub(super) fn step(&mut self, stop: usize) -> Result<StepStats, Failure> {
        let started = Instant::now();
        let substeps = self.substeps();
        let part = &mut self.part;
        let before = part.world.travel();
        let worn_before = part.world.candidates_worn().unwrap_or(0.0);
        let stepped = part.world.step_with_substeps(self.dt, substeps).copied();
        self.clock[0] += started.elapsed().as_secs_f64();
        // How far discs have moved (bounds from the broadphase's own check: no pass over
        // the discs), and with adaptive substeps the fastest speed and smallest radius over
        // the discs in this rank's domain (each disc is in one, and right there).
        let world = &part.world;
        let travel = world.travel();
        let drift = travel.since_start;
        let stride = (travel.since_start - before.since_start) + 2.0 * before.since_listing;
        let (speed2, radius) = if world.config().max_travel.is_some() {
            extremes_in(world, part.tally)
        } else {
            (0.0, f64::INFINITY)
        };
        // Where this part's candidate list will be after another step like this one.
        let worn = world.candidates_worn().unwrap_or(0.0);
        let worn_next = worn + (worn - worn_before).max(0.0);
        let stats = stepped.as_ref().ok().copied().unwrap_or_default();
        let flags = [
            f64::from(u8::from(stepped.is_err())),
            stop as f64,
            drift,
            stride,
            stats.max_overlap,
            speed2,
            -radius,
            worn_next,
        ];
        let reducing = Instant::now();
        let mut all = [0.0; 8];
        self.comm
            .all_reduce_into(&flags[..], &mut all[..], SystemOperation::max());
        let ([pairs, collisions], sums, bytes) = add_sums(
            self.comm,
            [stats.pairs, stats.collisions],
            world.step_sums(),
        );
        self.sent[2] += bytes;
        self.steps += 1;
        self.clock[1] += reducing.elapsed().as_secs_f64();

        if all[0] > 0.0 {
            let failed = stepped.err().map(|e| anyhow!(e));
            let failed = failed.map_or(Ok(()), Err);
            return Err(match agree(self.comm, failed) {
                Err(f) => f,
                Ok(()) => Failure::Agreed,
            });
        }
        self.stop = all[1] as usize;
        // The parts list their candidates together, when the first would have to: a step
        // waits for the slowest part, and a listing costs several plain steps.
        if self.size() > 1 && all[7] >= 1.0 {
            self.part.world.relist();
        }
        self.stride = all[3];
        self.max_speed2 = all[5];
        self.min_radius = -all[6];
        let merged = StepStats {
            pairs,
            collisions,
            max_overlap: all[4],
            virial: 0.5 * sums[0] / self.dt,
            wall_impulse: WallImpulse {
                left: sums[1],
                right: sums[2],
                bottom: sums[3],
                top: sums[4],
            },
            friction_work: sums[5],
            substeps,
            ..stats
        };
        self.last_stats = merged;
        self.friction_work += merged.friction_work;

        // Redistribute when the owners have drifted too far for the ghost width, else
        // refresh the ghosts.
        let part = &self.part;
        let size = self.size();
        if size > 1 && part.ghost_width - 2.0 * (all[2] + all[3]) < self.reach() {
            let t = Instant::now();
            self.redistribute()?;
            self.clock[3] += t.elapsed().as_secs_f64();
        } else if size > 1 {
            let t = Instant::now();
            self.refresh()?;
            self.clock[2] += t.elapsed().as_secs_f64();
        }
        if self.part.world.config().contact_events {
            self.gather_contacts(substeps);
        }
        if !self.part.world.config().sensors.is_empty() {
            self.gather_sensors();
        }
        self.step_times.push(started.elapsed().as_secs_f64());
        Ok(merged)
    }

    /// Rank 0's log takes the step's contacts: the parts' sightings (each part sends the
    /// contacts it counts), or with one rank the part's own log.
    pub(super) fn gather_contacts(&mut self, substeps: u32) {
        let world = &mut self.part.world;
        if self.part.tally.is_none() {
            if let Some(log) = &mut self.contact_log {
                *log = world.contact_log().clone();
            }
            return;
        }
        let threshold = world.config().contact_event_threshold;
        let words: Vec<f64> = world
            .take_contact_sightings()
            .iter()
            .flat_map(|(substep, e)| sighting_words(*substep, e))
            .collect();
        let Some(all) = self.gather_words(&words) else {
            return;
        };
        let sightings = all.chunks_exact(SIGHTING_WORDS).map(sighting_of).collect();
        if let Some(log) = &mut self.contact_log {
            log.record_step(sightings, substeps, threshold);
        }
    }

    /// Rank 0's sensors take the step's discs in each sensor: every part sends those in
    /// its domain (each disc is in one), or with one rank the part's own state is the
    /// whole world's.
    pub(super) fn gather_sensors(&mut self) {
        let world = &self.part.world;
        if self.part.tally.is_none() {
            if let Some(state) = &mut self.sensors {
                *state = world.sensor_state().clone();
            }
            return;
        }
        let words: Vec<f64> = (world.sensed().iter().enumerate())
            .flat_map(|(k, ids)| ids.iter().flat_map(move |id| [k as f64, id.0 as f64]))
            .collect();
        let sensors = world.config().sensors.clone();
        let Some(all) = self.gather_words(&words) else {
            return;
        };
        let mut now = vec![Vec::new(); sensors.len()];
        for pair in all.chunks_exact(2) {
            now[pair[0] as usize].push(ParticleId(pair[1] as u32));
        }
        if let Some(state) = &mut self.sensors {
            state.observe_sets(&sensors, now);
        }
    }

    /// The records of the discs now in this rank's domain (each disc is in one, and its
    /// state is right on that domain's rank: the domain lies within the ghost width's reach).
    pub(super) fn in_my_domain(&self) -> Vec<DiscRecord> {
        let world = &self.part.world;
        let p = world.particles();
        (0..world.len())
            .filter(|&i| self.part.tally.is_none_or(|t| t.counts(p.x()[i], p.y()[i])))
            .map(|i| world.record(i))
            .collect()
    }
    /// Owners send their discs' states to the ranks holding them as ghosts.
    pub(super) fn refresh(&mut self) -> Result<()> {
        let part = &self.part;
        let world = &part.world;
        let p = world.particles();
        let outgoing: Vec<Vec<f64>> = part
            .send
            .iter()
            .map(|ids| {
                let mut words = Vec::with_capacity(GHOST_WORDS * ids.len());
                for id in ids {
                    let i = world.index_of(*id).expect("owned discs are held");
                    let spin = p.angular_velocity().get(i).copied().unwrap_or(0.0);
                    words.extend([p.x()[i], p.y()[i], p.vx()[i], p.vy()[i], spin]);
                }
                words
            })
            .collect();
        self.sent[0] += outgoing.iter().map(|w| w.len() as u64 * 8).sum::<u64>();
        let incoming = exchange(self.comm, &outgoing);
        let mut states = Vec::new();
        for (ids, words) in self.part.recv.iter().zip(&incoming) {
            if words.len() != GHOST_WORDS * ids.len() {
                bail!(
                    "ghost exchange: expected {} states, got {}",
                    ids.len(),
                    words.len() / GHOST_WORDS
                );
            }
            for (id, w) in ids.iter().zip(words.chunks_exact(GHOST_WORDS)) {
                states.push((*id, [w[0], w[1], w[2], w[3], w[4]]));
            }
        }
        self.part.world.overwrite(&states)?;
        Ok(())
    }

    /// New cuts from where the discs are; every owner sends each of its discs to the ranks
    /// that hold it under them.
    pub(super) fn redistribute(&mut self) -> Result<()> {
        // Every disc held anywhere is right after a refresh; each one now in this rank's domain
        // goes to the ranks that will hold it and do not.
        self.refresh()?;
        let me = self.comm.rank() as usize;
        let mine = self.in_my_domain();
        let places: Vec<[f64; 2]> = mine.iter().map(|r| r.position).collect();
        let domains = self.cut(&places, false);
        let ghost_width = self.ghost_width();
        let size = self.size();
        let mut outgoing = vec![Vec::new(); size];
        for r in &mine {
            for (k, words) in outgoing.iter_mut().enumerate() {
                if k != me && domains.gap(r.position[0], r.position[1], k) < ghost_width {
                    words.extend(r.to_words());
                }
            }
        }
        self.sent[1] += outgoing.iter().map(|w| w.len() as u64 * 8).sum::<u64>();
        let incoming = exchange(self.comm, &outgoing);
        let world = &mut self.part.world;
        // Those not held here yet arrive; those beyond the new ghost width leave.
        let arriving: Vec<DiscRecord> = incoming
            .iter()
            .flat_map(|w| {
                w.chunks_exact(DiscRecord::WORDS)
                    .map(DiscRecord::from_words)
            })
            .filter(|r| world.index_of(r.id).is_none())
            .collect();
        let (x, y) = (
            world.particles().x().to_vec(),
            world.particles().y().to_vec(),
        );
        world.regroup(|i| domains.gap(x[i], y[i], me) < ghost_width, &arriving)?;
        let world = std::mem::replace(&mut self.part.world, World::new(bounce::Config::default())?);
        self.part = self.plan(world, domains, ghost_width);
        self.redistributions += 1;
        Ok(())
    }

    /// The whole world on rank 0 (its discs gathered from their owners), reporting `stats`;
    /// `None` on the other ranks.
    pub(super) fn gather(&mut self, stats: &StepStats) -> Result<Option<World>> {
        let words: Vec<f64> = self
            .in_my_domain()
            .iter()
            .flat_map(DiscRecord::to_words)
            .collect();
        let Some(all) = self.gather_words(&words) else {
            return Ok(None);
        };
        let mut records: Vec<DiscRecord> = all
            .chunks_exact(DiscRecord::WORDS)
            .map(DiscRecord::from_words)
            .collect();
        records.sort_unstable_by_key(|r| r.id);
        let mut whole = (self.part.world.part(&records)).context("assembling the whole world")?;
        let (energy, momentum) = bounce_scenario::analysis::motion_sums(&whole);
        let mut stats = *stats;
        (stats.kinetic_energy, stats.momentum) = (energy, momentum);
        if stats.pressure.is_some() {
            stats.pressure = whole.pressure(energy, momentum, stats.virial);
        }
        whole.set_reported_stats(stats);
        whole.set_reported_friction_work(self.friction_work);
        if let Some(log) = &self.contact_log {
            whole.set_contact_log(log.clone());
        }
        if let Some(state) = &self.sensors {
            whole
                .set_sensor_state(state.clone())
                .context("the gathered sensors")?;
        }
        Ok(Some(whole))
    }

    /// Every rank's `words`, in rank order, on rank 0 (`None` on the others).
    pub(super) fn gather_words(&mut self, words: &[f64]) -> Option<Vec<f64>> {
        let root = self.comm.process_at_rank(0);
        let count = words.len() as Count;
        self.sent[3] += words.len() as u64 * 8;
        if self.comm.rank() != 0 {
            root.gather_into(&count);
            root.gather_varcount_into(words);
            return None;
        }
        let mut counts = vec![0 as Count; self.size()];
        root.gather_into_root(&count, &mut counts[..]);
        let displs = displacements(&counts);
        let mut all = vec![0.0; counts.iter().map(|&c| c as usize).sum()];
        let mut partition = PartitionMut::new(&mut all[..], &counts[..], &displs[..]);
        root.gather_varcount_into_root(words, &mut partition);
        Some(all)
    }

    /// Bytes sent per rank per step (means over the ranks), and how often discs moved.
    pub(super) fn traffic(&self) -> String {
        let mine: Vec<f64> = self.sent.iter().map(|&b| b as f64).collect();
        let mut all = vec![0.0; mine.len()];
        self.comm
            .all_reduce_into(&mine[..], &mut all[..], SystemOperation::sum());
        let per = |k: usize| all[k] / (self.size() as f64 * self.steps.max(1) as f64);
        let counts = [self.part.owned as u64, self.part.world.len() as u64];
        let mut all_counts = vec![0u64; 2 * self.size()];
        self.comm.all_gather_into(&counts[..], &mut all_counts[..]);
        let owned: Vec<u64> = all_counts.iter().step_by(2).copied().collect();
        let ghosts: Vec<u64> = all_counts.chunks_exact(2).map(|c| c[1] - c[0]).collect();
        let mut sorted = self.step_times.clone();
        sorted.sort_by(f64::total_cmp);
        let steps = sorted.len().max(1) as f64;
        let mean = sorted.iter().sum::<f64>() / steps;
        let median = sorted.get(sorted.len() / 2).copied().unwrap_or(0.0);
        let [own, reduce, refresh, redistribute] = self.clock.map(|t| 1e3 * t / steps);
        format!(
            "mpi: rank 0's step {:.2} ms mean, {:.2} ms median: own discs and ghosts {own:.2}, reductions {reduce:.2}, ghost refresh {refresh:.2}, redistribution {redistribute:.2}\n\
             mpi: {} ranks; bytes sent per rank per step: ghost states {:.0}, redistributions {:.0} ({} times), reductions {:.0}, outputs {:.0}; discs owned per rank {owned:?}, ghosts {ghosts:?}",
            1e3 * mean,
            1e3 * median,
            self.size(),
            per(0),
            per(1),
            self.redistributions,
            per(2),
            per(3),
        )
    }
}

/// The fastest squared speed and the smallest radius among `world`'s discs that `tally`
/// counts (all without one).
pub(super) fn extremes_in(world: &World, tally: Option<Tally>) -> (f64, f64) {
    let p = world.particles();
    let (mut speed2, mut radius) = (0.0f64, f64::INFINITY);
    for i in 0..p.len() {
        if tally.is_none_or(|t| t.counts(p.x()[i], p.y()[i])) {
            speed2 = speed2.max(p.vx()[i] * p.vx()[i] + p.vy()[i] * p.vy()[i]);
            radius = radius.min(p.radius()[i]);
        }
    }
    (speed2, radius)
}
