//! One-point tests of the Paris-law fatigue law `fatigue_bilinear`
//! (crates/interface/src/law/fatigue_paris.rs).
//!
//! Every golden value comes from the closed forms written out here, not
//! from the law's output:
//! - the bilinear curve (BENCHMARKS.md section 4: onset `lam_0 = N/K`,
//!   Camanho & Davila's `delta_0m`, `lam_f = 2 G_c / (K lam_0)`, BK);
//! - Turon et al. 2007's fatigue ODE for the stiffness damage,
//!   `dd/dN = (lam_f (1 - d) + d lam_0)^2 / (lam_f lam_0) * r`, with
//!   `r = C(B) (DG/G_c)^m(B) / l_cz`, integrated here by classical RK4 in
//!   small steps, and its quadrature `N_f = (1 - D_0) / r` (the rate does
//!   not depend on the damage under a held jump);
//! - the mixed-mode Paris coefficients of Blanco et al. 2004.
//!
//! Material: AS4/PEEK strengths and toughnesses (BENCHMARKS.md section 4).
//! The Paris constants below are test values chosen so that a point fails
//! in a few thousand cycles, not material data.

mod common;

use junta_core::element::StepInfo;
use junta_core::law::{output, InterfaceLaw, LawContext, LawResponse};
use junta_core::registry::{find, LawEntry};
use junta_core::CrackDrive;
use junta_interface as _;
use junta_interface::law::fatigue_paris::slot;
use std::sync::Arc;

const K: f64 = 1e6;
const N: f64 = 80.0;
const S: f64 = 100.0;
const GIC: f64 = 0.969;
const GIIC: f64 = 1.719;
const ETA: f64 = 2.284;
// Paris test constants (mm/cycle, dimensionless)
const C_I: f64 = 0.02;
const M_I: f64 = 5.0;
const C_II: f64 = 0.05;
const M_II: f64 = 4.0;
const C_M: f64 = 0.6;
const M_M: f64 = 1.5;
const L_CZ: f64 = 1.0;
/// Energy damage of the static load before the cycles (d about 0.6).
const D_S: f64 = 0.005;

fn base_text() -> String {
    format!("K = {K:e}\nN = {N}\nS = {S}\nG_Ic = {GIC}\nG_IIc = {GIIC}\neta = {ETA}\n")
}

fn paris_text() -> String {
    format!("C_I = {C_I}\nm_I = {M_I}\nC_II = {C_II}\nm_II = {M_II}\nC_m = {C_M}\nm_m = {M_M}\n")
}

fn build_text(text: &str) -> Arc<dyn InterfaceLaw> {
    let t: toml::Table = toml::from_str(text).unwrap();
    (find::<LawEntry>("fatigue_bilinear").unwrap().build)(&t).unwrap()
}

fn build(extra: &str) -> Arc<dyn InterfaceLaw> {
    build_text(&format!(
        "{}{}l_cz = {L_CZ}\n{extra}",
        base_text(),
        paris_text()
    ))
}

fn build_err(text: &str) -> String {
    let t: toml::Table = toml::from_str(text).unwrap();
    (find::<LawEntry>("fatigue_bilinear").unwrap().build)(&t)
        .unwrap_err()
        .to_string()
}

fn step(inc: usize, n: f64, dn: f64, r: f64) -> StepInfo {
    StepInfo {
        increment: inc,
        load_factor: 1.0,
        delta_load_factor: if dn > 0.0 { 0.0 } else { 1.0 },
        cycles: n,
        delta_cycles: dn,
        load_ratio: r,
        crack_drive: None,
        ..StepInfo::default()
    }
}

/// A crack measured by the driver: J, its mode ratio and the zone length.
fn measured(j: f64, b: f64, zone: f64) -> Option<CrackDrive> {
    Some(CrackDrive {
        energy_release_rate: j,
        mode_ratio: b,
        process_zone_length: zone,
    })
}

/// A point driven through a jump history, committing after each step.
struct Point {
    law: Arc<dyn InterfaceLaw>,
    state: Vec<f64>,
    inc: usize,
    cycles: f64,
    r: f64,
    /// The crack the driver measured (`None`: the law's local estimate).
    drive: Option<CrackDrive>,
}

impl Point {
    fn new(law: Arc<dyn InterfaceLaw>) -> Self {
        let mut state = vec![0.0; law.state_len()];
        law.init_state(&mut state);
        Point {
            law,
            state,
            inc: 0,
            cycles: 0.0,
            r: 0.0,
            drive: None,
        }
    }
    fn trial(&self, jump: [f64; 3], dn: f64) -> (LawResponse, Vec<f64>) {
        let mut trial = vec![f64::NAN; self.state.len()];
        let r = self
            .law
            .evaluate(
                &LawContext {
                    jump,
                    state_committed: &self.state,
                    step: StepInfo {
                        crack_drive: self.drive,
                        ..step(self.inc + 1, self.cycles + dn, dn, self.r)
                    },
                },
                &mut trial,
            )
            .unwrap();
        (r, trial)
    }
    fn step(&mut self, jump: [f64; 3], dn: f64) -> LawResponse {
        let (r, t) = self.trial(jump, dn);
        self.state = t;
        self.inc += 1;
        self.cycles += dn;
        r
    }
    fn out(&self, name: &str) -> f64 {
        common::output_of(self.law.as_ref(), &self.state, name)
    }
    fn damage(&self) -> f64 {
        self.out(output::DAMAGE)
    }
    /// Central-difference tangent against the law's at the cycle step
    /// `dn` (trial states discarded).
    fn check_tangent(&self, jump: [f64; 3], dn: f64, what: &str) {
        let what = format!("{what} (dN {dn})");
        common::check_fd_tangent(|j| self.trial(j, dn).0, jump, 1e-7, &what);
    }
}

/// The closed-form equivalent law of a proportional jump direction with
/// one penalty `K` and the quadratic criterion: mode ratio, onset jump,
/// toughness, final jump (Camanho & Davila 2002; BENCHMARKS.md 4).
#[derive(Debug, Clone, Copy)]
struct Mode {
    b: f64,
    lam0: f64,
    g_c: f64,
    lam_f: f64,
}

/// The mode of the jump direction `(slip, opening) = (sin a, cos a)`.
fn mode(slip: f64, opening: f64) -> Mode {
    let norm = (slip * slip + opening * opening).sqrt();
    let (s, o) = (slip / norm, opening / norm);
    // onset: (K lam o / N)^2 + (K lam s / S)^2 = 1
    let lam0 = 1.0 / (K * ((o / N).powi(2) + (s / S).powi(2)).sqrt());
    let b = s * s; // K_s = K_n: B = slip^2 / lam^2
    let g_c = GIC + (GIIC - GIC) * b.powf(ETA);
    Mode {
        b,
        lam0,
        g_c,
        lam_f: 2.0 * g_c / (K * lam0),
    }
}

impl Mode {
    /// Static stiffness damage at `lam`.
    fn static_damage(&self, lam: f64) -> f64 {
        (self.lam_f * (lam - self.lam0) / (lam * (self.lam_f - self.lam0))).clamp(0.0, 1.0)
    }
    /// Area under the static curve up to `lam` (the law's `G_max`).
    fn g_max(&self, lam: f64) -> f64 {
        if lam <= self.lam0 {
            0.5 * K * lam * lam
        } else if lam < self.lam_f {
            let tau0 = K * self.lam0;
            self.g_c - 0.5 * tau0 * (self.lam_f - lam).powi(2) / (self.lam_f - self.lam0)
        } else {
            self.g_c
        }
    }
    /// Blanco et al. 2004: C(B), m(B).
    fn paris(&self) -> (f64, f64) {
        let b = self.b;
        let m = M_I + M_M * b + (M_II - M_I - M_M) * b * b;
        let ln_c = C_I.ln() + b * C_M.ln() + b * b * (C_II / (C_I * C_M)).ln();
        (ln_c.exp(), m)
    }
    /// Energy-damage rate r = dD/dN at a held `lam`, load ratio `r`.
    fn rate(&self, lam: f64, r: f64, l_cz: f64) -> f64 {
        let (c, m) = self.paris();
        c * ((1.0 - r * r) * self.g_max(lam) / self.g_c).powf(m) / l_cz
    }
    /// Turon's ODE for the stiffness damage: dd/dN.
    fn dd_dn(&self, d: f64, rate: f64) -> f64 {
        (self.lam_f * (1.0 - d) + d * self.lam0).powi(2) / (self.lam_f * self.lam0) * rate
    }
    /// d(N) by classical RK4 from `d0` over `n` cycles in `steps` steps.
    fn rk4(&self, d0: f64, rate: f64, n: f64, steps: usize) -> f64 {
        let h = n / steps as f64;
        let mut d = d0;
        for _ in 0..steps {
            let k1 = self.dd_dn(d, rate);
            let k2 = self.dd_dn(d + 0.5 * h * k1, rate);
            let k3 = self.dd_dn(d + 0.5 * h * k2, rate);
            let k4 = self.dd_dn(d + h * k3, rate);
            d += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
        }
        d
    }
    /// Energy damage of a stiffness damage (fraction of G_c dissipated).
    fn energy_damage(&self, d: f64) -> f64 {
        d * self.lam0 / (self.lam_f * (1.0 - d) + d * self.lam0)
    }
}

/// Load a fresh point statically to `jump`, then hold it for cycles in
/// steps of `dn` until it fails; compare `d(N)` with RK4 of Turon's ODE
/// and return (the law's N at failure, the closed form's).
fn held_jump_to_failure(
    law: Arc<dyn InterfaceLaw>,
    m: Mode,
    jump: [f64; 3],
    dn: f64,
    what: &str,
) -> (f64, f64) {
    let lam = (jump[0] * jump[0] + jump[1] * jump[1] + jump[2].max(0.0).powi(2)).sqrt();
    let mut p = Point::new(law);
    p.step(jump, 0.0);
    let d0 = m.static_damage(lam);
    assert!(
        (p.damage() - d0).abs() < 1e-12,
        "{what}: static damage {} against {d0}",
        p.damage()
    );
    assert!(
        d0 > 0.0 && d0 < 0.99,
        "{what}: choose a jump inside the softening branch"
    );
    let rate = m.rate(lam, 0.0, L_CZ);
    // the quadrature of dD/dN = r with D(0) = D_static
    let n_fail = (1.0 - m.energy_damage(d0)) / rate;
    let mut n_law = f64::NAN;
    let mut checked = 0;
    for k in 1..100_000 {
        let before = p.state.clone();
        p.step(jump, dn);
        // rate the law used, against the closed form
        let r_law = p.out(output::DAMAGE_RATE);
        assert!(
            (r_law - rate).abs() < 1e-10 * rate,
            "{what}: rate {r_law} against {rate}"
        );
        if p.damage() >= 1.0 {
            // N at failure: the cycles of the steps before, plus the
            // fraction of this step the remaining energy damage needed
            let d_prev = before[slot::DAMAGE];
            n_law = (k - 1) as f64 * dn + (1.0 - m.energy_damage(d_prev)) / r_law;
            break;
        }
        // d(N) against RK4 of Turon's ODE (in d) from the static damage
        let n = k as f64 * dn;
        let d_ode = m.rk4(d0, rate, n, 4000);
        assert!(
            (p.damage() - d_ode).abs() < 1e-8,
            "{what}: N = {n}: d = {} against RK4 {d_ode}",
            p.damage()
        );
        checked += 1;
    }
    assert!(
        checked >= 3,
        "{what}: too few increments before failure ({checked})"
    );
    assert!(n_law.is_finite(), "{what}: never failed");
    // fully failed: traction zero, energy = G_c (proportional path)
    let r = p.step(jump, dn);
    assert!(
        r.traction.iter().all(|t| *t == 0.0),
        "{what}: traction {:?}",
        r.traction
    );
    let e = p.out(output::DISSIPATED_ENERGY);
    assert!(
        (e - m.g_c).abs() < 1e-9 * m.g_c,
        "{what}: dissipated {e} against G_c {}",
        m.g_c
    );
    let fatigue = p.out(output::FATIGUE_DAMAGE);
    let expected = 1.0 - m.energy_damage(d0);
    assert!(
        (fatigue - expected).abs() < 1e-9,
        "{what}: fatigue_damage {fatigue} against {expected}"
    );
    (n_law, n_fail)
}

/// The held-jump test in one mode for several cycle jumps: d(N) on
/// Turon's ODE, N at failure on the closed form, and independent of the
/// jump size.
fn held_jump_mode(law: Arc<dyn InterfaceLaw>, slip: f64, opening: f64, d_s: f64, what: &str) {
    let m = mode(slip, opening);
    let norm = (slip * slip + opening * opening).sqrt();
    let lam = m.lam0 + d_s * (m.lam_f - m.lam0);
    let jump = [lam * slip / norm, 0.0, lam * opening / norm];
    let rate = m.rate(lam, 0.0, L_CZ);
    let n_fail = (1.0 - m.energy_damage(m.static_damage(lam))) / rate;
    let mut results = Vec::new();
    for parts in [10.0, 20.0, 37.0] {
        let dn = n_fail / parts * 1.000_001; // not a divisor of N_f
        let (n_law, n_closed) = held_jump_to_failure(
            law.clone(),
            m,
            jump,
            dn,
            &format!("{what}, dN = N_f/{parts}"),
        );
        assert!((n_closed - n_fail).abs() < 1e-12 * n_fail);
        let err = (n_law - n_fail).abs() / n_fail;
        assert!(
            err < 1e-9,
            "{what}: N_f {n_law} against closed form {n_fail} (rel. {err:.2e})"
        );
        results.push(n_law);
    }
    // halving the jump (and more) changes N at failure by < 1e-9
    for w in results.windows(2) {
        assert!(
            (w[0] - w[1]).abs() < 1e-9 * w[0],
            "{what}: N_f {} vs {}",
            w[0],
            w[1]
        );
    }
    eprintln!("{what}: B = {:.3}, lam = {lam:.4e}, G_max/G_c = {:.4}, N_f closed form {n_fail:.2}, law {results:.6?}", m.b, m.g_max(lam) / m.g_c);
}

#[test]
fn mode_i_held_opening_fails_at_the_paris_rate() {
    // D_static = 0.005 (d about 0.6: lam_f / lam_0 is about 300, G_max/G_c
    // about 0.013) and 0.05 (d about 0.94, G_max/G_c about 0.1)
    held_jump_mode(build(""), 0.0, 1.0, D_S, "mode I");
    held_jump_mode(build(""), 0.0, 1.0, 0.05, "mode I, deeper");
}

#[test]
fn mode_ii_held_slip_fails_at_the_paris_rate() {
    held_jump_mode(build(""), 1.0, 0.0, D_S, "mode II");
    held_jump_mode(build(""), 1.0, 0.0, 0.05, "mode II, deeper");
}

#[test]
fn mixed_mode_b_half_uses_the_interpolated_c_and_m() {
    let m = mode(1.0, 1.0);
    assert!((m.b - 0.5).abs() < 1e-15);
    held_jump_mode(build(""), 1.0, 1.0, D_S, "mixed B = 0.5");
    held_jump_mode(build(""), 1.0, 1.0, 0.05, "mixed B = 0.5, deeper");
    // the interpolation itself (Blanco et al. 2004 at B = 1/2):
    // m = m_I + m_m/2 + (m_II - m_I - m_m)/4, log C likewise
    let (c, mm) = m.paris();
    assert!((mm - (5.0 + 0.75 + (4.0 - 5.0 - 1.5) / 4.0)).abs() < 1e-12);
    let c_expected =
        (0.02f64.ln() + 0.5 * 0.6f64.ln() + 0.25 * (0.05f64 / (0.02 * 0.6)).ln()).exp();
    assert!((c - c_expected).abs() < 1e-15);
}

#[test]
fn cycle_jump_across_onset_and_with_steps_of_any_size() {
    // a point just past onset, held, with uneven jumps: N at failure
    // still on the quadrature N_f = (1 - D_0) / r
    let law = build("");
    let m = mode(0.0, 1.0);
    let lam = m.lam0 * 1.5;
    let jump = [0.0, 0.0, lam];
    let rate = m.rate(lam, 0.0, L_CZ);
    let d0 = m.static_damage(lam);
    let n_fail = (1.0 - m.energy_damage(d0)) / rate;
    let mut p = Point::new(law);
    p.step(jump, 0.0);
    let sizes = [0.013, 0.2, 0.05, 0.31, 0.002, 0.17];
    let mut n = 0.0;
    let mut k = 0;
    loop {
        let dn = sizes[k % sizes.len()] * n_fail;
        let before = p.state.clone();
        p.step(jump, dn);
        if p.damage() >= 1.0 {
            let d_prev = before[slot::DAMAGE];
            n += (1.0 - m.energy_damage(d_prev)) / p.out(output::DAMAGE_RATE);
            break;
        }
        n += dn;
        k += 1;
        let d_ode = m.rk4(d0, rate, n, 4000);
        assert!(
            (p.damage() - d_ode).abs() < 1e-8,
            "N = {n}: d {} RK4 {d_ode}",
            p.damage()
        );
    }
    assert!(
        (n - n_fail).abs() < 1e-9 * n_fail,
        "N_f {n} against {n_fail}"
    );
}

#[test]
fn delta_cycles_zero_is_the_bilinear_law_bit_for_bit() {
    let fat = build("");
    let t: toml::Table = toml::from_str(&base_text()).unwrap();
    let bil = (find::<LawEntry>("bilinear").unwrap().build)(&t).unwrap();
    let mut pf = Point::new(fat);
    let mut pb = Point::new(bil);
    let path = [
        [0.0, 0.0, 5e-5],
        [0.0, 0.0, 2e-4],
        [1e-4, 0.0, 3e-4],
        [5e-5, 0.0, 1e-4],
        [0.0, 3e-4, -1e-4],
        [2e-4, 1e-4, 8e-4],
        [0.0, 0.0, 3e-2],
        [1e-5, 0.0, -2e-5],
    ];
    for j in path {
        let rf = pf.step(j, 0.0);
        let rb = pb.step(j, 0.0);
        assert_eq!(rf, rb, "jump {j:?}");
        for s in [
            slot::DAMAGE,
            slot::DAMAGE_HISTORY,
            slot::ENERGY,
            slot::MODE_RATIO,
        ] {
            assert_eq!(pf.state[s], pb.state[s], "jump {j:?}, slot {s}");
        }
        assert_eq!(pf.out(output::FATIGUE_DAMAGE), 0.0);
    }
}

#[test]
fn threshold_and_load_ratio() {
    let m = mode(0.0, 1.0);
    let lam = m.lam0 + D_S * (m.lam_f - m.lam0);
    let g = m.g_max(lam);
    let jump = [0.0, 0.0, lam];
    // R: the rate scales with (1 - R^2)^m_I
    let mut p = Point::new(build(""));
    p.step(jump, 0.0);
    let r0 = p.trial(jump, 1.0).1[slot::DAMAGE_RATE];
    p.r = 0.5;
    let r5 = p.trial(jump, 1.0).1[slot::DAMAGE_RATE];
    assert!((r5 / r0 - 0.75f64.powf(M_I)).abs() < 1e-12, "{}", r5 / r0);
    assert!((r0 - m.rate(lam, 0.0, L_CZ)).abs() < 1e-12 * r0);
    assert!((p.trial(jump, 1.0).1[slot::ENERGY_RELEASE_RATE] - g).abs() < 1e-12 * g);
    // a load ratio outside [0, 1) is an error in a fatigue increment
    p.r = 1.0;
    let mut trial = vec![0.0; p.state.len()];
    let e = p
        .law
        .evaluate(
            &LawContext {
                jump,
                state_committed: &p.state,
                step: step(2, 1.0, 1.0, 1.0),
            },
            &mut trial,
        )
        .unwrap_err();
    assert!(e.to_string().contains("load ratio"), "{e}");
    // threshold above DG: no growth; below: growth at the Paris rate
    let mut above = Point::new(build(&format!("G_th = {}", 1.01 * g)));
    above.step(jump, 0.0);
    let d_static = above.damage();
    above.step(jump, 1e30);
    assert_eq!(above.damage(), d_static);
    assert_eq!(above.out(output::DAMAGE_RATE), 0.0);
    let mut below = Point::new(build(&format!("G_th = {}", 0.99 * g)));
    below.step(jump, 0.0);
    below.step(jump, 1.0);
    assert!((below.out(output::DAMAGE_RATE) - r0).abs() < 1e-12 * r0);
    // a pristine point below onset gets no fatigue damage
    let mut pristine = Point::new(build(""));
    pristine.step([0.0, 0.0, 0.9 * m.lam0], 1e30);
    assert_eq!(pristine.damage(), 0.0);
}

#[test]
fn zone_length_from_the_modulus() {
    // l_cz = M E G_c / tau_0^2 with tau_0 = K lam_0 (Hillerborg M = 1,
    // then M = 0.88), in mode I and at B = 0.5
    let e_mod = 10100.0;
    for (m_factor, extra) in [(1.0, String::new()), (0.88, "M = 0.88\n".to_string())] {
        let law = build_text(&format!(
            "{}{}E = {e_mod}\n{extra}",
            base_text(),
            paris_text()
        ));
        for (slip, opening) in [(0.0, 1.0), (1.0, 1.0)] {
            let m = mode(slip, opening);
            let norm = (slip * slip + opening * opening).sqrt();
            let lam = m.lam0 + 0.4 * (m.lam_f - m.lam0);
            let jump = [lam * slip / norm, 0.0, lam * opening / norm];
            let tau0 = K * m.lam0;
            let l_cz = m_factor * e_mod * m.g_c / (tau0 * tau0);
            let mut p = Point::new(law.clone());
            p.step(jump, 0.0);
            p.step(jump, 1.0);
            let r = p.out(output::DAMAGE_RATE);
            let expected = m.rate(lam, 0.0, l_cz);
            assert!(
                (r - expected).abs() < 1e-10 * expected,
                "M {m_factor}, B {}: {r} vs {expected}",
                m.b
            );
        }
    }
}

#[test]
fn fatigue_damage_is_irreversible() {
    let law = build("");
    let m = mode(0.0, 1.0);
    let lam = m.lam0 + D_S * (m.lam_f - m.lam0);
    let n_f = (1.0 - D_S) / m.rate(lam, 0.0, L_CZ);
    let mut p = Point::new(law);
    p.step([0.0, 0.0, lam], 0.0);
    p.step([0.0, 0.0, lam], 0.3 * n_f);
    let d = p.damage();
    assert!(d > m.static_damage(lam));
    // unloading, closing, reloading below the curve, and cycles at no
    // opening: damage stays
    for j in [
        [0.0, 0.0, 0.5 * lam],
        [0.0, 0.0, -lam],
        [0.0, 0.0, 0.0],
        [0.0, 0.0, lam],
    ] {
        p.step(j, 0.0);
        assert_eq!(p.damage(), d, "jump {j:?}");
    }
    p.step([0.0, 0.0, 0.0], n_f);
    assert_eq!(p.damage(), d);
    // a damaged point unloaded below onset still grows, slowly (its own
    // small G_max)
    p.step([0.0, 0.0, 0.5 * m.lam0], n_f);
    assert!(p.damage() > d);
}

#[test]
fn tangent_matches_finite_differences_in_every_regime() {
    let law = build("");
    let exact = build("tangent = \"exact\"");
    for (slip, opening, name) in [
        (0.0, 1.0, "mode I"),
        (1.0, 0.0, "mode II"),
        (1.0, 1.0, "B = 0.5"),
        (0.6, 1.0, "B = 0.26"),
    ] {
        let m = mode(slip, opening);
        let norm = (slip * slip + opening * opening).sqrt();
        // pure shear: a little contact pressure keeps the normal jump off
        // the kink at delta_n = 0 (the finite difference would straddle it)
        let closed = if opening == 0.0 { -0.01 } else { 0.0 };
        let dir = |lam: f64| {
            [
                lam * slip / norm,
                0.3 * lam * slip / norm,
                lam * (opening / norm + closed),
            ]
        };
        let dir0 = |lam: f64| [lam * slip / norm, 0.0, lam * (opening / norm + closed)];
        for law in [&law, &exact] {
            let fresh = Point::new(law.clone());
            let lam_s = m.lam0 + D_S * (m.lam_f - m.lam0);
            let n_f = (1.0 - D_S) / m.rate(lam_s, 0.0, L_CZ);
            // elastic (also in a fatigue increment: pristine, below onset)
            fresh.check_tangent(dir0(0.5 * m.lam0), 0.0, &format!("{name}: elastic"));
            fresh.check_tangent(dir0(0.5 * m.lam0), n_f, &format!("{name}: elastic, dN > 0"));
            // static softening from a pristine point
            fresh.check_tangent(dir0(lam_s), 0.0, &format!("{name}: static softening"));
            // static softening and fatigue in one increment
            fresh.check_tangent(
                dir0(lam_s),
                0.2 * n_f,
                &format!("{name}: softening + fatigue"),
            );
            // fatigue growth at a held jump (committed on the surface),
            // and in a turned direction (mode ratio changes)
            let mut held = Point::new(law.clone());
            held.step(dir0(lam_s), 0.0);
            held.step(dir0(lam_s), 0.3 * n_f);
            held.check_tangent(dir0(lam_s), 0.2 * n_f, &format!("{name}: fatigue, held"));
            held.check_tangent(
                dir0(0.97 * lam_s),
                0.2 * n_f,
                &format!("{name}: fatigue, unloaded a little"),
            );
            if slip > 0.0 {
                held.check_tangent(dir(lam_s), 0.2 * n_f, &format!("{name}: fatigue, turned"));
            }
            // compression with slip on a damaged point (contact + fatigue
            // from the slip)
            held.check_tangent(
                [0.5 * lam_s, 0.0, -0.2 * lam_s],
                0.2 * n_f,
                &format!("{name}: contact + slip"),
            );
            held.check_tangent(
                [0.0, 0.0, -0.2 * lam_s],
                0.2 * n_f,
                &format!("{name}: contact"),
            );
            // fully failed, open and closed
            let mut failed = Point::new(law.clone());
            failed.step(dir0(lam_s), 0.0);
            failed.step(dir0(lam_s), 2.0 * n_f);
            assert_eq!(failed.damage(), 1.0);
            failed.check_tangent(dir0(lam_s), n_f, &format!("{name}: failed, open"));
            failed.check_tangent(
                [0.3 * lam_s, 0.0, -0.1 * lam_s],
                n_f,
                &format!("{name}: failed, closed"),
            );
        }
    }
}

#[test]
fn fatigue_tangent_is_softer_than_the_static_one() {
    // mode I, held: dt/ddelta = (1 - d) K - K delta dd/ddelta, and the
    // fatigue increment adds dN dr/ddelta (through G_max) to dd/ddelta
    let law = build("");
    let m = mode(0.0, 1.0);
    let lam = m.lam0 + D_S * (m.lam_f - m.lam0);
    let mut p = Point::new(law);
    p.step([0.0, 0.0, lam], 0.0);
    let (r_static, _) = p.trial([0.0, 0.0, lam], 0.0);
    let dn = 0.3 * (1.0 - D_S) / m.rate(lam, 0.0, L_CZ);
    let (r_fat, tr) = p.trial([0.0, 0.0, lam], dn);
    assert!(r_fat.tangent[2][2] < r_static.tangent[2][2]);
    // closed form: D = D_s(lam) + dN r(lam), d = lam_f D / (lam_0 + D (lam_f - lam_0))
    let (c, mm) = m.paris();
    let g = m.g_max(lam);
    let tau = K * lam * (1.0 - m.static_damage(lam)); // dG_max/dlam
    let r = m.rate(lam, 0.0, L_CZ);
    let dr = mm * r / g * tau;
    let _ = c;
    let big_d = (lam - m.lam0) / (m.lam_f - m.lam0) + dn * r;
    let d_big_d = 1.0 / (m.lam_f - m.lam0) + dn * dr;
    let den = m.lam0 + big_d * (m.lam_f - m.lam0);
    let d = m.lam_f * big_d / den;
    let dd = m.lam_f * m.lam0 / (den * den) * d_big_d;
    assert!((tr[slot::DAMAGE] - d).abs() < 1e-12);
    let kt = (1.0 - d) * K - K * lam * dd;
    assert!(
        (r_fat.tangent[2][2] - kt).abs() < 1e-8 * K,
        "{} vs {kt}",
        r_fat.tangent[2][2]
    );
}

/// With the crack measured (J, its mode ratio, the zone length L), every
/// point of the zone grows its energy damage at `C(B_J) (J / G_c(B_J))^m
/// / L`, whatever its own jump; a point below onset at the start of the
/// increment gets none (the zone is frozen over the increment).
#[test]
fn measured_crack_drives_every_zone_point_at_the_paris_rate_over_the_zone() {
    let law = build("");
    let m1 = mode(0.0, 1.0);
    let half = mode(1.0, 1.0);
    for (j, b, zone) in [(0.4 * GIC, 0.0, 0.5), (0.3 * half.g_c, 0.5, 0.8)] {
        let target = Mode { b, ..half };
        let g_c = if b == 0.0 { m1.g_c } else { half.g_c };
        let (c, m) = target.paris();
        let rate = c * (j / g_c).powf(m) / zone;
        for lam_frac in [0.1, 0.4] {
            let mut p = Point::new(law.clone());
            let lam = m1.lam0 + lam_frac * (m1.lam_f - m1.lam0);
            p.step([0.0, 0.0, lam], 0.0);
            p.drive = measured(j, b, zone);
            let dn = 0.2 / rate;
            let before = p.out(output::FATIGUE_DAMAGE);
            p.step([0.0, 0.0, lam], dn);
            let grown = p.out(output::FATIGUE_DAMAGE) - before;
            assert!(
                (grown / (rate * dn) - 1.0).abs() < 1e-12,
                "B {b}, lam {lam_frac}: {grown} against {}",
                rate * dn
            );
            assert!((p.out(output::DAMAGE_RATE) / rate - 1.0).abs() < 1e-12);
            assert_eq!(p.out(output::ENERGY_RELEASE_RATE), j);
        }
    }
    // below onset at the start: no fatigue, even past onset at the end
    let mut p = Point::new(law.clone());
    p.step([0.0, 0.0, 0.5 * m1.lam0], 0.0);
    p.drive = measured(0.4 * GIC, 0.0, 0.5);
    p.step([0.0, 0.0, 1.2 * m1.lam0], 1e3);
    assert_eq!(p.out(output::FATIGUE_DAMAGE), 0.0);
    // a zone of no length moves nothing
    let mut p = Point::new(law);
    p.step([0.0, 0.0, 2.0 * m1.lam0], 0.0);
    p.drive = measured(0.4 * GIC, 0.0, 0.0);
    p.step([0.0, 0.0, 2.0 * m1.lam0], 1e3);
    assert_eq!(p.out(output::FATIGUE_DAMAGE), 0.0);
}

/// The tangent with a measured crack (its rate constant in the jump),
/// against central differences: held, softening + fatigue, turned, contact.
#[test]
fn tangent_with_a_measured_crack_matches_finite_differences() {
    for law in [build(""), build("tangent = \"exact\"")] {
        for (slip, opening, name) in [
            (0.0, 1.0, "mode I"),
            (1.0, 1.0, "B = 0.5"),
            (1.0, 0.0, "mode II"),
        ] {
            let m = mode(slip, opening);
            let norm = (slip * slip + opening * opening).sqrt();
            let closed = if opening == 0.0 { -0.01 } else { 0.0 };
            let dir = |lam: f64, turn: f64| {
                [
                    lam * slip / norm,
                    turn * lam,
                    lam * (opening / norm + closed),
                ]
            };
            let lam_s = m.lam0 + 0.05 * (m.lam_f - m.lam0);
            let drive = measured(0.35 * m.g_c, m.b, 0.7);
            let (c, mm) = m.paris();
            let n_f = 0.7 / (c * 0.35f64.powf(mm));
            let mut p = Point::new(law.clone());
            p.step(dir(lam_s, 0.0), 0.0);
            p.drive = drive;
            // off the static curve's kink (committed damage above d_B)
            p.step(dir(lam_s, 0.0), 0.3 * n_f);
            p.check_tangent(
                dir(lam_s, 0.0),
                0.2 * n_f,
                &format!("{name}: measured, held"),
            );
            p.check_tangent(
                dir(1.3 * lam_s, 0.0),
                0.2 * n_f,
                &format!("{name}: measured, softening + fatigue"),
            );
            p.check_tangent(
                dir(0.9 * lam_s, 0.0),
                0.2 * n_f,
                &format!("{name}: measured, unloaded"),
            );
            p.check_tangent(
                dir(lam_s, 0.2),
                0.2 * n_f,
                &format!("{name}: measured, turned"),
            );
            p.check_tangent(
                [0.5 * lam_s, 0.0, -0.2 * lam_s],
                0.2 * n_f,
                &format!("{name}: measured, contact + slip"),
            );
        }
    }
}

/// Without `l_cz` or `E` the local estimate has no zone length: a fatigue
/// increment without a measured crack fails with a message that says what
/// to give; a static one (the rate unused) does not.
#[test]
fn local_estimate_without_a_zone_length_says_what_to_give() {
    let law = build_text(&format!("{}{}", base_text(), paris_text()));
    let m1 = mode(0.0, 1.0);
    let mut p = Point::new(law.clone());
    p.step([0.0, 0.0, 2.0 * m1.lam0], 0.0);
    let mut trial = vec![0.0; law.state_len()];
    let e = law
        .evaluate(
            &LawContext {
                jump: [0.0, 0.0, 2.0 * m1.lam0],
                state_committed: &p.state,
                step: step(2, 10.0, 10.0, 0.0),
            },
            &mut trial,
        )
        .unwrap_err()
        .to_string();
    assert!(e.contains("`l_cz`") && e.contains("crack_front"), "{e}");
}

#[test]
fn parameter_errors_name_the_key() {
    let base = base_text();
    let full = format!("{base}{}l_cz = 1.0\n", paris_text());
    // missing Paris constants
    for key in ["C_I", "m_I", "C_II", "m_II"] {
        let text: String = full
            .lines()
            .filter(|l| !l.starts_with(&format!("{key} ")))
            .map(|l| format!("{l}\n"))
            .collect();
        let e = build_err(&text);
        assert!(
            e.contains("fatigue_bilinear") && e.contains(&format!("`{key}`")),
            "{e}"
        );
    }
    let e = build_err(&full.replace("C_I = 0.02", "C_I = -1"));
    assert!(e.contains("`C_I`") && e.contains("positive"), "{e}");
    let e = build_err(&format!("{full}G_th = -0.1\n"));
    assert!(e.contains("`G_th`"), "{e}");
    let e = build_err(&format!("{full}E = 1e4\n"));
    assert!(e.contains("`l_cz`") && e.contains("`E`"), "{e}");
    // neither l_cz nor E: the zone is measured; M alone has no E to scale
    let e = build_err(&format!("{base}{}M = 0.9\n", paris_text()));
    assert!(e.contains("`M`") && e.contains("`E`"), "{e}");
    let e = build_err(&format!("{base}{}E = 1e4\nM = 0\n", paris_text()));
    assert!(e.contains("`M`"), "{e}");
    let e = build_err(&full.replace("m_m = 1.5", "m_m = -30"));
    assert!(e.contains("`m_m`") && e.contains("m(B)"), "{e}");
    let e = build_err(&format!("{full}viscosity = 1e-3\n"));
    assert!(e.contains("`viscosity`"), "{e}");
    let e = build_err(&format!("{full}C_3 = 1\n"));
    assert!(
        e.contains("C_3") && e.contains("C_I") && e.contains("l_cz"),
        "{e}"
    );
    let e = build_err(&full.replace("m_I = 5", "m_I = \"five\""));
    assert!(e.contains("`m_I`") && e.contains("number"), "{e}");
    // the static part's errors still name their keys
    let e = build_err(&full.replace("G_Ic = 0.969", "G_Ic = 0"));
    assert!(
        e.contains("fatigue_bilinear") && e.contains("`G_Ic`"),
        "{e}"
    );
}

#[test]
fn a_jump_that_changes_within_the_increment_takes_the_end_rate() {
    // backward Euler in the jump: D = max(D_committed, D_static(lam_end))
    // + dN r(lam_end), mode I, loading and unloading within the increment
    let m = mode(0.0, 1.0);
    let lam_a = m.lam0 + D_S * (m.lam_f - m.lam0);
    for (lam_b, what) in [
        (m.lam0 + 2.0 * D_S * (m.lam_f - m.lam0), "loading"),
        (0.8 * lam_a, "unloading"),
    ] {
        let mut p = Point::new(build(""));
        p.step([0.0, 0.0, lam_a], 0.0);
        let d_c = m.energy_damage(p.damage());
        // a fifth of the cycles the end rate needs to fail the point
        let dn = 0.2 * (1.0 - 2.0 * D_S) / m.rate(lam_b, 0.0, L_CZ);
        p.step([0.0, 0.0, lam_b], dn);
        let d_s = ((lam_b - m.lam0) / (m.lam_f - m.lam0)).max(0.0);
        let big_d = d_c.max(d_s) + dn * m.rate(lam_b, 0.0, L_CZ);
        let expected = m.lam_f * big_d / (m.lam0 + big_d * (m.lam_f - m.lam0));
        assert!(
            (p.damage() - expected).abs() < 1e-12,
            "{what}: d = {} against {expected}",
            p.damage()
        );
        let e = p.out(output::DISSIPATED_ENERGY);
        assert!(
            (e - m.g_c * big_d).abs() < 1e-12 * m.g_c,
            "{what}: energy {e}"
        );
    }
}

/// The interface element hands the step's cycle information to the law:
/// an INTER8 under a uniform held opening grows the damage of every point
/// by the fatigue rate times `delta_cycles` (mode I closed form).
#[test]
fn interface_element_passes_the_cycles_to_the_law() {
    use junta_core::element::{Element, ElementContext};
    use junta_core::topology::CellShape;
    use junta_interface::{InterfaceElement, InterfaceRule};
    let el = InterfaceElement::new(CellShape::Inter8, InterfaceRule::Gauss, build("")).unwrap();
    let face = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    ];
    let coords: Vec<[f64; 3]> = face.iter().chain(face.iter()).copied().collect();
    let m = mode(0.0, 1.0);
    let lam = m.lam0 + D_S * (m.lam_f - m.lam0);
    let mut disp = vec![0.0; 24];
    for a in 4..8 {
        disp[3 * a + 2] = lam;
    }
    let rate = m.rate(lam, 0.0, L_CZ);
    let dn = 0.25 * (1.0 - D_S) / rate;
    let mut state = vec![0.0; el.state_len()];
    el.init_state(&mut state);
    let mut f = vec![0.0; 24];
    let mut k = vec![0.0; 24 * 24];
    for (inc, dn) in [(1, 0.0), (2, dn)] {
        let mut trial = vec![0.0; el.state_len()];
        el.compute(
            &ElementContext {
                coords: &coords,
                disp: &disp,
                state_committed: &state,
                step: step(inc, dn, dn, 0.0),
                law_responses: None,
                temperature: None,
            },
            &mut trial,
            &mut f,
            Some(&mut k),
        )
        .unwrap();
        state = trial;
    }
    let big_d = D_S + dn * rate;
    let expected = m.lam_f * big_d / (m.lam0 + big_d * (m.lam_f - m.lam0));
    for s in state.chunks(slot::STATE_LEN) {
        assert!(
            (s[slot::DAMAGE] - expected).abs() < 1e-12,
            "d = {} against {expected}",
            s[slot::DAMAGE]
        );
        assert!((s[slot::DAMAGE_RATE] - rate).abs() < 1e-10 * rate);
    }
    // the opening force of the unit square: (1 - d) K lam
    let fz: f64 = (4..8).map(|a| f[3 * a + 2]).sum();
    let t = (1.0 - expected) * K * lam;
    assert!((fz - t).abs() < 1e-9 * t, "F_z = {fz} against {t}");
}
