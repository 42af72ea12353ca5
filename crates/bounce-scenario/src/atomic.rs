//! Files that appear whole or not at all: written to a temporary file beside the target and
//! renamed into place when complete. Every output of the CLI and the viewer's checkpoints go
//! through here. (Not on wasm32, which has no file system.)

use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

use tempfile::NamedTempFile;

/// Temporary files start with this, so a later run can remove those a killed one left.
pub const TEMP_PREFIX: &str = ".bounce-tmp-";

/// An I/O error with the path it concerns in its message.
fn named(what: &str, path: &Path, e: io::Error) -> io::Error {
    io::Error::new(e.kind(), format!("cannot {what} {}: {e}", path.display()))
}

/// A file being written; it replaces `target` on [`AtomicFile::commit`] and vanishes if
/// dropped before that.
pub struct AtomicFile {
    target: PathBuf,
    writer: BufWriter<NamedTempFile>,
}

impl AtomicFile {
    /// Starts writing a file that will become `target`.
    pub fn create(target: &Path) -> io::Result<Self> {
        let dir = target
            .parent()
            .filter(|d| !d.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        let mut builder = tempfile::Builder::new();
        builder.prefix(TEMP_PREFIX);
        // Outputs are ordinary files (the umask still applies), not private temporaries.
        #[cfg(unix)]
        builder.permissions(std::os::unix::fs::PermissionsExt::from_mode(0o644));
        let temp = builder
            .tempfile_in(dir)
            .map_err(|e| named("write in", dir, e))?;
        Ok(AtomicFile {
            target: target.to_path_buf(),
            writer: BufWriter::with_capacity(1 << 20, temp),
        })
    }

    /// The writer to fill.
    pub fn writer(&mut self) -> &mut BufWriter<NamedTempFile> {
        &mut self.writer
    }

    /// Flushes and renames the file into place.
    pub fn commit(self) -> io::Result<()> {
        let target = self.target;
        let temp = self
            .writer
            .into_inner()
            .map_err(|e| named("write", &target, e.into_error()))?;
        temp.as_file()
            .sync_all()
            .map_err(|e| named("write", &target, e))?;
        temp.persist(&target)
            .map_err(|e| named("create", &target, e.error))?;
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
}
