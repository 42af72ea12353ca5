//! Helpers shared by the CLI's test files: the binary, scratch folders, captured output.
#![allow(dead_code)]

use std::path::PathBuf;
use std::process::Command;

use assert_cmd::cargo::cargo_bin;

pub fn bounce() -> Command {
    Command::new(cargo_bin("bounce"))
}

/// A scratch directory with a scenario file in it.
pub struct Scratch {
    dir: tempfile::TempDir,
}

impl Scratch {
    pub fn new() -> Self {
        Scratch {
            dir: tempfile::tempdir().unwrap(),
        }
    }

    pub fn path(&self, name: &str) -> PathBuf {
        self.dir.path().join(name)
    }

    pub fn scenario(&self, name: &str, text: &str) -> PathBuf {
        let path = self.path(name);
        std::fs::write(&path, text).unwrap();
        path
    }
}

/// Runs and returns (exit code, stdout, stderr).
pub fn output(cmd: &mut Command) -> (i32, String, String) {
    let out = cmd.output().unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// One chunk of a GSD file: its frame, name, element type (GSD's codes: 9 f32, 10 f64) and
/// data. Parsed from the index by hand: reading through bounce's own reader would be circular.
pub struct GsdChunk {
    pub frame: u64,
    pub name: String,
    pub kind: u8,
    pub data: Vec<u8>,
}

/// Every chunk of a GSD file this bounce wrote, in index order.
pub fn gsd_chunks(path: &std::path::Path) -> Vec<GsdChunk> {
    let bytes = std::fs::read(path).unwrap();
    let word = |at: usize| u64::from_le_bytes(bytes[at..at + 8].try_into().unwrap());
    let (index, allocated, names_at) = (word(8) as usize, word(16) as usize, word(24) as usize);
    let names: Vec<String> = bytes[names_at..]
        .split(|&b| b == 0)
        .map(|n| String::from_utf8_lossy(n).into_owned())
        .collect();
    let mut chunks = Vec::new();
    for k in 0..allocated {
        let e = &bytes[index + 32 * k..index + 32 * (k + 1)];
        let field = |a: usize, b: usize| {
            let mut w = [0u8; 8];
            w[..b - a].copy_from_slice(&e[a..b]);
            u64::from_le_bytes(w)
        };
        let location = field(16, 24) as usize;
        if location == 0 {
            break;
        }
        let kind = e[30];
        let size = match kind {
            1 | 5 => 1,
            2 | 6 => 2,
            3 | 7 | 9 => 4,
            _ => 8,
        };
        let length = field(8, 16) as usize * field(24, 28) as usize * size;
        chunks.push(GsdChunk {
            frame: field(0, 8),
            name: names[field(28, 30) as usize].clone(),
            kind,
            data: bytes[location..location + length].to_vec(),
        });
    }
    chunks
}
