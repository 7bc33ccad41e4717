//! Lamé's thick cylinder under internal pressure, axisymmetric (issue 39):
//! a CAX8 deck of `n` elements through the wall `a <= r <= b`, one along
//! the axis with both ends held axially (plane strain along the axis,
//! `eps_z = 0`), pressure `p` on the bore (`*DLOAD ... P4`). Closed form
//! (Timoshenko & Goodier, Theory of Elasticity, 3rd ed., section 28), with
//! `A = p a^2 / (b^2 - a^2)` and `B = p a^2 b^2 / (b^2 - a^2)`:
//!
//! ```text
//! sigma_r = A - B / r^2,   sigma_t = A + B / r^2,   sigma_z = 2 nu A
//! u_r = (1 + nu) / E ((1 - 2 nu) A r + B / r)
//! ```
//!
//! The radial and hoop stresses at every integration point are within
//! 1e-4 of `p` on the fine mesh (128 elements), and the errors fall with the
//! mesh as the quadratic element's should: the stress at the 3 x 3 Gauss
//! points (not all of them superconvergent) at order 2 (a ratio of at least
//! 3.5 per halving at the finest meshes; measured 3.55, 3.76, 3.88, 3.94 from 8 to 128
//! elements), the bore displacement at order 4 (nodal superconvergence:
//! a ratio of at least 8 per halving; measured 15.7 to 16.0). On 128
//! elements: stresses within 3.5e-5 of p, the bore displacement 6.6e-11.

mod common;
use common::*;

const A_IN: f64 = 1.0;
const B_OUT: f64 = 2.0;
const P: f64 = 100.0;
const E: f64 = 200000.0;
const NU: f64 = 0.3;

/// The deck: `n` CAX8 elements across the wall, height `h = 0.25`.
fn deck(n: usize) -> String {
    let h = 0.25;
    let dr = (B_OUT - A_IN) / n as f64;
    let mut s = String::from("*NODE, NSET=NALL\n");
    // nodes on rows y = 0, h/2 (corners only at mid-height: CAX8 mid-sides), h
    let id = |i: usize, row: usize| 1 + row * (2 * n + 1) + i;
    for row in 0..3 {
        for i in 0..=2 * n {
            if row == 1 && i % 2 == 1 {
                continue; // no centre node in CAX8
            }
            let r = A_IN + 0.5 * dr * i as f64;
            s += &format!("{}, {r:.17e}, {:.17e}\n", id(i, row), 0.5 * h * row as f64);
        }
    }
    s += "*ELEMENT, TYPE=CAX8, ELSET=WALL\n";
    for e in 0..n {
        let i = 2 * e;
        s += &format!(
            "{}, {}, {}, {}, {}, {}, {}, {}, {}\n",
            e + 1,
            id(i, 0),
            id(i + 2, 0),
            id(i + 2, 2),
            id(i, 2),
            id(i + 1, 0),
            id(i + 2, 1),
            id(i + 1, 2),
            id(i, 1)
        );
    }
    s += "*NSET, NSET=ENDS\n";
    for i in 0..=2 * n {
        s += &format!("{}, {}\n", id(i, 0), id(i, 2));
    }
    s += &format!(
        "*NSET, NSET=BORE\n{}, {}, {}\n",
        id(0, 0),
        id(0, 1),
        id(0, 2)
    );
    s += &format!(
        "*MATERIAL, NAME=STEEL\n*ELASTIC\n{E}, {NU}\n*SOLID SECTION, ELSET=WALL, MATERIAL=STEEL\n\
         *BOUNDARY\nENDS, 2, 2\n*STEP\n*STATIC\n*DLOAD\n1, P4, {P}\n\
         *NODE PRINT, NSET=BORE\nU\n*EL PRINT, ELSET=WALL\nS\n*END STEP\n"
    );
    s
}

/// Largest stress error (radial and hoop, at every Gauss point, relative
/// to p) and the relative error of the bore's radial displacement.
fn errors(n: usize) -> (f64, f64) {
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), "lame.inp", &deck(n));
    let s = run_ok(&path, &dir.path().join("o"));
    assert_eq!(s["plane"]["section"], "axisymmetric", "{s}");
    let (aa, bb) = (
        P * A_IN * A_IN / (B_OUT * B_OUT - A_IN * A_IN),
        P * A_IN * A_IN * B_OUT * B_OUT / (B_OUT * B_OUT - A_IN * A_IN),
    );
    let blocks = junta_blocks(&dir.path().join("o"));
    let stresses = &blocks[&("stresses".to_string(), "WALL".to_string())];
    let g = [-(0.6f64.sqrt()), 0.0, 0.6f64.sqrt()];
    let dr = (B_OUT - A_IN) / n as f64;
    let mut worst: f64 = 0.0;
    for e in 0..n {
        for q in 0..9 {
            let r = A_IN + dr * (e as f64 + 0.5 * (1.0 + g[q % 3]));
            let s = &stresses[&format!("{}.{}", e + 1, q + 1)];
            let (sr, st) = (aa - bb / (r * r), aa + bb / (r * r));
            worst = worst.max((s[0] - sr).abs() / P).max((s[2] - st).abs() / P);
            assert!((s[1] - 2.0 * NU * aa).abs() < 1e-2 * P, "sigma_z {s:?}");
        }
    }
    let u = &blocks[&("displacements".to_string(), "BORE".to_string())];
    let ur = (1.0 + NU) / E * ((1.0 - 2.0 * NU) * aa * A_IN + bb / A_IN);
    let du = u
        .values()
        .map(|v| (v[0] - ur).abs() / ur)
        .fold(0.0, f64::max);
    (worst, du)
}

#[test]
fn lame_cylinder_converges_to_the_closed_form() {
    let e: Vec<(f64, f64)> = [8, 16, 32, 64, 128].iter().map(|&n| errors(n)).collect();
    eprintln!("lame errors (stress, bore u) for n = 8..128: {e:?}");
    let (fine_s, fine_u) = e[4];
    assert!(
        fine_s < 1e-4,
        "stress error {fine_s:e} of p on 128 elements; all: {e:?}"
    );
    assert!(
        fine_u < 1e-8,
        "bore displacement error {fine_u:e}; all: {e:?}"
    );
    for w in e[2..].windows(2) {
        assert!(
            w[0].0 / w[1].0 > 3.5,
            "stress error ratio per halving {}: {e:?}",
            w[0].0 / w[1].0
        );
    }
    for w in e[..3].windows(2) {
        assert!(w[0].1 / w[1].1 > 8.0, "displacement error ratio {e:?}");
    }
}

/// A circular plate (radius 10, thickness 1) under a uniform edge moment
/// `M` per unit length: pure bending, `M_r = M_theta = M` everywhere, so
/// the mid-surface deflects as `w(r) - w(0) = kappa r^2 / 2` with `kappa =
/// M / (D (1 + nu))`, `D = E h^3 / (12 (1 - nu^2))` (Timoshenko &
/// Woinowsky-Krieger, Theory of Plates and Shells, sec. 15), and the
/// stresses `sigma_r = sigma_theta = 12 M z / h^3` are an exact solution of
/// elasticity. The edge moment is the consistent ring load of that linear
/// stress over the edge (two elements through the thickness: `-/+ 2 pi a
/// M` at the bottom and top nodes, none at mid-thickness). `cax4i` does
/// not lock: the rim deflection within 1 % on 10 elements along the
/// radius and converging at second order (measured +0.55, +0.15, +0.04 %
/// on 10, 20, 40); plain `cax4` locks (-10.7 % on 10).
#[test]
fn axisymmetric_plate_in_pure_bending_converges_with_cax4i() {
    let (a, h, m) = (10.0f64, 1.0f64, 100.0f64);
    let kappa = m / (E * h.powi(3) / (12.0 * (1.0 - NU * NU)) * (1.0 + NU));
    let f = 2.0 * std::f64::consts::PI * a * m;
    let dir = tempfile::tempdir().unwrap();
    let mut got = Vec::new();
    for (key, ndiv) in [("cax4i", 10), ("cax4", 10), ("cax4i", 20), ("cax4i", 40)] {
        let scene = format!(
            r#"
[materials.steel]
type = "isotropic"
E = {E}
nu = {NU}
[mesh]
type = "box"
size = [{a}, {h}]
origin = [0.0, {z0}]
divisions = [{ndiv}, 2]
element = "{key}"
material = "steel"
[[node_set]]
name = "centre"
within = [[0.0, 0.0, 0.0], [0.0, 0.0, 0.0]]
[[node_set]]
name = "half"
within = [[5.0, 0.0, 0.0], [5.0, 0.0, 0.0]]
[[node_set]]
name = "rim"
within = [[{a}, 0.0, 0.0], [{a}, 0.0, 0.0]]
[[node_set]]
name = "rim_bottom"
within = [[{a}, {z0}, 0.0], [{a}, {z0}, 0.0]]
[[node_set]]
name = "rim_top"
within = [[{a}, {z1}, 0.0], [{a}, {z1}, 0.0]]
[[boundary]]
set = "x0"
fixed = ["x"]
[[boundary]]
set = "centre"
fixed = ["y"]
[[load]]
set = "rim_bottom"
force = [{fb}, 0.0]
[[load]]
set = "rim_top"
force = [{f}, 0.0]
[output]
probes = ["half", "rim"]
"#,
            z0 = -h / 2.0,
            z1 = h / 2.0,
            fb = -f
        );
        let s = run_ok(
            &write(dir.path(), &format!("{key}{ndiv}.toml"), &scene),
            &dir.path().join(format!("{key}{ndiv}")),
        );
        let w = |p: &str| s["probes"][p][1].as_f64().unwrap();
        // the rim curls down: magnitudes
        let (half, rim) = (w("half").abs(), w("rim").abs());
        let (half_x, rim_x) = (kappa * 25.0 / 2.0, kappa * a * a / 2.0);
        eprintln!(
            "{key} {ndiv}: w(5) {half:.6e} against {half_x:.6e}, w(10) {rim:.6e} against {rim_x:.6e} ({:+.2e})",
            rim / rim_x - 1.0
        );
        got.push(rel(rim, rim_x));
    }
    assert!(got[0] < 0.01, "cax4i: {got:?}");
    assert!(got[1] > 0.1, "cax4 should lock: {got:?}");
    assert!(
        got[0] / got[2] > 3.0 && got[2] / got[3] > 3.0,
        "second order: {got:?}"
    );
}
