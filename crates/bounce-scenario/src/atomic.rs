//! Files that appear whole or not at all: written to a temporary file beside the target and
//! renamed into place when complete. Every output of the CLI and the viewer's checkpoints go
//! through here. (Not on wasm32, which has no file system.)
//!
//! Every temporary being written is listed, so that [`exit_now`] (a second Ctrl-C) can remove
//! them and end the process with nothing half-written left behind: a file is renamed into
//! place under the same lock, so each is either whole or gone.

use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard};

use tempfile::NamedTempFile;

/// Temporary files start with this, so a later run can remove those a killed one left.
pub const TEMP_PREFIX: &str = ".bounce-tmp-";

/// The temporaries being written now. Creating, renaming and removing one hold this lock.
static LIVE: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

fn live() -> MutexGuard<'static, Vec<PathBuf>> {
    // A thread that panicked holding the lock left the list whole (each change is one push
    // or one removal), so a poisoned lock is still good.
    LIVE.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
}

/// Removes every temporary being written and ends the process with `code`, at once. Files
/// already renamed into place stay; no other thread can create or rename one meanwhile.
pub fn exit_now(code: i32) -> ! {
    let live = live();
    for path in live.iter() {
        let _ = std::fs::remove_file(path);
    }
    std::process::exit(code)
}

/// Keeps a temporary's path in [`LIVE`] while it exists.
struct Listed(PathBuf);

impl Drop for Listed {
    fn drop(&mut self) {
        let mut live = live();
        if let Some(k) = live.iter().position(|p| *p == self.0) {
            live.swap_remove(k);
        }
    }
}

/// An I/O error with the path it concerns in its message.
fn named(what: &str, path: &Path, e: io::Error) -> io::Error {
    io::Error::new(e.kind(), format!("cannot {what} {}: {e}", path.display()))
}

/// A file being written; it replaces `target` on [`AtomicFile::commit`] and vanishes if
/// dropped before that.
pub struct AtomicFile {
    target: PathBuf,
    writer: BufWriter<NamedTempFile>,
    // Declared after `writer`, so it leaves the list after the temporary is gone.
    _listed: Listed,
}

impl AtomicFile {
    /// Starts writing a file that will become `target`.
    pub fn create(target: &Path) -> io::Result<Self> {
        crate::files::writable(target)?;
        let dir = target
            .parent()
            .filter(|d| !d.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        let mut builder = tempfile::Builder::new();
        builder.prefix(TEMP_PREFIX);
        // Outputs are ordinary files (the umask still applies), not private temporaries.
        #[cfg(unix)]
        builder.permissions(std::os::unix::fs::PermissionsExt::from_mode(0o644));
        let mut live = live();
        let temp = builder
            .tempfile_in(dir)
            .map_err(|e| named("write in", dir, e))?;
        live.push(temp.path().to_path_buf());
        let listed = Listed(temp.path().to_path_buf());
        drop(live);
        Ok(AtomicFile {
            target: target.to_path_buf(),
            writer: BufWriter::with_capacity(1 << 20, temp),
            _listed: listed,
        })
    }

    /// The writer to fill.
    pub fn writer(&mut self) -> &mut BufWriter<NamedTempFile> {
        &mut self.writer
    }

    /// Flushes and renames the file into place.
    pub fn commit(self) -> io::Result<()> {
        let AtomicFile {
            target,
            writer,
            _listed,
        } = self;
        let temp = writer
            .into_inner()
            .map_err(|e| named("write", &target, e.into_error()))?;
        temp.as_file()
            .sync_all()
            .map_err(|e| named("write", &target, e))?;
        let live = live();
        let renamed = temp.persist(&target);
        drop(live);
        renamed.map_err(|e| named("create", &target, e.error))?;
        Ok(())
    }
}

/// Writes `bytes` to `target` atomically.
pub fn write(target: &Path, bytes: &[u8]) -> io::Result<()> {
    let mut file = AtomicFile::create(target)?;
    file.writer()
        .write_all(bytes)
        .map_err(|e| named("write", target, e))?;
    file.commit()
}

impl Write for AtomicFile {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.writer.write(buf)
    }

    fn flush(&mut self) -> io::Result<()> {
        self.writer.flush()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_appears_whole_or_not_at_all() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("out.bin");
        {
            let mut file = AtomicFile::create(&target).unwrap();
            file.write_all(b"half").unwrap();
            // Dropped before commit: nothing appears, and no temporary is left.
        }
        assert!(!target.exists());
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
        write(&target, b"whole").unwrap();
        assert_eq!(std::fs::read(&target).unwrap(), b"whole");
        let missing = dir.path().join("no/such/dir/out.bin");
        let e = write(&missing, b"x").unwrap_err().to_string();
        assert!(e.contains("no/such/dir"), "{e}");
    }

    #[test]
    fn temporaries_are_listed_while_they_exist() {
        let dir = tempfile::tempdir().unwrap();
        let listed = |name: &str| live().iter().any(|p| p.starts_with(dir.path().join(name)));
        std::fs::create_dir(dir.path().join("a")).unwrap();
        std::fs::create_dir(dir.path().join("b")).unwrap();
        let a = AtomicFile::create(&dir.path().join("a/out")).unwrap();
        let b = AtomicFile::create(&dir.path().join("b/out")).unwrap();
        assert!(listed("a") && listed("b"));
        a.commit().unwrap();
        assert!(!listed("a") && listed("b"));
        drop(b);
        assert!(!listed("b"));
    }
}
