//! CalculiX / Abaqus decks as users write them (issue 12, part 1): each
//! keyword or parameter against a CalculiX run of the same deck.

mod common;
use common::*;

/// `examples/cube.inp` with its `*STATIC` line replaced.
fn cube_with_static(dir: &std::path::Path, static_line: &str) -> std::path::PathBuf {
    let text = std::fs::read_to_string(repo().join("examples/cube.inp")).unwrap();
    let out: Vec<String> = text
        .lines()
        .map(|l| {
            if l.trim().to_uppercase().starts_with("*STATIC") {
                static_line.to_string()
            } else {
                l.to_string()
            }
        })
        .collect();
    write(dir, "cube.inp", &out.join("\n"))
}

/// `*STATIC, SOLVER=SPOOLES` (what the CalculiX manual writes) runs on the
/// direct back end and gives the cube's reaction of CalculiX 2.20
/// (Fz = -2224.553 on TOP, README's examples table); the iterative names go
/// to CG.
#[test]
fn static_solver_parameter_maps_to_back_ends() {
    let dir = tempfile::tempdir().unwrap();
    for (line, key) in [
        ("*STATIC, SOLVER=SPOOLES", "cholesky"),
        ("*static, solver=Pardiso", "cholesky"),
        ("*STATIC, SOLVER=ITERATIVE CHOLESKY, TIME RESET", "cg"),
        ("*STATIC,SOLVER=iterative scaling", "cg"),
    ] {
        let deck = cube_with_static(dir.path(), line);
        let s = run_ok(&deck, &dir.path().join(key));
        let notes = s["notes"].to_string();
        assert!(notes.contains(&format!("`{key}`")), "{line}: {notes}");
        assert_eq!(s["solver"]["name"], key, "{line}");
        let fz = s["reactions"]["TOP"][2].as_f64().unwrap();
        assert!(rel(fz, -2224.553) < 1e-6, "{line}: {fz}");
    }
}

#[test]
fn static_parameters_that_change_the_answer_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let deck = cube_with_static(dir.path(), "*STATIC, STABILIZE");
    let err = run_err(&deck);
    assert!(err.contains("STABILIZE") && err.contains(":55:"), "{err}");
    // RIKS on a linear model: the linear answer (CalculiX 2.20's reaction),
    // with a note (a softening deck runs it with path following:
    // cohesive_deck.rs)
    let deck = cube_with_static(dir.path(), "*STATIC, RIKS");
    let s = run_ok(&deck, &dir.path().join("riks"));
    let fz = s["reactions"]["TOP"][2].as_f64().unwrap();
    assert!(rel(fz, -2224.553) < 1e-6, "{fz}");
    assert!(
        s.to_string()
            .contains("RIKS on a model without a softening law"),
        "{s}"
    );
    let deck = cube_with_static(dir.path(), "*STATIC, SOLVER=MAGIC");
    let err = run_err(&deck);
    assert!(err.contains("MAGIC") && err.contains("SPOOLES"), "{err}");
    let deck = cube_with_static(dir.path(), "*STATIC, BOGUS=1");
    let err = run_err(&deck);
    assert!(err.contains("BOGUS"), "{err}");
}

/// `*NODE PRINT` becomes node_print.csv: the cube's `TOTALS=ONLY` RF
/// request gives one row with CalculiX 2.20's total (Fz = -2224.553 on TOP,
/// README); a `U` request lists the set's nodes in ascending label with the
/// prescribed -0.01 in z (exact).
#[test]
fn node_print_is_written_as_csv() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(repo().join("examples/cube.inp")).unwrap();
    let text = text.replace("*END STEP", "*node print, nset=top\nU\n*END STEP");
    let deck = write(dir.path(), "cube.inp", &text);
    run_ok(&deck, &dir.path().join("out"));
    let csv = std::fs::read_to_string(dir.path().join("out/node_print.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some("step,set,variable,node,1,2,3"));
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows[0][..4], ["1", "TOP", "RF", "total"]);
    let fz: f64 = rows[0][6].parse().unwrap();
    assert!(rel(fz, -2224.553) < 1e-6, "{fz}");
    let u: Vec<&Vec<&str>> = rows.iter().filter(|r| r[2] == "U").collect();
    assert_eq!(u.len(), 9, "{csv}");
    let labels: Vec<usize> = u.iter().map(|r| r[3].parse().unwrap()).collect();
    assert!(labels.windows(2).all(|w| w[0] < w[1]), "{labels:?}");
    for r in &u {
        assert_eq!(r[6].parse::<f64>().unwrap(), -0.01, "{r:?}");
    }
}

/// The integers of the VTU DataArray `name` (ascii).
fn vtu_ints(vtu: &str, name: &str) -> Vec<u64> {
    let tag = format!("Name=\"{name}\"");
    let at = vtu
        .find(&tag)
        .unwrap_or_else(|| panic!("no {name} in the VTU"));
    let body = &vtu[at..];
    let body = &body[body.find('>').unwrap() + 1..body.find("</DataArray>").unwrap()];
    body.split_whitespace()
        .map(|t| t.parse().unwrap())
        .collect()
}

/// results.vtu carries the deck's own numbers: the cube's elements
/// renumbered 101..108 (in deck order) come back as `element_id`, its
/// nodes as `node_id` in point order.
#[test]
fn vtu_carries_the_deck_labels() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(repo().join("examples/cube.inp")).unwrap();
    let mut in_elements = false;
    let mut out = Vec::new();
    for l in text.lines() {
        if l.starts_with('*') {
            in_elements = l.to_uppercase().starts_with("*ELEMENT");
            out.push(l.to_string());
        } else if in_elements {
            let (label, rest) = l.split_once(',').unwrap();
            out.push(format!(
                "{},{rest}",
                100 + label.trim().parse::<u64>().unwrap()
            ));
        } else {
            out.push(l.to_string());
        }
    }
    let deck = write(dir.path(), "cube.inp", &out.join("\n"));
    run_ok(&deck, &dir.path().join("out"));
    let vtu = std::fs::read_to_string(dir.path().join("out/results.vtu")).unwrap();
    assert_eq!(
        vtu_ints(&vtu, "element_id"),
        (101..=108).collect::<Vec<_>>()
    );
    assert_eq!(vtu_ints(&vtu, "node_id"), (1..=27).collect::<Vec<_>>());
}

/// `*ELASTIC, TYPE=ORTHO` (nine D_ijkl) on the unit cube, TOP sheared by
/// 0.002 in x and compressed by 0.01 in z: CalculiX 2.11 on the same deck
/// (tests/data/ortho_cube.inp, `ccx ortho_cube`) prints the TOP total force
/// 4.169381E+01, -1.947878E-14, -8.090795E+02.
#[test]
fn elastic_ortho_matches_calculix() {
    let dir = tempfile::tempdir().unwrap();
    let deck = repo().join("crates/cli/tests/data/ortho_cube.inp");
    let s = run_ok(&deck, dir.path());
    let r = &s["reactions"]["TOP"];
    let (fx, fz) = (r[0].as_f64().unwrap(), r[2].as_f64().unwrap());
    assert!(rel(fx, 4.169381e1) < 2e-6, "{fx}");
    assert!(rel(fz, -8.090795e2) < 2e-6, "{fz}");
}

/// `node_print.csv` rows of `(set, variable)` of step 1: node -> [x, y, z].
fn printed(dir: &std::path::Path, set: &str, var: &str) -> Vec<(String, [f64; 3])> {
    printed_at(dir, 1, set, var)
}

/// `node_print.csv` rows of `(step, set, variable)`: node -> [x, y, z].
fn printed_at(dir: &std::path::Path, step: usize, set: &str, var: &str) -> Vec<(String, [f64; 3])> {
    let csv = std::fs::read_to_string(dir.join("node_print.csv")).unwrap();
    csv.lines()
        .skip(1)
        .map(|l| l.split(',').collect::<Vec<_>>())
        .filter(|r| r[0] == step.to_string() && r[1] == set && r[2] == var)
        .map(|r| {
            let v = |i: usize| r[i].parse::<f64>().unwrap();
            (r[3].to_string(), [v(4), v(5), v(6)])
        })
        .collect()
}

/// `*EQUATION` (tests/data/equation_cube.inp: 2- and 3-term equations, a
/// cascade, loads on the constrained face) against CalculiX 2.20 on the
/// same deck (`ccx -i equation_cube`, equation_cube.dat): displacements of
/// TOP and the BOTTOM total force, 7 printed digits.
#[test]
fn equation_matches_calculix() {
    const CCX_TOP_U: [(usize, [f64; 3]); 9] = [
        (19, [1.312892E-03, -6.236153E-04, -4.479507E-03]),
        (20, [3.685192E-04, -5.306496E-04, -4.479507E-03]),
        (21, [2.257265E-03, 3.685192E-04, -4.479507E-03]),
        (22, [3.342346E-04, 1.400270E-04, -4.479507E-03]),
        (23, [1.509031E-03, -9.014559E-04, -4.479507E-03]),
        (24, [1.954907E-03, 7.844389E-06, -4.479507E-03]),
        (25, [8.308703E-04, 9.090289E-04, -4.479507E-03]),
        (26, [3.634812E-04, 6.693411E-04, -4.479507E-03]),
        (27, [1.856337E-03, 1.055066E-03, -4.479507E-03]),
    ];
    const CCX_BOTTOM_RF: [f64; 3] = [-8.737777E+01, -1.262223E+01, 1.000000E+03];
    let dir = tempfile::tempdir().unwrap();
    let deck = repo().join("crates/cli/tests/data/equation_cube.inp");
    let s = run_ok(&deck, dir.path());
    assert!(
        s["notes"].to_string().contains("*EQUATION"),
        "{}",
        s["notes"]
    );
    let u = printed(dir.path(), "TOP", "U");
    assert_eq!(u.len(), 9);
    for ((node, got), (label, want)) in u.iter().zip(CCX_TOP_U) {
        assert_eq!(node, &label.to_string());
        for c in 0..3 {
            assert!(
                (got[c] - want[c]).abs() < 1e-6 * 4.5e-3,
                "node {node} u{}: {} vs CalculiX {}",
                c + 1,
                got[c],
                want[c]
            );
        }
    }
    let rf = printed(dir.path(), "BOTTOM", "RF");
    for c in 0..3 {
        assert!((rf[0].1[c] - CCX_BOTTOM_RF[c]).abs() < 1e-5, "{rf:?}");
    }

    // Abaqus' node-set form: one equation per member, the single node
    // repeated; same answer as the eight explicit equations
    let text = std::fs::read_to_string(&deck).unwrap();
    let explicit: String = (19..27)
        .map(|n| format!("2\n{n}, 3, 1.0, 27, 3, -1.0\n"))
        .collect();
    assert!(text.contains(&explicit));
    let sets = text.replace(&explicit, "2\nTOPZ, 3, 1.0, 27, 3, -1.0\n");
    let sets = sets.replacen(
        "\n*EQUATION\n",
        "\n*NSET, NSET=TOPZ\n19, 20, 21, 22, 23, 24, 25, 26\n*EQUATION\n",
        1,
    );
    let sets_deck = write(dir.path(), "sets.inp", &sets);
    run_ok(&sets_deck, &dir.path().join("sets"));
    let u2 = printed(&dir.path().join("sets"), "TOP", "U");
    for (a, b) in u.iter().zip(&u2) {
        for c in 0..3 {
            assert!((a.1[c] - b.1[c]).abs() < 1e-15, "{a:?} {b:?}");
        }
    }
}

/// Mistakes in `*EQUATION` name the line and what is wrong.
#[test]
fn equation_errors_name_the_line() {
    let dir = tempfile::tempdir().unwrap();
    let text =
        std::fs::read_to_string(repo().join("crates/cli/tests/data/equation_cube.inp")).unwrap();
    let line_of = |t: &str, pat: &str| t.lines().position(|l| l == pat).unwrap() + 1;
    // a dependent with a boundary condition
    let bad = text.replace("2\n19, 3, 1.0, 27, 3, -1.0", "2\n1, 3, 1.0, 27, 3, -1.0");
    let l = line_of(&bad, "1, 3, 1.0, 27, 3, -1.0");
    let err = run_err(&write(dir.path(), "a.inp", &bad));
    assert!(
        err.contains(&format!("a.inp:{}", l - 1)) && err.contains("boundary condition"),
        "{err}"
    );
    // a cycle: 21 y defined through 20 x, which is defined through 21 y
    let bad = text.replace("*STEP", "*EQUATION\n2\n21, 2, 1.0, 20, 1, -1.0\n*STEP");
    let err = run_err(&write(dir.path(), "b.inp", &bad));
    assert!(
        err.contains("cycle") || err.contains("already the dependent"),
        "{err}"
    );
    // fewer terms than announced
    let bad = text.replace("3\n19, 1, 2.0", "4\n19, 1, 2.0");
    let err = run_err(&write(dir.path(), "c.inp", &bad));
    assert!(err.contains("4 terms"), "{err}");
    // rotational dof
    let bad = text.replace("20, 1, -3.0, 21, 2, 3.0", "20, 1, -3.0, 21, 5, 3.0");
    let err = run_err(&write(dir.path(), "d.inp", &bad));
    assert!(err.contains("degree of freedom 5"), "{err}");
}

/// `*DLOAD` (GRAV, P4, CENTRIF with OP=NEW), `*SURFACE` and `*DSLOAD` on
/// tests/data/dload_cube.inp against CalculiX 2.20 on the same deck
/// (`ccx -i dload_cube`, dload_cube.dat, both steps): TOP displacements and
/// the BOTTOM total force as CalculiX prints it (the elements' force, which
/// leaves out the loads applied on the fixed nodes themselves), while the
/// summary's reactions balance every applied load (closed form: gravity
/// 100 (0, 0.6, -0.8), pressure 10 on the unit top, 5 on two quarter x+
/// faces; centrifugal 1000 x volume 1 x centroid distance 0.5 in y).
#[test]
fn distributed_loads_match_calculix() {
    // (step, node, [ux, uy, uz]) for nodes 19, 21, 25, 27
    const CCX_U: [(usize, usize, [f64; 3]); 8] = [
        (1, 19, [-4.355548E-05, 6.907770E-04, 3.546387E-05]),
        (1, 21, [-2.972263E-05, 7.145958E-04, -2.245874E-04]),
        (1, 25, [-1.760065E-05, 7.345194E-04, -4.861789E-04]),
        (1, 27, [1.293786E-05, 7.073717E-04, -4.555528E-04]),
        (2, 19, [-4.483310E-05, 5.682460E-03, 1.937350E-03]),
        (2, 21, [-1.969378E-18, 5.931570E-03, -1.808630E-04]),
        (2, 25, [-1.883801E-18, 6.074448E-03, -2.411323E-03]),
        (2, 27, [2.357430E-04, 5.963036E-03, -2.316877E-03]),
    ];
    const CCX_RF: [[f64; 3]; 2] = [[1.875, -45.0, 70.0], [0.0, -375.0, 0.0]];
    let dir = tempfile::tempdir().unwrap();
    let deck = repo().join("crates/cli/tests/data/dload_cube.inp");
    let s = run_ok(&deck, dir.path());
    let row = |step: usize, set: &str, var: &str, node: &str| -> [f64; 3] {
        printed_at(dir.path(), step, set, var)
            .into_iter()
            .find(|r| r.0 == node)
            .unwrap_or_else(|| panic!("no row {step} {set} {var} {node}"))
            .1
    };
    for (step, node, want) in CCX_U {
        let got = row(step, "TOP", "U", &node.to_string());
        let scale = if step == 1 { 7e-4 } else { 6e-3 };
        for c in 0..3 {
            assert!(
                (got[c] - want[c]).abs() < 2e-6 * scale,
                "step {step} node {node} u{}: {} vs CalculiX {}",
                c + 1,
                got[c],
                want[c]
            );
        }
    }
    for (k, want) in CCX_RF.iter().enumerate() {
        let got = row(k + 1, "BOTTOM", "RF", "total");
        for c in 0..3 {
            assert!(
                (got[c] - want[c]).abs() < 1e-5 * 375.0,
                "step {}: {got:?}",
                k + 1
            );
        }
    }
    // equilibrium reactions: minus the applied totals
    let steps = s["steps"].as_array().expect("two steps");
    let r1 = &steps[0]["reactions"]["BOTTOM"];
    let r2 = &steps[1]["reactions"]["BOTTOM"];
    let applied1 = [-2.5, 60.0, -80.0 - 10.0];
    let applied2 = [0.0, 500.0, 0.0];
    for c in 0..3 {
        assert!((r1[c].as_f64().unwrap() + applied1[c]).abs() < 1e-9, "{r1}");
        assert!((r2[c].as_f64().unwrap() + applied2[c]).abs() < 1e-9, "{r2}");
    }
}

/// Mistakes in distributed loads name the line and what would be valid.
#[test]
fn distributed_load_errors_name_the_line() {
    let dir = tempfile::tempdir().unwrap();
    let text =
        std::fs::read_to_string(repo().join("crates/cli/tests/data/dload_cube.inp")).unwrap();
    let line_of = |t: &str, pat: &str| t.lines().position(|l| l == pat).unwrap() + 1;
    for (from, to, expect) in [
        ("2, P4, 5.", "2, P7, 5.", "P1..P6"),
        ("2, P4, 5.", "2, HP, 5.", "not supported"),
        (
            "TOPS, P, 10.",
            "NOPE, P, 10.",
            "element surface `NOPE` is not defined",
        ),
        ("TOPEL, S2", "TOPEL, S9", "S1..S6"),
        (
            "EALL, GRAV, 100., 0., 0.6, -0.8",
            "EALL, GRAV, 100., 0., 0., 0.",
            "no length",
        ),
        (
            "EALL, GRAV, 100., 0., 0.6, -0.8",
            "EALL, GRAV, 100.",
            "takes 4 values",
        ),
    ] {
        let bad = text.replacen(from, to, 1);
        let l = line_of(&bad, to);
        let err = run_err(&write(dir.path(), "bad.inp", &bad));
        assert!(
            err.contains(&format!("bad.inp:{l}:")) && err.contains(expect),
            "{to}: {err}"
        );
    }
    // a surface face written P2 (CalculiX's *DLOAD face name) is S2
    let p_faces = text.replacen("TOPEL, S2", "TOPEL, P2", 1);
    run_ok(&write(dir.path(), "p.inp", &p_faces), &dir.path().join("p"));
    run_ok(&write(dir.path(), "s.inp", &text), &dir.path().join("s"));
    assert_eq!(
        std::fs::read_to_string(dir.path().join("p/node_print.csv")).unwrap(),
        std::fs::read_to_string(dir.path().join("s/node_print.csv")).unwrap()
    );
    // GRAV without a density names the material
    let bad = text.replacen("*DENSITY\n1.0\n", "", 1);
    let err = run_err(&write(dir.path(), "bad.inp", &bad));
    assert!(err.contains("*DENSITY") && err.contains("STEEL"), "{err}");
}

/// `*ORIENTATION` (rectangular) on `*SOLID SECTION, ORIENTATION=` with
/// `*ELASTIC, TYPE=ORTHO` (bottom layer) and `TYPE=ANISO` with couplings
/// (top layer), tests/data/orient_cube.inp, against CalculiX 2.20 on the
/// same deck (`ccx -i orient_cube`, orient_cube.dat): TOP total force and
/// the mid-plane displacements.
#[test]
fn orientation_and_aniso_match_calculix() {
    const CCX_RF: [f64; 3] = [-9.521915E-01, -2.559927E+01, -8.998045E+02];
    const CCX_U: [(&str, [f64; 3]); 4] = [
        ("5", [-6.652058E-04, -2.814890E-03, -5.535535E-03]),
        ("11", [2.732443E-03, -3.013099E-03, -5.750389E-03]),
        ("16", [-6.031371E-04, 2.510572E-05, -5.653035E-03]),
        ("18", [2.478011E-03, 1.619381E-04, -5.778593E-03]),
    ];
    let dir = tempfile::tempdir().unwrap();
    let deck = repo().join("crates/cli/tests/data/orient_cube.inp");
    run_ok(&deck, dir.path());
    let rf = printed(dir.path(), "TOP", "RF");
    for c in 0..3 {
        assert!((rf[0].1[c] - CCX_RF[c]).abs() < 1e-6 * 900.0, "{rf:?}");
    }
    let u = printed(dir.path(), "MIDPLANE", "U");
    for (node, want) in CCX_U {
        let got = u.iter().find(|r| r.0 == node).unwrap().1;
        for c in 0..3 {
            assert!(
                (got[c] - want[c]).abs() < 1e-6 * 6e-3,
                "node {node}: {got:?} vs CalculiX {want:?}"
            );
        }
    }

    // Abaqus' origin c (values 7-9): axes along a - c and b - c, so the
    // shifted points give the same answer, with a note
    let text = std::fs::read_to_string(&deck).unwrap();
    let shifted = text.replace(
        "1., 2., 3.5, 0., 3., 3.",
        "2., 3., 5.5, 1., 4., 5., 1., 1., 2.",
    );
    assert_ne!(shifted, text);
    let s = run_ok(&write(dir.path(), "c.inp", &shifted), &dir.path().join("c"));
    assert!(
        s["notes"].to_string().contains("origin c"),
        "{}",
        s["notes"]
    );
    let rf2 = printed(&dir.path().join("c"), "TOP", "RF");
    for c in 0..3 {
        assert!(
            (rf2[0].1[c] - rf[0].1[c]).abs() < 1e-9 * 900.0,
            "{rf2:?} {rf:?}"
        );
    }

    // errors name the line: a spherical system, an unknown name, a
    // degenerate system, a non-positive-definite ANISO stiffness
    let line_of = |t: &str, pat: &str| t.lines().position(|l| l.starts_with(pat)).unwrap() + 1;
    for (from, to, at, expect) in [
        (
            "*ORIENTATION, NAME=R2, SYSTEM=RECTANGULAR",
            "*ORIENTATION, NAME=R2, SYSTEM=SPHERICAL",
            "*ORIENTATION, NAME=R2",
            "SPHERICAL",
        ),
        (
            "MATERIAL=ORTHO, ORIENTATION=R1",
            "MATERIAL=ORTHO, ORIENTATION=R9",
            "*SOLID SECTION, ELSET=LOW",
            "orientation `R9` is not defined",
        ),
        (
            "1., 1., 0., -1., 1., 0.3",
            "1., 1., 0., 2., 2., 0.",
            "1., 1., 0.,",
            "must not lie",
        ),
    ] {
        let bad = text.replacen(from, to, 1);
        let l = line_of(&bad, at);
        let err = run_err(&write(dir.path(), "bad.inp", &bad));
        assert!(
            err.contains(&format!("bad.inp:{l}")) && err.contains(expect),
            "{to}: {err}"
        );
    }
    let bad = text.replacen(
        "*ELASTIC, TYPE=ANISO\n200000.",
        "*ELASTIC, TYPE=ANISO\n-200000.",
        1,
    );
    let err = run_err(&write(dir.path(), "bad.inp", &bad));
    assert!(
        err.contains("ANISO") || err.contains("positive definite"),
        "{err}"
    );
}

/// `*ORIENTATION, SYSTEM=CYLINDRICAL` (material axes r, theta, z about the
/// axis through points a and b, taken at every integration point as
/// CalculiX does) on a quarter of a thick tube about a skew axis, strongly
/// orthotropic (E_r 10000, E_theta 200000, E_z 50000), clamped at one end,
/// inner pressure and end loads (tests/data/cyl_ring_c3d20.inp: C3D20R with
/// ENGINEERING CONSTANTS, C3D20 with ORTHO, C3D20 with ANISO couplings;
/// cyl_ring_c3d8.inp: C3D8; both written by make_cyl_decks.py). Reference:
/// CalculiX 2.20 on the same decks (`ccx -i cyl_ring_c3d20`, `ccx -i
/// cyl_ring_c3d8`, their .dat files, 7 printed digits): U of END and the
/// FIX total force.
#[test]
fn cylindrical_orientation_matches_calculix() {
    const C3D20_U: [(&str, [f64; 3]); 13] = [
        ("49", [2.505462E-01, 2.252824E-01, 2.171219E-01]),
        ("50", [2.696399E-01, 2.025963E-01, 2.015568E-01]),
        ("51", [2.857016E-01, 1.867700E-01, 1.957808E-01]),
        ("52", [3.052947E-01, 1.846930E-01, 1.901017E-01]),
        ("53", [3.345947E-01, 1.873959E-01, 1.869181E-01]),
        ("72", [2.952620E-01, 2.271176E-01, 2.085584E-01]),
        ("73", [3.259442E-01, 1.856840E-01, 1.847548E-01]),
        ("74", [3.745909E-01, 1.860665E-01, 1.735173E-01]),
        ("123", [3.434872E-01, 2.309242E-01, 2.015651E-01]),
        ("124", [3.562513E-01, 2.035850E-01, 1.829999E-01]),
        ("125", [3.669939E-01, 1.861891E-01, 1.742215E-01]),
        ("126", [3.858277E-01, 1.842905E-01, 1.661998E-01]),
        ("127", [4.156240E-01, 1.855167E-01, 1.611767E-01]),
    ];
    const C3D20_RF: [f64; 3] = [-5.321040E+03, -4.812752E+03, -1.650611E+01];
    const C3D8_U: [(&str, [f64; 3]); 12] = [
        ("49", [2.242442E-01, 1.906405E-01, 1.917661E-01]),
        ("50", [2.488460E-01, 1.694996E-01, 1.776210E-01]),
        ("51", [2.719721E-01, 1.641667E-01, 1.695403E-01]),
        ("52", [3.031696E-01, 1.652274E-01, 1.623672E-01]),
        ("101", [2.624285E-01, 1.904764E-01, 1.828431E-01]),
        ("102", [2.855047E-01, 1.695012E-01, 1.681786E-01]),
        ("103", [3.076549E-01, 1.646589E-01, 1.589719E-01]),
        ("104", [3.391823E-01, 1.656006E-01, 1.509511E-01]),
        ("153", [3.025533E-01, 1.911723E-01, 1.751710E-01]),
        ("154", [3.228865E-01, 1.704793E-01, 1.590860E-01]),
        ("155", [3.435921E-01, 1.657712E-01, 1.488141E-01]),
        ("156", [3.760369E-01, 1.663654E-01, 1.404958E-01]),
    ];
    const C3D8_RF: [f64; 3] = [-5.181200E+03, -4.799392E+03, -5.765535E+00];
    for (name, want_u, want_rf) in [
        ("cyl_ring_c3d20.inp", &C3D20_U[..], C3D20_RF),
        ("cyl_ring_c3d8.inp", &C3D8_U[..], C3D8_RF),
    ] {
        let dir = tempfile::tempdir().unwrap();
        run_ok(&repo().join("crates/cli/tests/data").join(name), dir.path());
        let u = printed(dir.path(), "END", "U");
        assert_eq!(u.len(), want_u.len(), "{name}: {u:?}");
        for (node, want) in want_u {
            let got = u.iter().find(|r| r.0 == *node).unwrap().1;
            for c in 0..3 {
                assert!(
                    rel(got[c], want[c]) < 1e-5,
                    "{name} node {node}: {got:?} vs CalculiX {want:?}"
                );
            }
        }
        let rf = printed(dir.path(), "FIX", "RF");
        for c in 0..3 {
            assert!(
                (rf[0].1[c] - want_rf[c]).abs() < 1e-5 * 5.4e3,
                "{name}: {rf:?} vs CalculiX {want_rf:?}"
            );
        }
    }

    // *EL PRINT of an oriented element: CalculiX prints the stresses in
    // the material axes at each point (r, theta, z; xx, yy, zz, xy, xz, yz)
    #[rustfmt::skip]
    const C3D8_S: [[f64; 6]; 8] = [
        [3.327823E+01, 1.089114E+02, 2.995328E+01, 1.134206E+02, 8.746922E+00, 1.316460E+01],
        [2.867618E+01, -2.496425E+01, 1.712309E+01, 9.199713E+01, 1.014870E+01, 9.251793E+00],
        [1.885074E+01, -1.129350E+02, 6.583349E+00, 1.077650E+02, 7.528835E+00, 7.037313E+00],
        [1.553545E+01, -2.045685E+02, -3.300751E+00, 8.601528E+01, 9.540475E+00, 1.679375E+00],
        [3.274405E+01, 3.758934E+01, 2.420349E+01, 1.282242E+02, 8.806589E+00, 1.484164E+01],
        [2.782567E+01, -1.052702E+02, 1.046225E+01, 1.060572E+02, 1.020837E+01, 1.030060E+01],
        [1.819703E+01, -2.120808E+02, -1.342863E+00, 1.216084E+02, 7.481507E+00, 8.713190E+00],
        [1.461808E+01, -3.112024E+02, -1.198632E+01, 9.909137E+01, 9.493147E+00, 2.727013E+00],
    ];
    let el_rows = |deck: &std::path::Path, out: &std::path::Path| -> Vec<[f64; 6]> {
        run_ok(deck, out);
        let text = std::fs::read_to_string(out.join("el_print.csv")).unwrap();
        text.lines()
            .skip(1)
            .map(|l| {
                let r: Vec<f64> = l.split(',').skip(5).map(|x| x.parse().unwrap()).collect();
                r.try_into().unwrap()
            })
            .collect()
    };
    let dir = tempfile::tempdir().unwrap();
    let deck = repo().join("crates/cli/tests/data/cyl_ring_c3d8.inp");
    let local = el_rows(&deck, &dir.path().join("local"));
    assert_eq!(local.len(), 8);
    for (q, (got, want)) in local.iter().zip(&C3D8_S).enumerate() {
        for c in 0..6 {
            assert!(
                (got[c] - want[c]).abs() < 1e-5 * 311.0,
                "point {}: {got:?} vs CalculiX {want:?}",
                q + 1
            );
        }
    }
    // GLOBAL=YES: the global components, the same invariants
    let text = std::fs::read_to_string(&deck).unwrap();
    let global = text.replace(
        "*EL PRINT, ELSET=PRINTED",
        "*EL PRINT, ELSET=PRINTED, GLOBAL=YES",
    );
    assert_ne!(global, text);
    let global = el_rows(&write(dir.path(), "g.inp", &global), &dir.path().join("g"));
    for (l, g) in local.iter().zip(&global) {
        assert!((l[0] - g[0]).abs() > 1.0, "{l:?} {g:?}");
        assert!(((l[0] + l[1] + l[2]) - (g[0] + g[1] + g[2])).abs() < 1e-9 * 311.0);
    }
}

/// A malformed cylindrical `*ORIENTATION` is an error naming its data line:
/// coincident axis points, 9 values (an origin c has no meaning for a
/// cylindrical system), too few values, an additional rotation.
#[test]
fn cylindrical_orientation_errors_name_the_line() {
    let dir = tempfile::tempdir().unwrap();
    let text =
        std::fs::read_to_string(repo().join("crates/cli/tests/data/cyl_ring_c3d8.inp")).unwrap();
    let data = text
        .lines()
        .skip_while(|l| !l.starts_with("*ORIENTATION"))
        .nth(1)
        .unwrap();
    let at = text.lines().position(|l| l == data).unwrap() + 1;
    for (bad_data, expect) in [
        ("1.0, 2.0, 3.0, 1.0, 2.0, 3.0", "must differ"),
        (
            "1.0, 2.0, 3.0, 1.0, 2.0, 4.0, 0.0, 0.0, 0.0",
            "expected 6 values",
        ),
        ("1.0, 2.0, 3.0, 1.0, 2.0", "expected 6 values"),
        (
            "1.0, 2.0, 3.0, 1.0, 2.0, 4.0\n3, 10.0",
            "additional rotation",
        ),
    ] {
        let bad = text.replacen(data, bad_data, 1);
        let line = if bad_data.contains('\n') { at + 1 } else { at };
        let err = run_err(&write(dir.path(), "bad.inp", &bad));
        assert!(
            err.contains(&format!("bad.inp:{line}")) && err.contains(expect),
            "{bad_data}: {err}"
        );
    }
}

/// `*AMPLITUDE` in a linear static deck against CalculiX 2.20 on the same
/// deck (`tests/data/amplitude_cube.inp`; values from its `.dat`): a
/// `*CLOAD` scaled by a step-time amplitude at the step's end (0.5), the
/// same load carried unchanged into a step that does not give it again
/// (CalculiX keeps its value, not the amplitude at the new time), a
/// `TIME=TOTAL TIME` amplitude beyond its last point (constant 3), a
/// `*DLOAD` pressure at A(1.5) = 0.75 and a prescribed `*BOUNDARY` at
/// A(3) = 3 (uz = 0.03, total force 30 = E A u / h).
#[test]
fn amplitude_matches_calculix() {
    const CCX_UZ: [f64; 5] = [2.0e-3, 2.0e-3, 1.2e-2, 7.5e-4, 3.0e-2];
    let dir = tempfile::tempdir().unwrap();
    let deck = repo().join("crates/cli/tests/data/amplitude_cube.inp");
    run_ok(&deck, dir.path());
    for (k, want) in CCX_UZ.iter().enumerate() {
        let rows = printed_at(dir.path(), k + 1, "TOP", "U");
        let got = rows.iter().find(|r| r.0 == "5").expect("node 5").1;
        assert!(
            (got[2] - want).abs() < 1e-6 * want,
            "step {}: uz {} vs CalculiX {want}",
            k + 1,
            got[2]
        );
    }
    let rf = printed_at(dir.path(), 5, "TOP", "RF");
    let total = rf.iter().find(|r| r.0 == "total").expect("total").1;
    assert!((total[2] - 30.0).abs() < 1e-6 * 30.0, "{total:?}");
}

/// Mistakes with amplitudes name the line and what would be valid.
#[test]
fn amplitude_errors_name_the_line() {
    let base =
        std::fs::read_to_string(repo().join("crates/cli/tests/data/amplitude_cube.inp")).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let cases: [(&str, &str, &str); 5] = [
        (
            "*CLOAD, AMPLITUDE=A1\n",
            "*CLOAD, AMPLITUDE=NOPE\n",
            "no *AMPLITUDE of that name",
        ),
        (
            "*AMPLITUDE, NAME=A1\n",
            "*AMPLITUDE, NAME=A1, DEFINITION=SMOOTH STEP\n",
            "DEFINITION=TABULAR",
        ),
        (
            "0., 0., 1., 0.5, 2., 1.0, 3., 3.\n*AMPLITUDE, NAME=A2",
            "0., 0., 1., 0.5, 2., 1.0, 3.\n*AMPLITUDE, NAME=A2",
            "pairs",
        ),
        (
            "0., 0., 1., 0.5, 2., 1.0, 3., 3.\n*AMPLITUDE, NAME=A2",
            "0., 0., 1., 0.5, 0.5, 1.0, 3., 3.\n*AMPLITUDE, NAME=A2",
            "must not decrease",
        ),
        (
            "*BOUNDARY\nBOT, 1, 3\n",
            "*BOUNDARY, AMPLITUDE=A1\nBOT, 1, 3\n",
            "only valid inside *STEP",
        ),
    ];
    for (from, to, want) in cases {
        assert!(base.contains(from), "{from}");
        let text = base.replacen(from, to, 1);
        let first = to.lines().next().unwrap();
        let line = text.lines().position(|l| l == first).unwrap() + 1;
        let path = dir.path().join("bad.inp");
        std::fs::write(&path, &text).unwrap();
        let out = junta()
            .args(["check", path.to_str().unwrap()])
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{to}: accepted");
        assert!(err.contains(want), "{to}: {err}");
        assert!(err.contains(&format!("bad.inp:{line}")), "{to}: {err}");
    }
}

/// `*EL PRINT` S and E against CalculiX 2.20 on the same deck
/// (`tests/data/el_print_hex.inp`: two C3D8, one skewed, loaded off-axis;
/// values copied from ccx's `.dat`): stresses and strains at every
/// integration point in CalculiX's point order and component order
/// (`xy, xz, yz`; strains with tensor shear components).
#[test]
fn el_print_matches_calculix() {
    #[rustfmt::skip]
    const CCX: [(&str, usize, usize, [f64; 6]); 12] = [
        ("S", 2, 1, [4.005031E+00, 1.160920E+00, 8.027474E-02, 9.873799E-01, -6.509272E-01, -1.749835E-01]),
        ("S", 2, 2, [4.796768E+00, 2.711024E+00, 1.053843E+00, -8.706612E-01, -8.680904E-01, -4.976293E-01]),
        ("S", 2, 3, [-1.350172E+00, -5.317104E-01, -3.034704E-01, 1.325103E+00, -5.028606E-01, -4.370587E-01]),
        ("S", 2, 4, [-1.890021E+00, -1.820957E-01, -2.231317E+00, -6.700594E-01, 5.958719E-02, -9.359542E-01]),
        ("S", 2, 5, [2.903028E+00, -8.921916E-02, -6.167564E-01, 1.193662E+00, -5.590221E-01, 5.071235E-01]),
        ("S", 2, 6, [3.396116E+00, 7.598412E-01, 8.149454E-02, 2.215369E-01, -7.941984E-01, -6.859904E-01]),
        ("S", 2, 7, [2.550738E-01, -6.357694E-01, 1.290489E-01, 1.375469E+00, -1.288096E+00, 2.197986E-01]),
        ("S", 2, 8, [-7.408492E-01, -1.031502E+00, -2.198599E+00, 2.978607E-01, -6.555218E-01, -1.102978E+00]),
        ("E", 1, 1, [2.564647E-03, -9.329375E-05, -3.310671E-04, 1.926231E-03, -1.351095E-03, -1.575309E-05]),
        ("E", 1, 2, [2.564647E-03, -3.481770E-04, -1.235559E-03, -1.109009E-03, 2.737882E-04, -5.879133E-05]),
        ("E", 1, 3, [-3.505834E-03, -9.329375E-05, 2.157040E-04, 1.798790E-03, -2.032549E-03, -6.806022E-05]),
        ("E", 1, 4, [-3.505834E-03, -3.481770E-04, 8.050184E-04, -1.236451E-03, -3.725557E-04, -2.540042E-04]),
    ];
    let dir = tempfile::tempdir().unwrap();
    let deck = repo().join("crates/cli/tests/data/el_print_hex.inp");
    run_ok(&deck, dir.path());
    let text = std::fs::read_to_string(dir.path().join("el_print.csv")).unwrap();
    let rows: Vec<Vec<&str>> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    // two variables x two elements x eight points
    assert_eq!(rows.len(), 32);
    for (var, el, pt, want) in CCX {
        let row = rows
            .iter()
            .find(|r| r[2] == var && r[3] == el.to_string() && r[4] == pt.to_string())
            .unwrap_or_else(|| panic!("no row {var} {el} {pt}"));
        let scale = want.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        for c in 0..6 {
            let got: f64 = row[5 + c].parse().unwrap();
            assert!(
                (got - want[c]).abs() < 2e-6 * scale,
                "{var} element {el} point {pt} component {}: {got} vs CalculiX {}",
                c + 1,
                want[c]
            );
        }
    }
}

/// `*DLOAD P1..P5` and `*SURFACE S4` + `*DSLOAD` on wedges
/// (tests/data/wedge_dload_c3d6.inp, wedge_dload_c3d15.inp, written by
/// make_wedge_decks.py: pressures on the bottom and top triangles, on the
/// three kinds of quadrilateral side and on internal cut faces) against
/// CalculiX 2.20 on the same decks (`ccx -i wedge_dload_c3d6`, `ccx -i
/// wedge_dload_c3d15`, their .dat files: U of TIP, the FIX total force as
/// CalculiX prints it, 7 digits); the summary's reactions balance the
/// applied totals (closed form: P1 5 on the unit bottom +z, P2 10 on the
/// top -z, P3 3 on y = 0 +y, P4 4 on x = 1 -x, P5 1.5 on the two cut faces
/// of area 0.5 sqrt 2 x 0.5 along (1, -1, 0) / sqrt 2, DSLOAD 2 on y = 1
/// -y: total (-3.25, 0.25, -5)).
#[test]
fn wedge_pressures_match_calculix() {
    const C3D6_U: [(&str, [f64; 3]); 9] = [
        ("3", [-2.500308E-05, 5.401723E-06, -4.957964E-05]),
        ("6", [-3.037164E-05, 6.934598E-06, -5.042938E-05]),
        ("9", [-3.643927E-05, 1.096069E-05, -4.945901E-05]),
        ("12", [-4.010856E-06, 4.922267E-06, -5.985071E-05]),
        ("15", [-5.159735E-06, 6.238158E-06, -6.254579E-05]),
        ("18", [-7.024604E-06, 8.888074E-06, -6.484147E-05]),
        ("21", [1.847433E-05, 4.129196E-06, -7.659887E-05]),
        ("24", [2.062577E-05, 5.708471E-06, -7.780528E-05]),
        ("27", [2.027008E-05, 7.729208E-06, -7.649550E-05]),
    ];
    const C3D15_U: [(&str, [f64; 3]); 21] = [
        ("5", [-2.566623E-05, 1.092045E-05, -5.851424E-05]),
        ("10", [-2.915128E-05, 1.045743E-05, -5.807124E-05]),
        ("15", [-3.117870E-05, 1.067862E-05, -5.757290E-05]),
        ("20", [-3.362444E-05, 1.117415E-05, -5.759987E-05]),
        ("25", [-3.556263E-05, 1.193784E-05, -5.752894E-05]),
        ("28", [-1.199633E-05, 1.009325E-05, -6.192222E-05]),
        ("31", [-1.754376E-05, 1.072439E-05, -6.178354E-05]),
        ("34", [-2.248044E-05, 1.298606E-05, -6.250963E-05]),
        ("39", [-7.402430E-07, 8.971934E-06, -6.705457E-05]),
        ("44", [-3.261799E-06, 9.770121E-06, -6.670855E-05]),
        ("49", [-5.729364E-06, 1.085499E-05, -6.707422E-05]),
        ("54", [-8.350740E-06, 1.241752E-05, -6.706144E-05]),
        ("59", [-1.137977E-05, 1.428368E-05, -6.801768E-05]),
        ("62", [1.113660E-05, 7.933576E-06, -7.564894E-05]),
        ("65", [6.894022E-06, 1.097775E-05, -7.576163E-05]),
        ("68", [8.847462E-07, 1.548375E-05, -7.693653E-05]),
        ("73", [2.556698E-05, 7.082345E-06, -8.544685E-05]),
        ("78", [2.386741E-05, 9.020423E-06, -8.510178E-05]),
        ("83", [2.143605E-05, 1.108588E-05, -8.496601E-05]),
        ("88", [1.878989E-05, 1.385248E-05, -8.524271E-05]),
        ("93", [1.448657E-05, 1.679849E-05, -8.531882E-05]),
    ];
    /// (deck, element key, CalculiX U of TIP, CalculiX total force of FIX)
    type Case<'a> = (&'a str, &'a str, &'a [(&'a str, [f64; 3])], [f64; 3]);
    let cases: [Case; 2] = [
        (
            "wedge_dload_c3d6.inp",
            "wedge6r",
            &C3D6_U,
            [3.625000E+00, -3.750000E-01, 3.750000E+00],
        ),
        (
            "wedge_dload_c3d15.inp",
            "wedge15",
            &C3D15_U,
            [3.375000E+00, -2.916667E-01, 4.583333E+00],
        ),
    ];
    for (deck, key, ccx_u, ccx_rf) in cases {
        let dir = tempfile::tempdir().unwrap();
        let s = run_ok(&repo().join("crates/cli/tests/data").join(deck), dir.path());
        assert_eq!(s["elements"][key].as_u64(), Some(16), "{}", s["elements"]);
        let u = printed(dir.path(), "TIP", "U");
        assert_eq!(u.len(), ccx_u.len(), "{deck}");
        let scale = 8.5e-5;
        for (node, want) in ccx_u {
            let got = u.iter().find(|r| r.0 == *node).unwrap().1;
            for c in 0..3 {
                assert!(
                    (got[c] - want[c]).abs() < 1e-6 * scale,
                    "{deck} node {node} u{}: {} vs CalculiX {}",
                    c + 1,
                    got[c],
                    want[c]
                );
            }
        }
        let rf = printed(dir.path(), "FIX", "RF");
        for (got, want) in rf[0].1.iter().zip(ccx_rf) {
            assert!((got - want).abs() < 1e-6 * 5.0, "{deck}: {rf:?}");
        }
        let r = &s["reactions"]["FIX"];
        let applied = [-3.25, 0.25, -5.0];
        for c in 0..3 {
            assert!(
                (r[c].as_f64().unwrap() + applied[c]).abs() < 1e-9,
                "{deck}: {r}"
            );
        }
    }
}

/// A pressure on a face a wedge does not have (`P6`, or `S6` in a
/// `*SURFACE`) is an error naming the line and the wedge's faces.
#[test]
fn wedge_pressure_on_a_missing_face_names_the_line() {
    let dir = tempfile::tempdir().unwrap();
    let text =
        std::fs::read_to_string(repo().join("crates/cli/tests/data/wedge_dload_c3d6.inp")).unwrap();
    let line_of = |t: &str, pat: &str| t.lines().position(|l| l == pat).unwrap() + 1;
    let bad = text.replacen("CUT, P5, 1.5", "CUT, P6, 1.5", 1);
    let l = line_of(&bad, "CUT, P6, 1.5");
    let err = run_err(&write(dir.path(), "bad.inp", &bad));
    assert!(
        err.contains(&format!("bad.inp:{l}:")) && err.contains("P6") && err.contains("P1..P5"),
        "{err}"
    );
    let bad = text.replacen("YHI, S4", "YHI, S6", 1);
    let l = line_of(&bad, "YHIS, P, 2.");
    let s = line_of(&bad, "*SURFACE, NAME=YHIS, TYPE=ELEMENT");
    let err = run_err(&write(dir.path(), "bad.inp", &bad));
    assert!(
        err.contains(&format!("bad.inp:{l}:"))
            && err.contains(&format!("line {s}"))
            && err.contains("S6")
            && err.contains("S1..S5"),
        "{err}"
    );
}

/// `*EL PRINT` variables beyond S and E: `ENER` (energy density at the
/// points), `ELSE` (element strain energy), `EVOL` (element volume), `ME`
/// (mechanical strains, the strains here) and `COORD` (point
/// coordinates), on tests/data/el_print_hex.inp with the request
/// `ENER, ELSE, EVOL, ME, COORD, PEEQ` added. Golden values: CalculiX 2.20
/// (`ccx -i` on the same edited deck), its `.dat`; CalculiX prints no PEEQ
/// block for an elastic material, Junta notes it and writes none.
#[test]
fn el_print_energy_volume_and_coordinates_match_calculix() {
    #[rustfmt::skip]
    const CCX: [(&str, &str, &str, &[f64]); 9] = [
        ("ENER", "1", "1", &[8.155189E-03]),
        ("ENER", "1", "5", &[2.883258E-02]),
        ("ENER", "2", "8", &[4.080570E-03]),
        ("ELSE", "1", "", &[1.136892E-02]),
        ("ELSE", "2", "", &[7.041426E-03]),
        ("EVOL", "2", "", &[1.078333E+00]),
        ("ME", "1", "6", &[5.814414E-03, -7.386028E-04, -1.235559E-03, -4.097821E-04, -1.784578E-04, 9.614975E-04]),
        ("ME", "2", "8", &[2.281811E-04, -1.496680E-04, -1.666893E-03, 3.872189E-04, -8.521783E-04, -1.433872E-03]),
        ("COORD", "2", "2", &[1.886788E+00, 2.113249E-01, 2.674253E-01]),
    ];
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(repo().join("crates/cli/tests/data/el_print_hex.inp"))
        .unwrap()
        .replace(
            "*END STEP",
            "*EL PRINT, ELSET=HEX\nENER, ELSE, EVOL, ME, COORD, PEEQ\n*END STEP",
        );
    let deck = write(dir.path(), "vars.inp", &text);
    let out = junta()
        .arg("run")
        .arg(&deck)
        .arg("-o")
        .arg(dir.path().join("out"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(err.contains("variable PEEQ is not written"), "{err}");
    let csv = std::fs::read_to_string(dir.path().join("out/el_print.csv")).unwrap();
    let rows: Vec<Vec<&str>> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    let count = |v: &str| rows.iter().filter(|r| r[2] == v).count();
    // per point: 2 elements x 8 points; per element: 2
    assert_eq!(
        ["ENER", "ELSE", "EVOL", "ME", "COORD", "PEEQ"].map(count),
        [16, 2, 2, 16, 16, 0]
    );
    for (var, el, pt, want) in CCX {
        let row = rows
            .iter()
            .find(|r| r[2] == var && r[3] == el && r[4] == pt)
            .unwrap_or_else(|| panic!("no row {var} {el} {pt}"));
        assert_eq!(row.len(), 11, "{row:?}");
        let scale = want.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        for (c, w) in want.iter().enumerate() {
            let got: f64 = row[5 + c].parse().unwrap();
            assert!(
                (got - w).abs() < 2e-6 * scale,
                "{var} element {el} point {pt} component {}: {got} vs CalculiX {w}",
                c + 1
            );
        }
        assert!(
            row[5 + want.len()..].iter().all(|f| f.is_empty()),
            "{row:?}"
        );
    }
}
