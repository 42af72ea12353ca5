//! The headless build for clusters: `--no-default-features` leaves eframe, winit and X11 out
//! of the dependency tree, and that `bounce view` says how to get the viewer.
//!
//! Builds a second `bounce` (into its own target directory, about a minute), so it runs with
//! the system tests (`scripts/test`).
#![cfg(feature = "system-tests")]

use std::path::{Path, PathBuf};
use std::process::Command;

fn cargo() -> Command {
    let mut cmd = Command::new(std::env::var("CARGO").unwrap_or_else(|_| "cargo".into()));
    cmd.current_dir(Path::new(env!("CARGO_MANIFEST_DIR")).join("../.."));
    cmd
}

#[test]
fn a_build_without_the_view_feature_has_no_window_system() {
    let out = cargo()
        .args([
            "tree",
            "-p",
            "bounce-cli",
            "--no-default-features",
            "--prefix",
            "none",
        ])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let tree = String::from_utf8_lossy(&out.stdout);
    for heavy in [
        "eframe ",
        "egui ",
        "winit ",
        "x11-dl ",
        "glow ",
        "bounce-viewer ",
    ] {
        assert!(
            !tree.lines().any(|l| l.starts_with(heavy)),
            "{heavy}is in the headless tree"
        );
    }
    // And it is there by default.
    let out = cargo()
        .args(["tree", "-p", "bounce-cli", "--prefix", "none"])
        .output()
        .unwrap();
    assert!(String::from_utf8_lossy(&out.stdout).contains("eframe "));
}

#[test]
fn the_headless_bounce_runs_and_says_how_to_get_the_viewer() {
    let target: PathBuf = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../../target"))
        .join("headless");
    let build = cargo()
        .args([
            "build",
            "--release",
            "-p",
            "bounce-cli",
            "--no-default-features",
        ])
        .arg("--target-dir")
        .arg(&target)
        .output()
        .unwrap();
    assert!(
        build.status.success(),
        "{}",
        String::from_utf8_lossy(&build.stderr)
    );
    let bounce = target.join("release/bounce");
    let view = Command::new(&bounce).arg("view").output().unwrap();
    assert_eq!(view.status.code(), Some(1));
    let message = String::from_utf8_lossy(&view.stderr);
    assert!(
        message.contains("without the viewer")
            && message.contains("cargo install --path crates/bounce-cli"),
        "{message}"
    );
    // Everything else works: a short run of the shipped gas.
    let dir = tempfile::tempdir().unwrap();
    let scenario = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios/gas.toml");
    let run = Command::new(&bounce)
        .arg("run")
        .arg(&scenario)
        .args(["--steps", "3", "--quiet", "--out"])
        .arg(dir.path())
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    assert!(dir.path().join("stats.csv").exists());
}
