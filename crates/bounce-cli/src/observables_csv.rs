//! `profile.csv` and `msd.csv` (`[output] profile`, `[output] msd`): observables of the
//! state (`bounce_scenario::observables`) written at every `stats.csv` row.
//!
//! - `profile.csv`: `step,time,bin,centre,count,density,vx,vy,temperature`, one row per bin
//!   per stats row: the discs whose centre is in the bin, their number per area, their
//!   mass-weighted mean velocity and their temperature in that frame (2D kT, over
//!   `count − 1`: unbiased however few discs a bin holds).
//! - `msd.csv`: `step,time,msd,vacf`: the mean-square displacement of the discs from where
//!   they were at the run's start (unwrapped across a periodic box), and the velocity
//!   autocorrelation `⟨v(t)·v(0)⟩`, over the discs present then and now.
//!
//! Both are written whole or not at all; a resumed run keeps the rows up to its
//! checkpoint's step (and the origin the checkpoint saved), so its files equal an
//! uninterrupted run's byte for byte.

use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use bounce::World;
use bounce_scenario::atomic::AtomicFile;
use bounce_scenario::observables::{Origin, profile};
use bounce_scenario::{ProfileSpec, Session};

const PROFILE_HEADER: &str = "step,time,bin,centre,count,density,vx,vy,temperature";
const MSD_HEADER: &str = "step,time,msd,vacf";

/// A CSV file of rows that start with their step.
struct Rows {
    file: AtomicFile,
}

impl Rows {
    fn create(path: &Path, header: &str) -> Result<Rows> {
        let mut file =
            AtomicFile::create(path).with_context(|| format!("cannot write {}", path.display()))?;
        writeln!(file, "{header}")?;
        Ok(Rows { file })
    }

    /// The file at `path` continued: its rows whose step passes `keep`, byte for byte (a
    /// new file without an earlier one).
    fn resume(
        path: &Path,
        header: &str,
        keep: &dyn Fn(u64) -> bool,
        through: Option<u64>,
    ) -> Result<Rows> {
        match crate::rows::continue_rows(path, header, keep, through)? {
            Some(file) => Ok(Rows { file }),
            None => Rows::create(path, header),
        }
    }

    fn finish(self) -> Result<()> {
        Ok(self.file.commit()?)
    }
}

/// The open observables files.
pub struct ObservablesCsv {
    profile: Option<(ProfileSpec, Rows)>,
    msd: Option<(Origin, Rows)>,
}

impl ObservablesCsv {
    /// The files `session` asks for in `dir`, the MSD measured from the world now.
    pub fn create(dir: &Path, session: &Session) -> Result<Self> {
        let o = &session.output;
        Ok(ObservablesCsv {
            profile: match o.profile {
                Some(spec) => Some((
                    spec,
                    Rows::create(&dir.join("profile.csv"), PROFILE_HEADER)?,
                )),
                None => None,
            },
            msd: if o.msd {
                Some((
                    Origin::of(&session.world),
                    Rows::create(&dir.join("msd.csv"), MSD_HEADER)?,
                ))
            } else {
                None
            },
        })
    }

    /// The files continued in `dir`, keeping the rows whose step passes `keep`, the MSD
    /// measured from the checkpoint's `origin`.
    pub fn resume(
        dir: &Path,
        session: &Session,
        keep: &dyn Fn(u64) -> bool,
        through: Option<u64>,
        origin: Option<Origin>,
    ) -> Result<Self> {
        let o = &session.output;
        let path = |name: &str| -> PathBuf { dir.join(name) };
        Ok(ObservablesCsv {
            profile: match o.profile {
                Some(spec) => Some((
                    spec,
                    Rows::resume(&path("profile.csv"), PROFILE_HEADER, keep, through)?,
                )),
                None => None,
            },
            msd: match (o.msd, origin) {
                (false, _) => None,
                (true, Some(origin)) => Some((
                    origin,
                    Rows::resume(&path("msd.csv"), MSD_HEADER, keep, through)?,
                )),
                (true, None) => bail!(
                    "output.msd: the checkpoint holds no origin to measure the displacements \
                     from (its run did not write msd.csv); start the run anew"
                ),
            },
        })
    }

    /// The origin a checkpoint keeps (with `[output] msd`).
    pub fn origin(&self) -> Option<Origin> {
        self.msd.as_ref().map(|(origin, _)| origin.clone())
    }

    /// Writes the rows of the world's current step.
    pub fn row(&mut self, world: &World) -> Result<()> {
        let (step, time) = (world.step_count(), world.time());
        if let Some((spec, rows)) = &mut self.profile {
            let p = profile(world, spec.axis, spec.bins).map_err(anyhow::Error::msg)?;
            for k in 0..p.centre.len() {
                let [vx, vy] = p.velocity[k];
                writeln!(
                    rows.file,
                    "{step},{time},{k},{},{},{},{vx},{vy},{}",
                    p.centre[k], p.count[k], p.density[k], p.temperature[k]
                )?;
            }
        }
        if let Some((origin, rows)) = &mut self.msd {
            match origin.msd_vacf(world) {
                Some((msd, vacf)) => writeln!(rows.file, "{step},{time},{msd},{vacf}")?,
                None => writeln!(rows.file, "{step},{time},,")?,
            }
        }
        // The step's rows are whole: a second signal keeps them.
        for rows in [
            self.profile.as_mut().map(|p| &mut p.1),
            self.msd.as_mut().map(|m| &mut m.1),
        ]
        .into_iter()
        .flatten()
        {
            rows.file.mark_whole();
        }
        Ok(())
    }

    /// Completes the files.
    pub fn finish(self) -> Result<()> {
        if let Some((_, rows)) = self.profile {
            rows.finish()?;
        }
        if let Some((_, rows)) = self.msd {
            rows.finish()?;
        }
        Ok(())
    }
}
