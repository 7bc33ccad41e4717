//! End-to-end tests of the `junta` binary: reference values from
//! shared/BENCHMARKS.md section 1 (CalculiX 2.20 and scikit-fem 12.0.2
//! agree on them), beam theory for the cantilever, and bad input.

mod common;
use common::*;

/// The cube deck of BENCHMARKS.md section 1 written as `.inp` (C3D8/C3D20, labels 1-based).
fn cube_deck(etype: &str, n: usize) -> String {
    let quad = etype == "C3D20";
    let p = if quad { 2 } else { 1 };
    let m = p * n + 1;
    let corners = [
        [0, 0, 0],
        [2, 0, 0],
        [2, 2, 0],
        [0, 2, 0],
        [0, 0, 2],
        [2, 0, 2],
        [2, 2, 2],
        [0, 2, 2],
    ];
    let edges = [
        (0, 1),
        (1, 2),
        (2, 3),
        (3, 0),
        (4, 5),
        (5, 6),
        (6, 7),
        (7, 4),
        (0, 4),
        (1, 5),
        (2, 6),
        (3, 7),
    ];
    let mut local: Vec<[usize; 3]> = corners.to_vec();
    if quad {
        for (a, b) in edges {
            local.push([0, 1, 2].map(|d| (corners[a][d] + corners[b][d]) / 2));
        }
    } else {
        local = local.iter().map(|v| v.map(|c| c / 2)).collect();
    }
    let mut label = std::collections::BTreeMap::new();
    let mut order = Vec::new();
    let mut elems = Vec::new();
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                let mut conn = Vec::new();
                for l in &local {
                    let key = [p * i + l[0], p * j + l[1], p * k + l[2]];
                    let next = label.len() + 1;
                    let lab = *label.entry(key).or_insert_with(|| {
                        order.push(key);
                        next
                    });
                    conn.push(lab);
                }
                elems.push(conn);
            }
        }
    }
    let mut s = String::from("*NODE\n");
    for (i, key) in order.iter().enumerate() {
        let c = key.map(|v| v as f64 / (m - 1) as f64);
        s += &format!("{}, {}, {}, {}\n", i + 1, c[0], c[1], c[2]);
    }
    s += &format!("*ELEMENT, TYPE={etype}, ELSET=EALL\n");
    for (e, conn) in elems.iter().enumerate() {
        let v: Vec<String> = std::iter::once(e + 1)
            .chain(conn.iter().copied())
            .map(|x| x.to_string())
            .collect();
        let lines: Vec<String> = v.chunks(16).map(|c| c.join(", ")).collect();
        s += &lines.join(",\n");
        s += "\n";
    }
    for (name, z) in [("BOTTOM", 0), ("TOP", m - 1)] {
        s += &format!("*NSET, NSET={name}\n");
        for (i, key) in order.iter().enumerate() {
            if key[2] == z {
                s += &format!("{},\n", i + 1);
            }
        }
    }
    s += "*MATERIAL, NAME=STEEL\n*ELASTIC\n210000, 0.3\n*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n";
    s += "*BOUNDARY\nBOTTOM, 1, 3\n*STEP\n*STATIC\n*BOUNDARY\nTOP, 3, 3, -0.01\n";
    s += "*NODE PRINT, NSET=TOP, TOTALS=ONLY\nRF\n*END STEP\n";
    s
}

fn cube_scene(element: &str, n: usize) -> String {
    let base = std::fs::read_to_string(repo().join("examples/cube.toml")).unwrap();
    base.replace("element = \"h8\"", &format!("element = \"{element}\""))
        .replace(
            "divisions = [2, 2, 2]",
            &format!("divisions = [{n}, {n}, {n}]"),
        )
}

/// BENCHMARKS.md section 1: CalculiX 2.20 / scikit-fem 12.0.2 top reactions.
const CUBE_H8_N2: f64 = -2224.553;
const CUBE_H20_N2: f64 = -2183.070;

#[test]
fn cube_deck_matches_calculix_from_inp_and_toml() {
    for (etype, key, reference) in [("C3D8", "h8", CUBE_H8_N2), ("C3D20", "h20", CUBE_H20_N2)] {
        let dir = tempfile::tempdir().unwrap();
        let deck = dir.path().join("cube.inp");
        std::fs::write(&deck, cube_deck(etype, 2)).unwrap();
        let s = run_ok(&deck, &dir.path().join("inp"));
        let fz = s["reactions"]["TOP"][2].as_f64().unwrap();
        assert!(
            rel(fz, reference) < 1e-6,
            "{etype} inp: Fz = {fz}, CalculiX {reference}"
        );
        // bottom carries the opposite force
        let fz_bottom = s["reactions"]["BOTTOM"][2].as_f64().unwrap();
        assert!(rel(-fz_bottom, reference) < 1e-6);

        let scene = dir.path().join("cube.toml");
        std::fs::write(&scene, cube_scene(key, 2)).unwrap();
        let s = run_ok(&scene, &dir.path().join("toml"));
        let fz = s["reactions"]["z1"][2].as_f64().unwrap();
        assert!(
            rel(fz, reference) < 1e-6,
            "{key} toml: Fz = {fz}, CalculiX {reference}"
        );
        assert_eq!(s["elements"][key].as_u64(), Some(8));
        assert!(dir.path().join("toml/results.vtu").exists());
    }
}

#[test]
fn shipped_cube_examples_agree_with_calculix() {
    let dir = tempfile::tempdir().unwrap();
    let a = run_ok(&repo().join("examples/cube.inp"), &dir.path().join("a"));
    let b = run_ok(&repo().join("examples/cube.toml"), &dir.path().join("b"));
    assert!(rel(a["reactions"]["TOP"][2].as_f64().unwrap(), CUBE_H8_N2) < 1e-6);
    assert!(rel(b["reactions"]["z1"][2].as_f64().unwrap(), CUBE_H8_N2) < 1e-6);
    assert_eq!(a["dofs"], b["dofs"]);
}

/// CalculiX 2.20 top reaction of the H20 n=12 cube (`bench/make_cube_deck.py
/// C3D20 12`, `ccx -i`): -2.165699E+03 (7 digits).
const CUBE_H20_N12: f64 = -2165.699;

/// 22,919 equations: enough for the default `auto` precision of the direct
/// solver to factorise in single precision and refine in double. The
/// answer matches CalculiX to its printed digits and the double-precision
/// factor to 1e-10.
#[test]
fn cube_h20_n12_in_mixed_precision_matches_calculix_and_double() {
    let dir = tempfile::tempdir().unwrap();
    let deck = dir.path().join("cube.inp");
    std::fs::write(&deck, cube_deck("C3D20", 12)).unwrap();
    let mixed = run_ok(&deck, &dir.path().join("mixed"));
    assert_eq!(mixed["solver"]["precision"], "mixed");
    // the default ordering (auto) predicts both candidates and keeps nested
    // dissection on a cube; its prediction is the exact fill, below the
    // stored count (relaxed supernodes add explicit zeros)
    assert_eq!(mixed["solver"]["ordering"], "nested_dissection");
    let predicted = &mixed["solver"]["predicted_factor_nonzeros"];
    let nd = predicted["nested_dissection"].as_u64().unwrap();
    assert!(nd < predicted["amd"].as_u64().unwrap(), "{predicted}");
    assert!(nd <= mixed["solver"]["factor_nonzeros"].as_u64().unwrap());
    assert!(mixed["solver"]["notes"][0]
        .as_str()
        .unwrap()
        .starts_with("ordering auto: nested_dissection"));
    assert!(mixed["solver"]["refinement_steps"].as_u64().unwrap() >= 1);
    assert!(mixed["solver"]["residual"].as_f64().unwrap() < 1e-12);
    let fz_mixed = mixed["reactions"]["TOP"][2].as_f64().unwrap();
    assert!(
        rel(fz_mixed, CUBE_H20_N12) < 5e-7,
        "Fz = {fz_mixed}, CalculiX {CUBE_H20_N12}"
    );
    let scene = dir.path().join("cube.toml");
    let text = cube_scene("h20", 12).replace(
        "type = \"cholesky\"",
        "type = \"cholesky\"\nprecision = \"double\"",
    );
    std::fs::write(&scene, text).unwrap();
    let double = run_ok(&scene, &dir.path().join("double"));
    assert_eq!(double["solver"]["precision"], "double");
    let fz_double = double["reactions"]["z1"][2].as_f64().unwrap();
    assert!(
        rel(fz_mixed, fz_double) < 1e-10,
        "{fz_mixed} vs {fz_double}"
    );
    // the deck with the precision forced from the command line
    let out = dir.path().join("flag");
    let o = junta()
        .args(["run", "-q", "--solver", "precision=double", "-o"])
        .arg(&out)
        .arg(&deck)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let flag: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(flag["solver"]["precision"], "double");
    assert!(rel(flag["reactions"]["TOP"][2].as_f64().unwrap(), fz_double) < 1e-12);
    // a misspelt override names the key and the valid ones
    let o = junta()
        .args(["run", "-q", "--solver", "precison=double"])
        .arg(&deck)
        .output()
        .unwrap();
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("precison") && err.contains("precision"),
        "{err}"
    );
}

#[test]
fn cube_with_cg_matches_direct() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("cube.toml");
    let text = cube_scene("h20", 2).replace("type = \"cholesky\"", "type = \"cg\"");
    std::fs::write(&scene, text).unwrap();
    let s = run_ok(&scene, &dir.path().join("o"));
    assert!(rel(s["reactions"]["z1"][2].as_f64().unwrap(), CUBE_H20_N2) < 1e-6);
    assert!(s["solver"]["iterations"].as_u64().unwrap() > 0);
}

/// Timoshenko tip deflection of the cantilever example.
fn beam_theory() -> f64 {
    let (e, nu, l, b, h, p) = (2.1e11, 0.3, 1.0, 0.1, 0.1, 1000.0);
    let i = b * h * h * h / 12.0;
    let g = e / (2.0 * (1.0 + nu));
    p * l * l * l / (3.0 * e * i) + p * l / (5.0 / 6.0 * g * b * h)
}

#[test]
fn cantilever_converges_to_beam_theory() {
    let base = std::fs::read_to_string(repo().join("examples/cantilever.toml")).unwrap();
    let exact = beam_theory();
    let dir = tempfile::tempdir().unwrap();
    let mut errors = std::collections::BTreeMap::new();
    for (el, meshes) in [
        ("h8", vec![[10, 1, 1], [20, 2, 2], [40, 4, 4]]),
        ("h20", vec![[10, 1, 1], [20, 2, 2]]),
        ("h27", vec![[10, 1, 1], [20, 2, 2]]),
    ] {
        let mut e = Vec::new();
        for divs in meshes {
            let text = base
                .replace("element = \"h20\"", &format!("element = \"{el}\""))
                .replace("divisions = [10, 1, 1]", &format!("divisions = {divs:?}"));
            let name = format!("{el}_{}", divs[0]);
            let scene = dir.path().join(format!("{name}.toml"));
            std::fs::write(&scene, text).unwrap();
            let s = run_ok(&scene, &dir.path().join(&name));
            // mean deflection of the end face
            let tip = -s["probes"]["x1"][2].as_f64().unwrap();
            e.push((tip - exact) / exact);
            // equilibrium: the clamp carries the applied 1000 N
            let fz = s["reactions"]["x0"][2].as_f64().unwrap();
            assert!(rel(fz, 1000.0) < 1e-9, "reaction {fz}");
        }
        errors.insert(el, e);
    }
    for (el, e) in &errors {
        // refinement approaches beam theory from the stiff side
        assert!(
            e.windows(2).all(|w| w[0] < w[1] && w[1] < 0.0),
            "{el}: {errors:?}"
        );
    }
    // the fully clamped root (no Poisson contraction, no warping) keeps the
    // converged 3D answer ~0.7 % stiffer than Timoshenko theory
    assert!(
        errors["h20"][1].abs() < 0.012 && errors["h27"][1].abs() < 0.012,
        "{errors:?}"
    );
    assert!(
        errors["h20"][0].abs() < 0.025 && errors["h27"][0].abs() < 0.025,
        "{errors:?}"
    );
    // H8 locks in bending on coarse meshes
    assert!(
        errors["h8"][0].abs() > 0.2 && errors["h8"][2].abs() < 0.05,
        "{errors:?}"
    );
}

#[test]
fn bad_input_gives_clear_errors() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let good = std::fs::read_to_string(repo().join("examples/cube.toml")).unwrap();

    let e = run_err(&write(d, "malformed.toml", "[mesh\ntype = \"box\""));
    assert!(e.contains("malformed.toml") && e.contains("line 1"), "{e}");

    let e = run_err(&write(
        d,
        "unknown_key.toml",
        &good.replace("nu = 0.3\n", "nu = 0.3\ncolour = 1\n"),
    ));
    assert!(
        e.contains("colour") && e.contains("materials.steel") && e.contains("nu"),
        "{e}"
    );

    let e = run_err(&write(
        d,
        "unknown_top.toml",
        &format!("{good}\n[outptu]\ndirectory = \"x\"\n"),
    ));
    assert!(e.contains("outptu") && e.contains("line"), "{e}");

    let e = run_err(&write(
        d,
        "bad_element.toml",
        &good.replace("\"h8\"", "\"h9\""),
    ));
    assert!(
        e.contains("h9") && e.contains("h20") && e.contains("mesh.element"),
        "{e}"
    );

    let e = run_err(&write(
        d,
        "bad_material.toml",
        &good.replace("material = \"steel\"", "material = \"steal\""),
    ));
    assert!(e.contains("steal") && e.contains("steel"), "{e}");

    let e = run_err(&write(
        d,
        "bad_type.toml",
        &good.replace("type = \"isotropic\"", "type = \"isotropik\""),
    ));
    assert!(e.contains("isotropik") && e.contains("orthotropic"), "{e}");

    let e = run_err(&write(
        d,
        "missing_set.toml",
        &good.replace("set = \"z0\"", "set = \"bottom\""),
    ));
    assert!(
        e.contains("boundary[0].set") && e.contains("bottom") && e.contains("z0"),
        "{e}"
    );
    assert!(e.contains("missing_set.toml:"), "line number expected: {e}");

    let e = run_err(&write(
        d,
        "bad_nu.toml",
        &good.replace("nu = 0.3\n", "nu = 0.7\n"),
    ));
    assert!(e.contains("nu"), "{e}");

    // unconstrained: no boundary at all, a force only
    let free = good.split("[[boundary]]").next().unwrap().to_string()
        + "[[load]]\nset = \"z1\"\nforce = [0.0, 0.0, 1.0]\n";
    let e = run_err(&write(d, "unconstrained.toml", &free));
    assert!(
        e.contains("positive definite") || e.contains("singular"),
        "{e}"
    );

    // inverted element: z size negative flips the cells? use an .inp with swapped nodes
    let deck = cube_deck("C3D8", 1);
    let inverted = deck.replace("1, 1, 2, 3, 4, 5, 6, 7, 8", "1, 5, 6, 7, 8, 1, 2, 3, 4");
    let e = run_err(&write(d, "inverted.inp", &inverted));
    assert!(e.contains("Jacobian"), "{e}");

    let e = run_err(&write(
        d,
        "dynamic.inp",
        &deck.replace("*STATIC", "*DYNAMIC"),
    ));
    assert!(e.contains("*DYNAMIC") && e.contains("*STATIC"), "{e}");
    let line = deck.lines().position(|l| l == "*STATIC").unwrap() + 1;
    assert!(
        e.contains(&format!("dynamic.inp:{line}:")),
        "line {line} expected: {e}"
    );

    let e = run_err(&write(d, "scene.txt", "x"));
    assert!(e.contains(".toml") && e.contains(".inp"), "{e}");
}

#[test]
fn check_prints_summary_and_list_shows_registry() {
    let out = junta()
        .arg("check")
        .arg(repo().join("examples/cube.toml"))
        .output()
        .unwrap();
    assert!(out.status.success());
    let s = String::from_utf8_lossy(&out.stdout);
    assert!(s.contains("nodes: 27") && s.contains("dofs: 81"), "{s}");
    assert!(s.contains("h8: 8"), "{s}");
    let out = junta().arg("list").output().unwrap();
    let s = String::from_utf8_lossy(&out.stdout);
    for key in [
        "h8",
        "h8i",
        "h20",
        "h27",
        "h20r",
        "h27r",
        "inter6",
        "inter12",
        "isotropic",
        "orthotropic",
        "cholesky",
        "ldlt",
        "cg",
    ] {
        assert!(s.contains(key), "`junta list` lacks {key}:\n{s}");
    }
}

/// A deck with four `*STEP`s (examples/cube_steps.inp): CalculiX's rules for
/// loads and boundary conditions across steps (added within a step,
/// replaced by a later step, removed by OP=NEW), one factorisation for
/// steps 1-2, a new one when the constrained dofs change. Golden values:
/// CalculiX 2.20 on the same deck (with *NODE PRINT requests added).
#[test]
fn multi_step_deck_matches_calculix_step_by_step() {
    let dir = tempfile::tempdir().unwrap();
    let s = run_ok(&repo().join("examples/cube_steps.inp"), dir.path());
    let steps = s["steps"].as_array().expect("summary.json has steps");
    assert_eq!(steps.len(), 4);
    // (BOTTOM reaction [Fx, Fz], largest |u|) per step from ccx
    let ccx = [
        ([0.0, 150.0], 1.186556e-2),
        ([-20.0, 30.0], 2.619413e-3),
        ([0.0, 222.4553], 1.025095e-3),
        ([0.0, 10.0], 7.910372e-4),
    ];
    for (k, (step, ([fx, fz], umax))) in steps.iter().zip(ccx).enumerate() {
        let r = &step["reactions"]["BOTTOM"];
        let (gx, gz) = (r[0].as_f64().unwrap(), r[2].as_f64().unwrap());
        assert!(
            (gx - fx).abs() < 1e-6 * 150.0,
            "step {}: Fx {gx} vs {fx}",
            k + 1
        );
        assert!(rel(gz, fz) < 5e-7, "step {}: Fz {gz} vs {fz}", k + 1);
        let u = step["displacement_max"].as_f64().unwrap();
        assert!(rel(u, umax) < 5e-7, "step {}: |u| {u} vs {umax}", k + 1);
        assert!(dir
            .path()
            .join(format!("results_step{}.vtu", k + 1))
            .exists());
    }
    // steps 1 and 2 constrain the same dofs: one factorisation
    let shared: Vec<bool> = steps
        .iter()
        .map(|s| s["shares_factorisation_with_previous"].as_bool().unwrap())
        .collect();
    assert_eq!(shared, [false, true, false, false]);
    // step 3: the support supplies the balance of the -10 applied to a
    // constrained top node (CalculiX's RF would print -222.4553)
    let top3 = steps[2]["reactions"]["TOP"][2].as_f64().unwrap();
    assert!(rel(top3, -212.4553) < 5e-7, "{top3}");
    // the top level holds the last step
    assert_eq!(s["reactions"]["BOTTOM"], steps[3]["reactions"]["BOTTOM"]);
    let pvd = std::fs::read_to_string(dir.path().join("results.pvd")).unwrap();
    assert_eq!(pvd.matches("<DataSet").count(), 4);
}

/// `*ELEMENT, TYPE=C3D8I` runs as `h8i`. tests/data/cantilever_c3d8i.inp is
/// the cantilever example as a deck (10 x 1 x 1, end load 4 x 250 N); on
/// this rectangular mesh Junta's h8i and CalculiX's C3D8I are the same
/// element. Golden: CalculiX 2.20 on the same deck (values in its header).
#[test]
fn c3d8i_cantilever_deck_matches_calculix() {
    let dir = tempfile::tempdir().unwrap();
    let s = run_ok(
        &repo().join("crates/cli/tests/data/cantilever_c3d8i.inp"),
        dir.path(),
    );
    assert_eq!(s["elements"]["h8i"].as_u64(), Some(10), "{}", s["elements"]);
    // ccx: tip (ux, uy, uz) = (1.418228e-5, 1.799398e-8, -1.891733e-4) -> |u|
    let ccx = (1.418228e-5f64.powi(2) + 1.799398e-8f64.powi(2) + 1.891733e-4f64.powi(2)).sqrt();
    let u = s["displacement_max"].as_f64().unwrap();
    assert!(rel(u, ccx) < 1e-6, "|u| {u:.7e} vs ccx {ccx:.7e}");
    let fz = s["reactions"]["ROOT"][2].as_f64().unwrap();
    assert!(rel(fz, 1000.0) < 1e-9, "{fz}");
    // with C3D8 the same deck locks (ccx: uz = -1.233900e-4, |u| = 1.237339e-4)
    let deck = std::fs::read_to_string(repo().join("crates/cli/tests/data/cantilever_c3d8i.inp"))
        .unwrap()
        .replace("TYPE=C3D8I", "TYPE=C3D8");
    let d8 = dir.path().join("c3d8");
    let s8 = run_ok(&write(dir.path(), "cantilever_c3d8.inp", &deck), &d8);
    let ccx8 = (9.218229e-6f64.powi(2) + 1.047739e-8f64.powi(2) + 1.2339e-4f64.powi(2)).sqrt();
    let u8 = s8["displacement_max"].as_f64().unwrap();
    assert!(rel(u8, ccx8) < 1e-6, "C3D8 |u| {u8:.7e} vs ccx {ccx8:.7e}");
}

/// The displacement of node `i` in a results.vtu (ascii).
fn vtu_displacement(path: &std::path::Path, i: usize) -> [f64; 3] {
    let text = std::fs::read_to_string(path).unwrap();
    let start = text
        .find("Name=\"displacement\"")
        .expect("displacement array");
    let body = &text[start..];
    let body = &body[body.find('>').unwrap() + 1..body.find("</DataArray>").unwrap()];
    let v: Vec<f64> = body
        .split_whitespace()
        .skip(3 * i)
        .take(3)
        .map(|x| x.parse().unwrap())
        .collect();
    [v[0], v[1], v[2]]
}

/// tests/data/patch_c3d8i.inp: a distorted 2 x 2 x 2 patch with u = A x on
/// the boundary. Reference: the closed form A x at the interior node
/// (CalculiX 2.20's C3D8I misses it by up to 3.4 %, see the deck's header:
/// it lacks Taylor's det J0 / det J factor).
#[test]
fn c3d8i_patch_test_deck_is_exact() {
    let dir = tempfile::tempdir().unwrap();
    let s = run_ok(
        &repo().join("crates/cli/tests/data/patch_c3d8i.inp"),
        dir.path(),
    );
    assert_eq!(s["elements"]["h8i"].as_u64(), Some(8));
    let x = [0.62, 0.41, 0.57];
    let a = [[1.0, 0.3, -0.2], [0.5, -0.7, 0.4], [0.1, 0.6, 0.9]];
    let exact: Vec<f64> = a
        .iter()
        .map(|r| 1e-3 * (r[0] * x[0] + r[1] * x[1] + r[2] * x[2]))
        .collect();
    // node label 14 is the 14th node of the deck
    let u = vtu_displacement(&dir.path().join("results.vtu"), 13);
    for d in 0..3 {
        assert!((u[d] - exact[d]).abs() < 1e-9 * 1e-3, "{u:?} vs {exact:?}");
    }
    let ccx = [6.353291e-4, 2.425364e-4, 8.184597e-4];
    assert!(
        rel(ccx[1], exact[1]) > 0.03,
        "the deck's header is out of date"
    );
}

/// The cantilever example with h8i at one element through the depth:
/// within 2 % of Timoshenko beam theory (H8 on the same mesh: -36 %).
#[test]
fn h8i_cantilever_does_not_lock() {
    let base = std::fs::read_to_string(repo().join("examples/cantilever.toml")).unwrap();
    let exact = beam_theory();
    let dir = tempfile::tempdir().unwrap();
    let scene = write(
        dir.path(),
        "h8i.toml",
        &base.replace("element = \"h20\"", "element = \"h8i\""),
    );
    let s = run_ok(&scene, &dir.path().join("out"));
    let tip = -s["probes"]["x1"][2].as_f64().unwrap();
    let err = (tip - exact) / exact;
    eprintln!(
        "h8i 10x1x1: tip {tip:.4e} m, {:+.2} % vs Timoshenko {exact:.4e}",
        100.0 * err
    );
    // measured: 1.8917e-4 m, -1.45 % (the clamp stiffens, as for H20: -2.0 %)
    assert!(err < 0.0 && err > -0.02, "{err}");
}

/// `*ELEMENT, TYPE=C3D6` (as `wedge6r`, CalculiX's 2-point rule) and
/// `TYPE=C3D15` (`wedge15`): the cantilever split into 20 wedges.
/// Golden: CalculiX on the same decks (tests/data/cantilever_c3d6.inp,
/// cantilever_c3d15.inp; values in their headers).
#[test]
fn wedge_cantilever_decks_match_calculix() {
    for (deck, key, ccx) in [
        (
            "cantilever_c3d6.inp",
            "wedge6r",
            [-1.179377e-5, 1.765133e-6, -1.591284e-4],
        ),
        (
            "cantilever_c3d15.inp",
            "wedge15",
            [-1.410788e-5, 2.878743e-8, -1.881095e-4],
        ),
    ] {
        let dir = tempfile::tempdir().unwrap();
        let s = run_ok(&repo().join("crates/cli/tests/data").join(deck), dir.path());
        assert_eq!(s["elements"][key].as_u64(), Some(20), "{}", s["elements"]);
        let want = ccx.iter().map(|v| v * v).sum::<f64>().sqrt();
        let u = s["displacement_max"].as_f64().unwrap();
        assert!(rel(u, want) < 2e-6, "{deck}: |u| {u:.7e} vs ccx {want:.7e}");
        let fz = s["reactions"]["ROOT"][2].as_f64().unwrap();
        assert!(rel(fz, 1000.0) < 1e-9, "{deck}: {fz}");
    }
}

/// A Gmsh wedge mesh (crates/junta/tests/data/prism_stack_o1.msh and _o2,
/// written by Gmsh 4.15.2 from make_prism_msh.py: the unit square in
/// triangles, extruded into two volumes of one wedge layer each), the two
/// volumes bonded by INTER6 (prism6) or INTER12 (prism15) inserted on
/// their shared triangles, clamped on the `bottom` triangles, held
/// laterally on the `sides` quadrangles and pulled by `delta` on the `top`
/// triangles. Closed form of the bonded stack in uniaxial strain
/// (BENCHMARKS.md section 3): `sigma = delta / (2 h / M + 1 / d)`, `M =
/// E (1 - nu) / ((1 + nu)(1 - 2 nu))`, the same normal traction at every
/// interface point and the opening `sigma / d`.
#[test]
fn gmsh_wedge_stack_with_triangle_surfaces_matches_the_bonded_stack() {
    for (file, element, iface) in [
        ("prism_stack_o1.msh", "wedge6", "inter6"),
        ("prism_stack_o2.msh", "wedge15", "inter12"),
    ] {
        let s = bonded_stack(file, &[("lower", element), ("upper", element)]);
        let wedges = s["elements"][element].as_u64().unwrap();
        assert_eq!(
            s["elements"][iface].as_u64(),
            Some(wedges / 2),
            "{}",
            s["elements"]
        );
        check_bonded_stack(&s, file, &["bond"]);
    }
}

/// A Gmsh mesh whose volumes hold hexahedra and wedges side by side
/// (crates/junta/tests/data/mixed_stack_o1.msh and _o2, written by Gmsh
/// 4.15.2 from make_prism_msh.py: the left half of the square in
/// quadrangles, the right half in triangles), so the bonded surface mixes
/// quadrilaterals and triangles: the interface gets INTER8 + INTER6
/// (INTER16 + INTER12 at order 2) in blocks `bond` and `bond.tri` on one
/// set of duplicated nodes (the seam's topology is checked in
/// core's `mixed_triangle_and_quadrilateral_surface_gets_one_block_per_shape`).
/// The same closed form as the wedge stack, at every point of both blocks.
#[test]
fn gmsh_mixed_hexahedra_and_wedges_bonded_across_one_surface() {
    for (file, hex, wedge, quad_iface, tri_iface) in [
        ("mixed_stack_o1.msh", "h8", "wedge6", "inter8", "inter6"),
        ("mixed_stack_o2.msh", "h20", "wedge15", "inter16", "inter12"),
    ] {
        let (lw, uw) = (format!("lower_{wedge}"), format!("upper_{wedge}"));
        let blocks = [("lower", hex), (&lw, wedge), ("upper", hex), (&uw, wedge)];
        let s = bonded_stack(file, &blocks);
        let count = |k: &str| s["elements"][k].as_u64().unwrap_or(0);
        assert!(
            count(quad_iface) > 0 && count(tri_iface) > 0,
            "{}",
            s["elements"]
        );
        assert_eq!(count(quad_iface), count(hex) / 2, "{}", s["elements"]);
        assert_eq!(count(tri_iface), count(wedge) / 2, "{}", s["elements"]);
        check_bonded_stack(&s, file, &["bond", "bond.tri"]);
    }
}

/// Material, penalty and opening of the bonded-stack tests, and the closed
/// form `sigma = delta / (2 h / M + 1 / d)` (h = 0.5 per layer).
const STACK: (f64, f64, f64, f64) = (210000.0, 0.3, 1.0e5, 0.01);

fn stack_sigma() -> f64 {
    let (e, nu, d, delta) = STACK;
    let m = e * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu));
    delta / (2.0 * 0.5 / m + 1.0 / d)
}

/// Run the Gmsh mesh `file` (from crates/junta/tests/data) with its solid
/// blocks `(name, element)`, the volumes `lower` / `upper` bonded by a
/// linear penalty, clamped on `bottom`, held laterally on `sides` and
/// pulled on `top` ([`STACK`]); returns the summary.
fn bonded_stack(file: &str, blocks: &[(&str, &str)]) -> serde_json::Value {
    let (e, nu, d, delta) = STACK;
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(
        repo().join("crates/junta/tests/data").join(file),
        dir.path().join(file),
    )
    .unwrap();
    let mut scene = format!(
        r#"[materials.steel]
type = "isotropic"
E = {e}
nu = {nu}
[laws.bond]
type = "linear_penalty"
d = {d}
[mesh]
type = "gmsh"
file = "{file}"
[[interface]]
name = "bond"
between = ["lower", "upper"]
law = "bond"
[[boundary]]
set = "sides"
fixed = ["x", "y"]
[[boundary]]
set = "bottom"
fixed = "all"
[[boundary]]
set = "top"
fixed = ["x", "y"]
displacement = {{ z = {delta} }}
"#
    );
    for (name, element) in blocks {
        scene += &format!(
            "[[blocks]]\nname = \"{name}\"\nelement = \"{element}\"\nmaterial = \"steel\"\n"
        );
    }
    run_ok(
        &write(dir.path(), "stack.toml", &scene),
        &dir.path().join("out"),
    )
}

/// The reaction on `top` and the normal traction and opening at every
/// point of the interface blocks `blocks` equal the closed form.
fn check_bonded_stack(s: &serde_json::Value, file: &str, blocks: &[&str]) {
    let (sigma, d) = (stack_sigma(), STACK.2);
    let r = s["reactions"]["top"][2].as_f64().unwrap();
    assert!(
        rel(r, sigma) < 1e-9,
        "{file}: top reaction {r} vs closed form {sigma}"
    );
    for name in blocks {
        let b = &s["interfaces"][*name];
        for (key, want) in [("traction", sigma), ("jump", sigma / d)] {
            for mm in ["min", "max"] {
                let v = b[format!("{key}_{mm}")][2].as_f64();
                let v = v.unwrap_or_else(|| panic!("{file}: no {key}_{mm} of `{name}`: {b}"));
                assert!(
                    rel(v, want) < 1e-9,
                    "{file} {name}: {key}_{mm} {v} vs {want}"
                );
            }
        }
    }
}
