//! Files from outside the run: read only when they are regular files, since opening a FIFO
//! waits for a writer forever (deaf to signals) and a device is no scenario, trajectory or
//! table; and outputs never written over anything but a regular file (a device node would
//! be replaced by the rename).

use std::fs::File;
use std::io;
use std::path::Path;

/// Refuses a path that exists and is not a regular file (after following links).
fn regular(path: &Path, what: &str) -> io::Result<()> {
    match std::fs::metadata(path) {
        Ok(meta) if !meta.is_file() => Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            format!(
                "{} is not a regular file ({}): bounce {what} only regular files",
                path.display(),
                if meta.is_dir() {
                    "a folder"
                } else {
                    "a device, FIFO or socket"
                }
            ),
        )),
        _ => Ok(()),
    }
}

/// Opens `path` for reading, refusing anything but a regular file.
pub fn open(path: &Path) -> io::Result<File> {
    regular(path, "reads")?;
    File::open(path)
}

/// Reads `path` as text, refusing anything but a regular file.
pub fn read_to_string(path: &Path) -> io::Result<String> {
    regular(path, "reads")?;
    std::fs::read_to_string(path)
}

/// Reads `path`'s bytes, refusing anything but a regular file.
pub fn read(path: &Path) -> io::Result<Vec<u8>> {
    regular(path, "reads")?;
    std::fs::read(path)
}

/// Refuses to write over `path` when it exists and is not a regular file.
pub fn writable(path: &Path) -> io::Result<()> {
    regular(path, "writes over")
}

#[cfg(all(test, unix))]
mod tests {
    use super::*;

    #[test]
    fn a_device_is_neither_read_nor_written_over() {
        let null = Path::new("/dev/null");
        assert!(
            open(null)
                .unwrap_err()
                .to_string()
                .contains("not a regular file")
        );
        assert!(writable(null).is_err());
        assert!(writable(Path::new("/no/such/file")).is_ok());
        let dir = std::env::temp_dir();
        assert!(
            read_to_string(&dir)
                .unwrap_err()
                .to_string()
                .contains("a folder")
        );
    }
}
