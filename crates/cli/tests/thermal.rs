//! Thermal loads (issue 25, part 4): expansion coefficients, temperature
//! fields in scenes and decks, and a cool-down before the mechanical load,
//! each against a closed form or CalculiX.

mod common;
use common::*;
use serde_json::Value;

/// A block with every node fixed, heated by dT = 100: the strain is zero,
/// so `sigma = -C alpha dT`, for an isotropic material `-E alpha dT / (1 -
/// 2 nu)` in every normal component and no shear (the classic fully
/// restrained thermal stress, e.g. Timoshenko & Goodier, Theory of
/// Elasticity, 3rd ed., section 150), at every integration point of every
/// solid element kind: -200000 * 1.2e-5 * 100 / 0.4 = -600.
#[test]
fn constrained_block_stress_is_minus_e_alpha_dt_over_one_minus_two_nu() {
    let (e, nu, alpha, dt) = (200000.0, 0.3, 1.2e-5, 100.0);
    let exact = -e * alpha * dt / (1.0 - 2.0 * nu);
    let dir = tempfile::tempdir().unwrap();
    for element in ["h8", "h8i", "h20", "h27", "h20r", "wedge6", "wedge15"] {
        let fixed: String = ["x0", "x1", "y0", "y1", "z0", "z1"]
            .iter()
            .map(|s| format!("[[boundary]]\nset = \"{s}\"\nfixed = \"all\"\n"))
            .collect();
        let scene = format!(
            "[materials.steel]\ntype = \"isotropic\"\nE = {e}\nnu = {nu}\nalpha = {alpha}\n\
             [mesh]\ntype = \"box\"\nsize = [1.0, 2.0, 3.0]\ndivisions = [2, 2, 2]\n\
             element = \"{element}\"\nmaterial = \"steel\"\n{fixed}\
             [temperature]\nstress_free = 20.0\nvalue = {}\n",
            20.0 + dt
        );
        let s = run_ok(
            &write(dir.path(), &format!("{element}.toml"), &scene),
            &dir.path().join(element),
        );
        let solid = &s["solids"]["solid"];
        for key in ["stress_min", "stress_max"] {
            let v: Vec<f64> = solid[key]
                .as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_f64().unwrap())
                .collect();
            for c in 0..3 {
                assert!(rel(v[c], exact) < 1e-10, "{element} {key}[{c}] = {}", v[c]);
            }
            for c in 3..6 {
                assert!(
                    v[c].abs() < 1e-10 * exact.abs(),
                    "{element} {key}[{c}] = {}",
                    v[c]
                );
            }
        }
        assert_eq!(s["temperature"]["change_max"].as_f64(), Some(dt));
    }
}

/// Curvature of the free bimetal strip of `examples/thermal/bimetal.toml`
/// from three probes 4 apart on its bottom edge: `(w1 - 2 w2 + w3) / 16`.
fn bimetal_curvature(s: &Value) -> f64 {
    let w = |p: &str| s["probes"][p][2].as_f64().unwrap();
    (w("p1") - 2.0 * w("p2") + w("p3")) / 16.0
}

/// A free bimetal strip heated by dT: its curvature against Timoshenko's
/// formula (S. Timoshenko, "Analysis of bi-metal thermostats", J. Opt. Soc.
/// Am. 11 (1925) 233-255, eq. 4): with m = t1/t2, n = E1/E2, h = t1 + t2,
/// `kappa = 6 (a2 - a1) dT (1 + m)^2 / (h (3 (1 + m)^2 + (1 + m n)(m^2 +
/// 1/(m n))))`; nu = 0 makes the 3D strip a beam. Measured: H20 (10 x 1 x
/// 1 per layer) 7.0e-5, H8I (20 x 1 x 2 per layer) 3.7e-6 relative.
#[test]
fn bimetal_strip_curvature_matches_timoshenko() {
    let (m, n, h, da, dt) = (1.0f64, 2.0f64, 2.0, 1.0e-5, 100.0);
    let exact = 6.0 * da * dt * (1.0 + m).powi(2)
        / (h * (3.0 * (1.0 + m).powi(2) + (1.0 + m * n) * (m * m + 1.0 / (m * n))));
    let scene = repo().join("examples/thermal/bimetal.toml");
    let text = std::fs::read_to_string(&scene).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let h8i = text
        .replace("\"h20\"", "\"h8i\"")
        .replace("divisions = [10, 1, 1]", "divisions = [20, 1, 2]");
    for (name, input, tol) in [
        ("h20", scene.clone(), 1e-3),
        ("h8i", write(dir.path(), "h8i.toml", &h8i), 1e-4),
    ] {
        let s = run_ok(&input, &dir.path().join(name));
        // hotter and more expansive on top: the ends curl down
        let k = -bimetal_curvature(&s);
        assert!(rel(k, exact) < tol, "{name}: {k} vs Timoshenko {exact}");
        assert!(rel(k, exact) < 5e-3);
    }
    // the same strip as an incremental run: a thermal step of four
    // increments (the kept element matrices and thermal forces of the
    // Newton driver) ends where the linear solve does
    let linear = run_ok(&scene, &dir.path().join("linear"));
    let static_ = text.replace(
        "[output]",
        "[analysis]\ntype = \"static\"\n[analysis.newton]\ninitial_increment = 0.25\n[output]",
    );
    let s = run_ok(
        &write(dir.path(), "static.toml", &static_),
        &dir.path().join("static"),
    );
    assert_eq!(s["temperature"]["thermal_step_increments"], 4, "{s}");
    // (an incremental summary has no probes: the largest displacement)
    let umax = |s: &Value| s["displacement_max"].as_f64().unwrap();
    assert!(rel(umax(&s), umax(&linear)) < 1e-9, "{s} vs {linear}");
    assert_eq!(s["status"], "completed");
}

/// The bimetal strip as a plane model (issue 39): `cpe8` layers of 10 x 1
/// elements (nu = 0: plane strain is the beam), linear and as a thermal
/// step of four increments, against Timoshenko's curvature.
#[test]
fn plane_bimetal_strip_curvature_matches_timoshenko() {
    let (m, n, h, da, dt) = (1.0f64, 2.0f64, 2.0, 1.0e-5, 100.0);
    let exact = 6.0 * da * dt * (1.0 + m).powi(2)
        / (h * (3.0 * (1.0 + m).powi(2) + (1.0 + m * n) * (m * m + 1.0 / (m * n))));
    let text = std::fs::read_to_string(repo().join("examples/thermal/bimetal.toml")).unwrap();
    let mut plane = text.clone();
    for (from, to) in [
        ("size = [20.0, 1.0, 1.0]", "size = [20.0, 1.0]"),
        ("divisions = [10, 1, 1]", "divisions = [10, 1]"),
        ("origin = [0.0, 0.0, 1.0]", "origin = [0.0, 1.0]"),
        ("\"h20\"", "\"cpe8\""),
        ("fixed = [\"y\", \"z\"]", "fixed = [\"y\"]"),
        ("[[boundary]]\nset = \"c\"\nfixed = [\"z\"]\n", ""),
    ] {
        assert!(plane.contains(from), "{from}");
        plane = plane.replace(from, to);
    }
    let dir = tempfile::tempdir().unwrap();
    let w = |s: &Value, p: &str| s["probes"][p][1].as_f64().unwrap();
    let s = run_ok(
        &write(dir.path(), "plane.toml", &plane),
        &dir.path().join("linear"),
    );
    // hotter and more expansive on top: the ends curl down
    let k = -(w(&s, "p1") - 2.0 * w(&s, "p2") + w(&s, "p3")) / 16.0;
    eprintln!(
        "plane bimetal: curvature {k:.6e} against Timoshenko {exact:.6e} ({:+.1e})",
        k / exact - 1.0
    );
    assert!(rel(k, exact) < 1e-3, "{k} vs Timoshenko {exact}");
    let static_ = plane.replace(
        "[output]",
        "[analysis]\ntype = \"static\"\n[analysis.newton]\ninitial_increment = 0.25\n[output]",
    );
    let st = run_ok(
        &write(dir.path(), "static.toml", &static_),
        &dir.path().join("static"),
    );
    assert_eq!(st["temperature"]["thermal_step_increments"], 4, "{st}");
    let umax = |s: &Value| s["displacement_max"].as_f64().unwrap();
    assert!(rel(umax(&st), umax(&s)) < 1e-9, "{st} vs {s}");
}

/// CalculiX's own test deck `c3d6` (C3D6 wedges in tension, with
/// `*EXPANSION, TYPE=ISO`, `*ELASTIC` and `*EXPANSION` at one temperature,
/// `*DENSITY`, a `*MEMBRANE` on an empty set, no temperature change) runs as
/// it is and gives its shipped `.dat.ref` (tests/data/ccx_suite, GPL-2 test
/// data of CalculiX 2.11; see its README): U, RF and S to 1e-6 of each
/// block's largest value (the .dat prints 7 digits; measured 2e-7).
#[test]
fn calculix_c3d6_deck_matches_its_dat_ref() {
    let data = repo().join("crates/cli/tests/data/ccx_suite");
    let dir = tempfile::tempdir().unwrap();
    let s = run_ok(&data.join("c3d6.inp"), dir.path());
    let notes = s["notes"].to_string();
    assert!(notes.contains("*MEMBRANE, ELSET=P1 ignored"), "{notes}");
    assert!(notes.contains("*EXPANSION at temperature 70"), "{notes}");
    let dat = std::fs::read_to_string(data.join("c3d6.dat.ref")).unwrap();
    let worst = worst_against_dat(&dat, dir.path());
    assert!(worst < 1e-6, "worst relative difference {worst:e}");
}

/// Thermal strains against CalculiX 2.20 on the decks of
/// tests/data/make_thermal_decks.py (the cylindrical-orientation rings with
/// `*EXPANSION` TYPE=ORTHO and ANISO in axes taken at every integration
/// point, `*INITIAL CONDITIONS, TYPE=TEMPERATURE` and `*TEMPERATURE`:
/// a field linear in (r, theta, z) on the C3D20R / C3D20 ring, a uniform
/// change on the C3D8 ring, `ZERO=` noted), with the inner pressure and end
/// loads. Reference: `ccx -i thermal_ring_c3d20` and `ccx -i
/// thermal_ring_c3d8` (CalculiX 2.20), their .dat next to the decks: U,
/// the FIX total force and (C3D8) the stresses of one element, to 1e-6 of
/// each block's largest value (measured 1.2e-7 and 1.4e-7).
#[test]
fn thermal_ring_decks_match_calculix() {
    let data = repo().join("crates/cli/tests/data");
    for deck in ["thermal_ring_c3d20", "thermal_ring_c3d8"] {
        let dir = tempfile::tempdir().unwrap();
        let s = run_ok(&data.join(format!("{deck}.inp")), dir.path());
        assert!(
            s["temperature"]["change_min"].as_f64().unwrap() < 0.0,
            "{s}"
        );
        let dat = std::fs::read_to_string(data.join(format!("{deck}.dat"))).unwrap();
        let worst = worst_against_dat(&dat, dir.path());
        assert!(worst < 1e-6, "{deck}: worst relative difference {worst:e}");
    }
    // without the temperature change the same ring is another answer (the
    // thermal load is not negligible in the comparison above)
    let text = std::fs::read_to_string(data.join("thermal_ring_c3d8.inp")).unwrap();
    let cold = text.replace("NALL, -60.0", "NALL, 20.");
    let dir = tempfile::tempdir().unwrap();
    run_ok(&write(dir.path(), "cold.inp", &cold), &dir.path().join("o"));
    let dat = std::fs::read_to_string(data.join("thermal_ring_c3d8.dat")).unwrap();
    assert!(worst_against_dat(&dat, &dir.path().join("o")) > 1e-2);
}

/// `examples/thermal/cool_down.toml`: a thermal step (load factor 0,
/// temperature factor 0 -> 1 in four increments) before the opening, which
/// switches to path following at its peak (control = "auto"). A run
/// stopped inside the thermal step and one stopped in path following,
/// each restarted, give the uninterrupted run's curve.csv, reactions and
/// state bit for bit.
#[test]
fn cool_down_before_the_load_restarts_bit_for_bit() {
    let scene = repo().join("examples/thermal/cool_down.toml");
    let whole = tempfile::tempdir().unwrap();
    let a = run_ok(&scene, whole.path());
    assert_eq!(a["status"], "completed");
    assert_eq!(a["temperature"]["thermal_step_increments"], 4);
    assert_eq!(a["temperature"]["factor"], 1.0);
    let rows = curve_without_seconds(whole.path());
    let tf = rows[0]
        .split(',')
        .position(|h| h == "temperature_factor")
        .unwrap_or_else(|| panic!("no temperature_factor column: {}", rows[0]));
    // the thermal step: load factor 0, temperature factor 0.25 .. 1
    for (i, theta) in [0.25, 0.5, 0.75, 1.0].iter().enumerate() {
        let f: Vec<&str> = rows[i + 1].split(',').collect();
        assert_eq!((f[1], f[2]), ("0", "0e0"), "{}", rows[i + 1]);
        assert_eq!(f[tf].parse::<f64>().unwrap(), *theta);
    }
    assert!(rows[5].starts_with("5,1,"), "{}", rows[5]);
    assert!(
        rows.iter().any(|r| r.contains(",dissipation,")),
        "the opening should pass its peak under path following"
    );
    for n in ["2", "9"] {
        let parts = tempfile::tempdir().unwrap();
        run_ok_with(&scene, parts.path(), &["--max-increments", n]);
        restart_ok(parts.path());
        let text = std::fs::read_to_string(parts.path().join("summary.json")).unwrap();
        let b: Value = serde_json::from_str(&text).unwrap();
        for key in [
            "increments",
            "load_factor",
            "reactions",
            "interfaces",
            "status",
            "temperature",
        ] {
            assert_eq!(a[key], b[key], "restart after {n}: {key}");
        }
        assert_eq!(
            rows,
            curve_without_seconds(parts.path()),
            "restart after {n}"
        );
    }
}

/// Input mistakes name the file, the key or line and what is valid.
#[test]
fn thermal_input_errors_name_the_key_or_line() {
    let dir = tempfile::tempdir().unwrap();
    let base = std::fs::read_to_string(repo().join("examples/thermal/bimetal.toml")).unwrap();
    for (from, to, expect) in [
        ("value = 120.0", "value = 120.0\nramp = \"after\"", "ramp"),
        (
            "value = 120.0",
            "value = 120.0\nsets = [{ set = \"nowhere\", value = 1.0 }]",
            "temperature.sets[0].set",
        ),
        ("alpha = 1.0e-5", "alpha = \"hot\"", "alpha"),
        (
            "stress_free = 20.0",
            "stress_free = nan",
            "temperature.stress_free",
        ),
    ] {
        let bad = base.replacen(from, to, 1);
        assert_ne!(bad, base);
        let err = run_err(&write(dir.path(), "bad.toml", &bad));
        assert!(
            err.contains("bad.toml") && err.contains(expect),
            "{to}: {err}"
        );
    }
    // path following throughout cannot take a temperature change
    let arc = base.replace(
        "[output]",
        "[analysis]\ntype = \"static\"\ncontrol = \"arc_length\"\n[output]",
    );
    let err = run_err(&write(dir.path(), "arc.toml", &arc));
    assert!(err.contains("temperature") && err.contains("auto"), "{err}");
    // decks: unknown *INITIAL CONDITIONS type, *TEMPERATURE outside a step,
    // temperature-dependent expansion
    let deck = std::fs::read_to_string(repo().join("crates/cli/tests/data/thermal_ring_c3d8.inp"))
        .unwrap();
    let line_of = |t: &str, pat: &str| t.lines().position(|l| l.starts_with(pat)).unwrap() + 1;
    for (from, to, at, expect) in [
        (
            "*INITIAL CONDITIONS, TYPE=TEMPERATURE",
            "*INITIAL CONDITIONS, TYPE=STRESS",
            "*INITIAL CONDITIONS",
            "TYPE=TEMPERATURE",
        ),
        (
            "3.e-5, 1.e-6, 2.e-5",
            "3.e-5, 1.e-6, 2.e-5, 20.\n4.e-5, 1.e-6, 2.e-5, 100.",
            "4.e-5",
            "temperature-dependent",
        ),
        (
            "*EXPANSION, TYPE=ORTHO, ZERO=20.",
            "*EXPANSION, TYPE=CUBIC",
            "*EXPANSION",
            "TYPE=ISO",
        ),
    ] {
        let bad = deck.replacen(from, to, 1);
        assert_ne!(bad, deck);
        let l = line_of(&bad, at);
        let err = run_err(&write(dir.path(), "bad.inp", &bad));
        assert!(
            err.contains(&format!("bad.inp:{l}")) && err.contains(expect),
            "{to}: {err}"
        );
    }
}

/// A free cube heated under nlgeom: its Green strain equals the thermal
/// strain (S = C (E - alpha dT) = 0), so it stretches by
/// `sqrt(1 + 2 alpha dT)` in every direction, not by the small-strain
/// `1 + alpha dT`: with alpha dT = 0.05, 0.048809 against 0.05 (closed
/// form of the St. Venant-Kirchhoff material).
#[test]
fn free_cube_heated_under_nlgeom_stretches_by_the_green_strain() {
    let dir = tempfile::tempdir().unwrap();
    for (nlgeom, expect) in [(true, (1.1f64).sqrt() - 1.0), (false, 0.05)] {
        let scene = format!(
            "[materials.m]\ntype = \"isotropic\"\nE = 1000.0\nnu = 0.3\nalpha = 0.0005\n\
             [mesh]\ntype = \"box\"\nsize = [1.0, 1.0, 1.0]\ndivisions = [2, 2, 2]\n\
             element = \"h20\"\nmaterial = \"m\"\n\
             [[boundary]]\nset = \"x0\"\nfixed = [\"x\"]\n\
             [[boundary]]\nset = \"y0\"\nfixed = [\"y\"]\n\
             [[boundary]]\nset = \"z0\"\nfixed = [\"z\"]\n\
             [temperature]\nstress_free = 0.0\nvalue = 100.0\n\
             [analysis]\ntype = \"static\"\nnlgeom = {nlgeom}\n\
             [output]\ncurve = {{ reaction_set = \"x0\", reaction_component = \"x\", point_set = \"x1\", point_component = \"x\" }}\n"
        );
        let out = dir.path().join(format!("cube_{nlgeom}"));
        run_ok(
            &write(dir.path(), &format!("cube_{nlgeom}.toml"), &scene),
            &out,
        );
        let text = std::fs::read_to_string(out.join("curve.csv")).unwrap();
        let head: Vec<&str> = text.lines().next().unwrap().split(',').collect();
        let col = head.iter().position(|h| *h == "displacement").unwrap();
        let last = text.lines().last().unwrap().split(',').nth(col).unwrap();
        let stretch: f64 = last.parse().unwrap();
        assert!(
            rel(stretch, expect) < 1e-9,
            "nlgeom = {nlgeom}: {stretch} against {expect}"
        );
    }
}
