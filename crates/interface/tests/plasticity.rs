//! One-point tests of the plastic and frictional laws `coulomb_friction`,
//! `mohr_coulomb` and `bilinear_friction`.
//!
//! References (closed forms of the laws' definitions, no fitted numbers):
//! Coulomb's sliding traction `tau = mu p` under a pressure `p`; the
//! Mohr-Coulomb shear strength `tau = c + p tan(phi)` (per unit area: the
//! force `c A + N tan(phi)`); the dilatant normal lift of a non-associated
//! Mohr-Coulomb joint under constant pressure `Delta n_p = tan(psi) kappa`
//! (flow rule `d n_p = tan(psi) d kappa`); Alfano & Sacco 2006: a fully
//! debonded point under pressure carries `mu p` in shear.

mod common;

use junta_core::element::StepInfo;
use junta_core::law::{output, InterfaceLaw, LawContext, LawResponse};
use junta_core::registry::{find, LawEntry};
use junta_core::MatrixKind;
use junta_interface as _;
use junta_interface::law::{bilinear_friction, coulomb_friction, mohr_coulomb};
use std::sync::Arc;

const KN: f64 = 1e6;
const KS: f64 = 5e5;
const MU: f64 = 0.5;
const C: f64 = 2.0;
const PHI: f64 = 30.0;
const PSI: f64 = 10.0;

fn build(key: &str, text: &str) -> Arc<dyn InterfaceLaw> {
    let t: toml::Table = toml::from_str(text).unwrap();
    (find::<LawEntry>(key).unwrap().build)(&t).unwrap()
}

fn build_err(key: &str, text: &str) -> String {
    let t: toml::Table = toml::from_str(text).unwrap();
    (find::<LawEntry>(key).unwrap().build)(&t)
        .unwrap_err()
        .to_string()
}

fn friction() -> Arc<dyn InterfaceLaw> {
    build(
        "coulomb_friction",
        &format!("K = {KN:e}\nK_s = {KS:e}\nmu = {MU}"),
    )
}

fn mc(extra: &str) -> Arc<dyn InterfaceLaw> {
    build(
        "mohr_coulomb",
        &format!("K = {KN:e}\nK_s = {KS:e}\nc = {C}\nphi = {PHI}\npsi = {PSI}\n{extra}"),
    )
}

fn bf() -> Arc<dyn InterfaceLaw> {
    build(
        "bilinear_friction",
        &format!("K = {KN:e}\nN = 30.0\nS = 40.0\nG_Ic = 0.01\nG_IIc = 0.02\neta = 2.0\nmu = {MU}"),
    )
}

/// A point driven through a jump history, committing after each step.
struct Point {
    law: Arc<dyn InterfaceLaw>,
    state: Vec<f64>,
}

impl Point {
    fn new(law: Arc<dyn InterfaceLaw>) -> Self {
        let mut state = vec![0.0; law.state_len()];
        law.init_state(&mut state);
        Point { law, state }
    }
    fn trial(&self, jump: [f64; 3]) -> (LawResponse, Vec<f64>) {
        let mut trial = vec![f64::NAN; self.state.len()];
        let r = self
            .law
            .evaluate(
                &LawContext {
                    jump,
                    state_committed: &self.state,
                    step: StepInfo::at(1, 0.0, 1.0),
                },
                &mut trial,
            )
            .unwrap();
        (r, trial)
    }
    fn step(&mut self, jump: [f64; 3]) -> LawResponse {
        let (r, t) = self.trial(jump);
        self.state = t;
        r
    }
    fn out(&self, name: &str) -> f64 {
        common::output_of(self.law.as_ref(), &self.state, name)
    }
    /// Central-difference tangent against the law's (every entry, so the
    /// nonsymmetric part too); returns the law's tangent.
    fn check_tangent(&self, jump: [f64; 3], what: &str) -> [[f64; 3]; 3] {
        common::check_fd_tangent(|j| self.trial(j).0, jump, 1e-8, what)
    }
}

fn asymmetry(t: &[[f64; 3]; 3]) -> f64 {
    let mut m = 0.0f64;
    for i in 0..3 {
        for j in 0..3 {
            m = m.max((t[i][j] - t[j][i]).abs());
        }
    }
    m
}

fn state_of(p: &Point) -> f64 {
    p.out(output::SLIP_STATE)
}

#[test]
fn laws_are_registered_with_a_general_tangent() {
    for law in [friction(), mc(""), bf()] {
        assert_eq!(law.tangent_kind(), MatrixKind::General, "{}", law.key());
        for n in [
            output::PLASTIC_SLIP_1,
            output::PLASTIC_SLIP_2,
            output::ACCUMULATED_SLIP,
            output::SLIP_STATE,
            output::FRICTIONAL_DISSIPATION,
        ] {
            assert!(law.output_names().contains(&n), "{} lacks {n}", law.key());
        }
    }
}

#[test]
fn coulomb_tangent_matches_finite_differences_stick_slip_open_reloading() {
    let law = friction();
    let p = Point::new(law.clone());
    let t = p.check_tangent([1e-6, -2e-6, -2e-5], "stick");
    assert_eq!(p.trial([1e-6, -2e-6, -2e-5]).1[4], output::STICK);
    assert!(asymmetry(&t) < 1e-9);
    let j = [3e-5, 1e-5, -2e-5];
    let t = p.check_tangent(j, "slip");
    assert_eq!(p.trial(j).1[4], output::SLIP);
    // nonsymmetric: d tau / d delta_n = -mu K_n n, d sigma / d delta_s = 0
    let n = [3.0 / 10f64.sqrt(), 1.0 / 10f64.sqrt()];
    assert!((t[0][2] + MU * KN * n[0]).abs() < 1e-6 * KN, "{t:?}");
    assert!(t[2][0].abs() < 1e-12);
    assert!(asymmetry(&t) > 0.1 * MU * KN);
    p.check_tangent([3e-5, 1e-5, 1e-5], "open");
    // slide, then reverse: stick on the way back, then slip the other way
    let mut q = Point::new(law);
    q.step([2e-5, 0.0, -2e-5]);
    q.step([4e-5, 0.0, -2e-5]);
    assert_eq!(state_of(&q), output::SLIP);
    q.check_tangent([3.9e-5, 0.0, -2e-5], "unloading (stick)");
    q.check_tangent([0.0, 1e-5, -2e-5], "reverse slip");
    q.check_tangent([4.5e-5, 0.2e-5, -1e-5], "reloading slip");
}

#[test]
fn mohr_coulomb_tangent_matches_finite_differences_in_every_regime() {
    for extra in ["", "hardening = -2e4", "hardening = 3e4", "tension = 1.5"] {
        let law = mc(extra);
        let p = Point::new(law.clone());
        let what = |r: &str| format!("mohr_coulomb [{extra}] {r}");
        let t = p.check_tangent([1e-6, 1e-6, -1e-6], &what("elastic"));
        assert!(asymmetry(&t) < 1e-9);
        // face, in compression and in tension below the apex / cut-off
        let j = [2e-5, 1e-5, -2e-6];
        let t = p.check_tangent(j, &what("face, compression"));
        assert_eq!(p.trial(j).1[5], output::SLIP);
        assert!(asymmetry(&t) > 1.0, "{t:?}");
        let j = [1e-5, 0.0, 1e-6];
        p.check_tangent(j, &what("face, tension"));
        assert_eq!(p.trial(j).1[5], output::SLIP, "{}", what("face, tension"));
        // high tension: apex (no cut-off) or cut-off / corner
        let j = [1e-6, 0.5e-6, 2e-5];
        p.check_tangent(j, &what("apex or cut-off"));
        assert_eq!(p.trial(j).1[5], output::OPEN);
        let j = [8e-6, 0.0, 2e-5];
        p.check_tangent(j, &what("apex or corner"));
        // plastic history, then unload and reload
        let mut q = Point::new(law);
        q.step([1e-5, 0.0, -2e-6]);
        q.step([3e-5, 0.0, -2e-6]);
        assert_eq!(state_of(&q), output::SLIP);
        q.check_tangent([2.5e-5, 0.0, -2e-6], &what("unloading"));
        q.check_tangent([3.5e-5, 0.5e-5, -2e-6], &what("reloading"));
    }
    // the apex of the law without cut-off
    let p = Point::new(mc(""));
    let j = [1e-6, 0.5e-6, 2e-5];
    let (r, s) = p.trial(j);
    assert_eq!(r.traction[0], 0.0);
    let apex = C / PHI.to_radians().tan();
    assert!((r.traction[2] - apex).abs() < 1e-12 * apex, "{r:?}");
    assert!((s[0] - j[0]).abs() < 1e-20);
    // the softening floor: c reaches c_r
    let law = mc("hardening = -2e4\nresidual_cohesion = 0.5");
    let mut q = Point::new(law.clone());
    let r = q.step([3e-4, 0.0, -2e-6]);
    let f = r.traction[0].hypot(r.traction[1]) + r.traction[2] * PHI.to_radians().tan() - 0.5;
    assert!(f.abs() < 1e-12 * 10.0, "floor: F = {f}");
    q.check_tangent(
        [3.1e-4, 0.0, -2e-6],
        "mohr_coulomb at the residual cohesion",
    );
}

/// The return lands on the yield surface to round-off, the plastic
/// multiplier is never negative, elastic states are inside, and the
/// dissipation never decreases, along a path through every regime.
#[test]
fn return_mapping_lands_on_the_surface_and_dissipation_never_decreases() {
    let tp = PHI.to_radians().tan();
    for (extra, h) in [
        ("", 0.0),
        ("hardening = -2e4", -2e4),
        ("hardening = 3e4", 3e4),
    ] {
        let law = mc(extra);
        let mut p = Point::new(law);
        let path: Vec<[f64; 3]> = (0..80)
            .map(|k| {
                let t = k as f64 * 0.2;
                [
                    3e-5 * t.sin() + 1e-6 * k as f64,
                    2e-5 * (0.7 * t).cos(),
                    -4e-6 + 5e-6 * (0.3 * t).sin(),
                ]
            })
            .collect();
        let mut d_prev = 0.0;
        let mut kappa_prev = 0.0;
        for j in path {
            let r = p.step(j);
            let kappa = p.out(output::ACCUMULATED_SLIP);
            let c = (C + h * kappa).max(0.0);
            let q = r.traction[0].hypot(r.traction[1]);
            let f = q + r.traction[2] * tp - c;
            let scale = 10.0;
            match state_of(&p) {
                s if s == output::SLIP => {
                    assert!(f.abs() < 1e-12 * scale, "[{extra}] face: F = {f:e}")
                }
                s if s == output::STICK => {
                    assert!(f <= 1e-12 * scale, "[{extra}] elastic: F = {f:e}")
                }
                _ => assert!(f <= 1e-12 * scale, "[{extra}] apex: F = {f:e}"),
            }
            assert!(kappa >= kappa_prev, "plastic multiplier negative");
            let d = p.out(output::FRICTIONAL_DISSIPATION);
            assert!(
                d >= d_prev - 1e-15,
                "[{extra}] dissipation decreased: {d_prev} -> {d}"
            );
            d_prev = d;
            kappa_prev = kappa;
        }
        assert!(d_prev > 0.0);
    }
    // Coulomb: on the cone when slipping
    let mut p = Point::new(friction());
    let mut d_prev = 0.0;
    for k in 0..60 {
        let t = k as f64 * 0.25;
        let r = p.step([
            3e-5 * t.sin(),
            2e-5 * (0.5 * t).sin(),
            -2e-5 + 1.5e-5 * (0.4 * t).cos(),
        ]);
        let q = r.traction[0].hypot(r.traction[1]);
        let f = q + MU * r.traction[2];
        if state_of(&p) == output::SLIP {
            assert!(f.abs() < 1e-12 * 10.0, "cone: {f:e}");
        } else {
            assert!(f <= 1e-12 * 10.0);
        }
        let d = p.out(output::FRICTIONAL_DISSIPATION);
        assert!(d >= d_prev - 1e-15);
        d_prev = d;
    }
    assert!(d_prev > 0.0);
}

/// Sliding traction `mu p` under pressure `p`; dissipation `mu p` times the
/// plastic slip.
#[test]
fn coulomb_sliding_traction_is_mu_p_and_dissipation_mu_p_slip() {
    let p_press = 20.0;
    let dn = -p_press / KN;
    let mut p = Point::new(friction());
    let mut r = p.step([0.0, 0.0, dn]);
    for k in 1..=10 {
        r = p.step([1e-5 * k as f64, 0.0, dn]);
    }
    assert!(
        (r.traction[0] - MU * p_press).abs() < 1e-6 * MU * p_press,
        "{r:?}"
    );
    assert!((r.traction[2] + p_press).abs() < 1e-9);
    let slip = p.out(output::PLASTIC_SLIP_1);
    assert!((slip - (1e-4 - MU * p_press / KS)).abs() < 1e-12);
    let d = p.out(output::FRICTIONAL_DISSIPATION);
    assert!(
        (d - MU * p_press * slip).abs() < 1e-6 * d,
        "{d} vs {}",
        MU * p_press * slip
    );
}

/// Drive `p` in slip `s` with the normal jump that keeps `sigma = -press`
/// (Newton on the law's own `d sigma / d delta_n`).
fn step_at_pressure(p: &mut Point, s: f64, dn0: f64, press: f64) -> (LawResponse, f64) {
    let mut dn = dn0;
    for _ in 0..50 {
        let (r, _) = p.trial([s, 0.0, dn]);
        let g = r.traction[2] + press;
        if g.abs() < 1e-13 * press {
            break;
        }
        dn -= g / r.tangent[2][2];
    }
    (p.step([s, 0.0, dn]), dn)
}

/// Mohr-Coulomb strength `c + p tan(phi)` and the dilatant lift
/// `kappa tan(psi)` under constant pressure.
#[test]
fn mohr_coulomb_strength_and_dilatancy_lift() {
    let press = 10.0;
    let mut p = Point::new(mc(""));
    let (_, dn0) = step_at_pressure(&mut p, 0.0, -press / KN, press);
    let mut r = LawResponse::default();
    let mut dn = dn0;
    for k in 1..=20 {
        (r, dn) = step_at_pressure(&mut p, 2e-6 * k as f64, dn, press);
    }
    let strength = C + press * PHI.to_radians().tan();
    assert!((r.traction[0] - strength).abs() < 1e-6 * strength, "{r:?}");
    let kappa = p.out(output::ACCUMULATED_SLIP);
    assert!((kappa - (4e-5 - strength / KS)).abs() < 1e-12);
    let lift = dn - dn0;
    let expected = kappa * PSI.to_radians().tan();
    assert!(
        (lift - expected).abs() < 1e-6 * expected,
        "lift {lift:e}, closed form {expected:e}"
    );
    assert!((p.out(output::PLASTIC_OPENING) - expected).abs() < 1e-6 * expected);
    // dissipation: tau . ds_p + sigma dn_p = kappa (strength - p tan(psi))
    let d = p.out(output::FRICTIONAL_DISSIPATION);
    let d_exact = kappa * (strength - press * PSI.to_radians().tan());
    assert!((d - d_exact).abs() < 1e-6 * d_exact, "{d} vs {d_exact}");
}

/// Alfano-Sacco: undamaged, the law is `bilinear`; fully debonded under a
/// pressure `p`, the shear traction is `mu p`.
#[test]
fn bilinear_friction_keeps_mu_p_after_debonding() {
    let press = 20.0;
    let dn = -press / KN;
    let law = bf();
    // undamaged and elastic: the bilinear law's traction
    let plain = build(
        "bilinear",
        &format!("K = {KN:e}\nN = 30.0\nS = 40.0\nG_Ic = 0.01\nG_IIc = 0.02\neta = 2.0"),
    );
    let a = Point::new(law.clone()).trial([1e-5, 0.0, dn]).0;
    let b = Point::new(plain).trial([1e-5, 0.0, dn]).0;
    assert!((a.traction[0] - b.traction[0]).abs() < 1e-12);
    assert!((a.traction[2] - b.traction[2]).abs() < 1e-12);
    let mut p = Point::new(law);
    let mut r = LawResponse::default();
    for k in 1..=200 {
        r = p.step([1e-5 * k as f64, 0.0, dn]);
    }
    assert!(p.out(output::DAMAGE) >= 1.0 - 1e-9);
    assert!(
        (r.traction[0] - MU * press).abs() < 1e-6 * MU * press,
        "{r:?}"
    );
    assert!(p.out(output::FRICTIONAL_DISSIPATION) > 0.0);
    assert!(p.out(output::DISSIPATED_ENERGY) > 0.0);
}

#[test]
fn bilinear_friction_tangent_matches_finite_differences() {
    let law = bf();
    let p = Point::new(law.clone());
    p.check_tangent([1e-6, 2e-6, -1e-5], "undamaged, closed, stick");
    p.check_tangent([1e-6, 2e-6, 1e-5], "undamaged, open");
    // damage growing in shear under pressure, friction slipping
    let mut q = Point::new(law.clone());
    q.step([4e-5, 0.0, -2e-5]);
    q.step([6e-5, 0.0, -2e-5]);
    let d = q.out(output::DAMAGE);
    assert!(d > 0.0 && d < 1.0, "damage {d}");
    let t = q.check_tangent([7e-5, 1e-5, -2e-5], "damaging, slip");
    assert!(asymmetry(&t) > 1.0, "{t:?}");
    q.check_tangent([5e-5, 0.0, -2e-5], "unloading (stick)");
    q.check_tangent([7e-5, 0.0, 1e-6], "damaging, open");
    // fully debonded
    let mut f = Point::new(law);
    for k in 1..=200 {
        f.step([1e-5 * k as f64, 0.0, -2e-5]);
    }
    f.check_tangent([2.1e-3, 1e-5, -2e-5], "debonded, slip");
    f.check_tangent([1.99e-3, 0.0, -2e-5], "debonded, stick");
    f.check_tangent([2.1e-3, 0.0, 1e-5], "debonded, open");
}

#[test]
fn bad_parameters_are_clear_errors() {
    let e = build_err("coulomb_friction", "K = 1e6\nmu = -0.1");
    assert!(e.contains("coulomb_friction") && e.contains("mu"), "{e}");
    let e = build_err("mohr_coulomb", "K = 1e6\nc = -1.0\nphi = 30.0");
    assert!(e.contains("mohr_coulomb") && e.contains("cohesion"), "{e}");
    for phi in ["90.0", "-1.0", "120.0"] {
        let e = build_err("mohr_coulomb", &format!("K = 1e6\nc = 1.0\nphi = {phi}"));
        assert!(e.contains("phi") && e.contains("[0, 90)"), "{e}");
    }
    let e = build_err("mohr_coulomb", "K = 1e6\nc = 1.0\nphi = 20.0\npsi = 25.0");
    assert!(e.contains("psi") && e.contains("dilatancy"), "{e}");
    let e = build_err(
        "mohr_coulomb",
        "K = 1e6\nc = 1.0\nphi = 30.0\ntension = 5.0",
    );
    assert!(e.contains("tension"), "{e}");
    let e = build_err(
        "mohr_coulomb",
        "K = 1e6\nK_s = 1e3\nc = 1.0\nphi = 0.0\nhardening = -2e3",
    );
    assert!(e.contains("hardening"), "{e}");
    let e = build_err(
        "bilinear_friction",
        "K = 1e6\nN = 30.0\nS = 40.0\nG_Ic = 0.01\nG_IIc = 0.02\neta = 2.0\nmu = -1.0",
    );
    assert!(e.contains("bilinear_friction") && e.contains("mu"), "{e}");
    let e = build_err(
        "bilinear_friction",
        "K = 1e6\nN = 30.0\nS = -40.0\nG_Ic = 0.01\nG_IIc = 0.02\neta = 2.0\nmu = 0.3",
    );
    assert!(e.contains("bilinear_friction") && e.contains("`S`"), "{e}");
    let e = build_err(
        "bilinear_friction",
        "K = 1e6\nN = 30.0\nS = 40.0\nG_Ic = 0.3\nG_IIc = 0.8\neta = 2.0\nmu = \"high\"",
    );
    assert!(e.contains("mu") && e.contains("number"), "{e}");
    let e = build_err(
        "coulomb_friction",
        "K = 1e6\nmu = 0.3\ninterference = -1e-3",
    );
    assert!(e.contains("interference"), "{e}");
    let _ = (
        coulomb_friction::slot::STATE_LEN,
        mohr_coulomb::slot::STATE_LEN,
        bilinear_friction::slot::STATE_LEN,
    );
}

/// In an element and through the assembly: the interface element's
/// stiffness is the derivative of its internal force (finite differences,
/// nonsymmetric part included) for a sliding frictional interface, and the
/// assembler stores that full matrix when the storage is general
/// ([`junta_core::SymmetricCsc::set_general`]), its symmetric part
/// otherwise.
#[test]
fn element_and_assembly_keep_the_nonsymmetric_friction_tangent() {
    use junta_core::element::{Element, ElementContext};
    use junta_core::mesh::{ElementBlock, Mesh};
    use junta_core::topology::CellShape;
    use junta_core::Model;
    use junta_interface::{InterfaceElement, InterfaceRule};
    let law = friction();
    let el: Arc<dyn Element> =
        Arc::new(InterfaceElement::new(CellShape::Inter8, InterfaceRule::Gauss, law).unwrap());
    let face = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    ];
    let coords: Vec<[f64; 3]> = face.iter().chain(face.iter()).copied().collect();
    // top face slid (x, a little y) and pressed, more at one corner
    let mut disp = vec![0.0; 24];
    for a in 0..4 {
        let s = 1.0 + 0.2 * a as f64;
        disp[3 * (4 + a)] = 3e-5 * s;
        disp[3 * (4 + a) + 1] = 1e-5;
        disp[3 * (4 + a) + 2] = -2e-5 * s;
    }
    let mut state = vec![0.0; el.state_len()];
    el.init_state(&mut state);
    let compute = |u: &[f64], k: Option<&mut [f64]>| -> Vec<f64> {
        let mut trial = vec![0.0; state.len()];
        let mut f = vec![0.0; 24];
        el.compute(
            &ElementContext {
                coords: &coords,
                disp: u,
                state_committed: &state,
                step: StepInfo::default(),
                law_responses: None,
                temperature: None,
            },
            &mut trial,
            &mut f,
            k,
        )
        .unwrap();
        f
    };
    let mut ke = vec![0.0; 24 * 24];
    compute(&disp, Some(&mut ke));
    let kmax = ke.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let mut asym = 0.0f64;
    for i in 0..24 {
        for j in 0..24 {
            asym = asym.max((ke[i * 24 + j] - ke[j * 24 + i]).abs());
        }
    }
    assert!(
        asym > 0.05 * kmax,
        "element matrix symmetric: {asym} vs {kmax}"
    );
    let h = 1e-10;
    for j in 0..24 {
        let (mut a, mut b) = (disp.clone(), disp.clone());
        a[j] += h;
        b[j] -= h;
        let (fa, fb) = (compute(&a, None), compute(&b, None));
        for i in 0..24 {
            let fd = (fa[i] - fb[i]) / (2.0 * h);
            assert!(
                (fd - ke[i * 24 + j]).abs() < 1e-5 * kmax,
                "K[{i}][{j}] = {}, finite difference {fd}",
                ke[i * 24 + j]
            );
        }
    }
    // the same element in a model: bottom face held, top free
    let mesh = Mesh {
        nodes: coords.clone(),
        node_labels: Vec::new(),
        blocks: vec![ElementBlock {
            name: "contact".into(),
            shape: CellShape::Inter8,
            connectivity: (0..8).collect(),
            element_type: "inter8".into(),
            material: "friction".into(),
        }],
        node_sets: Default::default(),
        element_sets: Default::default(),
        face_sets: Default::default(),
        ..Default::default()
    };
    let constraints: Vec<(usize, f64)> = (0..12).map(|d| (d, 0.0)).collect();
    let model = Model::new(
        mesh,
        vec![el.clone()],
        &constraints,
        vec![0.0; 24],
        Vec::new(),
    )
    .unwrap();
    assert_eq!(model.matrix_kind(), MatrixKind::General);
    let asm = model.assembler();
    for general in [true, false] {
        let mut k = asm.pattern.clone();
        k.set_general(general);
        let mut st = model.initial_state();
        let mut f = vec![0.0; 24];
        asm.assemble(
            &model.mesh,
            &model.elements,
            &model.dofs,
            &disp,
            &mut st,
            StepInfo::default(),
            Some(&mut k),
            &mut f,
        )
        .unwrap();
        // column q of the assembled matrix by a product with e_q
        for q in 0..k.n {
            let mut e = vec![0.0; k.n];
            e[q] = 1.0;
            let mut col = vec![0.0; k.n];
            k.mul_vec(&e, &mut col);
            let dq = (0..24).find(|&d| model.dofs.eq[d] == q).unwrap();
            for (p, &v) in col.iter().enumerate() {
                let dp = (0..24).find(|&d| model.dofs.eq[d] == p).unwrap();
                let expect = if general {
                    ke[dp * 24 + dq]
                } else {
                    0.5 * (ke[dp * 24 + dq] + ke[dq * 24 + dp])
                };
                assert!(
                    (v - expect).abs() <= 1e-12 * kmax,
                    "general = {general}: A[{p}][{q}] = {v}, element {expect}"
                );
            }
        }
    } // the cached assembly of an incremental analysis, which keeps the
      // pattern positions of the nonlinear elements' entries, gives the same
      // matrix and force, twice over (the second call reuses the positions)
    for general in [true, false] {
        let mut k_plain = asm.pattern.clone();
        k_plain.set_general(general);
        let mut k_cached = k_plain.clone();
        let (mut f_plain, mut f_cached) = (vec![0.0; 24], vec![0.0; 24]);
        let mut st = model.initial_state();
        asm.assemble(
            &model.mesh,
            &model.elements,
            &model.dofs,
            &disp,
            &mut st,
            StepInfo::default(),
            Some(&mut k_plain),
            &mut f_plain,
        )
        .unwrap();
        let mut cached = model.assembler();
        for _ in 0..2 {
            cached
                .assemble_cached(
                    &model.mesh,
                    &model.elements,
                    &model.dofs,
                    &disp,
                    &mut st,
                    StepInfo::default(),
                    Some(&mut k_cached),
                    &mut f_cached,
                )
                .unwrap();
            assert_eq!(k_cached.values, k_plain.values, "general = {general}");
            assert_eq!(k_cached.lower, k_plain.lower, "general = {general}");
            assert_eq!(f_cached, f_plain);
        }
    }
}
