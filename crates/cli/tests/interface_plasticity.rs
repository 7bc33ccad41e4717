//! The examples of examples/interface_plasticity/ through the CLI, against
//! the closed forms in their headers: Coulomb sliding force mu N,
//! Mohr-Coulomb strength c A + N tan(phi) and dilatancy lift, the area of
//! a cyclic friction loop and the frictional dissipation, and the residual
//! friction of a debonded interface under pressure (Alfano-Sacco). Also:
//! the nonsymmetric tangent goes to `lu` automatically, and a symmetric
//! back end forced on it runs on the symmetric part and shows it in the
//! Newton iterations.

mod common;
use common::*;
use serde_json::Value;
use std::path::{Path, PathBuf};

fn f(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
}

fn example(name: &str) -> PathBuf {
    repo().join("examples/interface_plasticity").join(name)
}

/// (step, reaction, displacement) of every curve.csv row.
fn curve(dir: &Path) -> Vec<(usize, f64, f64)> {
    let text = std::fs::read_to_string(dir.join("curve.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert!(header.contains(&"frictional_dissipation"));
    lines
        .map(|l| {
            let c: Vec<&str> = l.split(',').collect();
            (
                c[1].parse().unwrap(),
                c[3].parse().unwrap(),
                c[4].parse().unwrap(),
            )
        })
        .collect()
}

fn close(a: f64, b: f64, rel: f64) -> bool {
    (a - b).abs() <= rel * b.abs()
}

#[test]
fn block_friction_slides_at_mu_n() {
    let dir = tempfile::tempdir().unwrap();
    let s = run_ok(&example("block_friction.toml"), dir.path());
    // Coulomb: F = mu p A = 0.4 x 2 x 100
    let fx = f(&s["reactions"]["upper.z0"][0]);
    assert!(close(fx, 80.0, 1e-9), "sliding force {fx}");
    assert_eq!(s["solver"]["name"], "lu");
    assert_eq!(
        s["solver"]["tangent"],
        "consistent (nonsymmetric, full storage)"
    );
    let c = &s["interfaces"]["contact"];
    assert_eq!(c["slip_state_points"]["slip"].as_u64(), Some(4));
    // backward-Euler dissipation of the proportional path, N = 10 increments:
    // mu p A (u - mu p / K_s) (N + 1) / (2 N)
    let d_exact = 80.0 * (0.02 - 8e-6) * 11.0 / 20.0;
    assert!(close(f(&c["frictional_dissipation"]), d_exact, 1e-9));
    assert!(close(f(&s["frictional_dissipation"]), d_exact, 1e-9));
    // the law outputs are VTU fields of the interface points
    let vtu = std::fs::read_to_string(dir.path().join("frames/interface_points_0010.vtu")).unwrap();
    for name in [
        "plastic_slip_1",
        "plastic_slip_2",
        "accumulated_slip",
        "slip_state",
        "frictional_dissipation",
        "plastic_jump_local",
    ] {
        assert!(
            vtu.contains(&format!("Name=\"{name}\"")),
            "VTU lacks {name}"
        );
    }
}

#[test]
fn block_mohr_coulomb_strength_and_dilatancy_lift() {
    let dir = tempfile::tempdir().unwrap();
    let s = run_ok(&example("block_mohr_coulomb.toml"), dir.path());
    let (c, p, a, ks, kn, u) = (0.5, 2.0, 100.0, 1e5, 1e5, 0.02);
    let (tp, tq) = (30f64.to_radians().tan(), 10f64.to_radians().tan());
    let strength = c * a + p * a * tp;
    let fx = f(&s["reactions"]["upper.z0"][0]);
    assert!(
        close(fx, strength, 1e-6),
        "{fx} vs c A + N tan(phi) = {strength}"
    );
    // normal jump = kappa tan(psi) - p / K_n, kappa = u - (c + p tan(phi)) / K_s
    let kappa = u - (c + p * tp) / ks;
    let dn = kappa * tq - p / kn;
    for key in ["jump_min", "jump_max"] {
        let j = f(&s["interfaces"]["joint"][key][2]);
        assert!(close(j, dn, 1e-6), "{key} {j} vs {dn}");
    }
}

#[test]
fn cyclic_shear_loop_area_is_the_frictional_dissipation() {
    let dir = tempfile::tempdir().unwrap();
    let s = run_ok(&example("cyclic_shear.toml"), dir.path());
    let (fy, u) = (80.0, 0.1);
    let uy = fy / (1.0 / (1.0 / 1e7 + 1e-6)); // k = 1 / (1/(K_s A) + H/(G A))
    let rows = curve(dir.path());
    // sliding branches: +-F_y
    for &(_, r, _) in &rows {
        assert!(r.abs() <= fy * (1.0 + 1e-9), "force {r} above F_y");
    }
    let (_, r_end, _) = rows[rows.len() - 1];
    assert!(close(r_end, fy, 1e-9), "{r_end}");
    // loop +u -> -u -> +u (steps 2 and 3), end-of-increment rule
    let mut area = 0.0;
    for w in rows.windows(2) {
        if w[1].0 >= 1 {
            area += w[1].1 * (w[1].2 - w[0].2);
        }
    }
    let area_exact = 4.0 * fy * (u - uy);
    assert!(
        close(area, area_exact, 1e-3),
        "loop area {area} vs {area_exact}"
    );
    let d_exact = 5.0 * fy * (u - uy);
    let d = f(&s["frictional_dissipation"]);
    assert!(close(d, d_exact, 1e-3), "dissipation {d} vs {d_exact}");
    // the loop area is the dissipation of the closed loop (its share of the
    // whole path's: 4 of 5 slip lengths)
    assert!(close(area, 0.8 * d, 2e-3));
    let lu_iterations = s["newton_iterations"]["total"].as_u64().unwrap();
    // forcing the symmetric back end: the run uses the symmetric part of the
    // tangent, says so, converges to the same answer with more iterations
    let dir2 = tempfile::tempdir().unwrap();
    let s2 = run_ok_with(
        &example("cyclic_shear.toml"),
        dir2.path(),
        &["--solver", "type=ldlt"],
    );
    assert!(s2["solver"]["tangent"]
        .as_str()
        .unwrap()
        .contains("symmetric part"));
    let notes = s2["solver"]["notes"].to_string();
    assert!(notes.contains("quadratic convergence"), "{notes}");
    assert!(close(f(&s2["frictional_dissipation"]), d, 1e-8));
    let sym_iterations = s2["newton_iterations"]["total"].as_u64().unwrap();
    assert!(
        sym_iterations > 2 * lu_iterations,
        "symmetric part: {sym_iterations} iterations, consistent: {lu_iterations}"
    );
}

#[test]
fn debonded_interface_under_pressure_keeps_the_friction_force() {
    let dir = tempfile::tempdir().unwrap();
    let s = run_ok(&example("debond_friction.toml"), dir.path());
    let b = &s["interfaces"]["bond"];
    assert!(close(f(&b["damaged_area"]), 100.0, 1e-12));
    // fracture energy G_IIc A
    assert!(close(f(&b["dissipated_energy"]), 0.05 * 100.0, 1e-6));
    // residual: mu p A at lambda = 1
    let fx = f(&s["reactions"]["upper.z0"][0]);
    assert!(close(fx, 80.0, 1e-6), "residual {fx}");
    // the peak is the cohesive strength, far above the friction
    let peak = curve(dir.path()).iter().map(|r| r.1).fold(0.0f64, f64::max);
    assert!(peak > 450.0 && peak <= 500.0 * (1.0 + 1e-9), "peak {peak}");
    assert!(f(&b["frictional_dissipation"]) > 0.0);
}
