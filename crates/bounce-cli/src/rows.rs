//! CSV files of rows that start with their step (`stats.csv`, `events.csv`, `profile.csv`,
//! `msd.csv`), continued by a resumed run: the rows up to its checkpoint kept byte for byte.

use std::io::Write;
use std::path::Path;

use anyhow::{Context, Result, bail};
use bounce_scenario::atomic::AtomicFile;

/// `path` begun anew (atomically) with `header` and the earlier file's rows whose step
/// passes `keep`, byte for byte: the file a resumed run continues. `None` when there is no
/// earlier file; an error when its header is not `header` (another run's file), or when its
/// rows end before step `through` (the checkpoint's run had written them: they were lost,
/// and continuing would leave a hole).
pub(crate) fn continue_rows(
    path: &Path,
    header: &str,
    keep: &dyn Fn(u64) -> bool,
    through: Option<u64>,
) -> Result<Option<AtomicFile>> {
    let Ok(old) = std::fs::read_to_string(path) else {
        return Ok(None);
    };
    let mut lines = old.lines();
    if lines.next() != Some(header) {
        let name = path.file_name().map_or_else(
            || path.display().to_string(),
            |n| n.to_string_lossy().into_owned(),
        );
        bail!(
            "{}: not the {name} of this bounce (its header differs); resume into the run's \
             own folder or use a new one",
            path.display()
        );
    }
    let mut file = AtomicFile::create(path)?;
    writeln!(file, "{header}")?;
    let mut last = None;
    for line in lines {
        let step: u64 = (line.split(',').next())
            .and_then(|s| s.parse().ok())
            .with_context(|| format!("{}: a row without a step: {line:?}", path.display()))?;
        if keep(step) {
            writeln!(file, "{line}")?;
            last = Some(step);
        }
    }
    if let Some(through) = through
        && last.is_none_or(|last| last < through)
    {
        let end = last.map_or_else(
            || "holds no row".to_string(),
            |l| format!("ends at step {l}"),
        );
        bail!(
            "{}: {end}, but the checkpoint's run wrote rows through step {through}: they are \
             gone (cut short after the checkpoint was saved), and continuing would leave a \
             hole; resume into a folder holding the run's whole files, or start the run anew",
            path.display()
        );
    }
    file.mark_whole();
    Ok(Some(file))
}
