//! The paper's linear examples (PAPER.md section 6) and the penalty study.
//! Golden values: the paper's reported stresses (T3: 3.5e8 Pa, T4/T5:
//! 1.01e8 Pa), and the closed forms of BENCHMARKS.md section 3 (bonded
//! stack in uniaxial strain / simple shear with the series penalty term).

mod common;
use common::*;
use serde_json::Value;

const E: f64 = 2.1e11;
const NU: f64 = 0.3;
const H: f64 = 0.01;
const DELTA: f64 = 1.25e-5;
const AREA: f64 = 0.04;

fn p_modulus() -> f64 {
    E * (1.0 - NU) / ((1.0 + NU) * (1.0 - 2.0 * NU))
}
fn shear_modulus() -> f64 {
    E / (2.0 * (1.0 + NU))
}

fn run_scene(name: &str, edit: impl Fn(String) -> String) -> Value {
    let text = std::fs::read_to_string(repo().join("examples/paper").join(name)).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let scene = write(dir.path(), name, &edit(text));
    run_ok(&scene, &dir.path().join("out"))
}

fn f(v: &Value) -> f64 {
    v.as_f64().unwrap()
}

/// Every traction component `k` of the interface and stress component `s`
/// of both solids lies within `tol` (relative) of `value`.
fn assert_uniform(s: &Value, k: usize, voigt: usize, value: f64, tol: f64) {
    let b = &s["interfaces"]["bond"];
    for key in ["traction_min", "traction_max"] {
        let t = f(&b[key][k]);
        assert!(
            rel(t, value) < tol,
            "interface {key}[{k}] = {t:e}, expected {value:e}"
        );
    }
    for solid in ["lower", "upper"] {
        for key in ["stress_min", "stress_max"] {
            let v = f(&s["solids"][solid][key][voigt]);
            assert!(
                rel(v, value) < tol,
                "{solid} {key}[{voigt}] = {v:e}, expected {value:e}"
            );
        }
    }
}

#[test]
fn prism_tension_t3_matches_paper_and_closed_form() {
    // the paper's d = 1e25: sigma_33 = 3.5e8 at every point (two digits)
    let s = run_scene("prism_tension.toml", |t| t);
    assert_uniform(&s, 2, 2, 3.5e8, 0.0105);
    // d = 1e14, where the penalty term of the series matters (1/d = 0.28 H/M)
    let d = 1e14;
    let s = run_scene("prism_tension.toml", |t| {
        t.replace("d = 1.0e25", &format!("d = {d:e}"))
    });
    let sigma = DELTA / (H / p_modulus() + 1.0 / d);
    assert_uniform(&s, 2, 2, sigma, 1e-6);
    let reaction = f(&s["reactions"]["upper.z1"][2]);
    assert!(
        rel(reaction, sigma * AREA) < 1e-6,
        "{reaction:e} vs {:e}",
        sigma * AREA
    );
    // the opening of the interface is sigma / d
    let b = &s["interfaces"]["bond"];
    assert!(
        rel(f(&b["jump_min"][2]), sigma / d) < 1e-6 && rel(f(&b["jump_max"][2]), sigma / d) < 1e-6
    );
}

#[test]
fn prism_shear_t4_t5_match_paper_and_closed_form() {
    for (file, k, voigt) in [("prism_shear_x.toml", 0, 5), ("prism_shear_y.toml", 1, 4)] {
        let s = run_scene(file, |t| t);
        // paper: 1.01e8 Pa (three digits: 1.00962e8 rounds to 1.01e8)
        assert_uniform(&s, k, voigt, 1.01e8, 0.005);
        let d = 1e14;
        let s = run_scene(file, |t| t.replace("d = 1.0e25", &format!("d = {d:e}")));
        let tau = DELTA / (H / shear_modulus() + 1.0 / d);
        assert_uniform(&s, k, voigt, tau, 1e-6);
        let c = ["x", "y"][k];
        let reaction = f(&s["reactions"]["upper.z1"][k]);
        assert!(
            rel(reaction, tau * AREA) < 1e-6,
            "{file}: F{c} = {reaction:e} vs {:e}",
            tau * AREA
        );
    }
}

#[test]
fn penalty_cube_opening_scales_as_one_over_d() {
    let jump = |d: f64| {
        let s = run_scene("penalty_cube.toml", |t| {
            t.replace("d = 1.0e14", &format!("d = {d:e}"))
        });
        let b = &s["interfaces"]["bond"];
        (f(&b["jump_min"][2]), f(&b["jump_max"][2]))
    };
    let (a_min, a_max) = jump(1e16);
    let (b_min, b_max) = jump(1e18);
    let (c_min, _) = jump(1e20);
    assert!(
        a_min < 0.0 && a_max < 0.0,
        "compression closes the interface"
    );
    // 1/d scaling once the constraint is nearly satisfied (paper: delta_3 ~ 1/d)
    assert!(rel(a_min / b_min, 100.0) < 0.01, "{a_min:e} / {b_min:e}");
    assert!(rel(a_max / b_max, 100.0) < 0.01, "{a_max:e} / {b_max:e}");
    assert!(rel(b_min / c_min, 100.0) < 0.01, "{b_min:e} / {c_min:e}");
}

#[test]
fn penalty_sweep_charts_where_methods_fail() {
    let dir = tempfile::tempdir().unwrap();
    let out = junta()
        .args(["sweep", "penalty"])
        .arg(repo().join("examples/paper/prism_tension.toml"))
        .args(["--from", "1e12", "--to", "1e30", "-o"])
        .arg(dir.path())
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(dir.path().join("sweep.svg").exists());
    let csv = std::fs::read_to_string(dir.path().join("sweep.csv")).unwrap();
    let rows: Vec<Vec<String>> = csv
        .lines()
        .skip(1)
        .map(|l| l.splitn(12, ',').map(str::to_string).collect())
        .collect();
    let get = |solver: &str| -> Vec<(f64, String, Option<f64>)> {
        rows.iter()
            .filter(|r| r[1] == solver)
            .map(|r| (r[0].parse().unwrap(), r[2].clone(), r[3].parse().ok()))
            .collect()
    };
    let direct = get("cholesky");
    let cg = get("cg");
    assert_eq!(direct.len(), 19);
    // the AMG row family: a row per penalty, converged or failed with its
    // message
    assert_eq!(get("amg").len(), 19);
    // the mixed-precision direct solve: single precision while the penalty
    // leaves it usable, with the double's answer; from some d on it falls
    // back to double by itself (and says so), never a silent wrong answer
    let mixed: Vec<(f64, String, Option<f64>, String)> = rows
        .iter()
        .filter(|r| r[1] == "cholesky_mixed")
        .map(|r| {
            (
                r[0].parse().unwrap(),
                r[2].clone(),
                r[3].parse().ok(),
                r[10].clone(),
            )
        })
        .collect();
    assert_eq!(mixed.len(), 19);
    let first_fallback = mixed
        .iter()
        .position(|r| r.3 == "double")
        .expect("the mixed mode falls back to double at high penalties");
    assert!(first_fallback >= 3, "mixed holds at low penalties");
    assert!(mixed[first_fallback..].iter().all(|r| r.3 != "mixed"));
    assert!(csv.contains("mixed precision abandoned"));
    for (m, d) in mixed[..first_fallback].iter().zip(&direct) {
        assert_eq!(m.3, "mixed");
        let (em, ed) = (m.2.unwrap(), d.2.unwrap());
        assert!(
            (em - ed).abs() <= 1e-9 * ed.max(1e-6),
            "d = {:e}: mixed error {em:e}, double {ed:e}",
            m.0
        );
    }
    // constraint regime: error ~ 1/d (eq. 51)
    let e = |d: f64| {
        direct
            .iter()
            .find(|r| rel(r.0, d) < 1e-9)
            .unwrap()
            .2
            .unwrap()
    };
    assert!(
        rel(e(1e16) / e(1e18), 100.0) < 0.05,
        "{} {}",
        e(1e16),
        e(1e18)
    );
    // the best direct error is near the paper's bound 2 sqrt(n e_c) or better
    let best = direct
        .iter()
        .filter_map(|r| r.2)
        .fold(f64::INFINITY, f64::min);
    assert!(best < 1e-6, "best {best:e}");
    // past the optimum the direct solve degrades, and it says so: every
    // result worse than 1e-4 beyond d = 1e22 carries a warning or failed
    for (d, status, err) in &direct {
        if *d > 1e22 && err.is_none_or(|v| v > 1e-4) {
            assert!(
                status != "ok",
                "silent wrong answer at d = {d:e}: {status} {err:?}"
            );
        }
    }
    assert!(
        direct.iter().any(|r| r.1 == "failed"),
        "the direct solver must refuse at d = 1e30"
    );
    // CG fails (with a message) well before the direct solver does
    let first_cg_fail = cg.iter().find(|r| r.1 == "failed").map(|r| r.0).unwrap();
    let first_direct_fail = direct
        .iter()
        .find(|r| r.1 == "failed")
        .map(|r| r.0)
        .unwrap();
    assert!(
        first_cg_fail < first_direct_fail,
        "{first_cg_fail:e} vs {first_direct_fail:e}"
    );
    assert!(
        csv.contains("did not converge"),
        "CG failures carry their numbers"
    );
    // the advisor's optimum lies within a decade of the best d
    let best_d = direct
        .iter()
        .filter(|r| r.2 == Some(best))
        .map(|r| r.0)
        .next()
        .unwrap();
    let summary = run_ok(
        &repo().join("examples/paper/prism_tension.toml"),
        &dir.path().join("run"),
    );
    let d_op = f(&summary["penalty_advice"]["bond"]["d_op"]);
    assert!(
        (best_d / d_op).log10().abs() <= 1.0,
        "best d {best_d:e}, advisor {d_op:e}"
    );
}

#[test]
fn bad_interface_input_gives_clear_errors() {
    let good = std::fs::read_to_string(repo().join("examples/paper/prism_tension.toml")).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // sets that share no face: move the upper box away
    let e = run_err(&write(
        d,
        "apart.toml",
        &good.replace("origin = [0.0, 0.0, 0.005]", "origin = [0.0, 0.0, 0.5]"),
    ));
    assert!(
        e.contains("interface[0].between") && e.contains("share no face"),
        "{e}"
    );
    // mismatched element orders
    let text = good.replacen("element = \"h27\"", "element = \"h20\"", 1);
    let e = run_err(&write(d, "orders.toml", &text));
    assert!(
        e.contains("mismatched element orders") && e.contains("hex20") && e.contains("hex27"),
        "{e}"
    );
    // d <= 0
    let e = run_err(&write(
        d,
        "zero.toml",
        &good.replace("d = 1.0e25", "d = 0.0"),
    ));
    assert!(e.contains("laws.paper") && e.contains("positive"), "{e}");
    let e = run_err(&write(
        d,
        "negative.toml",
        &good.replace("d = 1.0e25", "d = -1.0e10"),
    ));
    assert!(e.contains("positive"), "{e}");
    // unknown law type, unknown law name
    let e = run_err(&write(
        d,
        "type.toml",
        &good.replace("\"linear_penalty\"", "\"linear_penalti\""),
    ));
    assert!(
        e.contains("linear_penalti") && e.contains("linear_penalty"),
        "{e}"
    );
    let e = run_err(&write(
        d,
        "name.toml",
        &good.replace("law = \"paper\"", "law = \"glue\""),
    ));
    assert!(
        e.contains("interface[0]") && e.contains("glue") && e.contains("paper"),
        "{e}"
    );
    // unknown integration rule
    let e = run_err(&write(
        d,
        "rule.toml",
        &good.replace("integration = \"gauss\"", "integration = \"simpson\""),
    ));
    assert!(e.contains("simpson") && e.contains("lobatto"), "{e}");
    // unknown element set
    let e = run_err(&write(
        d,
        "set.toml",
        &good.replace(
            "between = [\"lower\", \"upper\"]",
            "between = [\"lower\", \"top\"]",
        ),
    ));
    assert!(e.contains("top") && e.contains("upper"), "{e}");
}

#[test]
fn lobatto_removes_gauss_traction_oscillations() {
    // BENCHMARKS.md section 5 (Schellekens & de Borst 1993): Gauss-integrated
    // stiff interfaces oscillate where the traction gradient is steep;
    // nodal (Lobatto) integration does not.
    let dir = tempfile::tempdir().unwrap();
    let out = junta()
        .args(["sweep", "integration"])
        .arg(repo().join("examples/oscillation/notched_beam.toml"))
        .args(["--d", "1e5,1e9", "-o"])
        .arg(dir.path())
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout).to_string();
    assert!(
        out.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(dir.path().join("traction.svg").exists());
    let extrema = |d: &str, rule: &str| -> usize {
        let line = stdout
            .lines()
            .find(|l| l.contains(&format!("d = {d:>9}")) && l.contains(rule))
            .unwrap_or_else(|| panic!("no line for {d} {rule}:\n{stdout}"));
        let i = line.find(" local extrema").unwrap();
        line[..i].rsplit(' ').next().unwrap().parse().unwrap()
    };
    assert_eq!(extrema("1.0e5", "gauss"), 0, "{stdout}");
    assert_eq!(extrema("1.0e5", "lobatto"), 0, "{stdout}");
    assert!(extrema("1.0e9", "gauss") >= 4, "{stdout}");
    assert_eq!(extrema("1.0e9", "lobatto"), 0, "{stdout}");
    // equilibrium: both rules carry the same resultant (the csv has every point)
    let csv = std::fs::read_to_string(dir.path().join("traction.csv")).unwrap();
    assert!(csv.lines().count() > 64);
}

#[test]
fn punch_transmits_compression_and_tension() {
    for (file, sign) in [
        ("punch_compression.toml", -1.0),
        ("punch_tension.toml", 1.0),
    ] {
        let s = run_scene(file, |t| {
            t.replace(
                "law = \"paper\"",
                "law = \"paper\"\nintegration = \"lobatto\"",
            )
        });
        let b = &s["interfaces"]["bond"];
        // every interface point carries normal traction of the punch's sign
        let (lo, hi) = (f(&b["traction_min"][2]), f(&b["traction_max"][2]));
        assert!(
            sign * lo > 0.0 && sign * hi > 0.0,
            "{file}: t_n in [{lo:e}, {hi:e}]"
        );
        // the nearly rigid punch moves with its top (2.5e-4) and drags the foundation
        let punch = f(&s["probes"]["punch.z0"][2]);
        assert!(
            rel(punch, sign * 2.5e-4) < 1e-3,
            "{file}: punch bottom {punch:e}"
        );
        // equilibrium: punch force = foundation reaction
        let fp = f(&s["reactions"]["punch.z1"][2]);
        let ff = f(&s["reactions"]["foundation.z0"][2]);
        assert!(
            rel(-fp, ff) < 1e-6 && sign * fp > 0.0,
            "{file}: {fp} vs {ff}"
        );
    }
}

#[test]
fn interfaces_in_imported_meshes_and_cohesive_decks() {
    // two C3D8 stacked in a deck, ELSETs LOWER / UPPER; the interface is
    // inserted by the scene between the two sets; confined uniaxial strain
    // gives the closed form of BENCHMARKS.md section 3.
    let mut deck = String::from("*NODE\n");
    let mut id = 0;
    for z in [0.0, 0.5, 1.0] {
        for (x, y) in [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)] {
            id += 1;
            deck += &format!("{id}, {x}, {y}, {z}\n");
        }
    }
    deck += "*ELEMENT, TYPE=C3D8, ELSET=LOWER\n1, 1, 2, 3, 4, 5, 6, 7, 8\n";
    deck += "*ELEMENT, TYPE=C3D8, ELSET=UPPER\n2, 5, 6, 7, 8, 9, 10, 11, 12\n";
    deck += "*NSET, NSET=ALL, GENERATE\n1, 12, 1\n*NSET, NSET=BOTTOM\n1, 2, 3, 4\n*NSET, NSET=TOP\n9, 10, 11, 12\n";
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "stack.inp", &deck);
    let scene = r#"
[materials.steel]
type = "isotropic"
E = 2.1e11
nu = 0.3
[laws.glue]
type = "linear_penalty"
d = 1.0e11
[mesh]
type = "inp"
file = "stack.inp"
[[blocks]]
name = "LOWER"
element = "h8"
material = "steel"
[[blocks]]
name = "UPPER"
element = "h8"
material = "steel"
[[interface]]
name = "bond"
between = ["LOWER", "UPPER"]
law = "glue"
[[boundary]]
set = "ALL"
fixed = ["x", "y"]
[[boundary]]
set = "BOTTOM"
fixed = "all"
[[boundary]]
set = "TOP"
displacement = { z = 1.0e-4 }
"#;
    let s = run_ok(
        &write(dir.path(), "stack.toml", scene),
        &dir.path().join("a"),
    );
    assert_eq!(s["elements"]["inter8"].as_u64(), Some(1));
    let sigma = 1e-4 / (1.0 / p_modulus() + 1.0 / 1e11);
    assert!(
        rel(f(&s["reactions"]["TOP"][2]), sigma) < 1e-9,
        "{}",
        s["reactions"]["TOP"]
    );
    // the same model as a deck with a ready-made COH3D8 (nodes 13-16 on top)
    let mut coh = deck.clone();
    coh = coh.replace(
        "*ELEMENT, TYPE=C3D8, ELSET=UPPER\n2, 5, 6, 7, 8, 9, 10, 11, 12\n",
        "*ELEMENT, TYPE=C3D8, ELSET=UPPER\n2, 13, 14, 15, 16, 9, 10, 11, 12\n*ELEMENT, TYPE=COH3D8, ELSET=GLUE\n3, 5, 6, 7, 8, 13, 14, 15, 16\n",
    );
    coh = coh.replace(
        "*NODE\n",
        "*NODE\n13, 0, 0, 0.5\n14, 1, 0, 0.5\n15, 1, 1, 0.5\n16, 0, 1, 0.5\n",
    );
    coh = coh.replace(
        "*NSET, NSET=ALL, GENERATE\n1, 12, 1\n",
        "*NSET, NSET=ALL, GENERATE\n1, 16, 1\n",
    );
    coh += "*MATERIAL, NAME=STEEL\n*ELASTIC\n2.1e11, 0.3\n*MATERIAL, NAME=GLUE\n*ELASTIC, TYPE=TRACTION\n1e11, 1e11, 1e11\n";
    coh += "*SOLID SECTION, ELSET=LOWER, MATERIAL=STEEL\n*SOLID SECTION, ELSET=UPPER, MATERIAL=STEEL\n";
    coh += "*COHESIVE SECTION, ELSET=GLUE, MATERIAL=GLUE, RESPONSE=TRACTION SEPARATION\n";
    coh += "*BOUNDARY\nALL, 1, 2\nBOTTOM, 1, 3\n*STEP\n*STATIC\n*BOUNDARY\nTOP, 3, 3, 1.0e-4\n*END STEP\n";
    let s = run_ok(&write(dir.path(), "coh.inp", &coh), &dir.path().join("b"));
    assert_eq!(s["elements"]["inter8"].as_u64(), Some(1));
    assert!(
        rel(f(&s["reactions"]["TOP"][2]), sigma) < 1e-9,
        "{}",
        s["reactions"]["TOP"]
    );
}

/// The prisms of T3 / T4 with wedge layers: each layer 2 x 2 cells cut into
/// 8 wedges (`wedge6` or `wedge15`), the interface inserted between the
/// layers' triangles (8 INTER6 or INTER12; INTER6 also with its nodal
/// vertex rule), d = 1e14 so that the penalty term matters. Closed forms of
/// the bonded stack (BENCHMARKS.md section 3), exact for these meshes
/// (the solution is linear in z in each layer, with every lateral node held
/// as in the scene): tension sigma = Delta / (H / M + 1 / d) in uniaxial
/// strain, shear tau = Delta / (H / G + 1 / d) in simple shear; uniform in
/// every solid point, reaction = value x area, interface jump = value / d.
///
/// The local frame of a triangle has e1 along its edge 0-1: along x on the
/// generator's wedges A (cell corners 0-1-2), along the cut (1, 1, 0) /
/// sqrt 2 on the wedges B (0-2-3). So in shear the local traction is
/// (tau, 0, 0) on A and (tau, -tau, 0) / sqrt 2 on B: the summary's
/// component ranges are [tau / sqrt 2, tau] and [-tau / sqrt 2, 0], the
/// jumps the same over d; in tension (0, 0, sigma) everywhere.
#[test]
fn wedge_prisms_with_inter6_and_inter12_match_the_closed_forms() {
    let d = 1e14;
    let r = std::f64::consts::FRAC_1_SQRT_2;
    for (element, interface, rule) in [
        ("wedge6", "inter6", "gauss"),
        ("wedge6", "inter6", "lobatto"),
        ("wedge15", "inter12", "gauss"),
    ] {
        for (file, k, voigt, modulus) in [
            ("prism_tension.toml", 2, 2, p_modulus()),
            ("prism_shear_x.toml", 0, 5, shear_modulus()),
        ] {
            let s = run_scene(file, |t| {
                t.replace("element = \"h27\"", &format!("element = \"{element}\""))
                    .replace("divisions = [1, 1, 1]", "divisions = [2, 2, 1]")
                    .replace("d = 1.0e25", &format!("d = {d:e}"))
                    .replace(
                        "integration = \"gauss\"",
                        &format!("integration = \"{rule}\""),
                    )
            });
            let name = format!("{file} {element} {interface} {rule}");
            assert_eq!(s["elements"][element].as_u64(), Some(16), "{name}");
            assert_eq!(s["elements"][interface].as_u64(), Some(8), "{name}");
            let value = DELTA / (H / modulus + 1.0 / d);
            for solid in ["lower", "upper"] {
                for key in ["stress_min", "stress_max"] {
                    let v = f(&s["solids"][solid][key][voigt]);
                    assert!(rel(v, value) < 1e-6, "{name}: {solid} {key} {v:e}");
                }
            }
            let reaction = f(&s["reactions"]["upper.z1"][k]);
            assert!(
                rel(reaction, value * AREA) < 1e-6,
                "{name}: {reaction:e} vs {:e}",
                value * AREA
            );
            // [min, max] of the local components 0, 1, 2
            let want: [[f64; 2]; 3] = if k == 2 {
                [[0.0, 0.0], [0.0, 0.0], [value, value]]
            } else {
                [[r * value, value], [-r * value, 0.0], [0.0, 0.0]]
            };
            let b = &s["interfaces"]["bond"];
            for (c, [lo, hi]) in want.iter().enumerate() {
                for (key, scale) in [("traction", 1.0), ("jump", 1.0 / d)] {
                    let (gmin, gmax) = (
                        f(&b[format!("{key}_min")][c]),
                        f(&b[format!("{key}_max")][c]),
                    );
                    let tol = 1e-6 * value * scale;
                    assert!(
                        (gmin - lo * scale).abs() < tol && (gmax - hi * scale).abs() < tol,
                        "{name}: {key}[{c}] in [{gmin:e}, {gmax:e}], expected [{:e}, {:e}]",
                        lo * scale,
                        hi * scale
                    );
                }
            }
        }
    }
}

/// interfaces.vtu of a wedge15 prism: the 8 INTER12 as mid-surface
/// VTK_QUADRATIC_TRIANGLE cells (type 22, 6 points each, our node order =
/// VTK's), on the 25 node pairs of the surface ((2 x 2 + 1)^2 for the 2 x
/// 2 cells); results.vtu holds the 16 wedges as VTK_QUADRATIC_WEDGE (26).
#[test]
fn wedge15_prism_writes_quadratic_triangles() {
    let text = std::fs::read_to_string(repo().join("examples/paper/prism_tension.toml"))
        .unwrap()
        .replace("element = \"h27\"", "element = \"wedge15\"")
        .replace("divisions = [1, 1, 1]", "divisions = [2, 2, 1]");
    let dir = tempfile::tempdir().unwrap();
    let scene = write(dir.path(), "w.toml", &text);
    run_ok(&scene, &dir.path().join("out"));
    let ints = |file: &str, name: &str| -> Vec<u64> {
        let vtu = std::fs::read_to_string(dir.path().join("out").join(file)).unwrap();
        let at = vtu.find(&format!("Name=\"{name}\"")).unwrap();
        let body = &vtu[at..];
        let body = &body[body.find('>').unwrap() + 1..body.find("</DataArray>").unwrap()];
        body.split_whitespace()
            .map(|t| t.parse().unwrap())
            .collect()
    };
    assert_eq!(ints("interfaces.vtu", "types"), vec![22; 8]);
    let conn = ints("interfaces.vtu", "connectivity");
    assert_eq!(conn.len(), 48);
    assert_eq!(conn.iter().max(), Some(&24));
    assert_eq!(ints("results.vtu", "types"), vec![26; 16]);
}
