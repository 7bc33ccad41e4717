//! An axisymmetric bonded joint (issue 39): `examples/plane/tube_lap_joint.toml`,
//! two tubes bonded over an overlap by a film, against Volkersen's shear
//! lag (the tubes as bars, the film as shear springs over the
//! circumference; formulas in the example's header).

mod common;
use common::*;

/// Volkersen's film shear stress at both ends of the overlap for a pull
/// `p`: `(tau(0), tau(l))`.
fn volkersen(p: f64) -> (f64, f64) {
    let (e, r1, r2, r3, k, l) = (70000.0, 10.0f64, 11.0f64, 12.0f64, 200.0, 50.0);
    let pi = std::f64::consts::PI;
    let (a1, a2, b) = (
        pi * (r2 * r2 - r1 * r1),
        pi * (r3 * r3 - r2 * r2),
        2.0 * pi * r2,
    );
    let w = (k * b * (1.0 / (e * a1) + 1.0 / (e * a2))).sqrt();
    let n1p = p * a1 / (a1 + a2);
    let c1 = p - n1p;
    let c2 = -(n1p + c1 * (w * l).cosh()) / (w * l).sinh();
    let q = |y: f64| -w * (c1 * (w * y).sinh() + c2 * (w * y).cosh());
    (q(0.0) / b, q(l) / b)
}

/// The peak film shear stress (where the inner tube enters the overlap)
/// within 5 % of Volkersen's, and so the load at which a film of shear
/// strength S starts to fail (measured -3.0 %: the tubes' free end faces
/// relieve the overlap's ends); the full ring carries the pull (the
/// reaction is P, not P / 2 pi).
#[test]
fn tube_lap_joint_against_volkersen() {
    let dir = tempfile::tempdir().unwrap();
    let s = run_ok(
        &repo().join("examples/plane/tube_lap_joint.toml"),
        dir.path(),
    );
    assert_eq!(s["plane"]["width"], "full_ring", "{s}");
    let fy = s["reactions"]["outer.y1"][1].as_f64().unwrap();
    assert!(rel(fy, 1000.0) < 1e-9, "{fy}");
    let film = &s["interfaces"]["film"];
    let tau = film["traction_max"][0].as_f64().unwrap();
    let (t0, tl) = volkersen(1000.0);
    assert!(t0 > tl);
    assert!(rel(tau, t0) < 0.05, "peak {tau} against Volkersen's {t0}");
    let strength = 25.0;
    let (onset, want) = (strength / tau * 1000.0, strength / t0 * 1000.0);
    assert!(rel(onset, want) < 0.05, "onset load {onset} against {want}");
}
