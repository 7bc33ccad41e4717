//! What `junta` says and where: each warning of a run once on standard
//! error, `junta check`'s named sets summarised unless `--verbose`, and
//! every `[output]` key honoured by every kind of run (or refused with a
//! message naming it).

mod common;
use common::*;

/// The warnings of a run (lines `warning: ...` on stderr) each appear
/// exactly once: the run's end used to log them through `tracing` and the
/// CLI printed them again. examples/fatigue/held_opening.toml (0.03 s)
/// ends with the process-zone warning.
#[test]
fn each_warning_of_a_run_is_printed_once() {
    let dir = tempfile::tempdir().unwrap();
    let out = junta()
        .arg("run")
        .arg(repo().join("examples/fatigue/held_opening.toml"))
        .arg("-o")
        .arg(dir.path())
        .arg("-q")
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "{err}");
    let warnings: Vec<&str> = err
        .lines()
        .filter_map(|l| l.strip_prefix("warning: "))
        .collect();
    assert!(!warnings.is_empty(), "the example warns: {err}");
    for w in &warnings {
        // the message's text, wherever and however it is printed
        let key: String = w.chars().take(80).collect();
        assert_eq!(err.matches(key.as_str()).count(), 1, "{key}\n{err}");
    }
    assert!(!err.contains("WARN"), "{err}");
    // the same warnings are in summary.json
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("summary.json")).unwrap())
            .unwrap();
    let listed = s["warnings"].to_string();
    for w in &warnings {
        assert!(listed.contains(&w[..40.min(w.len())]), "{w}");
    }
}

fn check(args: &[&str], path: &std::path::Path) -> String {
    let out = junta().arg("check").args(args).arg(path).output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// The box DCB of examples/fatigue/dcb_paris.toml has 50 node sets, 11
/// element sets and 48 face sets (every block's six sides): without
/// `--verbose` one short line per kind (count and the first 4 names),
/// with it every name.
#[test]
fn check_summarises_the_sets_unless_verbose() {
    let path = repo().join("examples/fatigue/dcb_paris.toml");
    let short = check(&[], &path);
    let lines: Vec<&str> = short.lines().filter(|l| l.contains(" sets: ")).collect();
    assert!(lines.len() <= 3, "{short}");
    for l in &lines {
        assert!(l.len() < 200, "{l}");
    }
    assert!(
        short.contains("  node sets: 50 (bond.bottom (386), bond.top (386),")
            && short.contains("... and 46 more; --verbose lists them all)"),
        "{short}"
    );
    assert!(!short.contains("upper_far.z1"), "{short}");
    let long = check(&["--verbose"], &path);
    let node_line = long
        .lines()
        .find(|l| l.starts_with("  node sets: "))
        .unwrap_or_else(|| panic!("{long}"));
    assert_eq!(node_line.matches(" (").count(), 50, "{node_line}");
    assert!(long.contains("upper_far.z1 (36)"), "{long}");
    assert!(!long.contains("more; --verbose"), "{long}");
}

/// examples/cantilever.toml under `nlgeom = true` (an incremental run)
/// writes `probes` to summary.json, as the linear run does: at P = 1000 N
/// the tip deflection (1.9e-4 m on a 1 m beam) is far in the linear range,
/// so the two agree within 0.5 %.
#[test]
fn an_incremental_run_writes_its_probes() {
    let dir = tempfile::tempdir().unwrap();
    let base = std::fs::read_to_string(repo().join("examples/cantilever.toml")).unwrap();
    let linear = write(dir.path(), "linear.toml", &base);
    let s_lin = run_ok(&linear, &dir.path().join("linear"));
    let nl = write(
        dir.path(),
        "nlgeom.toml",
        &format!("{base}\n[analysis]\nnlgeom = true\n"),
    );
    let s_nl = run_ok(&nl, &dir.path().join("nlgeom"));
    assert_eq!(s_nl["analysis"], "static", "{s_nl}");
    let uz = |s: &serde_json::Value| s["probes"]["x1"][2].as_f64().unwrap_or(f64::NAN);
    let (a, b) = (uz(&s_lin), uz(&s_nl));
    assert!(
        a < 0.0 && b < 0.0 && rel(b, a) < 5e-3,
        "linear {a:e}, nlgeom {b:e}"
    );
}

/// `[output] fractions` scales a linear run's one solution; an incremental
/// run refuses it, naming the key.
#[test]
fn an_incremental_run_refuses_fractions() {
    let dir = tempfile::tempdir().unwrap();
    let base = std::fs::read_to_string(repo().join("examples/cantilever.toml")).unwrap();
    let p = write(
        dir.path(),
        "f.toml",
        &format!(
            "{}\nfractions = [0.5, 1.0]\n\n[analysis]\nnlgeom = true\n",
            base.trim_end()
        ),
    );
    let err = run_err(&p);
    assert!(
        err.contains("key `output.fractions`") && err.contains("every"),
        "{err}"
    );
}

/// `[output] vtu = false` writes no VTU file in an incremental run either
/// (it wrote every frame before), and the curve and the summary are the
/// same as with frames.
#[test]
fn vtu_false_writes_no_frame_in_an_incremental_run() {
    let dir = tempfile::tempdir().unwrap();
    let base = std::fs::read_to_string(repo().join("examples/cantilever.toml")).unwrap();
    let with = write(
        dir.path(),
        "with.toml",
        &format!("{}\n\n[analysis]\nnlgeom = true\n", base.trim_end()),
    );
    let without = write(
        dir.path(),
        "without.toml",
        &format!(
            "{}\nvtu = false\n\n[analysis]\nnlgeom = true\n",
            base.trim_end()
        ),
    );
    let (a, b) = (dir.path().join("with"), dir.path().join("without"));
    let s_with = run_ok(&with, &a);
    let s_without = run_ok(&without, &b);
    assert!(a.join("results.pvd").exists() && a.join("frames").exists());
    assert!(!b.join("results.pvd").exists(), "a pvd without frames");
    assert!(!b.join("frames").exists(), "a frames folder");
    assert_eq!(curve_without_seconds(&a), curve_without_seconds(&b));
    assert_eq!(s_with["displacement_max"], s_without["displacement_max"]);
}
