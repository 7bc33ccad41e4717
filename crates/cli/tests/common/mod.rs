//! Helpers shared by the CLI test programs.
#![allow(dead_code)]

use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;

pub fn junta() -> Command {
    Command::new(env!("CARGO_BIN_EXE_junta"))
}

pub fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Run `junta run input -o dir`, return summary.json.
pub fn run_ok(input: &Path, dir: &Path) -> Value {
    run_ok_with(input, dir, &[])
}

/// [`run_ok`] with extra arguments (e.g. `--max-increments 40`).
pub fn run_ok_with(input: &Path, dir: &Path, args: &[&str]) -> Value {
    let out = junta()
        .arg("run")
        .arg(input)
        .arg("-o")
        .arg(dir)
        .arg("-q")
        .args(args)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "junta run {} failed:\n{}",
        input.display(),
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(dir.join("summary.json")).unwrap();
    serde_json::from_str(&text).unwrap()
}

/// `junta run --restart dir -q`, which must succeed.
pub fn restart_ok(dir: &Path) {
    let out = junta()
        .args(["run", "-q", "--restart"])
        .arg(dir)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "junta run --restart {} failed:\n{}",
        dir.display(),
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Run and expect failure; return stderr.
pub fn run_err(input: &Path) -> String {
    let dir = tempfile::tempdir().unwrap();
    let out = junta()
        .arg("run")
        .arg(input)
        .arg("-o")
        .arg(dir.path())
        .arg("-q")
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr).to_string();
    assert!(
        !out.status.success(),
        "expected failure for {}",
        input.display()
    );
    assert!(!err.contains("panicked"), "panic on bad input:\n{err}");
    assert!(
        err.starts_with("error: "),
        "error message should start with `error: `:\n{err}"
    );
    err
}

pub fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

pub fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

/// The lines of `DIR/curve.csv` (header included) without the wall-clock
/// column `seconds`, found by its name: what a repeated or restarted run
/// must reproduce bit for bit.
pub fn curve_without_seconds(dir: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(dir.join("curve.csv")).unwrap();
    let head: Vec<&str> = text.lines().next().unwrap_or("").split(',').collect();
    let seconds = head
        .iter()
        .position(|h| *h == "seconds")
        .expect("curve.csv has a seconds column");
    text.lines()
        .map(|l| {
            let mut f: Vec<&str> = l.split(',').collect();
            f.remove(seconds);
            f.join(",")
        })
        .collect()
}
