//! Progressive debonding through the CLI: the paper's F9/F11 beams, the
//! first failure against beam theory, restart, and a run that must fail.

mod common;
use common::*;
use serde_json::Value;
use std::path::Path;

fn f(v: &Value) -> f64 {
    v.as_f64().unwrap()
}

fn summary(dir: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap()
}

#[test]
fn beam_shear_first_failure_matches_beam_theory_and_splits() {
    let dir = tempfile::tempdir().unwrap();
    let s = run_ok(&repo().join("examples/paper/beam_shear.toml"), dir.path());
    // beam theory: tau = 3 V / (2 A), V = p b L at the root, per unit load factor
    let (p, b, l, h) = (1e6, 0.025, 0.2, 0.04);
    let tau_per_lambda = 1.5 * p * b * l / (b * h);
    let lambda_theory = 4e6 / tau_per_lambda; // 0.5333
    let lambda_fe = f(&s["first_failure"]["load_factor"]);
    assert!(
        (lambda_fe - lambda_theory).abs() / lambda_theory < 0.05,
        "first failure at lambda = {lambda_fe}, beam theory {lambda_theory}"
    );
    assert_eq!(
        f(&s["interfaces"]["bond"]["failed_fraction"]),
        1.0,
        "the beam splits"
    );
    assert!(s["status"]
        .as_str()
        .unwrap()
        .contains("every interface point has failed"));
    // the symbolic factorisation was done once for the whole run
    assert_eq!(s["symbolic_analyses"].as_u64(), Some(1));
    // frames and the pvd index are on disk
    assert!(dir.path().join("results.pvd").exists() && dir.path().join("curve.svg").exists());
}

#[test]
fn beam_peel_splits_from_the_free_end_and_load_moves_to_the_clamps() {
    let dir = tempfile::tempdir().unwrap();
    let s = run_ok(&repo().join("examples/paper/beam_peel.toml"), dir.path());
    assert_eq!(f(&s["interfaces"]["bond"]["failed_fraction"]), 1.0);
    // split: the interface transmits nothing any more (every traction zero)
    for key in ["traction_min", "traction_max"] {
        for k in 0..3 {
            assert_eq!(f(&s["interfaces"]["bond"][key][k]), 0.0, "{key}[{k}]");
        }
    }
    // bonded, the opposite end forces equilibrate through the interface and
    // the upper clamp carries nothing; split, the upper arm is a cantilever
    // whose clamp carries the whole 3 x 1000 N x lambda
    let first = f(&s["first_failure"]["reaction"]);
    assert!(first.abs() < 1e-3, "upper clamp before the crack: {first}");
    let lambda = f(&s["load_factor"]);
    let fz = f(&s["reactions"]["upper.x0"][2]);
    assert!(
        (fz + 3000.0 * lambda).abs() < 1e-6 * 3000.0 * lambda,
        "{fz} vs {}",
        -3000.0 * lambda
    );
    // the failed fraction never decreases and the first failure is early
    let rows = curve_without_seconds(dir.path());
    let failed: Vec<usize> = rows[1..]
        .iter()
        .map(|r| r.split(',').nth(5).unwrap().parse().unwrap())
        .collect();
    assert!(failed.windows(2).all(|w| w[0] <= w[1]));
    assert!(f(&s["first_failure"]["load_factor"]) < lambda);
}

#[test]
fn restart_equals_an_uninterrupted_run() {
    let scene = repo().join("examples/paper/beam_shear.toml");
    let whole = tempfile::tempdir().unwrap();
    run_ok(&scene, whole.path());
    let parts = tempfile::tempdir().unwrap();
    let out = junta()
        .arg("run")
        .arg(&scene)
        .arg("-o")
        .arg(parts.path())
        .args(["-q", "--max-increments", "40"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let partial = summary(parts.path());
    assert_eq!(partial["increments"].as_u64(), Some(40));
    assert!(partial["status"]
        .as_str()
        .unwrap()
        .contains("requested number"));
    let out = junta()
        .args(["run", "-q", "--restart"])
        .arg(parts.path())
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let a = summary(whole.path());
    let b = summary(parts.path());
    assert_eq!(b["restarted_from_increment"].as_u64(), Some(40));
    for key in [
        "increments",
        "load_factor",
        "first_failure",
        "newton_iterations",
    ] {
        assert_eq!(a[key], b[key], "{key}");
    }
    // same increments; values equal to round-off (the parallel factorisation
    // may sum in another order)
    assert!(rel(f(&a["displacement_max"]), f(&b["displacement_max"])) < 1e-12);
    let (ca, cb) = (
        curve_without_seconds(whole.path()),
        curve_without_seconds(parts.path()),
    );
    assert_eq!(ca.len(), cb.len());
    for (ra, rb) in ca.iter().zip(&cb).skip(1) {
        for (x, y) in ra.split(',').zip(rb.split(',')) {
            match (x.parse::<f64>(), y.parse::<f64>()) {
                (Ok(x), Ok(y)) => {
                    assert!((x - y).abs() <= 1e-9 * x.abs().max(y.abs()), "{ra}\n{rb}")
                }
                _ => assert_eq!(x, y),
            }
        }
    }
}

#[test]
fn newton_past_a_limit_point_stops_clearly_with_frames_on_disk() {
    // the paper's prism with a debonding interface, the top block pulled by a
    // force: once the interface has released, nothing holds the top block,
    // so force control cannot go on (limit point)
    let text = std::fs::read_to_string(repo().join("examples/paper/prism_tension.toml")).unwrap();
    let head = text.split("[[boundary]]").next().unwrap().replace(
        "[laws.paper]\ntype = \"linear_penalty\"\nd = 1.0e25",
        "[laws.paper]\ntype = \"paper_debond\"\nd = 1.0e14\ncriterion = { type = \"quadratic\", sigma_lim = 2.0e6, tau_lim = 4.0e6 }",
    );
    let scene = head
        + r#"
[[boundary]]
set = "lower.z0"
fixed = "all"
[[load]]
face_set = "upper.z1"
traction = [0.0, 0.0, 1.0e6]
[analysis]
type = "static"
steps = [4.0]
[analysis.newton]
initial_increment = 0.1
max_increment = 0.1
min_increment = 1e-4
[output]
curve = { reaction_set = "lower.z0", reaction_component = "z", point_set = "upper.z1", point_component = "z" }
every = 1000
"#;
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), "pull.toml", &scene);
    let out_dir = dir.path().join("out");
    let out = junta()
        .arg("run")
        .arg(&path)
        .arg("-o")
        .arg(&out_dir)
        .arg("-q")
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "the run must fail");
    assert!(!err.contains("panicked"), "{err}");
    assert!(
        err.contains("load increment too small") && err.contains("lambda"),
        "{err}"
    );
    assert!(err.contains("restart"), "{err}");
    // converged increments are on disk, with a restart point and frames
    let s = summary(&out_dir);
    assert!(s["status"].as_str().unwrap().starts_with("failed"));
    let n = s["increments"].as_u64().unwrap();
    assert!(n >= 2, "{s}");
    assert_eq!(curve_without_seconds(&out_dir).len() as u64, n + 1);
    assert!(out_dir.join("checkpoint.json").exists());
    // no periodic frames (every = 1000), but the last converged increment
    // is a frame, listed in the pvd and in the checkpoint
    let pvd = std::fs::read_to_string(out_dir.join("results.pvd")).unwrap();
    let last_frame = format!("frames/results_{n:04}.vtu");
    assert!(pvd.contains(&last_frame), "{pvd}");
    assert!(out_dir.join(&last_frame).exists());
    assert!(pvd.matches("<DataSet").count() as u64 <= 2, "{pvd}");
    let checkpoint = std::fs::read_to_string(out_dir.join("checkpoint.json")).unwrap();
    assert!(checkpoint.contains(&last_frame));
    // failure at sigma_lim: the top traction 1e6 x lambda reaches 2e6 at lambda = 2
    let last: f64 = s["load_factor"].as_f64().unwrap();
    assert!((1.9..2.6).contains(&last), "last converged lambda {last}");
}

/// Ctrl-C (SIGINT) during an incremental run: the run stops after the
/// increment in progress with a non-zero exit, says so in `summary.json`,
/// keeps the converged frames, curve and checkpoint, and the restart from
/// there finishes the run (the beam splits).
#[cfg(unix)]
#[test]
fn ctrl_c_stops_cleanly_and_the_run_can_be_restarted() {
    let scene = repo().join("examples/paper/beam_shear.toml");
    let dir = tempfile::tempdir().unwrap();
    // forced mixed precision: under the default auto this small model
    // would always be solved in double, so "mixed" (or a note that the
    // solver fell back from it) shows that the override is applied, also by
    // the restart below
    let mut child = junta()
        .args(["run", "-q", "--solver", "precision=mixed", "-o"])
        .arg(dir.path())
        .arg(&scene)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // interrupt as soon as the first increment is on disk
    // (no clock: the wait ends with the checkpoint or with the run, however
    // busy the machine is)
    let checkpoint = dir.path().join("checkpoint.json");
    while !checkpoint.exists() {
        if let Some(status) = child.try_wait().unwrap() {
            panic!("the run ended ({status}) before its first checkpoint");
        }
        std::thread::yield_now();
    }
    let killed = std::process::Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "an interrupted run exits non-zero");
    assert!(stderr.contains("interrupted"), "{stderr}");
    let s = summary(dir.path());
    assert!(
        s["status"].as_str().unwrap().contains("interrupted"),
        "{}",
        s["status"]
    );
    let forced_mixed = |s: &Value| {
        s["solver"]["precision"] == "mixed"
            || s["solver"]["notes"]
                .as_array()
                .unwrap()
                .iter()
                .any(|n| n.as_str().unwrap().contains("mixed precision abandoned"))
    };
    assert!(forced_mixed(&s), "{}", s["solver"]);
    let done = s["increments"].as_u64().unwrap();
    // beam_shear takes 77 increments uninterrupted
    assert!((1..70).contains(&done), "{done} increments before the stop");
    assert_eq!(
        curve_without_seconds(dir.path()).len() as u64,
        done + 1,
        "header + one row per increment"
    );
    // the last converged increment is a frame, listed in the pvd
    let last = format!("frames/results_{done:04}.vtu");
    assert!(dir.path().join(&last).exists(), "{last}");
    let pvd = std::fs::read_to_string(dir.path().join("results.pvd")).unwrap();
    assert!(pvd.contains(&last), "{pvd}");
    // the restart finishes the job
    run_restart_ok(dir.path());
    let s = summary(dir.path());
    assert_eq!(s["restarted_from_increment"].as_u64(), Some(done));
    assert!(
        forced_mixed(&s),
        "the restart reuses --solver: {}",
        s["solver"]
    );
    assert_eq!(f(&s["interfaces"]["bond"]["failed_fraction"]), 1.0);
}

fn run_restart_ok(dir: &Path) {
    let out = junta()
        .args(["run", "-q", "--restart"])
        .arg(dir)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}
