//! `fatigue_cf20` at one integration point: the static law without
//! cycles, the damage history under a held jump against a high-order
//! (RK4) solution of the CF20 rate equation (Davila 2020), initiation
//! below onset, the endurance limit and the load ratio, and the tangent
//! against central differences in every regime.
//!
//! The rate written out here from the paper's form:
//! `dD/dN = (1 - D)^(beta - p) (lambda / eps_R)^beta / ((p + 1) gamma)`,
//! `lambda = lam / ((1 - D) lam_0 + D lam_f)`, `eps_B = eps (1 - 0.42 B)`,
//! `eps_R = 2 eps_B / (eps_B + 1 + R (eps_B - 1))`,
//! `beta = -7 eta / log10(eps_R)`, `p = beta + p_mod`.

mod common;

use junta_core::element::StepInfo;
use junta_core::law::{output, InterfaceLaw, LawContext, LawResponse};
use junta_core::registry::{find, LawEntry};
use junta_interface as _;
use std::sync::Arc;

const K: f64 = 1e6;
const N: f64 = 80.0;
const G_C: f64 = 0.969;
const EPS: f64 = 0.3;
const ETA: f64 = 0.9;
const P_MOD: f64 = 0.5;
const GAMMA: f64 = 1e7;

fn text(extra: &str) -> String {
    format!(
        "K = {K}\nN = {N}\nS = 100.0\nG_Ic = {G_C}\nG_IIc = 1.719\neta = 2.284\nepsilon = {EPS}\nbrittleness = {ETA}\np_mod = {P_MOD}\ngamma = {GAMMA}\n{extra}"
    )
}

fn build_text(t: &str) -> Result<Arc<dyn InterfaceLaw>, String> {
    let t: toml::Table = toml::from_str(t).unwrap();
    (find::<LawEntry>("fatigue_cf20").unwrap().build)(&t).map_err(|e| e.to_string())
}

fn build(extra: &str) -> Arc<dyn InterfaceLaw> {
    build_text(&text(extra)).unwrap()
}

/// A point driven through a jump history, committing after each step.
struct Point {
    law: Arc<dyn InterfaceLaw>,
    state: Vec<f64>,
    inc: usize,
    r: f64,
}

impl Point {
    fn new(law: Arc<dyn InterfaceLaw>, r: f64) -> Self {
        let mut state = vec![0.0; law.state_len()];
        law.init_state(&mut state);
        Point {
            law,
            state,
            inc: 0,
            r,
        }
    }
    fn trial(&self, jump: [f64; 3], dn: f64) -> (LawResponse, Vec<f64>) {
        let mut trial = vec![f64::NAN; self.state.len()];
        let step = StepInfo {
            increment: self.inc + 1,
            delta_cycles: dn,
            load_ratio: self.r,
            ..StepInfo::default()
        };
        let r = self
            .law
            .evaluate(
                &LawContext {
                    jump,
                    state_committed: &self.state,
                    step,
                },
                &mut trial,
            )
            .unwrap();
        (r, trial)
    }
    fn step(&mut self, jump: [f64; 3], dn: f64) {
        self.state = self.trial(jump, dn).1;
        self.inc += 1;
    }
    fn out(&self, name: &str) -> f64 {
        common::output_of(self.law.as_ref(), &self.state, name)
    }
    fn check_tangent(&self, jump: [f64; 3], dn: f64, what: &str) {
        common::check_fd_tangent(
            |j| self.trial(j, dn).0,
            jump,
            1e-7,
            &format!("{what} (dN {dn})"),
        );
    }
}

/// Mode I: onset and final jumps.
fn lam0() -> f64 {
    N / K
}
fn lam_f() -> f64 {
    2.0 * G_C / N
}

/// The paper's rate in mode I at load ratio `r`, energy damage `d`, jump `lam`.
fn rate(d: f64, lam: f64, r: f64) -> f64 {
    let eps_r = 2.0 * EPS / (EPS + 1.0 + r * (EPS - 1.0));
    let beta = -7.0 * ETA / eps_r.log10();
    let p = beta + P_MOD;
    let lambda = lam / ((1.0 - d) * lam0() + d * lam_f());
    if lambda < eps_r {
        return 0.0;
    }
    (1.0 - d).powf(beta - p) * (lambda / eps_r).powf(beta) / ((p + 1.0) * GAMMA)
}

/// D(N) under a held jump by classical RK4 from `d0` over `n` cycles.
fn rk4(d0: f64, lam: f64, r: f64, n: f64, steps: usize) -> f64 {
    let h = n / steps as f64;
    let mut d = d0;
    for _ in 0..steps {
        let k1 = rate(d, lam, r);
        let k2 = rate((d + 0.5 * h * k1).min(1.0), lam, r);
        let k3 = rate((d + 0.5 * h * k2).min(1.0), lam, r);
        let k4 = rate((d + h * k3).min(1.0), lam, r);
        d = (d + h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)).min(1.0);
    }
    d
}

/// With no cycles it is the `bilinear` law: same traction, tangent and
/// damage along a loading path, bit for bit.
#[test]
fn without_cycles_it_is_the_bilinear_law() {
    let cf20 = build("");
    let t: toml::Table = toml::from_str(&format!(
        "K = {K}\nN = {N}\nS = 100.0\nG_Ic = {G_C}\nG_IIc = 1.719\neta = 2.284\n"
    ))
    .unwrap();
    let bilinear = (find::<LawEntry>("bilinear").unwrap().build)(&t).unwrap();
    let mut a = Point::new(cf20, 0.0);
    let mut b = Point::new(bilinear, 0.0);
    for k in 1..=12 {
        let jump = [0.3e-4 * k as f64, 0.0, 1e-4 * k as f64];
        let (ra, rb) = (a.trial(jump, 0.0).0, b.trial(jump, 0.0).0);
        assert_eq!(ra.traction, rb.traction, "step {k}");
        assert_eq!(ra.tangent, rb.tangent, "step {k}");
        a.step(jump, 0.0);
        b.step(jump, 0.0);
        assert_eq!(a.out(output::DAMAGE), b.out(output::DAMAGE));
    }
}

/// The damage at which a held jump `lam` reaches the endurance limit
/// (R = 0): `lambda(D*) = eps_R`.
fn arrest(lam: f64) -> f64 {
    let eps_r = 2.0 * EPS / (EPS + 1.0);
    (lam / eps_r - lam0()) / (lam_f() - lam0())
}

/// Cycles for RK4 to take D from `d0` to `target` at the held jump `lam`.
fn cycles_to(d0: f64, lam: f64, target: f64) -> f64 {
    let (mut lo, mut hi) = (1e-3, 1e9);
    for _ in 0..100 {
        let mid = (lo * hi as f64).sqrt();
        if rk4(d0, lam, 0.0, mid, 2000) < target {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    hi
}

/// Under a held jump the damage follows the rate equation (backward Euler
/// in D: first order, converging to RK4) and arrests where the relative
/// jump reaches the endurance limit, whatever the jump size: past onset
/// (D_0 = 0.02 from the static loading) and below onset (a pristine point:
/// initiation by fatigue alone).
#[test]
fn held_jump_follows_the_rate_equation_and_arrests_at_the_endurance_limit() {
    let law = build("");
    for (lam, d0, what) in [
        (lam0() + 0.02 * (lam_f() - lam0()), 0.02, "past onset"),
        (0.8 * lam0(), 0.0, "below onset"),
    ] {
        let d_star = arrest(lam);
        let target = d0 + 0.5 * (d_star - d0);
        let n_half = cycles_to(d0, lam, target);
        let mut errors = Vec::new();
        for jumps in [50usize, 100, 200] {
            let mut p = Point::new(law.clone(), 0.0);
            p.step([0.0, 0.0, lam], 0.0);
            assert!((p.out(output::ENERGY_DAMAGE) - d0).abs() < 1e-9, "{what}");
            for _ in 0..jumps {
                p.step([0.0, 0.0, lam], n_half / jumps as f64);
            }
            let d = p.out(output::ENERGY_DAMAGE);
            errors.push((d - target).abs() / (target - d0));
            println!("{what}: {jumps} jumps to N = {n_half:.4e}: D = {d:.6e} (RK4 {target:.6e})");
        }
        assert!(errors[2] < 0.01, "{what}: {errors:?}");
        for w in errors.windows(2) {
            assert!(
                (w[0] / w[1] - 2.0).abs() < 0.3,
                "{what}: first order: {errors:?}"
            );
        }
        // arrest: one jump of 1e9 cycles stops on D*
        let mut one = Point::new(law.clone(), 0.0);
        one.step([0.0, 0.0, lam], 0.0);
        one.step([0.0, 0.0, lam], 1e9);
        assert!(
            (one.out(output::ENERGY_DAMAGE) / d_star - 1.0).abs() < 1e-9,
            "{what}: {d_star}"
        );
        assert_eq!(one.out(output::DAMAGE_RATE), 0.0);
        assert!(one.out(output::FATIGUE_DAMAGE) > 0.0);
    }
}

/// Under the endurance limit nothing grows; a load ratio R = 0.5 raises
/// the limit (Goodman) and slows the damage, at the paper's rate.
#[test]
fn endurance_limit_and_load_ratio() {
    let law = build("");
    let mut q = Point::new(law.clone(), 0.0);
    q.step([0.0, 0.0, 0.45 * lam0()], 1e9);
    assert_eq!(q.out(output::ENERGY_DAMAGE), 0.0);
    assert_eq!(rate(0.0, 0.45 * lam0(), 0.0), 0.0);
    let lam = 0.8 * lam0();
    let (mut a, mut b) = (Point::new(law.clone(), 0.0), Point::new(law, 0.5));
    let dn = 1.0;
    a.step([0.0, 0.0, lam], dn);
    b.step([0.0, 0.0, lam], dn);
    let (da, db) = (a.out(output::ENERGY_DAMAGE), b.out(output::ENERGY_DAMAGE));
    assert!(db < da, "{db} {da}");
    // one cycle: backward Euler, D = dN times the rate at its end
    assert!((db / (dn * rate(db, lam, 0.5)) - 1.0).abs() < 1e-9, "{db}");
    assert!((da / (dn * rate(da, lam, 0.0)) - 1.0).abs() < 1e-9, "{da}");
}

/// The tangent against central differences: elastic without cycles,
/// fatigue below onset, softening + fatigue, fatigue at a held damaged
/// point, mixed mode, contact with slip, failed.
#[test]
fn tangent_matches_finite_differences_in_every_regime() {
    for law in [build(""), build("tangent = \"exact\"")] {
        let n = 5e3;
        let fresh = Point::new(law.clone(), 0.1);
        fresh.check_tangent([0.0, 0.0, 0.5 * lam0()], 0.0, "elastic");
        fresh.check_tangent([0.0, 0.0, 0.8 * lam0()], n, "fatigue below onset");
        fresh.check_tangent(
            [0.3 * lam0(), 0.1 * lam0(), 0.8 * lam0()],
            n,
            "mixed, below onset",
        );
        let lam_s = lam0() + 0.02 * (lam_f() - lam0());
        fresh.check_tangent([0.0, 0.0, lam_s], n, "softening + fatigue");
        let mut held = Point::new(law.clone(), 0.1);
        held.step([0.0, 0.0, lam_s], 0.0);
        held.step([0.0, 0.0, lam_s], n);
        held.check_tangent([0.0, 0.0, lam_s], n, "fatigue, held");
        held.check_tangent([0.2 * lam_s, 0.1 * lam_s, lam_s], n, "fatigue, turned");
        held.check_tangent([0.5 * lam_s, 0.0, -0.2 * lam_s], n, "contact + slip");
        // a held jump arrests at the endurance limit: fail it statically
        let mut failed = Point::new(law, 0.1);
        failed.step([0.0, 0.0, 1.5 * lam_f()], 0.0);
        assert_eq!(failed.out(output::DAMAGE), 1.0);
        failed.check_tangent([0.0, 0.0, lam_s], n, "failed, open");
        failed.check_tangent([0.2 * lam_s, 0.0, -0.1 * lam_s], n, "failed, closed");
    }
}

/// Parameter mistakes name the key and what is valid.
#[test]
fn parameter_errors_name_the_key() {
    for (edit, expect) in [
        (("epsilon = 0.3", "epsilon = 1.2"), "`epsilon`"),
        (("epsilon = 0.3\n", ""), "missing `epsilon`"),
        (("brittleness = 0.9", "brittleness = -1"), "`brittleness`"),
        (("gamma = 10000000", "gamma = 0"), "`gamma`"),
        (("p_mod = 0.5", "p_mod = \"x\""), "`p_mod`"),
        (
            ("gamma = 10000000", "gamma = 1e7\nviscosity = 1e-3"),
            "`viscosity`",
        ),
        (("gamma = 10000000", "gamma = 1e7\nC_I = 1"), "fatigue key"),
    ] {
        let t = text("");
        assert!(t.contains(edit.0), "{}", edit.0);
        let e = build_text(&t.replace(edit.0, edit.1)).unwrap_err();
        assert!(
            e.contains("fatigue_cf20") && e.contains(expect),
            "{expect}: {e}"
        );
    }
}
