//! `mpirun -np R bounce run SCENARIO --out DIR` (cargo feature `mpi`): one world across R
//! ranks, with the same bits as one process, for any R.
//!
//! **Decomposition.** The box is cut into R domains: rows across y, each cut into columns
//! across x (as square as R divides: 4 ranks make 2 × 2, 1,000 make 40 × 25), each holding
//! about as many discs (histograms summed over the ranks, so a pile at the bottom of a box
//! gets thin rows there), cut on the order grid's block edges (each block's contacts are one
//! rank's) and recomputed whenever discs are redistributed. A rank *owns* the discs whose
//! (wrapped) place is in its domain and holds copies, *ghosts*, of every disc within a ghost
//! width of it.
//!
//! **One exchange per step.** Each rank steps its discs and ghosts as one `World` part
//! (`bounce::World::part`). A disc's new state depends only on the discs its step's chains
//! of contacts reach: in one solver pass a disc meets the discs of one order block and its
//! ring (4 × 4 order cells) in each of 4 colour phases, so a chain reaches at most 13 order
//! cells (`c`, 1.01 times the largest collision distance) per pass, plus what the discs move
//! in the step. With the ghost width at least that reach for every substep and pass, the
//! owned discs come out exactly as in one process; the ghosts near the edge come out wrong
//! and are overwritten by their owners' states after every step (4 words each). So the
//! resolution's colour phases need no message of their own: each rank recomputes the ghost
//! layer instead (a few order cells of extra work against 4 × passes × substeps latencies).
//!
//! **Redistribution.** Ranks keep their discs until the discs' travel (a bound the
//! broadphase keeps anyway, `bounce::World::travel`) leaves too little of the ghost width
//! (`G − 2 (travel + stride) < reach`); then, after a refresh, new cuts are made and each
//! disc in a rank's domain goes to the ranks that will hold it and do not: only the discs that
//! change holders move (`bounce::World::regroup`). The parts list their candidate pairs
//! together, when the first one would have to (a step waits for the slowest part, and a
//! listing costs several plain steps).
//!
//! **Same sums.** Each part counts the contacts and wall hits in its domain
//! (`bounce::World::set_tally`), summed exactly (`bounce::ExactSum`); the ranks add their
//! sums' lanes. The largest radius sizes every part's order grid. Energies, momenta and
//! pressures in files are summed in id order on rank 0 from the gathered world. So
//! `stats.csv`, the GSD and the state hash equal one process's, byte for byte.
//!
//! **Outputs and failure.** Rank 0 gathers the discs when an output is due and writes it like
//! `bounce run` (atomically); checkpoints hold the whole world, so they resume with any R or
//! none. An error every rank meets (a bad scenario) is reported once and every rank exits
//! with 1; an error or a panic on one rank prints it and aborts the job (`MPI_Abort`).
//! `BOUNCE_MPI_PANIC_AT=RANK:STEP` makes rank RANK panic after step STEP (for the tests).
//!
//! **Contact events.** Each part keeps the contacts its tally counts (by the place of their
//! disc `a`, as the sums do) as sightings; rank 0 gathers them after every step and turns
//! them into `begin` and `end` events in the whole world's log (`bounce::ContactLog`), which
//! the gathered world carries into `events.csv` and the checkpoints: the same bytes as one
//! process.
//!
//! **Sensors.** Each part sends the ids of the discs in its domain inside each sensor after
//! every step; rank 0 compares them with the last step's in the whole world's sensor state
//! (`bounce::SensorState`), which the gathered world carries into `stats.csv` and the
//! checkpoints: the same counts as one process.
//!
//! A Lees–Edwards box is cut in rows only (a disc through its top or bottom comes back slid
//! along x, so a row's neighbours across that edge may be anywhere along it), and each part
//! steps with the box's sliding images as one process does.
//!
//! Not yet across ranks: obstacles, emitters, sinks, thermostats, the pressure tensor and
//! collision counts, and the event-driven method (refused with a message). Rough discs
//! run across ranks: a disc's record carries its angular velocity and orientation, a ghost's
//! state its angular velocity, and the energy friction removed is one more exact sum.

use std::process::ExitCode;
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use anyhow::{Context, Result, anyhow, bail};
use bounce::{
    Boundary, ContactEvent, ContactKind, ContactLog, DiscRecord, ExactSum, ParticleId, Party,
    SensorState, StepStats, StepSums, Tally, WallImpulse, WallSide, World, wrap_coordinate,
};
use bounce_scenario::Session;
use mpi::Count;
use mpi::collective::SystemOperation;
use mpi::datatype::{Partition, PartitionMut};
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;

use crate::run::{
    Outcome, Outputs, Report, RunArgs, Schedule, load_session, mechanical_energy, prepare_out_dir,
    progress_bar,
};

/// Height bins of the histogram the cuts are taken from.
const BINS: usize = 4096;
/// Order-grid cells a contact chain can cross in one solver pass (4 colour phases, each
/// within one block and its ring: 3 cells, plus the cell a disc sits in).
const CELLS_PER_PASS: f64 = 13.0;
/// Order cells the discs may drift before they are redistributed. More means fewer
/// redistributions (each rebuilds every part: measured ~0.3 s at 10^6 discs on 2 ranks) and
/// thicker ghost layers (each ghost is stepped on two ranks).
const DRIFT_CELLS: f64 = 4.0;
/// Exact sums a step reduces: the virial, the four walls and the energy friction removed.
const SUMS: usize = 6;
/// Words of a ghost's state: x, y, vx, vy, ω.
const GHOST_WORDS: usize = 5;

/// Whether an MPI launcher (Open MPI's `mpirun`, or a PMI one) started this process.
pub fn launched() -> bool {
    ["OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"]
        .iter()
        .any(|v| std::env::var_os(v).is_some())
}

/// Threads per rank when none are asked for: the cores shared among this node's ranks.
pub fn default_threads() -> usize {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let local: usize = std::env::var("OMPI_COMM_WORLD_LOCAL_SIZE")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(1);
    (cores / local.max(1)).max(1)
}

/// A failure: either every rank met it (reported once, all exit) or this rank alone.
enum Failure {
    Agreed,
    Alone(anyhow::Error),
}

impl From<anyhow::Error> for Failure {
    fn from(e: anyhow::Error) -> Self {
        Failure::Alone(e)
    }
}

/// Runs `bounce run` across the ranks of `mpirun`.
pub fn main(args: &RunArgs, stop: Arc<AtomicUsize>) -> ExitCode {
    let Some(universe) = mpi::initialize() else {
        eprintln!("error: MPI was already initialised");
        return ExitCode::FAILURE;
    };
    let comm = universe.world();
    let rank = comm.rank();
    // A panic on one rank must not leave the others waiting in a collective forever.
    std::panic::set_hook(Box::new(move |info| {
        eprintln!("error: rank {rank} panicked: {info}");
        // SAFETY: aborting the job is always allowed; nothing is used afterwards.
        unsafe {
            mpi::ffi::MPI_Abort(mpi::ffi::RSMPI_COMM_WORLD, 101);
        }
        std::process::abort();
    }));
    match run(&comm, args, stop) {
        Ok(Outcome::Finished) => ExitCode::SUCCESS,
        Ok(Outcome::Stopped(signal)) => ExitCode::from((128 + signal.clamp(0, 127)) as u8),
        Err(Failure::Agreed) => ExitCode::FAILURE,
        Err(Failure::Alone(e)) => {
            for line in format!("{e:#}").lines() {
                eprintln!("error: rank {rank}: {line}");
            }
            comm.abort(1)
        }
    }
}

/// Every rank's outcome of the same phase: `Ok` on all, or the lowest failing rank prints
/// its error and all return [`Failure::Agreed`].
fn agree<T>(comm: &SimpleCommunicator, result: Result<T>) -> Result<T, Failure> {
    let size = comm.size();
    let mine = if result.is_err() { comm.rank() } else { size };
    let mut first = size;
    comm.all_reduce_into(&mine, &mut first, SystemOperation::min());
    match result {
        Ok(v) if first == size => Ok(v),
        Ok(_) => Err(Failure::Agreed),
        Err(e) => {
            if comm.rank() == first {
                for line in format!("{e:#}").lines() {
                    eprintln!("error: {line}");
                }
            }
            Err(Failure::Agreed)
        }
    }
}

/// What the distributed run refuses, with the reason.
fn check_supported(session: &Session) -> Result<()> {
    match bounce_scenario::support::across_ranks_unsupported(session.world.config()) {
        Some(what) => bail!(
            "{}: {what} is not supported across MPI ranks yet; run it without mpirun",
            session.origin
        ),
        None => Ok(()),
    }
}

fn run(
    comm: &SimpleCommunicator,
    args: &RunArgs,
    stop: Arc<AtomicUsize>,
) -> Result<Outcome, Failure> {
    let setup = Instant::now();
    let root = comm.rank() == 0;
    // Every rank builds the scenario (deterministic) and, resuming, loads the checkpoint.
    let loaded = load_session(args).and_then(|loaded| check_supported(&loaded.0).map(|()| loaded));
    let (session, run_state, total) = agree(comm, loaded)?;
    // Rank 0 alone writes.
    let outputs = if root {
        prepare_out_dir(&args.out, args.resume.is_some(), args.force)
            .and_then(|()| Outputs::start(&session, &args.out, total, run_state).map(Some))
    } else {
        Ok(None)
    };
    let mut outputs = agree(comm, outputs)?;
    let schedule = Schedule {
        total,
        output: session.output.clone(),
    };
    let energy_start = mechanical_energy(&session.world);
    let time_step = session.time_step_report().to_string();
    let start_step = session.world.step_count();
    let dt = session.dt;

    let mut ranks = Ranks::new(comm, &session.world, args.threads, dt)?;
    let setup_time = setup.elapsed().as_secs_f64();
    let progress = progress_bar(total - start_step, args.quiet || !root);
    let clock = Instant::now();
    let mut output_time = 0.0;
    let mut collisions = 0usize;
    let panic_at = panic_at();
    let mut stopped = false;
    while ranks.part.world.step_count() < total {
        let stats = ranks.step(stop.load(Ordering::SeqCst))?;
        let step = ranks.part.world.step_count();
        if panic_at == Some((comm.rank(), step)) {
            panic!("BOUNCE_MPI_PANIC_AT asked for a panic after step {step}");
        }
        collisions += stats.collisions;
        let stop_now = ranks.stop != 0 && step < total;
        if stop_now {
            // Every rank ends as the first one stopped says.
            stop.store(ranks.stop, Ordering::SeqCst);
        }
        let t = Instant::now();
        if let Some(outputs) = &mut outputs {
            let sensors = ranks.sensors.as_ref().map_or(&[][..], |s| s.counts());
            outputs
                .stats
                .totals
                .add(&stats, &ranks.part.world, sensors, dt);
            if let Some(log) = &ranks.contact_log {
                let end = ranks.part.world.time();
                outputs.contact_events(step, end, stats.substeps, log.events())?;
            }
        }
        if schedule.any_due(step) {
            let whole = ranks.gather(&stats)?;
            if let (Some(outputs), Some(whole)) = (&mut outputs, whole) {
                outputs.record(&whole)?;
            }
        }
        output_time += t.elapsed().as_secs_f64();
        progress.inc(1);
        if stop_now {
            stopped = true;
            break;
        }
    }
    progress.finish_and_clear();
    let physics_time = (clock.elapsed().as_secs_f64() - output_time).max(0.0);
    let last = ranks.last_stats;
    let whole = ranks.gather(&last)?;
    let traffic = ranks.traffic();
    let Some((outputs, whole)) = outputs.zip(whole) else {
        return Ok(if stopped {
            Outcome::Stopped(stop.load(Ordering::SeqCst) as i32)
        } else {
            Outcome::Finished
        });
    };
    let t = Instant::now();
    let ran = whole.step_count() - start_step;
    let headline = outputs.finish(&whole, stopped, Some((physics_time, ran)))?;
    output_time += t.elapsed().as_secs_f64();
    let report = Report {
        title: &session.title,
        ran: whole.step_count() - start_step,
        total,
        collisions,
        energy_start,
        physics_time,
        output_time,
        setup_time,
        time_step,
        headline,
    };
    report.print(args, &whole);
    println!("{traffic}");
    Ok(report.outcome(args, &whole, !stopped, &stop))
}

/// `BOUNCE_MPI_PANIC_AT=RANK:STEP`.
fn panic_at() -> Option<(i32, u64)> {
    let v = std::env::var("BOUNCE_MPI_PANIC_AT").ok()?;
    let (rank, step) = v.split_once(':')?;
    Some((rank.parse().ok()?, step.parse().ok()?))
}

/// Cuts along one axis: part `k` is `[cuts[k], cuts[k + 1])` of the (wrapped) coordinate;
/// the first and last cuts are infinite.
#[derive(Clone, Debug, PartialEq)]
struct Cuts {
    cuts: Vec<f64>,
    /// `(min, size)` of a periodic box along this axis.
    period: Option<(f64, f64)>,
}

impl Cuts {
    fn parts(&self) -> usize {
        self.cuts.len() - 1
    }

    fn wrapped(&self, v: f64) -> f64 {
        match self.period {
            Some((min, size)) => wrap_coordinate(v, min, size),
            None => v,
        }
    }

    /// The part holding `v`.
    fn part_of(&self, v: f64) -> usize {
        let v = self.wrapped(v);
        self.cuts[1..self.parts()].partition_point(|&c| c <= v)
    }

    /// How far `v` is from part `k` (0 inside), across a periodic box's edge too.
    fn gap(&self, v: f64, k: usize) -> f64 {
        let v = self.wrapped(v);
        let (mut a, mut b) = (self.cuts[k], self.cuts[k + 1]);
        let (first, last) = (k == 0, k == self.parts() - 1);
        match self.period {
            Some((min, size)) => {
                if first {
                    a = min;
                }
                if last {
                    b = min + size;
                }
                if (a <= v && v < b) || (first && v < a) || (last && v >= b) {
                    0.0
                } else {
                    (a - v).rem_euclid(size).min((v - b).rem_euclid(size))
                }
            }
            None if v < a => a - v,
            None if v >= b => v - b,
            None => 0.0,
        }
    }

    fn range(&self, k: usize) -> [f64; 2] {
        [self.cuts[k], self.cuts[k + 1]]
    }
}

/// The domains: rows across y, each cut across x into as many columns; rank
/// `row × columns + column`. Rows and columns hold about as many discs each.
#[derive(Clone, Debug, PartialEq)]
struct Domains {
    rows: Cuts,
    /// Each row's columns.
    columns: Vec<Cuts>,
}

impl Domains {
    #[cfg(test)]
    fn ranks(&self) -> usize {
        self.rows.parts() * self.columns[0].parts()
    }

    /// The row and column of rank `k`.
    fn place(&self, k: usize) -> (usize, usize) {
        let columns = self.columns[0].parts();
        (k / columns, k % columns)
    }

    /// The rank owning the place `(x, y)`.
    fn owner(&self, x: f64, y: f64) -> usize {
        let row = self.rows.part_of(y);
        row * self.columns[0].parts() + self.columns[row].part_of(x)
    }

    /// How far `(x, y)` is from rank `k`'s domain (0 inside).
    fn gap(&self, x: f64, y: f64, k: usize) -> f64 {
        let (row, column) = self.place(k);
        self.columns[row]
            .gap(x, column)
            .hypot(self.rows.gap(y, row))
    }

    fn tally(&self, k: usize) -> Tally {
        let (row, column) = self.place(k);
        Tally::new(
            self.columns[row].range(column),
            self.rows.range(row),
            [self.columns[row].period, self.rows.period],
        )
    }
}

/// Rows and columns for `ranks`: as square as divides evenly (columns = the largest divisor
/// up to the square root), more rows than columns.
fn grid_shape(ranks: usize) -> (usize, usize) {
    let columns = (1..=ranks)
        .take_while(|c| c * c <= ranks)
        .filter(|c| ranks.is_multiple_of(*c))
        .last()
        .unwrap_or(1);
    (ranks / columns, columns)
}

/// `parts` cuts from a histogram of `counts` over `[lo, lo + bins × width)`: about as many
/// counted in each part.
fn cuts_by_count(counts: &[u64], lo: f64, width: f64, parts: usize) -> Vec<f64> {
    let mut cuts = vec![f64::NEG_INFINITY; parts + 1];
    cuts[parts] = f64::INFINITY;
    let n: u64 = counts.iter().sum();
    let mut below = 0u64;
    let mut k = 1;
    for (bin, &c) in counts.iter().enumerate() {
        below += c;
        while k < parts && below * parts as u64 >= n * k as u64 {
            cuts[k] = lo + (bin + 1) as f64 * width;
            k += 1;
        }
    }
    let hi = lo + counts.len() as f64 * width;
    for cut in &mut cuts[k..parts] {
        *cut = hi;
    }
    cuts
}

/// This rank's part of the world and who it exchanges with.
struct Part {
    world: World,
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
struct Ranks<'c> {
    comm: &'c SimpleCommunicator,
    part: Part,
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
    stop: usize,
    last_stats: StepStats,
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
    contact_log: Option<ContactLog>,
    /// With sensors, on rank 0: the whole world's sensors, fed with the discs every part
    /// sees in them after each step.
    sensors: Option<SensorState>,
}

impl<'c> Ranks<'c> {
    /// Every rank starts from the whole world (built from the scenario or a checkpoint)
    /// and keeps its part.
    fn new(comm: &'c SimpleCommunicator, whole: &World, threads: usize, dt: f64) -> Result<Self> {
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

    fn size(&self) -> usize {
        self.comm.size() as usize
    }

    /// The reach of one step's chains of contacts (see the module docs), with the distance a
    /// disc may move in it.
    fn reach(&self) -> f64 {
        let config = self.part.world.config();
        let cell = bounce::order_cell_width(config, self.max_radius);
        let substeps = self.substeps() as f64;
        let passes = f64::from(config.solver_iterations);
        let [gx, gy] = config.gravity;
        let fall = (gx * gx + gy * gy).sqrt() * self.dt;
        let step = 2.0 * (self.stride.max((self.max_speed2.sqrt() + fall) * self.dt)) + cell;
        substeps * passes * (CELLS_PER_PASS * cell + 2.0 * step) + 2.0 * step
    }

    fn substeps(&self) -> u32 {
        self.part
            .world
            .substeps_for_extremes(self.dt, self.max_speed2, self.min_radius)
    }

    /// Domains with about as many of `places` (this rank's discs; with `everyone`, every
    /// disc, which every rank holds) in each, cut on the order grid's block edges (each
    /// block's contacts are one rank's).
    fn cut(&self, places: &[[f64; 2]], everyone: bool) -> Domains {
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
    fn build(&self, clock: &World, domains: Domains, records: &[DiscRecord]) -> Result<Part> {
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
    fn plan(&self, mut world: World, domains: Domains, ghost_width: f64) -> Part {
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
    fn ghost_width(&self) -> f64 {
        let cell = bounce::order_cell_width(self.part.world.config(), self.max_radius);
        self.reach() + 2.0 * DRIFT_CELLS * cell
    }

    /// One step of the whole world; returns its statistics (the same on every rank).
    /// `stop` is the signal this rank received (0: none); `self.stop` becomes the largest
    /// any rank received.
    fn step(&mut self, stop: usize) -> Result<StepStats, Failure> {
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
    fn gather_contacts(&mut self, substeps: u32) {
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
    fn gather_sensors(&mut self) {
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
    fn in_my_domain(&self) -> Vec<DiscRecord> {
        let world = &self.part.world;
        let p = world.particles();
        (0..world.len())
            .filter(|&i| self.part.tally.is_none_or(|t| t.counts(p.x()[i], p.y()[i])))
            .map(|i| world.record(i))
            .collect()
    }
    /// Owners send their discs' states to the ranks holding them as ghosts.
    fn refresh(&mut self) -> Result<()> {
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
    fn redistribute(&mut self) -> Result<()> {
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
    fn gather(&mut self, stats: &StepStats) -> Result<Option<World>> {
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
    fn gather_words(&mut self, words: &[f64]) -> Option<Vec<f64>> {
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
    fn traffic(&self) -> String {
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

/// The whole step's contact and collision counts and exact sums (virial, the four walls,
/// friction), from every
/// part's, and the bytes this rank sent: the counts and the sums' lanes are integers added by
/// one reduction, the non-finite parts by another (their sum does not depend on order either).
/// Words a contact sighting travels as.
const SIGHTING_WORDS: usize = 11;

/// A part's contact sighting as words: the substep, the disc, the other party (its kind:
/// 0 a disc, 1 a wall, 2 an obstacle; and which), the point, the normal, the impulses and
/// the approach speed (ids and small integers are exact in an `f64`).
fn sighting_words(substep: u32, e: &ContactEvent) -> [f64; SIGHTING_WORDS] {
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
fn sighting_of(w: &[f64]) -> (u32, ContactEvent) {
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

fn add_sums(
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
    let lanes_per_sum = ExactSum::WORDS - 1;
    let mut lanes = vec![counts[0] as i64, counts[1] as i64];
    let mut special = [0.0; SUMS];
    for (k, sum) in exact.iter().enumerate() {
        let words = sum.to_words();
        lanes.extend_from_slice(&words[..lanes_per_sum]);
        special[k] = f64::from_bits(words[lanes_per_sum] as u64);
    }
    let mut lanes_all = vec![0i64; lanes.len()];
    comm.all_reduce_into(&lanes[..], &mut lanes_all[..], SystemOperation::sum());
    let mut special_all = [0.0; SUMS];
    comm.all_reduce_into(&special[..], &mut special_all[..], SystemOperation::sum());
    let bytes = ((lanes.len() + special.len()) * 8) as u64;
    let value = |k: usize| {
        let at = 2 + k * lanes_per_sum;
        ExactSum::from_words(&lanes_all[at..at + lanes_per_sum], special_all[k]).value()
    };
    (
        [lanes_all[0] as usize, lanes_all[1] as usize],
        [0, 1, 2, 3, 4, 5].map(value),
        bytes,
    )
}

/// The fastest squared speed and the smallest radius among `world`'s discs that `tally`
/// counts (all without one).
fn extremes_in(world: &World, tally: Option<Tally>) -> (f64, f64) {
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

fn displacements(counts: &[Count]) -> Vec<Count> {
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
fn exchange(comm: &SimpleCommunicator, outgoing: &[Vec<f64>]) -> Vec<Vec<f64>> {
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cuts_own_every_coordinate_once_and_measure_gaps_across_a_periodic_edge() {
        let cuts = Cuts {
            cuts: vec![f64::NEG_INFINITY, 3.0, 7.0, f64::INFINITY],
            period: Some((0.0, 10.0)),
        };
        assert_eq!(cuts.part_of(-0.5), 2); // wraps to 9.5
        assert_eq!(cuts.part_of(3.0), 1);
        assert_eq!(cuts.part_of(12.0), 0);
        assert_eq!(cuts.gap(5.0, 1), 0.0);
        assert!((cuts.gap(9.5, 0) - 0.5).abs() < 1e-12, "across the edge");
        assert!((cuts.gap(2.0, 2) - 2.0).abs() < 1e-12, "across the edge");
        assert!((cuts.gap(2.0, 1) - 1.0).abs() < 1e-12);
        let walls = Cuts {
            cuts: vec![f64::NEG_INFINITY, 3.0, f64::INFINITY],
            period: None,
        };
        assert_eq!(walls.gap(-100.0, 0), 0.0);
        assert_eq!(walls.gap(1.0, 1), 2.0);
        assert_eq!(walls.gap(5.0, 0), 2.0);
    }

    #[test]
    fn domains_tile_the_plane_in_rows_of_columns() {
        assert_eq!(grid_shape(1), (1, 1));
        assert_eq!(grid_shape(2), (2, 1));
        assert_eq!(grid_shape(3), (3, 1));
        assert_eq!(grid_shape(4), (2, 2));
        assert_eq!(grid_shape(12), (4, 3));
        assert_eq!(grid_shape(1000), (40, 25));
        let inf = f64::INFINITY;
        let domains = Domains {
            rows: Cuts {
                cuts: vec![-inf, 5.0, inf],
                period: None,
            },
            columns: vec![
                Cuts {
                    cuts: vec![-inf, 2.0, inf],
                    period: None,
                },
                Cuts {
                    cuts: vec![-inf, 8.0, inf],
                    period: None,
                },
            ],
        };
        assert_eq!(domains.ranks(), 4);
        assert_eq!(domains.owner(1.0, 1.0), 0);
        assert_eq!(domains.owner(3.0, 1.0), 1);
        assert_eq!(domains.owner(3.0, 6.0), 2);
        assert_eq!(domains.owner(9.0, 6.0), 3);
        // From (3, 4) to rank 2's domain (x < 8, y >= 5): 1 up; to rank 3's: the corner.
        assert_eq!(domains.gap(3.0, 4.0, 2), 1.0);
        assert!((domains.gap(3.0, 4.0, 3) - 26f64.sqrt()).abs() < 1e-12);
        for k in 0..4 {
            let t = domains.tally(k);
            assert_eq!(t.counts(3.0, 6.0), k == 2);
        }
        // Cuts by count: 10 in the first bin, 10 spread over the rest.
        let mut counts = vec![0u64; 10];
        counts[0] = 10;
        for c in &mut counts[1..] {
            *c = 1;
        }
        counts[9] = 2;
        assert_eq!(cuts_by_count(&counts, 0.0, 1.0, 2), vec![-inf, 1.0, inf]);
    }
}
