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
//! cells (`c`, 1.01 times the largest collision distance) per pass (the core's
//! `bounce::order_pass_reach`), plus what the discs move in the step. With the ghost width at least that reach for every substep and pass, the
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
//! sums' limbs. The largest radius sizes every part's order grid. Energies, momenta and
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

use anyhow::{Result, bail};
use bounce_scenario::Session;
use bounce_scenario::analysis::mechanical_energy;
use mpi::collective::SystemOperation;
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;

use crate::run::{
    Outcome, Outputs, Report, RunArgs, Schedule, load_session, prepare_out_dir, progress_bar,
};

mod decomposition;
mod ranks;
mod wire;

use ranks::Ranks;

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
            if let (Some(out), Some(whole)) = (&mut outputs, whole)
                && let Err(e) = out.record(&whole)
            {
                // What was written is kept, as one process keeps it.
                let out = outputs.take().expect("rank 0 writes");
                return Err(Failure::Alone(out.salvage(&whole, e)));
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
