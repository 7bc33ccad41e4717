//! Restart equals the uninterrupted run, bit for bit; a finished run is
//! left alone; an edited scene is refused unless asked; a corrupt
//! checkpoint is a clear error.

mod common;
use common::{curve_without_seconds, junta, repo, run_ok, run_ok_with};
use serde_json::Value;
use std::path::Path;

fn summary(dir: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap()
}

fn restart(dir: &Path, extra: &[&str]) -> std::process::Output {
    junta()
        .args(["run", "-q", "--restart"])
        .arg(dir)
        .args(extra)
        .output()
        .unwrap()
}

/// The last VTU frame of a run (ASCII floats written shortest-round-trip).
fn last_frame(dir: &Path) -> String {
    let mut frames: Vec<_> = std::fs::read_dir(dir.join("frames"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "vtu"))
        .collect();
    frames.sort();
    std::fs::read_to_string(frames.last().unwrap()).unwrap()
}

#[test]
fn restarted_run_is_bit_identical_to_the_uninterrupted_one() {
    let scene = repo().join("examples/paper/beam_peel.toml");
    let whole = tempfile::tempdir().unwrap();
    let a = run_ok(&scene, whole.path());
    let parts = tempfile::tempdir().unwrap();
    run_ok_with(&scene, parts.path(), &["--max-increments", "30"]);
    let out = restart(parts.path(), &[]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let b = summary(parts.path());
    assert_eq!(b["restarted_from_increment"].as_u64(), Some(30));
    for key in [
        "increments",
        "load_factor",
        "first_failure",
        "newton_iterations",
        "reactions",
        "displacement_max",
        "interfaces",
        "status",
    ] {
        assert_eq!(a[key], b[key], "{key}");
    }
    assert_eq!(
        curve_without_seconds(whole.path()),
        curve_without_seconds(parts.path())
    );
    assert_eq!(last_frame(whole.path()), last_frame(parts.path()));
}

/// A copy of beam_peel in its own directory, run for `n` increments.
fn partial_run(n: &str) -> (tempfile::TempDir, std::path::PathBuf, std::path::PathBuf) {
    let tmp = tempfile::tempdir().unwrap();
    let scene = tmp.path().join("beam_peel.toml");
    std::fs::copy(repo().join("examples/paper/beam_peel.toml"), &scene).unwrap();
    let out = tmp.path().join("out");
    run_ok_with(&scene, &out, &["--max-increments", n]);
    (tmp, scene, out)
}

fn snapshot(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut v: Vec<(String, Vec<u8>)> = ["summary.json", "curve.csv", "checkpoint.json"]
        .iter()
        .map(|f| (f.to_string(), std::fs::read(dir.join(f)).unwrap()))
        .collect();
    v.push(("frame".into(), last_frame(dir).into_bytes()));
    v
}

#[test]
fn restart_of_a_finished_run_leaves_it_unchanged_and_says_so() {
    let dir = tempfile::tempdir().unwrap();
    run_ok(&repo().join("examples/paper/beam_peel.toml"), dir.path());
    let before = snapshot(dir.path());
    let out = restart(dir.path(), &[]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let said = String::from_utf8_lossy(&out.stdout);
    assert!(
        said.contains("already finished") && said.contains("unchanged"),
        "{said}"
    );
    assert!(before == snapshot(dir.path()), "files changed");
}

#[test]
fn restart_after_an_edit_is_refused_naming_the_change_unless_allowed() {
    let (_tmp, scene, out) = partial_run("10");
    let text = std::fs::read_to_string(&scene).unwrap();
    assert!(text.contains("E = 2.1e11"));
    std::fs::write(&scene, text.replacen("E = 2.1e11", "E = 2.0e11", 1)).unwrap();
    let before = snapshot(&out);
    let r = restart(&out, &[]);
    let err = String::from_utf8_lossy(&r.stderr);
    assert!(!r.status.success(), "edited scene accepted");
    assert!(
        err.contains("materials.") && err.contains(".E") && err.contains("--allow-edited"),
        "{err}"
    );
    assert!(
        before == snapshot(&out),
        "a refused restart changed the files"
    );
    let r = restart(&out, &["--allow-edited"]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    assert!(String::from_utf8_lossy(&r.stderr).contains("edited input"));
    assert_eq!(summary(&out)["restarted_from_increment"].as_u64(), Some(10));
}

#[test]
fn checkpoint_fields_out_of_range_are_clear_errors() {
    let (_tmp, _scene, out) = partial_run("5");
    let path = out.join("checkpoint.json");
    let good: Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    for (field, value, name) in [
        ("increment_size", serde_json::json!(0.0), "increment_size"),
        ("increment_size", serde_json::json!(-1.0), "increment_size"),
        ("step_fraction", serde_json::json!(1.5), "step_fraction"),
        (
            "increment_index",
            serde_json::json!(1u64 << 63),
            "increment_index",
        ),
    ] {
        let mut bad = good.clone();
        bad["checkpoint"][field] = value;
        std::fs::write(&path, serde_json::to_vec(&bad).unwrap()).unwrap();
        let r = restart(&out, &[]);
        let err = String::from_utf8_lossy(&r.stderr);
        assert!(
            !r.status.success() && !err.contains("panicked"),
            "{field}: {err}"
        );
        assert!(err.contains(name) && err.contains("out of range"), "{err}");
    }
}
