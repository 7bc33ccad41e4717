//! Runs that pass their limit points by themselves (`control = "auto"`,
//! the default; `junta_solvers::path_switch`): load or displacement control
//! until a limit point, path following from there, load control again
//! where the path loads on a stable branch.
//!
//! References: corrected beam theory (BENCHMARKS.md section 4: AS4/PEEK DCB,
//! `P = (G_Ic b)^(3/4) (E11 b h^3 / 12)^(1/4) sqrt(2 / (3 delta))`; ENF,
//! `C(a) = (3 a^3 + 2 L^3) / (8 E11 b h^3)`), and Junta's own path
//! following (`control = "arc_length"`) on the same input, which the
//! existing path-following tests hold against those references.

mod common;
use common::*;
use std::path::Path;

/// `(displacement, reaction, control)` of every row of curve.csv.
fn curve(dir: &Path) -> Vec<(f64, f64, String)> {
    let text = std::fs::read_to_string(dir.join("curve.csv")).unwrap();
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |n: &str| head.iter().position(|h| *h == n).unwrap();
    let (d, r, c) = (col("displacement"), col("reaction"), col("control"));
    lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            (
                f[d].parse().unwrap(),
                f[r].parse().unwrap(),
                f[c].to_string(),
            )
        })
        .collect()
}

/// The load where the curve last passes the displacement `d` (linear
/// between the two rows around it).
fn load_at(rows: &[(f64, f64, String)], d: f64) -> f64 {
    for w in rows.windows(2).rev() {
        let ((d0, p0, _), (d1, p1, _)) = (&w[0], &w[1]);
        if (d0 - d) * (d1 - d) <= 0.0 && d0 != d1 {
            return p0 + (d - d0) / (d1 - d0) * (p1 - p0);
        }
    }
    panic!("the curve never reaches {d}");
}

/// The cut-backs curve.csv records on the load-controlled increments
/// before the first path-following one: the failed attempts before the
/// switch (the one that showed the limit point is not a converged row).
fn cutbacks_before_switch(dir: &Path) -> usize {
    let text = std::fs::read_to_string(dir.join("curve.csv")).unwrap();
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |n: &str| head.iter().position(|h| *h == n).unwrap();
    let (c, k) = (col("control"), col("cutbacks"));
    lines
        .map(|l| l.split(',').collect::<Vec<_>>())
        .take_while(|f| f[c] == "load")
        .map(|f| f[k].parse::<usize>().unwrap())
        .sum()
}

/// The deviation of the mean load of curve `a` over the propagation
/// branch (delta from 5.5 to 10 mm in 0.25 mm steps) from curve `b`'s:
/// the "mean load over the propagation". (Point by point, two
/// samplings of the element-by-element saw-tooth differ by more.)
fn mean_deviation(a: &[(f64, f64, String)], b: &[(f64, f64, String)]) -> f64 {
    let grid: Vec<f64> = (0..=18).map(|i| 5.5 + 0.25 * i as f64).collect();
    let mean = |c: &[(f64, f64, String)]| grid.iter().map(|&d| load_at(c, d)).sum::<f64>();
    (mean(a) / mean(b) - 1.0).abs()
}

fn peak(rows: &[(f64, f64, String)]) -> f64 {
    rows.iter().map(|r| r.1).fold(0.0, f64::max)
}

/// Corrected beam theory's propagation branch of the AS4/PEEK DCB.
fn dcb_cbt(delta: f64) -> f64 {
    let (gic, b, e11, h): (f64, f64, f64, f64) = (0.969, 25.4, 122700.0, 1.56);
    (gic * b).powf(0.75) * (e11 * b * h.powi(3) / 12.0).powf(0.25) * (2.0 / (3.0 * delta)).sqrt()
}

/// examples/delamination/dcb_h8.toml (the deck's twin: same mesh, law and
/// opening) with `[analysis.arc_length]` settings added and `control` set.
fn dcb_h8_with(dir: &Path, name: &str, arc: &str, control: Option<&str>) -> std::path::PathBuf {
    let text = std::fs::read_to_string(repo().join("examples/delamination/dcb_h8.toml")).unwrap();
    assert!(!text.contains("control"), "dcb_h8.toml sets no control");
    let extra = format!("[analysis.arc_length]\n{arc}\n\n[analysis.newton]");
    let mut text = text.replacen("[analysis.newton]", &extra, 1);
    if let Some(c) = control {
        text = text.replacen(
            "type = \"static\"",
            &format!("type = \"static\"\ncontrol = \"{c}\""),
            1,
        );
    }
    write(dir, name, &text)
}

/// The repository's Abaqus DCB deck as it is (no stabilisation, no Riks)
/// runs to its end opening: the switch comes at the first failed attempt
/// (no cut-back before it), the peak is the one path following finds with
/// short arcs on the twin scene (within 1 %), the propagation branch is
/// path following's throughout (`--solver control=arc_length`: the mean
/// load within 1 %) and follows corrected beam theory (the mean of the
/// saw-tooth within 3 %, and the end point within 3 %).
/// Measured: switch at increment 42 (lambda 0.42, the first attempt past
/// it stopped after 3 iterations without descent), peak 141.79 N against
/// 141.88 N (-0.06 %), 70 increments; propagation points +2.8 % above CBT
/// on average (the element-by-element saw-tooth of 2 mm elements and the
/// fully integrated H8's shear locking, which `junta check` warns about).
#[test]
fn abaqus_dcb_deck_runs_past_its_peak_to_the_end() {
    let dir = tempfile::tempdir().unwrap();
    let s = run_ok(
        &repo().join("examples/delamination/dcb_abaqus.inp"),
        &dir.path().join("deck"),
    );
    assert!(
        s["status"].as_str().unwrap().starts_with("completed"),
        "{s}"
    );
    assert_eq!(s["control"], "auto");
    let switches = s["path_switches"].as_array().unwrap();
    assert_eq!(switches[0]["to"], "arc_length", "{switches:?}");
    let lambda = switches[0]["lambda"].as_f64().unwrap();
    assert!(lambda > 0.4 && lambda < 0.5, "switch at {lambda}");
    assert_eq!(cutbacks_before_switch(&dir.path().join("deck")), 0);
    let rows = curve(&dir.path().join("deck"));
    let last = rows.last().unwrap();
    assert!((last.0 - 10.0).abs() < 1e-9, "ends at {}", last.0);
    // the reference peak: path following on the twin scene, arcs no
    // longer than the first increment so that they do not cut the peak
    let arc = dcb_h8_with(
        dir.path(),
        "arc.toml",
        "max_arc = 1.0\nmax_dissipation = 2.0",
        Some("arc_length"),
    );
    run_ok(&arc, &dir.path().join("arc"));
    let reference = peak(&curve(&dir.path().join("arc")));
    let pk = peak(&rows);
    assert!(
        (pk / reference - 1.0).abs() < 0.01,
        "peak {pk} against {reference}"
    );
    let errors: Vec<f64> = rows
        .iter()
        .filter(|r| r.0 > 5.5)
        .map(|r| r.1 / dcb_cbt(r.0) - 1.0)
        .collect();
    assert!(errors.len() >= 10, "{} propagation points", errors.len());
    let mean = errors.iter().sum::<f64>() / errors.len() as f64;
    assert!(mean.abs() < 0.03, "mean {mean} against CBT");
    assert!(
        (last.1 / dcb_cbt(last.0) - 1.0).abs() < 0.03,
        "P(10) = {}",
        last.1
    );
    // path following throughout on the same deck
    run_ok_with(
        &repo().join("examples/delamination/dcb_abaqus.inp"),
        &dir.path().join("deck_arc"),
        &["--solver", "control=arc_length"],
    );
    let mean = mean_deviation(&rows, &curve(&dir.path().join("deck_arc")));
    assert!(mean < 0.01, "mean load {mean} off path following's");
}

/// The 0.5 mm H8 DCB scene without `control`: the whole curve, and after
/// the switch the very path of the arc-length run with the same
/// path-following settings. `max_dissipation = 2` N mm samples the
/// element-by-element saw-tooth (about 12 N mm per 0.5 mm element column)
/// finely enough that "the load at delta" belongs to the path, not to
/// where the increments fell. Measured: equal to 1e-11 at 6, 8 and 10 mm.
#[test]
fn dcb_without_control_follows_the_arc_length_path() {
    let dir = tempfile::tempdir().unwrap();
    let fine = "max_dissipation = 2.0";
    let auto = dcb_h8_with(dir.path(), "auto.toml", fine, None);
    let arc = dcb_h8_with(dir.path(), "arc.toml", fine, Some("arc_length"));
    let s = run_ok(&auto, &dir.path().join("auto"));
    assert!(
        s["status"].as_str().unwrap().starts_with("completed"),
        "{s}"
    );
    run_ok(&arc, &dir.path().join("arc"));
    let (a, b) = (
        curve(&dir.path().join("auto")),
        curve(&dir.path().join("arc")),
    );
    assert!(a.iter().any(|r| r.2 == "load") && a.iter().any(|r| r.2 == "dissipation"));
    assert!((a.last().unwrap().0 - 10.0).abs() < 1e-9);
    assert_eq!(cutbacks_before_switch(&dir.path().join("auto")), 0);
    for d in [6.0, 8.0, 10.0] {
        let (pa, pb) = (load_at(&a, d), load_at(&b, d));
        assert!(
            (pa / pb - 1.0).abs() < 0.005,
            "P({d}) = {pa} against the arc length's {pb}"
        );
    }
}

/// `control = "displacement"` written out keeps the stop at the first
/// limit point, with the remedy named.
#[test]
fn explicit_displacement_control_keeps_the_stop() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dcb_h8_with(dir.path(), "disp.toml", "", Some("displacement"));
    let out = junta()
        .arg("run")
        .arg(&scene)
        .arg("-o")
        .arg(dir.path().join("out"))
        .arg("-q")
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("load increment too small"), "{err}");
    let rows = curve(&dir.path().join("out"));
    let last = rows.last().unwrap().0;
    assert!(last > 4.0 && last < 5.0, "stopped at {last}");
    assert!(rows.iter().all(|r| r.2 == "load"));
    // the same with the option on the command line, for decks
    let out = junta()
        .arg("run")
        .arg(repo().join("examples/delamination/dcb_abaqus.inp"))
        .args(["--solver", "control=load", "-q", "-o"])
        .arg(dir.path().join("deck"))
        .output()
        .unwrap();
    assert!(!out.status.success());
    let bad = junta()
        .arg("run")
        .arg(&scene)
        .args(["--solver", "control=riks", "-q", "-o"])
        .arg(dir.path().join("bad"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&bad.stderr);
    assert!(
        !bad.status.success() && err.contains("control=riks") && err.contains("arc_length"),
        "{err}"
    );
}

/// The ENF with a0/L = 0.5 under displacement control (the example with
/// its `control` line removed): the snap-back of the unstable crack is
/// traced, and the run ends at the prescribed deflection. Beam theory
/// (LEFM; enf_snapback.toml's header): the deflection falls from 3.80 to
/// 3.46 mm after the peak; the crack then reaches mid-span. Measured: the switch at increment 3 (the first failed attempt), peak
/// 1086.6 N at 3.68 mm, minimum deflection 3.53 mm after it, end at 4.3 mm
/// with the crack at the load point.
#[test]
fn enf_snap_back_under_displacement_control() {
    let dir = tempfile::tempdir().unwrap();
    let ex = repo().join("examples/delamination");
    let text = std::fs::read_to_string(ex.join("enf_snapback.toml")).unwrap();
    let text = text.replace("control = \"arc_length\"\n", "");
    assert!(!text.lines().any(|l| l.starts_with("control")));
    // its reference curve beside it
    std::fs::copy(
        ex.join("enf_snapback_beam_theory.csv"),
        dir.path().join("enf_snapback_beam_theory.csv"),
    )
    .unwrap();
    let scene = write(dir.path(), "enf.toml", &text);
    let s = run_ok(&scene, &dir.path().join("out"));
    assert!(
        s["status"].as_str().unwrap().starts_with("completed"),
        "{s}"
    );
    // (the exact tangent may take over first: mode II with contact at the
    // crack tip is not symmetric either)
    let switches = s["path_switches"].as_array().unwrap();
    assert!(
        switches.iter().any(|w| w["to"] == "arc_length"),
        "{switches:?}"
    );
    assert_eq!(cutbacks_before_switch(&dir.path().join("out")), 0);
    let rows = curve(&dir.path().join("out"));
    let ipk = (0..rows.len())
        .max_by(|&i, &j| rows[i].1.total_cmp(&rows[j].1))
        .unwrap();
    let dmin = rows[ipk..].iter().map(|r| r.0).fold(f64::MAX, f64::min);
    assert!(rows[ipk].0 - dmin > 0.1, "no snap-back after {ipk}");
    assert!((rows.last().unwrap().0 - 4.3).abs() < 1e-9);
    let (b, l) = (25.4, 50.0);
    // the crack (failed, traction-free points) runs to within the mode II
    // process zone of the load point (measured: 23.1 of the 25 mm)
    let area = s["interfaces"]["bond"]["damaged_area"].as_f64().unwrap();
    assert!(area / b > 0.9 * (l - 25.0), "crack growth {} mm", area / b);
}

/// Load control takes over again after the limit point: the snap-back bar
/// of crates/cli/tests/data/snapback_bar.toml (a cohesive point in series
/// with a bar, closed form in its header) beside an elastic spring (an
/// equal bar on a `linear_penalty` interface, d = 0.5 N/mm^3), both tops
/// pulled by 0.2 mm per unit load factor up to 3 (0.6 mm), no `control`.
/// Displacement control stops at the cohesive peak; path following traces
/// the snap-back to separation; the spring alone then loads on a stable
/// branch, where load control takes over to the end. Closed form at the
/// end: the spring carries `0.6 / (1/(d A) + L/(E A)) = 0.6 / (2 + 0.1) =
/// 0.285714 N`, the separated bar nothing. Measured: to path following at
/// lambda 0.497 (six cut-backs in a row below the peak at 0.505), back to
/// load control at 0.676, 28 increments.
/// The scene of `load_control_takes_over_again_on_a_stable_branch`, in `dir`.
fn bar_and_spring(dir: &Path) -> std::path::PathBuf {
    let text = std::fs::read_to_string(repo().join("crates/cli/tests/data/snapback_bar.toml"))
        .unwrap()
        .replace("control = \"arc_length\"\n", "")
        .replace("steps = [1.0]", "steps = [3.0]")
        .replace(
            "[mesh]",
            "[laws.soft]\ntype = \"linear_penalty\"\nd = 0.5\n\n[mesh]",
        )
        .replace(
            "[[interface]]\nname = \"bond\"",
            "[[mesh.boxes]]\nname = \"base2\"\norigin = [2.0, 0.0, 0.0]\nsize = [1.0, 1.0, 1.0]\n\
             divisions = [1, 1, 1]\nelement = \"h8\"\nmaterial = \"rigid\"\n\
             [[mesh.boxes]]\nname = \"spring\"\norigin = [2.0, 0.0, 1.0]\nsize = [1.0, 1.0, 10.0]\n\
             divisions = [1, 1, 2]\nelement = \"h8\"\nmaterial = \"bar\"\n\n\
             [[interface]]\nname = \"elastic\"\nbetween = [\"base2\", \"spring\"]\nlaw = \"soft\"\n\n\
             [[interface]]\nname = \"bond\"",
        )
        .replace(
            "[analysis]",
            "[[boundary]]\nset = \"base2.z0\"\nfixed = \"all\"\n[[boundary]]\nset = \"base2.z1\"\n\
             fixed = \"all\"\n[[boundary]]\nset = \"spring.z1\"\nfixed = [\"x\", \"y\"]\n\
             displacement = { z = 0.2 }\n\n[analysis]",
        );
    assert!(text.contains("spring.z1") && !text.contains("control ="));
    write(dir, "bar_and_spring.toml", &text)
}

#[test]
fn load_control_takes_over_again_on_a_stable_branch() {
    let dir = tempfile::tempdir().unwrap();
    let scene = bar_and_spring(dir.path());
    let s = run_ok(&scene, &dir.path().join("out"));
    assert!(
        s["status"].as_str().unwrap().starts_with("completed"),
        "{s}"
    );
    let to: Vec<&str> = s["path_switches"]
        .as_array()
        .unwrap()
        .iter()
        .map(|w| w["to"].as_str().unwrap())
        .collect();
    assert_eq!(to, ["arc_length", "load"], "{}", s["path_switches"]);
    let back = s["path_switches"][1]["lambda"].as_f64().unwrap();
    let rows = curve(&dir.path().join("out"));
    let after = &rows[s["path_switches"][1]["increment"].as_u64().unwrap() as usize..];
    assert!(
        !after.is_empty() && after.iter().all(|r| r.2 == "load"),
        "{back}"
    );
    let spring = s["reactions"]["spring.z1"][2].as_f64().unwrap();
    let bar = s["reactions"]["bar.z1"][2].as_f64().unwrap();
    let closed_form = 0.6 / (1.0 / 0.5 + 10.0 / 100.0);
    assert!(
        rel(spring, closed_form) < 1e-9,
        "{spring} against {closed_form}"
    );
    assert!(bar.abs() < 1e-9, "{bar}");
}

/// A `control = "auto"` run stopped and restarted before the switch to
/// path following, during it, and after the return to load control gives
/// the uninterrupted run's increments, bit for bit (the load phase keeps
/// what the switch needs in the checkpoint; the path phase its path state).
#[test]
fn restarted_auto_run_equals_the_uninterrupted_one() {
    let dir = tempfile::tempdir().unwrap();
    let scene = bar_and_spring(dir.path());
    let full = dir.path().join("full");
    run_ok(&scene, &full);
    let reference = curve_without_seconds(&full);
    for stop in [3, 12, 24] {
        let part = dir.path().join(format!("part{stop}"));
        run_ok_with(&scene, &part, &["--max-increments", &stop.to_string()]);
        restart_ok(&part);
        assert_eq!(curve_without_seconds(&part), reference, "stopped at {stop}");
        let s: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(part.join("summary.json")).unwrap())
                .unwrap();
        assert_eq!(
            s["path_switches"].as_array().unwrap().len(),
            2,
            "stopped at {stop}"
        );
    }
}
