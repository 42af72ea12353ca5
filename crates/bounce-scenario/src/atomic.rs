//! Files that appear whole or not at all: written to a temporary file beside the target and
//! renamed into place when complete. Every output of the CLI and the viewer's checkpoints go
//! through here. (Not on wasm32, which has no file system.)
//!
//! Every temporary being written is listed, so that [`exit_now`] (a second Ctrl-C) can end
//! the process at once with nothing half-written left behind. A file that grows row by row or
//! frame by frame (`stats.csv`, a GSD trajectory) marks where its last whole row or frame
//! ends ([`AtomicFile::mark_whole`]); `exit_now` keeps such a file up to that mark, closed as
//! its format needs ([`AtomicFile::set_closing`]), so a second signal drops only what it
//! interrupts. The others are removed. Writes hold the file's lock, so `exit_now` never meets
//! one half done.

use std::io::{self, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, MutexGuard};

use tempfile::NamedTempFile;

/// Temporary files start with this, so a later run can remove those a killed one left.
pub const TEMP_PREFIX: &str = ".bounce-tmp-";

/// Bytes a file gathers before they go to its temporary.
const BUFFER: usize = 1 << 20;

/// A format's closing bytes for a file kept at a given length: what follows, and what is
/// written over its start (a header pointing at what follows).
pub type Closing = Box<dyn Fn(u64) -> (Vec<u8>, Vec<u8>) + Send>;

/// A file being written, as its writer and [`exit_now`] share it.
struct Shared {
    /// The temporary (`None` once committed).
    temp: Option<NamedTempFile>,
    target: PathBuf,
    /// Bytes written but not yet in the temporary.
    buffer: Vec<u8>,
    /// Bytes in the temporary.
    flushed: u64,
    /// How much of the file a second signal keeps; `None`: none of it.
    whole: Option<u64>,
    closing: Option<Closing>,
}

type SharedFile = Arc<Mutex<Shared>>;

/// The files being written now. Creating, renaming and removing one hold this lock.
static LIVE: Mutex<Vec<SharedFile>> = Mutex::new(Vec::new());

/// A lock whose holder panicked still guards whole data (each change is one push, one
/// removal or one write), so a poisoned lock is still good.
fn lock<T>(mutex: &Mutex<T>) -> MutexGuard<'_, T> {
    mutex
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner())
}

fn live() -> MutexGuard<'static, Vec<SharedFile>> {
    lock(&LIVE)
}

/// Ends the process with `code` at once: each file being written is kept up to its last
/// whole row or frame (closed as its format needs) where it marks one, and removed
/// otherwise. Files already renamed into place stay; no other thread can create, rename or
/// write one meanwhile.
pub fn exit_now(code: i32) -> ! {
    let live = live();
    for file in live.iter() {
        let mut shared = lock(file);
        let kept = match shared.whole {
            Some(whole) => keep(&mut shared, whole),
            None => Err(io::Error::other("not kept")),
        };
        if kept.is_err()
            && let Some(temp) = &shared.temp
        {
            let _ = std::fs::remove_file(temp.path());
        }
    }
    std::process::exit(code)
}

/// Cuts `shared`'s temporary at `whole` bytes, closes it and renames it into place.
fn keep(shared: &mut Shared, whole: u64) -> io::Result<()> {
    let Shared {
        temp: Some(temp),
        target,
        buffer,
        flushed,
        closing,
        ..
    } = shared
    else {
        return Ok(());
    };
    let file = temp.as_file_mut();
    if whole > *flushed {
        file.write_all(&buffer[..(whole - *flushed) as usize])?;
    }
    file.set_len(whole)?;
    if let Some(closing) = closing {
        let (tail, head) = closing(whole);
        file.seek(SeekFrom::Start(whole))?;
        file.write_all(&tail)?;
        file.seek(SeekFrom::Start(0))?;
        file.write_all(&head)?;
    }
    file.sync_all()?;
    std::fs::rename(temp.path(), target)
}

/// An I/O error with the path it concerns in its message.
fn named(what: &str, path: &Path, e: io::Error) -> io::Error {
    io::Error::new(e.kind(), format!("cannot {what} {}: {e}", path.display()))
}

/// A file being written; it replaces `target` on [`AtomicFile::commit`] and vanishes if
/// dropped before that (or, on [`exit_now`], is kept up to its last whole part).
pub struct AtomicFile {
    shared: SharedFile,
    target: PathBuf,
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
        let shared = Arc::new(Mutex::new(Shared {
            temp: Some(temp),
            target: target.to_path_buf(),
            buffer: Vec::with_capacity(BUFFER),
            flushed: 0,
            whole: None,
            closing: None,
        }));
        live.push(shared.clone());
        Ok(AtomicFile {
            shared,
            target: target.to_path_buf(),
        })
    }

    /// Marks everything written so far as whole: a second signal ([`exit_now`]) keeps the
    /// file up to here.
    pub fn mark_whole(&self) {
        let mut shared = lock(&self.shared);
        shared.whole = Some(shared.flushed + shared.buffer.len() as u64);
    }

    /// What closes the file when [`exit_now`] keeps it: `closing(length)` gives the bytes to
    /// append after its first `length` bytes and those to write over its start.
    pub fn set_closing(&mut self, closing: Closing) {
        lock(&self.shared).closing = Some(closing);
    }

    /// Flushes and renames the file into place.
    pub fn commit(self) -> io::Result<()> {
        self.commit_with_head(&[])
    }

    /// Writes `head` over the file's first bytes (a header that points at what follows),
    /// flushes and renames the file into place.
    pub fn commit_with_head(self, head: &[u8]) -> io::Result<()> {
        let target = self.target.clone();
        // Held to the rename, so that `exit_now` meets the file either being written or in
        // place, never taken out of the list and not yet renamed.
        let live = live();
        let mut shared = lock(&self.shared);
        let buffer = std::mem::take(&mut shared.buffer);
        let mut temp = shared.temp.take().expect("a file is committed once");
        let file = temp.as_file_mut();
        file.write_all(&buffer)
            .map_err(|e| named("write", &target, e))?;
        if !head.is_empty() {
            file.seek(SeekFrom::Start(0))
                .and_then(|_| file.write_all(head))
                .map_err(|e| named("write", &target, e))?;
        }
        file.sync_all().map_err(|e| named("write", &target, e))?;
        let renamed = temp.persist(&target);
        drop(shared);
        drop(live);
        renamed.map_err(|e| named("create", &target, e.error))?;
        Ok(())
    }
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        let mut live = live();
        if let Some(k) = live.iter().position(|f| Arc::ptr_eq(f, &self.shared)) {
            live.swap_remove(k);
        }
        // The temporary (if not committed) is removed with the last reference.
        lock(&self.shared).temp.take();
    }
}

/// Writes `bytes` to `target` atomically.
pub fn write(target: &Path, bytes: &[u8]) -> io::Result<()> {
    let mut file = AtomicFile::create(target)?;
    file.write_all(bytes)
        .map_err(|e| named("write", target, e))?;
    file.commit()
}

impl Write for AtomicFile {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        let mut shared = lock(&self.shared);
        if shared.buffer.len() + buf.len() > BUFFER {
            flush_buffer(&mut shared).map_err(|e| named("write", &self.target, e))?;
        }
        if buf.len() >= BUFFER {
            let temp = shared.temp.as_mut().expect("not committed");
            temp.as_file_mut()
                .write_all(buf)
                .map_err(|e| named("write", &self.target, e))?;
            shared.flushed += buf.len() as u64;
        } else {
            shared.buffer.extend_from_slice(buf);
        }
        Ok(buf.len())
    }

    fn flush(&mut self) -> io::Result<()> {
        let mut shared = lock(&self.shared);
        flush_buffer(&mut shared).map_err(|e| named("write", &self.target, e))
    }
}

/// Moves the buffered bytes into the temporary.
fn flush_buffer(shared: &mut Shared) -> io::Result<()> {
    let Shared {
        temp: Some(temp),
        buffer,
        flushed,
        ..
    } = shared
    else {
        return Ok(());
    };
    temp.as_file_mut().write_all(buffer)?;
    *flushed += buffer.len() as u64;
    buffer.clear();
    Ok(())
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
    fn a_kept_file_ends_at_its_last_whole_part_closed_as_its_format_needs() {
        // What `exit_now` does to each file it keeps, without ending the test's process.
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("rows.csv");
        let mut file = AtomicFile::create(&target).unwrap();
        file.write_all(b"HEAD\nrow 1\n").unwrap();
        file.mark_whole();
        file.write_all(b"row 2, half wri").unwrap();
        file.set_closing(Box::new(|end| {
            (format!("end at {end}\n").into_bytes(), b"head".to_vec())
        }));
        let whole = lock(&file.shared).whole.unwrap();
        assert_eq!(whole, 11);
        keep(&mut lock(&file.shared), whole).unwrap();
        assert_eq!(std::fs::read(&target).unwrap(), b"head\nrow 1\nend at 11\n");
        // A file past its buffer: the whole part lies in the temporary, the rest is cut.
        let big = dir.path().join("big.bin");
        let mut file = AtomicFile::create(&big).unwrap();
        file.write_all(&vec![1u8; BUFFER + 10]).unwrap();
        file.mark_whole();
        file.write_all(&vec![2u8; BUFFER + 10]).unwrap();
        keep(&mut lock(&file.shared), (BUFFER + 10) as u64).unwrap();
        assert_eq!(std::fs::read(&big).unwrap(), vec![1u8; BUFFER + 10]);
    }

    #[test]
    fn temporaries_are_listed_while_they_exist() {
        let dir = tempfile::tempdir().unwrap();
        let listed = |name: &str| {
            live().iter().any(|f| {
                let shared = lock(f);
                shared.target.starts_with(dir.path().join(name))
            })
        };
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
