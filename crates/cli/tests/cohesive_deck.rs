//! Abaqus cohesive decks run as is: the DCB deck
//! (examples/delamination/dcb_abaqus.inp, C3D8 + COH3D8 with *DAMAGE
//! keywords) against its twin TOML scene (dcb_h8.toml, the same mesh built
//! by the box generator, the same `bilinear` law), both written by
//! examples/delamination/make_dcb_deck.py.
//!
//! The runs stop at delta = 3 mm, before the peak (about 4.4 mm), where the
//! tangent is positive definite: they force `cholesky` (the `auto` choice
//! for a softening law is `ldlt`, which gives the same answer there).

mod common;
use common::*;
use std::path::Path;

/// `(load factor, reaction, displacement)` of every row of curve.csv.
fn curve(dir: &Path) -> Vec<[f64; 3]> {
    let text = std::fs::read_to_string(dir.join("curve.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let (l, r, d) = (col("load_factor"), col("reaction"), col("displacement"));
    lines
        .map(|line| {
            let f: Vec<&str> = line.split(',').collect();
            [l, r, d].map(|k| f[k].parse::<f64>().unwrap())
        })
        .collect()
}

fn run_incremental(input: &Path, dir: &Path, max_increments: usize) -> serde_json::Value {
    let n = max_increments.to_string();
    run_ok_with(
        input,
        dir,
        &["--solver", "type=cholesky", "--max-increments", &n],
    )
}

#[test]
fn abaqus_dcb_deck_equals_toml_scene() {
    let dir = tempfile::tempdir().unwrap();
    let ex = repo().join("examples/delamination");
    // 30 increments of 0.01 of the step = 0.1 mm of opening each
    let deck = run_incremental(&ex.join("dcb_abaqus.inp"), &dir.path().join("deck"), 30);
    let scene = run_incremental(&ex.join("dcb_h8.toml"), &dir.path().join("scene"), 30);
    assert_eq!(deck["analysis"], "static");
    assert_eq!(deck["status"], scene["status"]);
    assert!(
        deck["status"]
            .as_str()
            .unwrap()
            .contains("requested number"),
        "{}",
        deck["status"]
    );
    let a = curve(&dir.path().join("deck"));
    let b = curve(&dir.path().join("scene"));
    assert_eq!(a.len(), 30);
    assert_eq!(a.len(), b.len());
    for (k, (x, y)) in a.iter().zip(&b).enumerate() {
        // the deck's load factor runs 0 -> 1 over its step, the scene's is
        // the opening in mm (0 -> 10)
        assert!(rel(10.0 * x[0], y[0]) < 1e-12, "row {k}: {x:?} vs {y:?}");
        assert!(rel(x[2], y[2]) < 1e-12, "row {k}: {x:?} vs {y:?}");
        assert!(rel(x[1], y[1]) < 1e-6, "row {k}: {x:?} vs {y:?}");
    }
    // the last row: delta = 3 mm on the linear branch. Corrected beam
    // theory (BENCHMARKS.md section 4): delta = 2 P a_e^3 / (3 E11 I),
    // a_e = a0 + chi h; the 3D model with its elastic interface ahead of the
    // tip is within a few percent of it
    let (e11, e22, g13, b_, h, a0) = (122700.0f64, 10100.0f64, 5500.0, 25.4, 1.56, 32.9);
    let gamma = 1.18 * (e11 * e22).sqrt() / g13;
    let chi = (e11 / (11.0 * g13) * (3.0 - 2.0 * (gamma / (1.0 + gamma)).powi(2))).sqrt();
    let ae = a0 + chi * h;
    let i = b_ * h.powi(3) / 12.0;
    let [_, p, delta] = a[29];
    assert!((delta - 3.0).abs() < 1e-9, "delta = {delta}");
    let cbt = 3.0 * e11 * i * delta / (2.0 * ae.powi(3));
    assert!(
        rel(p, cbt) < 0.05,
        "P(3 mm) = {p} N, corrected beam theory {cbt} N"
    );
}

#[test]
fn deck_step_inc_stops_the_run_with_a_status() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(repo().join("examples/delamination/dcb_abaqus.inp"))
        .unwrap()
        .replace("INC=1000", "INC=4");
    let deck = write(dir.path(), "dcb_inc.inp", &text);
    let s = run_incremental(&deck, &dir.path().join("out"), 100);
    let status = s["status"].as_str().unwrap();
    let line = text.lines().position(|l| l.starts_with("*STEP")).unwrap() + 1;
    assert!(
        status.contains("INC=4") && status.contains(&format!("line {line}")),
        "{status}"
    );
    assert_eq!(curve(&dir.path().join("out")).len(), 4);
}

#[test]
fn bad_cohesive_decks_name_file_and_line() {
    let dir = tempfile::tempdir().unwrap();
    let text =
        std::fs::read_to_string(repo().join("examples/delamination/dcb_abaqus.inp")).unwrap();
    let line_of = |t: &str, pat: &str| t.lines().position(|l| l.starts_with(pat)).unwrap() + 1;
    // G_IIc != G_IIIc: Junta's law has one shear toughness
    let bad = text.replace("0.969, 1.719, 1.719", "0.969, 1.719, 2.5");
    let e = run_err(&write(dir.path(), "g3.inp", &bad));
    let line = line_of(&bad, "0.969, 1.719, 2.5");
    assert!(
        e.contains(&format!("g3.inp:{line}:")) && e.contains("G_IIIc"),
        "{e}"
    );
    // no *DAMAGE EVOLUTION
    let evo = line_of(&text, "*DAMAGE EVOLUTION");
    let bad: String = text
        .lines()
        .enumerate()
        .filter(|(k, _)| *k + 1 != evo && *k + 1 != evo + 1)
        .map(|(_, l)| format!("{l}\n"))
        .collect();
    let e = run_err(&write(dir.path(), "noevo.inp", &bad));
    let line = line_of(&bad, "*DAMAGE INITIATION");
    assert!(
        e.contains(&format!("noevo.inp:{line}:")) && e.contains("never soften"),
        "{e}"
    );
    // an unsupported option
    let bad = text.replace("SOFTENING=LINEAR", "SOFTENING=TABULAR");
    let e = run_err(&write(dir.path(), "tab.inp", &bad));
    assert!(
        e.contains(&format!("tab.inp:{evo}:")) && e.contains("SOFTENING=TABULAR"),
        "{e}"
    );
}

/// `*STATIC, RIKS` runs the deck with path following: the DCB deck of
/// examples/delamination with RIKS (max LPF 1 = 10 mm, INC=40) passes its
/// peak. References: Akantu's peak on this specimen and mesh density
/// (hex8, 0.5 mm, 1 x 2: 142.7 N, BENCHMARKS.md section 6) and corrected
/// beam theory's propagation branch (section 4). Measured: 139.1 N at
/// 4.52 mm (the arc's increments straddle the peak), 93.8 N at 9.34 mm
/// (CBT 93.0 N).
#[test]
fn riks_deck_runs_with_path_following() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(repo().join("examples/delamination/dcb_abaqus.inp"))
        .unwrap()
        .replace(
            "*STEP, NAME=OPEN, NLGEOM=NO, INC=1000\n*STATIC\n0.01, 1.0, 1e-06, 0.01",
            "*STEP, NAME=OPEN, NLGEOM=NO, INC=40\n*STATIC, RIKS\n0.01, 1.0, , , 1.0",
        );
    assert!(text.contains("RIKS"));
    let deck = dir.path().join("riks.inp");
    std::fs::write(&deck, text).unwrap();
    let s = run_ok(&deck, &dir.path().join("out"));
    assert!(
        s["status"].as_str().unwrap().contains("INC=40"),
        "{}",
        s["status"]
    );
    assert_eq!(s["control"], "arc_length");
    let rows = curve(&dir.path().join("out"));
    assert_eq!(rows.len(), 40);
    let (ipk, pk) = rows
        .iter()
        .enumerate()
        .map(|(i, r)| (i, r[1]))
        .fold((0, 0.0), |a, b| if b.1 > a.1 { b } else { a });
    assert!((pk / 142.7 - 1.0).abs() < 0.03, "peak {pk}");
    let [_, _, delta] = rows[rows.len() - 1];
    assert!(
        ipk < rows.len() - 5 && delta > 8.0,
        "did not pass the peak far"
    );
    assert_end_on_cbt_branch(&rows);
}

/// The last point `(load factor, P, delta)` of a DCB run lies within 3 %
/// of corrected beam theory's propagation branch (BENCHMARKS.md section 4:
/// `P = (G_Ic b)^(3/4) (E11 b h^3 / 12)^(1/4) sqrt(2 / (3 delta))`,
/// AS4/PEEK, b = 25.4 mm, h = 1.56 mm).
fn assert_end_on_cbt_branch(rows: &[[f64; 3]]) {
    let [_, p, delta] = rows[rows.len() - 1];
    let (gic, b, e11, h): (f64, f64, f64, f64) = (0.969, 25.4, 122700.0, 1.56);
    let cbt = (gic * b).powf(0.75)
        * (e11 * b * h.powi(3) / 12.0).powf(0.25)
        * (2.0 / (3.0 * delta)).sqrt();
    assert!(
        (p / cbt - 1.0).abs() < 0.03,
        "P({delta}) = {p} against {cbt}"
    );
}

/// The program of tests/data/amplitude_cohesive.inp written as three
/// steps without an amplitude: open to 0.02, close to 0.008, reopen to 0.03.
const THREE_STEPS: &str =
    "*STEP, INC=200\n*STATIC\n0.1, 1.0\n*BOUNDARY\nTOP, 3, 3, 0.02\n*END STEP\n\
     *STEP, INC=200\n*STATIC\n0.1, 1.0\n*BOUNDARY\nTOP, 3, 3, 0.008\n*END STEP\n\
     *STEP, INC=200\n*STATIC\n0.1, 1.0\n*BOUNDARY\nTOP, 3, 3, 0.03\n*END STEP\n";

/// `*AMPLITUDE` drives an incremental run (tests/data/amplitude_cohesive.inp:
/// a glued pair of bricks opened past the cohesive peak, closed to 40 %,
/// reopened to 150 % through one amplitude): the run equals the same deck
/// written as three steps without an amplitude (the same load program),
/// increment for increment, and its unloading and reloading points lie on
/// the damaged secant through the origin (bilinear law: unloading at
/// constant damage; brick elasticity in series is linear too), until the
/// reloading passes the earlier maximum opening and softens again.
#[test]
fn amplitude_drives_an_incremental_run() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(repo().join("crates/cli/tests/data/amplitude_cohesive.inp"))
        .unwrap();
    let amp = write(dir.path(), "amp.inp", &text);
    run_ok_with(&amp, &dir.path().join("a"), &["--solver", "type=ldlt"]);
    let steps = THREE_STEPS;
    let start = text.find("*STEP").unwrap();
    let plain = write(
        dir.path(),
        "steps.inp",
        &format!("{}{steps}", &text[..start]),
    );
    run_ok_with(&plain, &dir.path().join("s"), &["--solver", "type=ldlt"]);
    let (a, s) = (curve(&dir.path().join("a")), curve(&dir.path().join("s")));
    assert_eq!(a.len(), s.len());
    for (x, y) in a.iter().zip(&s) {
        for k in 0..3 {
            assert!(
                (x[k] - y[k]).abs() <= 1e-12 * y[k].abs().max(1e-12),
                "{x:?} vs {y:?}"
            );
        }
    }
    // the load factor passes through 1, 0.4 and 1.5 (the amplitude's points)
    for want in [1.0, 0.4, 1.5] {
        assert!(
            a.iter().any(|r| (r[0] - want).abs() < 1e-12),
            "{want}: {a:?}"
        );
    }
    // secant through the origin from the unloading start (lambda = 1) to
    // the reloading back to it
    let i1 = a.iter().position(|r| (r[0] - 1.0).abs() < 1e-12).unwrap();
    let secant = a[i1][1] / a[i1][2];
    let back = a[i1..].iter().take_while(|r| r[0] <= 1.0 + 1e-12).count();
    assert!(back >= 4, "{a:?}");
    for r in &a[i1..i1 + back] {
        assert!(
            (r[1] / r[2] - secant).abs() < 1e-9 * secant,
            "{r:?} off the secant {secant}"
        );
    }
    // beyond the earlier maximum the interface softens again
    let last = a.last().unwrap();
    assert!(last[1] / last[2] < 0.9 * secant, "{last:?}");
}

/// `*ELEMENT, TYPE=COH3D6` with `*COHESIVE SECTION` and `*ELASTIC,
/// TYPE=TRACTION` (tests/data/coh3d6_stack.inp, written by
/// make_wedge_decks.py): two C3D6 layers (h = 0.5 each) bonded by two
/// INTER6, every node held laterally. Closed forms of the bonded stack
/// (series of the two layers and the penalty, BENCHMARKS.md section 3):
/// tension in uniaxial strain `sigma = delta / (2 h / M + 1 / K_nn)`, `M =
/// E (1 - nu) / ((1 + nu)(1 - 2 nu))`; simple shear (the deck edited: y, z
/// held, the top slid 0.01 in x) `tau = delta / (2 h / G + 1 / K_ss)`; the
/// interface opens / slides by `sigma / K`. The local frame of a triangle
/// has e1 along its edge 0-1: x for element 5 (nodes 5-6-7), the diagonal
/// (1, 1, 0) / sqrt 2 for element 6 (5-7-8), so in shear the local
/// tractions are (tau, 0, 0) and (tau, -tau, 0) / sqrt 2. interfaces.vtu
/// holds the two mid-surface triangles (VTK_TRIANGLE = 5).
#[test]
fn coh3d6_deck_matches_the_bonded_stack() {
    let (e, nu, h, k, delta) = (210000.0f64, 0.3f64, 0.5, 1.0e5, 0.01);
    let m = e * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu));
    let g = e / (2.0 * (1.0 + nu));
    let text =
        std::fs::read_to_string(repo().join("crates/cli/tests/data/coh3d6_stack.inp")).unwrap();
    let shear = text
        .replace("NALL, 1, 2", "NALL, 2, 3")
        .replace("BOTTOM, 3, 3", "BOTTOM, 1, 1")
        .replace("TOP, 3, 3, 0.01", "TOP, 1, 1, 0.01");
    let dir = tempfile::tempdir().unwrap();
    for (what, deck, c, modulus) in [("tension", &text, 2, m), ("shear", &shear, 0, g)] {
        let out = dir.path().join(what);
        let s = run_ok(&write(dir.path(), &format!("{what}.inp"), deck), &out);
        assert_eq!(
            s["elements"]["inter6"].as_u64(),
            Some(2),
            "{}",
            s["elements"]
        );
        let t = delta / (2.0 * h / modulus + 1.0 / k);
        let r = s["reactions"]["TOP"][c].as_f64().unwrap();
        assert!(rel(r, t) < 1e-9, "{what}: reaction {r} vs closed form {t}");
        // [min, max] of the local components 0, 1, 2
        let r2 = std::f64::consts::FRAC_1_SQRT_2;
        let want: [[f64; 2]; 3] = if c == 2 {
            [[0.0, 0.0], [0.0, 0.0], [t, t]]
        } else {
            [[r2 * t, t], [-r2 * t, 0.0], [0.0, 0.0]]
        };
        let glue = &s["interfaces"]["GLUE"];
        for (i, [lo, hi]) in want.iter().enumerate() {
            for (key, scale) in [("traction", 1.0), ("jump", 1.0 / k)] {
                let v = |m: &str| glue[format!("{key}_{m}")][i].as_f64().unwrap();
                let tol = 1e-9 * t * scale;
                assert!(
                    (v("min") - lo * scale).abs() < tol && (v("max") - hi * scale).abs() < tol,
                    "{what}: {key}[{i}] in [{}, {}], expected [{}, {}]",
                    v("min"),
                    v("max"),
                    lo * scale,
                    hi * scale
                );
            }
        }
        let vtu = std::fs::read_to_string(out.join("interfaces.vtu")).unwrap();
        let at = vtu.find("Name=\"types\"").expect("types array");
        let body = &vtu[at..];
        let body = &body[body.find('>').unwrap() + 1..body.find("</DataArray>").unwrap()];
        let types: Vec<&str> = body.split_whitespace().collect();
        assert_eq!(types, ["5", "5"], "{what}");
    }
}

/// `*EQUATION` in incremental runs. The DCB deck of examples/delamination
/// with its loaded ends tied by linear equations to one node each (`u_z`
/// of every other LOAD_UP / LOAD_LOW node equals that of node 727 / 1,
/// the way a deck ties a face to a reference node), only those two nodes
/// displaced. Physically the same model, so:
/// * Newton (displacement control) follows the untied deck increment for
///   increment to its limit point (52 increments, peak 142.5258 N, see
///   the deck's header), the curves equal to 1e-9;
/// * `*STATIC, RIKS` (path following in the reduced unknowns) follows the
///   untied deck's path and passes the peak like
///   `riks_deck_runs_with_path_following`: peak within 3 % of Akantu's
///   142.7 N (BENCHMARKS.md section 6), the end of the propagation branch
///   within 3 % of corrected beam theory.
#[test]
fn equations_tie_the_loaded_ends_in_incremental_runs() {
    let dir = tempfile::tempdir().unwrap();
    let text =
        std::fs::read_to_string(repo().join("examples/delamination/dcb_abaqus.inp")).unwrap();
    let (up, low) = (
        [727, 848, 969, 1090, 1211, 1332],
        [1, 122, 243, 364, 485, 606],
    );
    let mut eqs = String::from("*EQUATION\n");
    for set in [up, low] {
        for n in &set[1..] {
            eqs += &format!("2\n{n}, 3, 1.0, {}, 3, -1.0\n", set[0]);
        }
    }
    let tied = text
        .replace("*STEP, NAME=OPEN", &format!("{eqs}*STEP, NAME=OPEN"))
        .replace("LOAD_UP, 3, 3, 5.0", "727, 3, 3, 5.0")
        .replace("LOAD_LOW, 3, 3, -5.0", "1, 3, 3, -5.0");
    assert_ne!(tied, text);
    let riks = |t: &str| {
        t.replace(
            "*STEP, NAME=OPEN, NLGEOM=NO, INC=1000\n*STATIC\n0.01, 1.0, 1e-06, 0.01",
            "*STEP, NAME=OPEN, NLGEOM=NO, INC=40\n*STATIC, RIKS\n0.01, 1.0, , , 1.0",
        )
    };
    // Newton alone (`control=load`: no path following at the limit
    // point): both stop at the limit point; the converged increments agree
    let mut curves = Vec::new();
    for (name, deck) in [("plain", &text), ("tied", &tied)] {
        let path = write(dir.path(), &format!("{name}.inp"), deck);
        let out = dir.path().join(name);
        let o = junta()
            .arg("run")
            .arg(&path)
            .args(["--solver", "control=load", "-q", "-o"])
            .arg(&out)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            err.contains("Limit point") && !err.contains("panicked"),
            "{name}: {err}"
        );
        curves.push(curve(&out));
    }
    assert_eq!(curves[0].len(), 52, "the untied deck's documented run");
    assert_eq!(curves[0].len(), curves[1].len());
    for (a, b) in curves[0].iter().zip(&curves[1]) {
        for k in 0..3 {
            assert!(
                (a[k] - b[k]).abs() <= 1e-9 * b[k].abs().max(1.0),
                "{a:?} vs {b:?}"
            );
        }
    }
    // RIKS with the equations: the untied deck's path (measured: the same
    // 40 increments, peak 139.137395 N at 4.517 mm in both, curves equal
    // to 5e-10), which passes the peak
    let mut paths = Vec::new();
    for (name, deck) in [("riks", riks(&text)), ("riks_tied", riks(&tied))] {
        let path = write(dir.path(), &format!("{name}.inp"), &deck);
        let s = run_ok(&path, &dir.path().join(name));
        assert_eq!(s["control"], "arc_length");
        paths.push(curve(&dir.path().join(name)));
    }
    assert_eq!(paths[0].len(), paths[1].len());
    for (a, b) in paths[0].iter().zip(&paths[1]) {
        for k in 0..3 {
            assert!(
                (a[k] - b[k]).abs() <= 1e-7 * b[k].abs().max(1.0),
                "{a:?} vs {b:?}"
            );
        }
    }
    let rows = &paths[1];
    let pk = rows.iter().map(|r| r[1]).fold(0.0, f64::max);
    assert!((pk / 142.7 - 1.0).abs() < 0.03, "peak {pk}");
    let delta = rows[rows.len() - 1][2];
    assert!(delta > 8.0, "did not pass the peak far: {delta}");
    assert_end_on_cbt_branch(rows);
}

/// `*NODE PRINT` / `*EL PRINT` in an incremental run: rows at the end of
/// every deck step (tests/data/amplitude_cohesive.inp written as three
/// steps opening the glued bricks to 0.02, closing to 0.008, reopening to
/// 0.03). Checks: `U` of TOP is the prescribed opening of each step; the
/// `RF` total of TOP is the curve's reaction at the step's end; the mean
/// `sigma_zz` over the 8 equally weighted Gauss points of the upper brick
/// equals that force over its unit area (for isoparametric elements
/// `int sigma_zz dV = sum_a z_a f_int,z^a`, and the brick spans z = 1..2
/// with its bottom nodes carrying -F, so the integral is F exactly). A run
/// stopped after 5 increments and restarted writes the same tables; a
/// run stopped inside a step prints that step at its last increment, with
/// a note.
#[test]
fn print_tables_of_an_incremental_deck() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(repo().join("crates/cli/tests/data/amplitude_cohesive.inp"))
        .unwrap();
    let steps = format!(
        "*NODE PRINT, NSET=TOP, TOTALS=YES\nU, RF\n*EL PRINT, ELSET=ARMS\nS\n{THREE_STEPS}"
    );
    let start = text.find("*STEP").unwrap();
    let deck = write(
        dir.path(),
        "steps.inp",
        &format!("{}{steps}", &text[..start]),
    );
    let full = dir.path().join("full");
    run_ok_with(&deck, &full, &["--solver", "type=ldlt"]);
    let rows = curve(&full);
    let table = std::fs::read_to_string(full.join("node_print.csv")).unwrap();
    let el = std::fs::read_to_string(full.join("el_print.csv")).unwrap();
    let field = |line: &str, k: usize| line.split(',').nth(k).unwrap().parse::<f64>().unwrap();
    // the curve's rows at the ends of the steps: load factor 1, 0.4, 1.5
    for (step, (lambda, opening)) in [(1.0, 0.02), (0.4, 0.008), (1.5, 0.03)].iter().enumerate() {
        let s = step + 1;
        let end = rows
            .iter()
            .rev()
            .find(|r| (r[0] - lambda).abs() < 1e-12)
            .unwrap_or_else(|| panic!("no row at {lambda}"));
        let u: Vec<&str> = table
            .lines()
            .filter(|l| l.starts_with(&format!("{s},TOP,U,")) && !l.contains("total"))
            .collect();
        assert_eq!(u.len(), 4, "{table}");
        for l in &u {
            assert!((field(l, 6) - opening).abs() < 1e-15, "{l}");
        }
        let total = table
            .lines()
            .find(|l| l.starts_with(&format!("{s},TOP,RF,total")))
            .unwrap();
        let f = field(total, 6);
        assert!(
            rel(f, end[1]) < 1e-9,
            "step {s}: RF total {f} vs curve {}",
            end[1]
        );
        let szz: Vec<f64> = el
            .lines()
            .filter(|l| l.starts_with(&format!("{s},ARMS,S,2,")))
            .map(|l| field(l, 7))
            .collect();
        assert_eq!(szz.len(), 8, "{el}");
        let mean = szz.iter().sum::<f64>() / 8.0;
        assert!(
            rel(mean, f) < 1e-9,
            "step {s}: mean sigma_zz {mean} vs F {f}"
        );
    }
    // stopped after 5 increments and restarted: the same tables
    let part = dir.path().join("part");
    run_ok_with(
        &deck,
        &part,
        &["--solver", "type=ldlt", "--max-increments", "5"],
    );
    let cut = std::fs::read_to_string(part.join("node_print.csv")).unwrap();
    assert!(cut.lines().all(|l| !l.starts_with("2,")), "{cut}");
    assert!(cut.lines().any(|l| l.starts_with("1,TOP,U,")), "{cut}");
    restart_ok(&part);
    for name in ["node_print.csv", "el_print.csv"] {
        let a = std::fs::read_to_string(full.join(name)).unwrap();
        let b = std::fs::read_to_string(part.join(name)).unwrap();
        assert_eq!(a, b, "{name}");
    }
    // a run stopped inside step 1 notes it
    let out = junta()
        .arg("run")
        .arg(&deck)
        .args(["--solver", "type=ldlt", "--max-increments", "3", "-o"])
        .arg(dir.path().join("three"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("step 1 did not finish"), "{err}");
}
