//! Path following (`[analysis] control = "arc_length"`) against a closed
//! form: a cohesive point in series with an elastic bar long enough to snap
//! back (tests/data/snapback_bar.toml, whose header derives the path).

mod common;

use common::{junta, repo, restart_ok, run_ok, run_ok_with, write};
use std::path::{Path, PathBuf};

// The scene's data (tests/data/snapback_bar.toml).
const K: f64 = 1000.0; // N/mm^3
const N: f64 = 1.0; // MPa
const G: f64 = 0.01; // N/mm
const L_OVER_EA: f64 = 10.0 / 100.0; // mm/N (A = 1 mm^2)

fn scene() -> PathBuf {
    repo().join("crates/cli/tests/data/snapback_bar.toml")
}

#[derive(Debug, Clone)]
struct Row {
    increment: usize,
    lambda: f64,
    p: f64,
    delta: f64,
    dissipated: f64,
    pivots: usize,
    control: String,
    raw: String,
}

fn rows(dir: &Path) -> Vec<Row> {
    let text = std::fs::read_to_string(dir.join("curve.csv")).unwrap();
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |n: &str| head.iter().position(|h| *h == n).unwrap();
    let (ci, cl, cr, cd, ce, cp, cc) = (
        col("increment"),
        col("load_factor"),
        col("reaction"),
        col("displacement"),
        col("dissipated_energy"),
        col("negative_pivots"),
        col("control"),
    );
    lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            Row {
                increment: f[ci].parse().unwrap(),
                lambda: f[cl].parse().unwrap(),
                p: f[cr].parse().unwrap(),
                delta: f[cd].parse().unwrap(),
                dissipated: f[ce].parse().unwrap(),
                pivots: f[cp].parse().unwrap_or(0),
                control: f[cc].to_string(),
                raw: f[..cc + 1]
                    .iter()
                    .enumerate()
                    .filter(|(i, _)| *i != 9) // wall time
                    .map(|(_, v)| *v)
                    .collect::<Vec<_>>()
                    .join(","),
            }
        })
        .collect()
}

/// Exact traction of the bilinear mode-I law for an opening `d` reached
/// along a path whose largest opening so far is `dmax` (secant unloading).
fn traction(d: f64, dmax: f64) -> f64 {
    let (d0, df) = (N / K, 2.0 * G / N);
    let virgin = |x: f64| {
        if x <= d0 {
            K * x
        } else if x <= df {
            N * (df - x) / (df - d0)
        } else {
            0.0
        }
    };
    if d >= dmax || dmax <= d0 {
        virgin(d)
    } else {
        virgin(dmax) / dmax * d.max(0.0)
    }
}

/// Every converged point lies on the exact path: with the opening
/// `delta = Delta - P L / (E A)`, `P = t(delta)` to 1e-6 N (1e-6 of the
/// strength).
fn check_on_path(rows: &[Row]) {
    let mut dmax: f64 = 0.0;
    for r in rows {
        let d = r.delta - r.p * L_OVER_EA;
        let t = traction(d, dmax);
        assert!(
            (r.p - t).abs() < 1e-6 * N,
            "increment {}: P = {:.9e}, exact {:.9e} at opening {d:.6e}",
            r.increment,
            r.p,
            t
        );
        dmax = dmax.max(d);
    }
}

#[test]
fn arc_length_traces_the_snap_back_of_a_bar_on_a_cohesive_point() {
    let dir = tempfile::tempdir().unwrap();
    let s = run_ok(&scene(), dir.path());
    let rows = rows(dir.path());
    check_on_path(&rows);
    // the snap-back itself: load and displacement fall together, and the
    // run follows it in several increments
    let back: Vec<&Row> = rows
        .windows(2)
        .filter(|w| w[1].delta < w[0].delta - 1e-9 && w[1].p < w[0].p && w[1].p > 1e-9)
        .map(|w| &w[1])
        .collect();
    assert!(back.len() >= 5, "only {} snap-back increments", back.len());
    // peak within 1 % of the strength N A = 1 N (the path passes near it)
    let peak = rows.iter().map(|r| r.p).fold(0.0, f64::max);
    assert!(peak > 0.99 * N && peak <= N + 1e-9, "peak {peak}");
    // the whole fracture energy G A is dissipated, no more
    let last = rows.last().unwrap();
    assert!(
        (last.dissipated - G).abs() < 1e-9,
        "dissipated {}",
        last.dissipated
    );
    // inertia: zero on the rising elastic branch; one negative pivot on the
    // snap-back, where the equilibrium under displacement control is
    // unstable (the softening interface is stiffer in magnitude than the
    // bar: 52.6 > 10 N/mm)
    for r in rows.iter().filter(|r| r.dissipated == 0.0) {
        assert_eq!(r.pivots, 0, "rising branch, increment {}", r.increment);
    }
    for r in &back {
        assert_eq!(r.pivots, 1, "snap-back, increment {}", r.increment);
        assert_eq!(r.control, "dissipation");
    }
    // the summary lists the load maximum and the displacement turning point
    let lp = &s["limit_points"]["counts"];
    assert!(lp["load_maximum"].as_u64().unwrap() >= 1, "{s}");
    assert!(lp["displacement_maximum"].as_u64().unwrap() >= 1, "{s}");
    assert!(lp["stability_change"].as_u64().unwrap() >= 1, "{s}");
    assert_eq!(s["control"], "arc_length");
}

#[test]
fn arc_length_under_force_control_dissipates_the_whole_fracture_energy() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(scene())
        .unwrap()
        .replace("displacement = { z = 0.2 }\n", "")
        .replace(
            "[analysis]\n",
            // one H8 face: the consistent split is 1/4 per node, as the equal one
            "[[load]]\nset = \"bar.z1\"\ntotal_force = [0.0, 0.0, 1.2]\nsplit = \"consistent\"\n\n[analysis]\n",
        );
    let file = dir.path().join("force.toml");
    std::fs::write(&file, text).unwrap();
    let out = dir.path().join("out");
    let s = run_ok(&file, &out);
    assert!(
        s["status"].as_str().unwrap().contains("fell back to zero"),
        "{}",
        s["status"]
    );
    let rows = rows(&out);
    // reaction column is the support-free top: use the applied load 1.2 lambda
    let rows: Vec<Row> = rows
        .into_iter()
        .map(|mut r| {
            r.p = 1.2 * r.lambda;
            r
        })
        .collect();
    check_on_path(&rows);
    let back = rows
        .windows(2)
        .filter(|w| w[1].delta < w[0].delta && w[1].p < w[0].p)
        .count();
    assert!(back >= 5, "{back}");
    // energy balance at the end (the load has all but vanished): dissipated
    // + the energy still stored at the opening, ½ P delta (secant), = G A
    let last = rows.last().unwrap();
    let opening = last.delta - last.p * L_OVER_EA;
    let stored = 0.5 * last.p * opening;
    assert!(
        ((last.dissipated + stored) / G - 1.0).abs() < 1e-6,
        "dissipated {} + stored {stored}",
        last.dissipated
    );
    assert!(last.p < 1e-3 * N, "final load {}", last.p);
}

#[test]
fn load_control_stops_at_the_limit_point_and_names_the_remedy() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(scene())
        .unwrap()
        .replace("control = \"arc_length\"", "control = \"load\"");
    let file = dir.path().join("load.toml");
    std::fs::write(&file, text).unwrap();
    let out = junta()
        .arg("run")
        .arg(&file)
        .arg("-o")
        .arg(dir.path().join("out"))
        .arg("-q")
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("Limit point"), "{err}");
    assert!(err.contains("control = \"arc_length\""), "{err}");
    // the converged part is on the exact elastic path up to the peak
    let rows = rows(&dir.path().join("out"));
    check_on_path(&rows);
    let peak = rows.iter().map(|r| r.p).fold(0.0, f64::max);
    assert!(peak > 0.95 * N, "{peak}");
}

#[test]
fn restarted_arc_length_run_equals_the_uninterrupted_one() {
    let dir = tempfile::tempdir().unwrap();
    let full = dir.path().join("full");
    run_ok(&scene(), &full);
    restart_repeats(&scene(), &rows(&full), dir.path(), 6);
}

/// Stop `scene` after `stop` increments, restart it, and compare every
/// row with `full` (the uninterrupted run), wall time excepted.
fn restart_repeats(scene: &Path, full: &[Row], dir: &Path, stop: usize) {
    let part = dir.join("part");
    run_ok_with(scene, &part, &["--max-increments", &stop.to_string()]);
    restart_ok(&part);
    let b = rows(&part);
    assert_eq!(full.len(), b.len());
    for (x, y) in full.iter().zip(&b) {
        assert_eq!(x.raw, y.raw, "increment {}", x.increment);
    }
}

/// `examples/delamination/enf_snapback.toml` (ENF, a0 = 0.5 L, 1 mm H20
/// elements): the crack runs unstably and the arc length follows it.
/// Reference: beam theory (LEFM, BENCHMARKS.md section 4), the
/// propagation branch `P_c(a) = 4 b sqrt(E11 h^3 G_IIc) / (3 a)`,
/// `delta = P C(a)`, `C(a) = (3 a^3 + 2 L^3) / (8 E11 b h^3)`.
/// Measured (this mesh): peak 1085 N against 1212 N (the short crack's
/// cohesive zone and shear compliance lower it), snap-back from 3.68 to
/// 3.53 mm (LEFM 3.80 to 3.46 mm), propagation branch 1.1 to 2.1 % stiffer
/// in deflection than LEFM at the same load for a from 28 to 47 mm;
/// dissipated 1072.7 N mm against G_IIc x damaged area 1112 N mm.
#[test]
fn enf_snapback_follows_the_lefm_propagation_branch() {
    let (e11, b, h, g2, l) = (122700.0, 25.4, 1.56, 1.719, 50.0);
    let dir = tempfile::tempdir().unwrap();
    let scene = repo().join("examples/delamination/enf_snapback.toml");
    let s = run_ok(&scene, dir.path());
    assert!(
        s["status"].as_str().unwrap().starts_with("completed"),
        "{s}"
    );
    let rows = rows(dir.path());
    let ipk = (0..rows.len())
        .max_by(|&i, &j| rows[i].p.total_cmp(&rows[j].p))
        .unwrap();
    let (pk, dpk) = (rows[ipk].p, rows[ipk].delta);
    assert!(pk > 0.85 * 1212.2 && pk < 1212.2, "peak {pk}");
    // snap-back: after the peak the deflection decreases by > 0.1 mm
    let dmin = rows[ipk..].iter().map(|r| r.delta).fold(f64::MAX, f64::min);
    assert!(dpk - dmin > 0.1, "peak at {dpk}, minimum after it {dmin}");
    // the propagation branch against LEFM at the same load
    let comp = |a: f64| (3.0 * a * a * a + 2.0 * l * l * l) / (8.0 * e11 * b * h * h * h);
    let mut compared = 0;
    for r in &rows[ipk..] {
        let a = 4.0 * b * (e11 * h * h * h * g2).sqrt() / (3.0 * r.p);
        if a > 28.0 && a < 47.0 {
            let d_lefm = r.p * comp(a);
            let err = r.delta / d_lefm - 1.0;
            assert!(
                err.abs() < 0.03,
                "P = {} N: delta {} against LEFM {d_lefm}",
                r.p,
                r.delta
            );
            compared += 1;
        }
    }
    assert!(compared >= 10, "only {compared} points on the branch");
    // the crack reached the load point (a = L) before the end
    let last = rows.last().unwrap();
    // (the failed points: to within the mode II process zone of the load
    // point, measured 23.1 of the 25 mm)
    let area = s["interfaces"]["bond"]["damaged_area"].as_f64().unwrap();
    assert!(area / b > 0.9 * (l - 25.0), "crack growth {} mm", area / b);
    // dissipated energy = G_IIc x cracked area (the failed points), plus
    // what the process zone ahead has dissipated (measured +6.2 %)
    let zone = s["interfaces"]["bond"]["process_zone_area"]
        .as_f64()
        .unwrap_or(0.0);
    assert!(
        last.dissipated >= g2 * area * (1.0 - 1e-3) && last.dissipated <= g2 * (area + zone),
        "dissipated {} against G_IIc x area {}",
        last.dissipated,
        g2 * area
    );
    // unstable increments were met (negative pivots) and listed
    assert!(rows.iter().any(|r| r.pivots > 0));
    assert!(
        s["limit_points"]["counts"]["load_maximum"]
            .as_u64()
            .unwrap()
            >= 1
    );
}

/// `junta sweep control`: arc length follows the whole path; displacement
/// and load control stop at the load maximum (the strength N A = 1 N of the
/// closed form) and say why.
#[test]
fn sweep_control_charts_where_each_method_stops() {
    let dir = tempfile::tempdir().unwrap();
    let out = junta()
        .args(["sweep", "control"])
        .arg(scene())
        .arg("-o")
        .arg(dir.path())
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(dir.path().join("control_summary.csv")).unwrap();
    let lines: Vec<&str> = text.lines().skip(1).collect();
    assert_eq!(lines.len(), 3, "{text}");
    let line = |m: &str| *lines.iter().find(|l| l.starts_with(m)).unwrap();
    assert!(line("arc_length").contains("completed"), "{text}");
    for m in ["displacement", "load"] {
        let l = line(m);
        assert!(l.contains("Limit point"), "{l}");
        assert!(l.contains("arc_length"), "{l}");
    }
    // each stopped method got to the peak (within 1 % of N A = 1 N) and not
    // beyond it
    let curve = std::fs::read_to_string(dir.path().join("control.csv")).unwrap();
    for m in ["displacement", "load"] {
        let peak = curve
            .lines()
            .filter(|l| l.starts_with(&format!("{m},")))
            .map(|l| l.split(',').nth(3).unwrap().parse::<f64>().unwrap())
            .fold(0.0, f64::max);
        assert!(peak > 0.99 && peak < 1.0 + 1e-9, "{m}: {peak}");
    }
    let svg = std::fs::read_to_string(dir.path().join("control.svg")).unwrap();
    assert!(svg.contains("arc length") && svg.contains("where a method stopped"));
}

/// Corrected beam theory of the MMB (Reeder & Crews; BENCHMARKS.md section
/// 4): critical lever load at crack length `a` for lever `c` (mode I with
/// `a + chi h`, mode II with `a + 0.42 chi h`, BK toughness).
fn mmb_cbt(c: f64, a: f64) -> f64 {
    let (e11, e22, g13) = (122700.0_f64, 10100.0_f64, 5500.0_f64);
    let (gic, giic, eta) = (0.969_f64, 1.719_f64, 2.284_f64);
    let (b, h, l) = (25.4_f64, 1.56_f64, 51.0_f64);
    let gamma = 1.18 * (e11 * e22).sqrt() / g13;
    let chi = (e11 / (11.0 * g13) * (3.0 - 2.0 * (gamma / (1.0 + gamma)).powi(2))).sqrt();
    let (a1, a2) = (a + chi * h, a + 0.42 * chi * h);
    let den = b * b * h.powi(3) * l * l * e11;
    let g1 = 3.0 * (3.0 * c - l).powi(2) * a1 * a1 / (4.0 * den);
    let g2 = 9.0 * (c + l).powi(2) * a2 * a2 / (16.0 * den);
    let gc = gic + (giic - gic) * (g2 / (g1 + g2)).powf(eta);
    (gc / (g1 + g2)).sqrt()
}

/// Run an MMB scene with a short precrack for `increments` increments and
/// check it against corrected beam theory (lever `c`): the peak within
/// `peak_tol`, a snap-back of the lever's load point of more than
/// `snap_back` mm, then, with the crack grown by more than 3 mm and up to
/// `a_max`, the load within `branch_tol` of corrected beam theory at the
/// crack length read from the damaged area and the process zone
/// (`a0 + damaged_area / b + process_zone_length / 2`), at `points`
/// points or more.
/// Returns the largest crack length reached.
#[allow(clippy::too_many_arguments)]
fn mmb_snap_back(
    scene: &str,
    c: f64,
    increments: usize,
    peak_tol: f64,
    snap_back: f64,
    a_max: f64,
    branch_tol: f64,
    points: usize,
) -> f64 {
    let dir = tempfile::tempdir().unwrap();
    let scene = repo().join(scene);
    run_ok_with(
        &scene,
        dir.path(),
        &["--max-increments", &increments.to_string()],
    );
    // the crack length corrected beam theory reads lies inside the
    // process zone: the failed (traction-free) points' crack plus half the
    // process zone (measured: within -0.9 .. +0.5 % of CBT on the MMB80
    // branch, -3.1 .. -5.5 % at the failed points' crack alone, -2.3 ..
    // -9 % at the dissipated energy over the nominal G_c(B) b)
    let zone = load_displacement_column(dir.path(), "process_zone_length");
    let pts: Vec<(f64, f64, f64)> = load_displacement_area(dir.path())
        .into_iter()
        .zip(zone)
        .map(|((p, d, area), z)| (p, d, 20.4 + area / 25.4 + 0.5 * z.2.max(0.0)))
        .collect();
    // the first peak: before the crack has grown by 3 mm
    let ipk = (0..pts.len())
        .filter(|&i| pts[i].2 < 23.4)
        .max_by(|&i, &j| pts[i].0.total_cmp(&pts[j].0))
        .unwrap();
    let (pk, dpk, _) = pts[ipk];
    let cbt0 = mmb_cbt(c, 20.4);
    assert!(
        (pk / cbt0 - 1.0).abs() < peak_tol,
        "peak {pk} against {cbt0}"
    );
    let dmin = pts[ipk..].iter().map(|p| p.1).fold(f64::MAX, f64::min);
    assert!(dpk - dmin > snap_back, "snap-back {dpk} -> {dmin}");
    let mut n = 0;
    for &(p, _, a) in &pts[ipk..] {
        if a > 23.4 && a <= a_max {
            let cbt = mmb_cbt(c, a);
            assert!(
                (p / cbt - 1.0).abs() < branch_tol,
                "a = {a}: {p} against {cbt}"
            );
            n += 1;
        }
    }
    assert!(n >= points, "only {n} points past 3 mm of growth");
    pts.iter().map(|p| p.2).fold(0.0, f64::max)
}

/// `examples/delamination/mmb50_short.toml` (G_II/G_T = 0.5, a0 = 0.4 L, the lever
/// as its two forces): load control has no solution past the peak; the arc
/// length passes it and follows the lever's load point back (snap-back).
/// Measured (the lever forces split consistently over their load edges):
/// peak 398.3 N against corrected beam theory 409.9 N (-2.8 %); lever
/// displacement 5.10 mm at the peak, down to 4.92 mm (beam theory 5.32 to
/// 4.86 mm); past the snap-back the load is within 2 % of corrected beam
/// theory at the crack length of the failed points plus half the process
/// zone (within 2 %). (With
/// `split = "equal"`: 388.3 N, 5.36 mm down to 5.17 mm.)
#[test]
fn mmb50_snap_back_against_corrected_beam_theory() {
    mmb_snap_back(
        "examples/delamination/mmb50_short.toml",
        44.596,
        32,
        0.08,
        0.1,
        f64::INFINITY,
        0.03,
        3,
    );
}

/// `examples/delamination/mmb80_short.toml` (G_II/G_T = 0.8, a0 = 0.4 L)
/// with the exact, nonsymmetric mixed-mode tangent (`tangent = "exact"`,
/// solved by `lu`): traced through the whole snap-back to the mid-span.
/// Measured: peak 673.0 N against corrected beam theory 716.4 N (-6.1 %),
/// lever displacement 5.48 mm at the peak, down to 4.89 mm (beam theory
/// 5.91 to 4.92 mm), then within -1.2 to -0.2 % of corrected beam theory
/// from a = 23.4 to 49.4 mm (-0.9 .. +0.5 % at the failed crack plus half
/// the process zone), the mid-span reached at increment 40. (With
/// `split = "equal"`: 649.6 N, -9.3 %, 5.61 mm down to 5.08 mm.)
/// With the symmetric part of the tangent the same run stagnated at
/// a = 30.5 mm.
#[test]
fn mmb80_traced_through_the_snap_back_with_the_exact_tangent() {
    let a_end = mmb_snap_back(
        "examples/delamination/mmb80_short.toml",
        28.471,
        40,
        0.11,
        0.3,
        50.0,
        0.025,
        20,
    );
    assert!(a_end > 49.0, "the crack stopped at a = {a_end}");
}

/// Bad path-following input is refused by `junta check` (and `run`) with the
/// file and the key, before anything is solved.
#[test]
fn bad_path_following_input_names_the_key() {
    let dir = tempfile::tempdir().unwrap();
    let base = std::fs::read_to_string(scene()).unwrap();
    let cases = [
        (
            base.replace("steps = [1.0]", "steps = [1.0, 0.0]"),
            "analysis.steps",
        ),
        (
            base.replace("control = \"arc_length\"", "control = \"arclength\""),
            "arc_length",
        ),
        (
            base.replace(
                "[analysis.newton]",
                "[analysis.arc_length]\ntarget_iterations = 0\n\n[analysis.newton]",
            ),
            "analysis.arc_length",
        ),
        (
            base.replace(
                "[analysis.newton]",
                "[analysis.arc_length]\nmax_arc_dissipation = 1e-9\n\n[analysis.newton]",
            ),
            "max_arc_dissipation",
        ),
    ];
    for (i, (text, key)) in cases.iter().enumerate() {
        let file = dir.path().join(format!("bad{i}.toml"));
        std::fs::write(&file, text).unwrap();
        let out = junta().arg("check").arg(&file).output().unwrap();
        assert!(!out.status.success(), "case {i} accepted");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            err.contains(&format!("bad{i}.toml")) && err.contains(key),
            "case {i}: {err}"
        );
        assert!(!err.contains("panicked"));
    }
}

/// `examples/delamination/mmb20.toml`, `mmb50.toml`, `mmb80.toml`: mixed-mode
/// bending of the DCB specimen (a0 = 32.9 mm) at G_II/G_T = 0.2, 0.5, 0.8,
/// the lever as its two forces. Load control stops at the load maximum;
/// the arc length passes it. Peak against corrected beam theory (BK):
/// measured 92.1 / 258.7 / 436.9 N against 92.2 / 263.7 / 457.4 N
/// (-0.2, -1.9, -4.5 %); past the peak the load follows beam theory at the
/// crack length read from the damaged area.
#[test]
fn mmb_peaks_against_corrected_beam_theory() {
    for (pct, c, tol) in [(20, 109.890, 0.02), (50, 44.596, 0.03), (80, 28.471, 0.06)] {
        let dir = tempfile::tempdir().unwrap();
        let scene = repo().join(format!("examples/delamination/mmb{pct}.toml"));
        run_ok_with(&scene, dir.path(), &["--max-increments", "20"]);
        let text = std::fs::read_to_string(dir.path().join("curve.csv")).unwrap();
        let mut lines = text.lines();
        let head: Vec<&str> = lines.next().unwrap().split(',').collect();
        let col = |n: &str| head.iter().position(|h| *h == n).unwrap();
        let (cp, ca) = (col("reaction"), col("damaged_area"));
        let pts: Vec<(f64, f64)> = lines
            .map(|l| {
                let f: Vec<f64> = l
                    .split(',')
                    .map(|v| v.parse().unwrap_or(f64::NAN))
                    .collect();
                (f[cp], 32.9 + f[ca] / 25.4)
            })
            .collect();
        let ipk = (0..pts.len())
            .max_by(|&i, &j| pts[i].0.total_cmp(&pts[j].0))
            .unwrap();
        let cbt = mmb_cbt(c, 32.9);
        assert!(
            (pts[ipk].0 / cbt - 1.0).abs() < tol,
            "MMB{pct}: peak {} against {cbt}",
            pts[ipk].0
        );
        // the arc length went past the maximum: the load falls after it
        assert!(
            pts.len() > ipk + 3 && pts.last().unwrap().0 < 0.99 * pts[ipk].0,
            "MMB{pct}: no descending branch: {pts:?}"
        );
        for &(p, a) in &pts[ipk..] {
            if a > 34.9 {
                let b = mmb_cbt(c, a);
                assert!(
                    (p / b - 1.0).abs() < tol,
                    "MMB{pct} a = {a}: {p} against {b}"
                );
            }
        }
    }
}

/// `examples/delamination/dcb_arc.toml`: the DCB of dcb.toml traced by
/// path following without viscosity, full curve to 10 mm. Corrected beam
/// theory (BENCHMARKS.md section 4): peak 138.5 N at 4.21 mm, propagation
/// P(delta) = (G_Ic b)^(3/4) (E11 I)^(1/4) sqrt(2 / (3 delta)).
/// Measured: peak 137.0 N; +1.0 % at 5.94 mm, +0.1 % at 7.96 mm, -0.2 % at
/// 10 mm; 60 increments.
#[test]
fn dcb_by_arc_length_follows_corrected_beam_theory_without_viscosity() {
    let (gic, b, e11, h): (f64, f64, f64, f64) = (0.969, 25.4, 122700.0, 1.56);
    let ei = e11 * b * h.powi(3) / 12.0;
    let p_cbt = |d: f64| (gic * b).powf(0.75) * ei.powf(0.25) * (2.0 / (3.0 * d)).sqrt();
    let dir = tempfile::tempdir().unwrap();
    let scene = repo().join("examples/delamination/dcb_arc.toml");
    let s = run_ok(&scene, dir.path());
    assert!(
        s["status"].as_str().unwrap().starts_with("completed"),
        "{s}"
    );
    let rows = rows(dir.path());
    let peak = rows.iter().map(|r| r.p).fold(0.0, f64::max);
    assert!((peak / 138.51 - 1.0).abs() < 0.02, "peak {peak}");
    let mut checked = 0;
    for r in rows.iter().filter(|r| r.delta > 5.5) {
        // past the peak's process zone: the propagation branch
        let e = r.p / p_cbt(r.delta) - 1.0;
        assert!(
            e.abs() < 0.025,
            "P({}) = {} against {}",
            r.delta,
            r.p,
            p_cbt(r.delta)
        );
        checked += 1;
    }
    assert!(checked >= 10, "{checked}");
    let last = rows.last().unwrap();
    assert!((last.delta - 10.0).abs() < 1e-9);
    let bond = &s["interfaces"]["bond"];
    assert_eq!(bond["viscous_energy"].as_f64(), Some(0.0));
    // fracture energy: G_Ic per unit of cracked area, no more
    let (w, area) = (
        bond["dissipated_energy"].as_f64().unwrap(),
        bond["damaged_area"].as_f64().unwrap() + bond["process_zone_area"].as_f64().unwrap(),
    );
    assert!(w <= gic * area && w > 0.9 * gic * bond["damaged_area"].as_f64().unwrap());
}

/// `predictor = "secant"` (start each dissipation-controlled increment from
/// the last one, extrapolated): every converged point still lies on the
/// closed-form path of the snap-back bar, the whole fracture energy is
/// dissipated, it takes no more iterations than the default start, and a
/// restarted run (the last dissipation step is in the checkpoint) repeats
/// the uninterrupted one.
#[test]
fn secant_predictor_stays_on_the_exact_path_and_restarts() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(scene()).unwrap();
    let secant = write(
        dir.path(),
        "secant.toml",
        &format!("{text}\n[analysis.arc_length]\npredictor = \"secant\"\n"),
    );
    let full = dir.path().join("full");
    let s = run_ok(&secant, &full);
    let rs = rows(&full);
    check_on_path(&rs);
    let last = rs.last().unwrap();
    assert!(
        (last.dissipated - G).abs() < 1e-9,
        "dissipated {}",
        last.dissipated
    );
    let tangent = dir.path().join("tangent");
    let t = run_ok(&scene(), &tangent);
    let its = |s: &serde_json::Value| s["newton_iterations"]["total"].as_u64().unwrap();
    assert!(
        its(&s) <= its(&t),
        "secant {} against tangent {}",
        its(&s),
        its(&t)
    );
    // restart from the middle of the softening branch
    restart_repeats(&secant, &rs, dir.path(), rs.len() / 2);
}

/// `(reaction, displacement, damaged area)` of every row of curve.csv.
/// `(reaction, displacement, damaged_area)` of every row of curve.csv.
fn load_displacement_area(dir: &Path) -> Vec<(f64, f64, f64)> {
    load_displacement_column(dir, "damaged_area")
}

/// `(reaction, displacement, column)` of every row of curve.csv.
fn load_displacement_column(dir: &Path, column: &str) -> Vec<(f64, f64, f64)> {
    let text = std::fs::read_to_string(dir.join("curve.csv")).unwrap();
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |n: &str| head.iter().position(|h| *h == n).unwrap();
    let (cp, cd, ca) = (col("reaction"), col("displacement"), col(column));
    lines
        .map(|l| {
            let f: Vec<f64> = l
                .split(',')
                .map(|v| v.parse().unwrap_or(f64::NAN))
                .collect();
            (f[cp], f[cd], f[ca])
        })
        .collect()
}

/// The peak of a curve.csv: `(load, lever displacement)` at the largest
/// load, and the first point `(load, displacement)` (elastic: no damage).
fn mmb_peak_and_first(dir: &Path) -> ((f64, f64), (f64, f64)) {
    let pts = load_displacement_area(dir);
    assert_eq!(pts[0].2, 0.0, "the first increment is elastic");
    let pk = pts
        .iter()
        .copied()
        .max_by(|a, b| a.0.total_cmp(&b.0))
        .unwrap();
    ((pk.0, pk.1), (pts[0].0, pts[0].1))
}

/// `examples/delamination/mmb50.toml` (a0 = 32.9 mm) with the lever
/// forces split consistently over their load edges (1/6, 2/3, 1/6 of each,
/// the scene as written) and equally (1/3 each, `split = "equal"`). The
/// equal split puts more of each force on the specimen's sides: a local
/// compliance at the load points, which the elastic first increment
/// measures (C = delta / P, 4 % more). The peak, which the crack front 33
/// mm from the lever's end decides, is the same (within 0.5 %), and the
/// lever displacement at the peak differs by that local compliance times
/// the peak load (within 10 %), the consistent one smaller.
/// Measured: peaks 258.7 / 259.1 N at 5.16 / 5.37 mm; C = 0.01915 /
/// 0.01994 mm/N, (C_eq - C_cons) P = 0.204 mm against 0.208 mm.
#[test]
fn mmb_lever_displacement_loses_the_equal_splits_local_compliance() {
    let scene = repo().join("examples/delamination/mmb50.toml");
    let text = std::fs::read_to_string(&scene).unwrap();
    assert_eq!(text.matches("split = \"consistent\"").count(), 2);
    let dir = tempfile::tempdir().unwrap();
    let equal = dir.path().join("mmb50_equal.toml");
    std::fs::write(
        &equal,
        text.replace("split = \"consistent\"", "split = \"equal\"")
            .replace(
                "file = \"mmb50_beam_theory.csv\"",
                &format!(
                    "file = {:?}",
                    scene
                        .with_file_name("mmb50_beam_theory.csv")
                        .display()
                        .to_string()
                ),
            ),
    )
    .unwrap();
    let (out_c, out_e) = (dir.path().join("c"), dir.path().join("e"));
    run_ok_with(&scene, &out_c, &["--max-increments", "20"]);
    run_ok_with(&equal, &out_e, &["--max-increments", "20"]);
    let ((pc, dc), (p1c, d1c)) = mmb_peak_and_first(&out_c);
    let ((pe, de), (p1e, d1e)) = mmb_peak_and_first(&out_e);
    let (cc, ce) = (d1c / p1c, d1e / p1e);
    assert!(ce / cc > 1.02, "compliance {ce} (equal) against {cc}");
    assert!(
        (pc / pe - 1.0).abs() < 0.005,
        "peaks {pc} (consistent) and {pe} (equal)"
    );
    let drop = de - dc;
    let local = (ce - cc) * pc;
    assert!(
        drop > 0.0,
        "displacement at the peak {dc} (consistent) against {de}"
    );
    assert!(
        (drop / local - 1.0).abs() < 0.1,
        "drop {drop} against (C_eq - C_cons) P = {local}"
    );
}
