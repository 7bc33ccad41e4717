//! Peel tests under large deformation (`[analysis] nlgeom = true`): a
//! stiff elastic tape peeled from a rigid substrate by a dead force at 90
//! and 45 degrees, against Kendall's steady state (Kendall 1975, J. Phys.
//! D 8, 1449):
//!
//! ```text
//! G_c = (P/b)(1 - cos theta) + (P/b)^2 / (2 E h)
//! ```
//!
//! The scenes are those of `examples/large_deformation/peel90.toml` and
//! `peel45.toml` (their headers give the set-up): a tape (H8I, one element
//! through its thickness and across its width) bonded by a bilinear law
//! with `G_Ic = G_IIc` to a substrate whose nodes are all fixed, a free
//! tab pulled by a dead force with its x displacement free, so that the
//! peeled arm lines up with the force. The examples (20 mm tab, 30 mm
//! bond) are the `#[ignore]`d test; the default suite runs the same tape
//! on a 12 mm tab and bond (90 degrees) and an 8 mm tab and bond (45),
//! whose plateaus are the examples' to 0.15 %.

mod common;
use common::*;
use std::path::Path;

/// Kendall's steady peel force per width `P/b` at angle `theta` (degrees)
/// for toughness `gc` and membrane stiffness `eh = E h`: the positive root
/// of `p (1 - cos theta) + p^2 / (2 E h) = G_c`.
fn kendall(theta: f64, gc: f64, eh: f64) -> f64 {
    // the root in the form without cancellation for a stiff tape
    let (a, b) = (1.0 / (2.0 * eh), 1.0 - theta.to_radians().cos());
    2.0 * gc / (b + (b * b + 4.0 * a * gc).sqrt())
}

/// The tape: E = 20 GPa, h = 0.2 mm, b = 1 mm (N, mm); the bond's G_c.
const E: f64 = 20000.0;
const H: f64 = 0.2;
const B: f64 = 1.0;
const GC: f64 = 1.0;

/// The peel scene of the examples with a tab of `tab` mm (`tab` elements)
/// and a bond of `bond` mm (2 `bond` elements), the force at `theta`
/// degrees from the peeled side: `P0 (-cos theta, 0, sin theta)`,
/// `P0 = G_c b / (1 - cos theta)` per unit load factor.
fn scene(theta: f64, nlgeom: bool, tab: f64, bond: f64) -> String {
    let p0 = GC * B / (1.0 - theta.to_radians().cos());
    let (fx, fz) = (
        -p0 * theta.to_radians().cos(),
        p0 * theta.to_radians().sin(),
    );
    let (ntab, nbond) = (tab.round() as usize, (2.0 * bond).round() as usize);
    format!(
        r#"
[materials.tape]
type = "isotropic"
E = {E}
nu = 0.0
[laws.glue]
type = "bilinear"
K = 5.0e6
N = 3.0
S = 3.0
G_Ic = {GC}
G_IIc = {GC}
eta = 2.0
[mesh]
type = "boxes"
[[mesh.boxes]]
name = "tab"
group = "tape"
size = [{tab}, {B}, {H}]
divisions = [{ntab}, 1, 1]
element = "h8i"
material = "tape"
[[mesh.boxes]]
name = "bonded"
group = "tape"
origin = [{tab}, 0.0, 0.0]
size = [{bond}, {B}, {H}]
divisions = [{nbond}, 1, 1]
element = "h8i"
material = "tape"
[[mesh.boxes]]
name = "substrate"
origin = [{tab}, 0.0, -{H}]
size = [{bond}, {B}, {H}]
divisions = [{nbond}, 1, 1]
element = "h8"
material = "tape"
[[interface]]
name = "bond"
between = ["substrate", "tape"]
law = "glue"
[[boundary]]
set = "substrate.z0"
fixed = "all"
[[boundary]]
set = "bond.bottom"
fixed = "all"
[[load]]
set = "tab.x0"
total_force = [{fx}, 0.0, {fz}]
[analysis]
type = "static"
nlgeom = {nlgeom}
steps = [1.5]
stop_when_separated = true
[analysis.newton]
initial_increment = 0.02
max_increment = 0.05
[output]
vtu = false
curve = {{ reaction_set = "tab.x0", reaction_component = "z", point_set = "tab.x0", point_component = "z" }}
"#
    )
}

/// One row of `curve.csv`.
struct Row {
    lambda: f64,
    dissipated: f64,
    damaged: f64,
    control: String,
    /// `f_ext . u`: the load factor's work-conjugate displacement.
    conjugate: f64,
    /// Far end of the process zone from the bond's start, `crack_front +
    /// process_zone_length` (NaN before the first failed point).
    zone_end: f64,
}

fn curve(dir: &Path) -> Vec<Row> {
    let text = std::fs::read_to_string(dir.join("curve.csv")).unwrap();
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| head.iter().position(|h| *h == name).unwrap();
    let (l, d, a, c, w) = (
        col("load_factor"),
        col("dissipated_energy"),
        col("damaged_area"),
        col("control"),
        col("conjugate_displacement"),
    );
    let (f, z) = (col("crack_front"), col("process_zone_length"));
    lines
        .map(|row| {
            let v: Vec<&str> = row.split(',').collect();
            Row {
                lambda: v[l].parse().unwrap(),
                dissipated: v[d].parse().unwrap(),
                damaged: v[a].parse().unwrap(),
                control: v[c].to_string(),
                conjugate: v[w].parse().unwrap(),
                zone_end: v[f].parse::<f64>().unwrap_or(f64::NAN)
                    + v[z].parse::<f64>().unwrap_or(f64::NAN),
            }
        })
        .collect()
}

/// The steady part of a peel: the increments where the front advances
/// (the dissipated energy D grows) with the peeled length `D / (G_c b)`
/// between `from` and `to` (fractions of the bond `bond`, leaving out the
/// start and the end of the bond). Not `damaged_area`: the failed
/// points (traction-free, all of G_c dissipated) lag the energy front by
/// the part of the process zone that has already dissipated energy
/// (K = 5e6, N = 3: onset at 6e-7 mm, failure at 0.67 mm).
/// Returned: their `P/b` (`P0 lambda / b`), the dissipated
/// energy per damaged area over that part, and the work of the load over
/// it (trapezoids of `lambda` against `f_ext . u`) per dissipated energy.
fn steady(rows: &[Row], p0: f64, bond: f64, from: f64, to: f64) -> (Vec<f64>, f64, f64) {
    let mut p = Vec::new();
    let (mut first, mut last) = (None, None);
    for (i, w) in rows.windows(2).enumerate() {
        let length = w[1].dissipated / (GC * B);
        // and the process zone clear of the bond's end (the last row of
        // points, still softening, while the load falls: past the old stop
        // at "every point failed", which came before the zone reached the
        // end when a point counted as failed at secant damage 0.99)
        let clear = !(w[1].zone_end > bond - 0.5);
        if w[1].dissipated > w[0].dissipated
            && length >= from * bond
            && length <= to * bond
            && clear
        {
            p.push(p0 * w[1].lambda / B);
            first.get_or_insert(i + 1);
            last = Some(i + 1);
        }
    }
    let (i0, i1) = (first.unwrap(), last.unwrap());
    let work: f64 = rows[i0..=i1]
        .windows(2)
        .map(|w| 0.5 * (w[0].lambda + w[1].lambda) * (w[1].conjugate - w[0].conjugate))
        .sum();
    let (r0, r1) = (&rows[i0], &rows[i1]);
    let dissipated = r1.dissipated - r0.dissipated;
    (p, dissipated / (r1.damaged - r0.damaged), work / dissipated)
}

/// Run the peel at `theta` (scene text) and return its steady part's
/// `P/b` against Kendall's: (mean, lowest, highest) relative deviation,
/// the number of steady increments, `G` (dissipated energy per damaged
/// area) and the load's work per dissipated energy over that part.
fn peel(
    dir: &Path,
    name: &str,
    text: &str,
    theta: f64,
    bond: f64,
) -> ((f64, f64, f64), usize, f64, f64) {
    let input = write(dir, &format!("{name}.toml"), text);
    let out = dir.join(name);
    let run = junta()
        .arg("run")
        .arg(&input)
        .arg("-o")
        .arg(&out)
        .arg("-q")
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&run.stderr).into_owned();
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let rows = curve(&out);
    // the bond comes apart: every point failed, or the last row, still in
    // its process zone, holds no load any more (a failed point has
    // dissipated all of G_c; the last one's traction need not reach zero
    // before the load factor does), or the run stops at a limit point
    // while the last rows of the bond soften, past the steady part (peel90:
    // at increment 307; before a point had to dissipate all of G_c to
    // count as failed, the run stopped as "separated" before that end)
    let status = s["status"].as_str().unwrap_or("");
    let peeled = rows.last().unwrap().dissipated / (GC * B);
    assert!(
        status == "stopped: every interface point has failed"
            || status.starts_with("completed: the load factor fell back to zero")
            || (!run.status.success() && err.contains("Limit point") && peeled > 0.8 * bond),
        "{name}: {status}, peeled {peeled} of {bond}\n{err}"
    );
    let nlgeom = text.contains("nlgeom = true");
    if nlgeom {
        // under nlgeom the peel front is followed by the dissipation
        // constraint on the interfaces' energy balance (issue 37 item 2;
        // before it path following stayed on the cylindrical arc length)
        assert!(
            rows.iter().any(|r| r.control == "dissipation"),
            "{name}: no dissipation-controlled increment under nlgeom"
        );
    }
    let p0 = GC * B / (1.0 - theta.to_radians().cos());
    let (p, g, balance) = steady(&rows, p0, bond, 0.2, 0.8);
    let k = kendall(theta, GC, E * H);
    let dev: Vec<f64> = p.iter().map(|x| x / k - 1.0).collect();
    let mean = dev.iter().sum::<f64>() / dev.len() as f64;
    let lo = dev.iter().cloned().fold(f64::INFINITY, f64::min);
    let hi = dev.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
    eprintln!(
        "{name}: Kendall P/b = {k:.5}; steady part ({} increments): mean P/b {:.5}, {:+.2} %, {:+.2} .. {:+.2} %; G = {g:.4}; work / dissipation = {balance:.4}",
        p.len(),
        k * (1.0 + mean),
        100.0 * mean,
        100.0 * lo,
        100.0 * hi
    );
    ((mean, lo, hi), p.len(), g, balance)
}

/// The closed form itself: at 90 degrees P/b -> G_c as E h -> infinity,
/// the stretch term's share, and the root satisfying the balance.
#[test]
fn kendall_closed_form() {
    assert!((kendall(90.0, 1.0, 1e12) - 1.0).abs() < 1e-9);
    assert!((kendall(45.0, 1.0, 1e12) - 1.0 / (1.0 - 0.5f64.sqrt())).abs() < 1e-6);
    for theta in [45.0, 90.0] {
        let p = kendall(theta, GC, E * H);
        let g = p * (1.0 - f64::to_radians(theta).cos()) + p * p / (2.0 * E * H);
        assert!((g - GC).abs() < 1e-12, "{theta}: {g}");
    }
    // the figures quoted in the examples' headers
    assert!((kendall(90.0, GC, E * H) - 0.999875).abs() < 1e-6);
    assert!((kendall(45.0, GC, E * H) - 3.409253).abs() < 1e-6);
}

/// 90 degrees, the default suite's tape (12 mm tab, 12 mm bond): over the
/// steady part (peeled length 2.4 to 9.6 mm) the peel force is Kendall's
/// within 3 % at every increment and within 1 % on average, and the load's
/// work over that part equals the energy the interfaces dissipate (2 %;
/// before the energies were integrated over the reference area, a peeled
/// point's energy read 1/sqrt(2) of its own and this ratio 1.4). Measured:
/// mean -0.12 %, -2.5 .. +2.6 % (the saw-tooth of 0.5 mm elements against
/// a ~2 mm cohesive zone), work / dissipation 0.997.
#[test]
fn peel_90_degrees_plateau_is_kendalls() {
    let tmp = tempfile::tempdir().unwrap();
    let ((mean, lo, hi), n, _, balance) = peel(
        tmp.path(),
        "peel90",
        &scene(90.0, true, 12.0, 12.0),
        90.0,
        12.0,
    );
    assert!(n >= 40, "only {n} steady increments");
    assert!(mean.abs() < 0.01, "mean {mean:+.4}");
    assert!(lo > -0.03 && hi < 0.03, "{lo:+.4} .. {hi:+.4}");
    assert!((balance - 1.0).abs() < 0.02, "work / dissipation {balance}");
}

/// 45 degrees, same tape on an 8 mm tab and an 8 mm bond (the arm is
/// under 3.4 N: its bending length is 2 mm): P/b = 3.409 (Kendall, with
/// the stretch term), within 3 % at every steady increment and 1 % on
/// average, the load's work = the dissipated energy (2 %). Measured: mean
/// +0.00 %, -1.65 .. +1.28 %, work / dissipation 0.998 under the
/// dissipation constraint on the interfaces' balance (on the cylindrical
/// arc length before it: -0.08 %, -1.8 .. +1.3 %, 1.0007).
#[test]
fn peel_45_degrees_plateau_is_kendalls() {
    let tmp = tempfile::tempdir().unwrap();
    let ((mean, lo, hi), n, _, balance) = peel(
        tmp.path(),
        "peel45",
        &scene(45.0, true, 8.0, 8.0),
        45.0,
        8.0,
    );
    assert!(n >= 30, "only {n} steady increments");
    assert!(mean.abs() < 0.01, "mean {mean:+.4}");
    assert!(lo > -0.03 && hi < 0.03, "{lo:+.4} .. {hi:+.4}");
    assert!((balance - 1.0).abs() < 0.02, "work / dissipation {balance}");
}

/// The same 90-degree scene under small strain (`nlgeom = false`) cannot
/// peel at 90 degrees: the tab's swing reads as strain and it peels as a
/// linear cantilever of free length a, `P = sqrt(2 E I G_c b) / a`, far
/// below Kendall and falling as the crack grows: the test asks for the
/// mean 50 % and every steady increment 30 % below Kendall, and for the
/// cantilever within 10 % (below it: the bond's compliance at the root
/// lengthens the cantilever). Measured (12 mm tab and bond): P/b 0.276 on
/// average, -72 % (-77 .. -66 %) from Kendall; -7.8 .. -4.0 % from the
/// cantilever (the example's 30 mm bond: -85 %, and -5.4 .. -1.3 %).
#[test]
fn peel_90_degrees_under_small_strain_is_far_from_kendall() {
    let tmp = tempfile::tempdir().unwrap();
    let ((mean, _, hi), _, _, _) = peel(
        tmp.path(),
        "small90",
        &scene(90.0, false, 12.0, 12.0),
        90.0,
        12.0,
    );
    assert!(
        mean < -0.5 && hi < -0.3,
        "mean {mean:+.4}, highest {hi:+.4}"
    );
    // against the linear cantilever (Euler-Bernoulli, G = P^2 a^2 / (2 E I b),
    // clamped at the front): a = tab + peeled length D / (G_c b)
    let ei = E * B * H.powi(3) / 12.0;
    let rows = curve(&tmp.path().join("small90"));
    let mut devs = Vec::new();
    for w in rows.windows(2) {
        let peeled = w[1].dissipated / (GC * B);
        if w[1].dissipated > w[0].dissipated && (2.4..=9.6).contains(&peeled) {
            let cantilever = (2.0 * ei * GC * B).sqrt() / (12.0 + peeled);
            devs.push(w[1].lambda / cantilever - 1.0);
        }
    }
    let lo = devs.iter().cloned().fold(f64::INFINITY, f64::min);
    let hi = devs.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
    eprintln!("small90 against the linear cantilever: {lo:+.4} .. {hi:+.4}");
    assert!(lo > -0.1 && hi < 0.0, "{lo:+.4} .. {hi:+.4}");
}

/// `junta check` on the examples (the penalty advisor evaluates the H8I
/// solids under nlgeom, which keep their incompatible modes as state: it
/// used to panic on an empty committed state) gives the cohesive-zone
/// advice.
#[test]
fn check_of_the_peel_examples_gives_the_cohesive_zone_advice() {
    for f in ["peel90.toml", "peel45.toml"] {
        let path = repo().join("examples/large_deformation").join(f);
        let out = junta().arg("check").arg(&path).output().unwrap();
        let text = String::from_utf8_lossy(&out.stdout).to_string()
            + &String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{f}: {text}");
        assert!(
            text.contains("mesh advice: interface `bond`") && text.contains("adequate"),
            "{f}: {text}"
        );
        assert!(
            text.contains("penalty advisor: interface `bond`"),
            "{f}: {text}"
        );
    }
}

/// The examples (20 mm tab, 30 mm bond, peeled length from 6 to 24 mm):
/// the same bounds, and G = dissipated energy per damaged area within 3 %
/// (the damaged area moves in steps of 0.25 mm^2, one row of points).
/// Measured: 90 degrees mean -0.19 %, -2.5 .. +2.6 %, G 0.995, work /
/// dissipation 0.999; 45 degrees mean +0.06 %, -1.8 .. +1.3 %, G 0.997,
/// 1.0006. [ignored: 106 s and 83 s in a release build; run with `cargo
/// test --release -p junta-cli --test peel -- --ignored`]
#[test]
#[ignore]
fn peel_examples_plateaus_are_kendalls() {
    let tmp = tempfile::tempdir().unwrap();
    for (f, theta) in [("peel90.toml", 90.0), ("peel45.toml", 45.0)] {
        let text = std::fs::read_to_string(repo().join("examples/large_deformation").join(f))
            .unwrap()
            .replace("[output]\n", "[output]\nvtu = false\n");
        let ((mean, lo, hi), n, g, balance) = peel(tmp.path(), f, &text, theta, 30.0);
        assert!(n >= 100, "{f}: only {n} steady increments");
        assert!(mean.abs() < 0.01, "{f}: mean {mean:+.4}");
        assert!(lo > -0.03 && hi < 0.03, "{f}: {lo:+.4} .. {hi:+.4}");
        assert!((g / GC - 1.0).abs() < 0.03, "{f}: G = {g}");
        assert!(
            (balance - 1.0).abs() < 0.02,
            "{f}: work / dissipation {balance}"
        );
    }
}
