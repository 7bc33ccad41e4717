//! One-point tests of the fracture-energy laws `bilinear` and
//! `exponential` (crates/interface/src/law/cohesive.rs).
//!
//! References: the closed forms of BENCHMARKS.md section 4 (Camanho &
//! Davila 2002 mixed-mode bilinear law: onsets, delta_0m, BK toughness) and
//! section 3 (one cohesive point: onset at tau_0/K, dissipated energy G_c).
//! Material data: AS4/PEEK (BENCHMARKS.md section 4).

mod common;

use junta_core::element::StepInfo;
use junta_core::law::{InterfaceLaw, LawContext, LawResponse};
use junta_core::registry::{find, LawEntry};
use junta_interface as _;
use junta_interface::law::cohesive::slot;
use std::sync::Arc;

const K: f64 = 1e6;
const N: f64 = 80.0;
const S: f64 = 100.0;
const GIC: f64 = 0.969;
const GIIC: f64 = 1.719;
const ETA: f64 = 2.284;

fn build(key: &str, extra: &str) -> Arc<dyn InterfaceLaw> {
    let text =
        format!("K = {K:e}\nN = {N}\nS = {S}\nG_Ic = {GIC}\nG_IIc = {GIIC}\neta = {ETA}\n{extra}");
    let t: toml::Table = toml::from_str(&text).unwrap();
    (find::<LawEntry>(key).unwrap().build)(&t).unwrap()
}

fn build_err(key: &str, text: &str) -> String {
    let t: toml::Table = toml::from_str(text).unwrap();
    (find::<LawEntry>(key).unwrap().build)(&t)
        .unwrap_err()
        .to_string()
}

/// A point driven through a jump history, committing after each step.
struct Point {
    law: Arc<dyn InterfaceLaw>,
    state: Vec<f64>,
    inc: usize,
}

impl Point {
    fn new(law: Arc<dyn InterfaceLaw>) -> Self {
        let mut state = vec![0.0; law.state_len()];
        law.init_state(&mut state);
        Point { law, state, inc: 0 }
    }
    fn trial(&self, jump: [f64; 3], dt: f64) -> (LawResponse, Vec<f64>) {
        let mut trial = vec![f64::NAN; self.state.len()];
        let r = self
            .law
            .evaluate(
                &LawContext {
                    jump,
                    state_committed: &self.state,
                    step: StepInfo::at(self.inc + 1, 0.0, dt),
                },
                &mut trial,
            )
            .unwrap();
        (r, trial)
    }
    fn step(&mut self, jump: [f64; 3]) -> LawResponse {
        self.step_dt(jump, 1.0)
    }
    fn step_dt(&mut self, jump: [f64; 3], dt: f64) -> LawResponse {
        let (r, t) = self.trial(jump, dt);
        self.state = t;
        self.inc += 1;
        r
    }
    fn damage(&self) -> f64 {
        self.state[slot::DAMAGE]
    }
    fn energy(&self) -> f64 {
        self.state[slot::ENERGY]
    }
    /// Central-difference tangent against the law's (trial state
    /// discarded).
    fn check_tangent(&self, jump: [f64; 3], what: &str) {
        common::check_fd_tangent(|j| self.trial(j, 1.0).0, jump, 1e-7, what);
    }
}

fn bk_toughness(b: f64) -> f64 {
    GIC + (GIIC - GIC) * b.powf(ETA)
}

/// Proportional path at mode ratio B (one penalty: B = sin^2 of the angle
/// between the jump and the normal) to full separation in `steps` steps.
fn drive_to_failure(p: &mut Point, b: f64, lam_end: f64, steps: usize) {
    let (s, c) = (b.sqrt(), (1.0 - b).sqrt());
    for i in 1..=steps {
        let lam = lam_end * i as f64 / steps as f64;
        p.step([lam * s, 0.0, lam * c]);
    }
}

#[test]
fn dissipated_energy_is_the_toughness_in_modes_i_ii_and_bk_mixed() {
    for key in ["bilinear", "exponential"] {
        let law = build(key, "");
        for (b, expected, what) in [
            (0.0, GIC, "mode I (G_Ic)"),
            (1.0, GIIC, "mode II (G_IIc)"),
            (0.2, bk_toughness(0.2), "BK B = 0.2"),
            (0.5, bk_toughness(0.5), "BK B = 0.5"),
            (0.8, bk_toughness(0.8), "BK B = 0.8"),
        ] {
            // exponential needs a long tail: 40 decay lengths
            let lam_end = if key == "bilinear" { 0.05 } else { 0.6 };
            for steps in [7, 400] {
                let mut p = Point::new(law.clone());
                drive_to_failure(&mut p, b, lam_end, steps);
                assert!(
                    p.damage() >= 1.0 - 1e-12,
                    "{key} {what}: d = {}",
                    p.damage()
                );
                let rel = (p.energy() - expected).abs() / expected;
                assert!(
                    rel < 1e-6,
                    "{key} {what} in {steps} steps: dissipated {} against {expected} (rel {rel:.2e})",
                    p.energy()
                );
                // the curve's own area, integrated numerically on a fine
                // path, is the same energy (trapezoid, the traction is
                // continuous)
            }
        }
    }
}

#[test]
fn work_of_the_traction_equals_the_dissipated_energy() {
    // independent check of F(d): trapezoidal work along a fine monotone
    // path to full separation (nothing stored at the end)
    for key in ["bilinear", "exponential"] {
        let law = build(key, "");
        let b: f64 = 0.5;
        let (s, c) = (b.sqrt(), (1.0 - b).sqrt());
        let mut p = Point::new(law.clone());
        let lam_end = if key == "bilinear" { 0.05 } else { 0.6 };
        let steps = 200_000;
        let mut work = 0.0;
        let mut prev = [0.0; 3];
        let mut t_prev = [0.0; 3];
        for i in 1..=steps {
            let lam = lam_end * i as f64 / steps as f64;
            let jump = [lam * s, 0.0, lam * c];
            let t = p.step(jump).traction;
            for k in 0..3 {
                work += 0.5 * (t[k] + t_prev[k]) * (jump[k] - prev[k]);
            }
            prev = jump;
            t_prev = t;
        }
        let rel = (work - p.energy()).abs() / p.energy();
        assert!(
            rel < 1e-4,
            "{key}: work {work} vs dissipated {}",
            p.energy()
        );
    }
}

#[test]
fn onset_at_the_closed_form_jump() {
    let law = build("bilinear", "");
    // mode I: delta_0n = N / K
    let d0n = N / K;
    let p = Point::new(law.clone());
    assert_eq!(
        p.trial([0.0, 0.0, d0n * (1.0 - 1e-9)], 1.0).1[slot::DAMAGE],
        0.0
    );
    assert!(p.trial([0.0, 0.0, d0n * (1.0 + 1e-6)], 1.0).1[slot::DAMAGE] > 0.0);
    // traction at onset = N
    let t = p.trial([0.0, 0.0, d0n], 1.0).0.traction[2];
    assert!((t - N).abs() < 1e-9 * N);
    // mixed, quadratic criterion: Camanho-Davila delta_0m (BENCHMARKS 4)
    let d0s = S / K;
    for beta in [0.5f64, 1.0, 3.0] {
        let d0m =
            d0n * d0s * (1.0 + beta * beta).sqrt() / (d0s * d0s + (beta * d0n).powi(2)).sqrt();
        let dir = [
            beta / (1.0 + beta * beta).sqrt(),
            1.0 / (1.0 + beta * beta).sqrt(),
        ];
        let below = d0m * (1.0 - 1e-7);
        let above = d0m * (1.0 + 1e-7);
        let d_below = p.trial([below * dir[0], 0.0, below * dir[1]], 1.0).1[slot::DAMAGE];
        let d_above = p.trial([above * dir[0], 0.0, above * dir[1]], 1.0).1[slot::DAMAGE];
        assert_eq!(d_below, 0.0, "beta {beta}");
        assert!(d_above > 0.0, "beta {beta}");
        // full separation at Camanho-Davila's delta_fm (BK)
        let b = beta * beta / (1.0 + beta * beta);
        let dfm = 2.0 / (K * d0m) * bk_toughness(b);
        let at = dfm * (1.0 - 1e-6);
        let past = dfm * (1.0 + 1e-9);
        assert!(p.trial([at * dir[0], 0.0, at * dir[1]], 1.0).1[slot::DAMAGE] < 1.0);
        assert_eq!(
            p.trial([past * dir[0], 0.0, past * dir[1]], 1.0).1[slot::DAMAGE],
            1.0
        );
    }
}

#[test]
fn bk_onset_criterion_gives_turons_onset() {
    let law = build("bilinear", "onset = \"bk\"");
    let p = Point::new(law);
    let (d0n, d0s) = (N / K, S / K);
    for b in [0.3f64, 0.7] {
        let d0 = (d0n * d0n + (d0s * d0s - d0n * d0n) * b.powf(ETA)).sqrt();
        let dir = [b.sqrt(), (1.0 - b).sqrt()];
        let below = d0 * (1.0 - 1e-7);
        let above = d0 * (1.0 + 1e-7);
        assert_eq!(
            p.trial([below * dir[0], 0.0, below * dir[1]], 1.0).1[slot::DAMAGE],
            0.0
        );
        assert!(p.trial([above * dir[0], 0.0, above * dir[1]], 1.0).1[slot::DAMAGE] > 0.0);
    }
}

#[test]
fn tangent_matches_finite_differences_in_every_regime() {
    for (key, extra) in [
        ("bilinear", ""),
        ("exponential", ""),
        ("bilinear", "onset = \"bk\"\nshear_penalty = \"turon2018\""),
        (
            "bilinear",
            "propagation = \"power_law\"\nalpha = 1.5\nonset = \"max_stress\"",
        ),
        ("exponential", "viscosity = 0.5"),
    ] {
        let law = build(key, extra);
        let what = |r: &str| format!("{key} [{}] {r}", extra.replace('\n', ", "));
        let p = Point::new(law.clone());
        // elastic: opening, slip, mixed
        p.check_tangent([1e-5, -2e-5, 3e-5], &what("elastic"));
        // compression (closed): no damage, penalty contact
        p.check_tangent([2e-5, 1e-5, -3e-5], &what("compression"));
        // softening: mode I, mode II, mixed
        p.check_tangent([0.0, 0.0, 2e-4], &what("softening mode I"));
        p.check_tangent([2.2e-4, 0.0, -1e-5], &what("softening mode II, closed"));
        p.check_tangent(
            [1.5e-4, 1.7e-4, 1e-6],
            &what("softening mode II, barely open"),
        );
        p.check_tangent([1.5e-4, 0.7e-4, 1.2e-4], &what("softening mixed"));
        // damage a point, then unload, reload below the curve, load on
        let mut q = Point::new(law.clone());
        q.step([0.8e-4, 0.0, 1.2e-4]);
        q.step([1.2e-4, 0.0, 1.8e-4]);
        assert!(
            q.damage() > 0.0 && q.damage() < 1.0,
            "{}",
            what("partly damaged")
        );
        q.check_tangent([0.6e-4, 0.0, 0.9e-4], &what("unloading"));
        q.check_tangent([1.1e-4, 0.0, 1.7e-4], &what("reloading"));
        q.check_tangent([1.4e-4, 0.0, 2.0e-4], &what("softening again"));
        q.check_tangent([1.0e-4, 0.3e-4, -0.5e-4], &what("damaged, closed"));
        q.check_tangent([1.8e-4, 0.5e-4, 0.5e-4], &what("damaged, mode turned"));
        // fully failed: open carries nothing, closed is contact
        let mut f = Point::new(law.clone());
        drive_to_failure(&mut f, 0.3, 0.8, 50);
        assert!(f.damage() >= 1.0 - 1e-9);
        f.check_tangent([1e-3, 2e-3, 3e-3], &what("failed, open"));
        f.check_tangent([1e-3, 2e-3, -3e-5], &what("failed, closed"));
        let r = f.trial([1e-3, 2e-3, 3e-3], 1.0).0;
        assert!(r.traction.iter().all(|t| t.abs() < 1e-9), "{r:?}");
        let r = f.trial([1e-3, 2e-3, -3e-5], 1.0).0;
        assert!((r.traction[2] + K * 3e-5).abs() < 1e-9 && r.traction[0].abs() < 1e-9);
    }
}

#[test]
fn rotating_mode_never_heals_and_never_dissipates_less() {
    for key in ["bilinear", "exponential"] {
        let law = build(key, "");
        let mut p = Point::new(law);
        let mut d_prev = 0.0;
        let mut e_prev = 0.0;
        let (mut b_min, mut b_max) = (1.0f64, 0.0f64);
        // load-unload-reload cycles whose mixity turns from mode I to II
        let mut amp: f64 = 1.0e-4;
        for cycle in 0..60 {
            let angle = (cycle as f64 / 59.0) * std::f64::consts::FRAC_PI_2;
            let dir = [angle.sin(), 0.0, angle.cos()];
            for frac in [1.0, 0.3, -0.2, 1.0] {
                let j = [amp * frac * dir[0], 0.0, amp * frac * dir[2]];
                let j = if frac < 0.0 {
                    [j[0].abs(), 0.0, j[2]]
                } else {
                    j
                };
                p.step(j);
                assert!(
                    p.damage() >= d_prev,
                    "{key}: damage healed {d_prev} -> {}",
                    p.damage()
                );
                assert!(
                    p.energy() >= e_prev,
                    "{key}: energy fell {e_prev} -> {}",
                    p.energy()
                );
                d_prev = p.damage();
                e_prev = p.energy();
            }
            if p.damage() > 0.0 && p.damage() < 1.0 {
                let b = p.state[slot::MODE_RATIO];
                b_min = b_min.min(b);
                b_max = b_max.max(b);
            }
            amp *= if key == "bilinear" { 1.12 } else { 1.16 };
        }
        assert!(
            p.damage() >= 1.0 - 1e-12,
            "{key}: not failed, d = {}",
            p.damage()
        );
        let (lo, hi) = (bk_toughness(0.0), bk_toughness(1.0));
        assert!(
            p.energy() >= lo * (1.0 - 1e-9) && p.energy() <= hi * (1.0 + 1e-9),
            "{key}: dissipated {} outside [{lo}, {hi}]",
            p.energy()
        );
        assert!(
            b_max > b_min + 0.3,
            "{key}: the mode did not turn ({b_min}..{b_max})"
        );
    }
}

#[test]
fn viscous_regularisation_lags_and_books_its_energy_apart() {
    let law = build("bilinear", "viscosity = 0.01");
    let inviscid = build("bilinear", "");
    let mut p = Point::new(law);
    let mut q = Point::new(inviscid);
    for i in 1..=300 {
        let j = [0.0, 0.0, 1e-4 * i as f64];
        p.step_dt(j, 0.001);
        q.step_dt(j, 0.001);
        assert!(p.damage() <= q.damage() + 1e-15);
    }
    // then hold the jump: the viscous damage catches up
    for _ in 0..200 {
        p.step_dt([0.0, 0.0, 0.03], 0.01);
    }
    assert!((p.damage() - 1.0).abs() < 1e-9, "{}", p.damage());
    assert!(
        (p.energy() - GIC).abs() < 1e-6 * GIC,
        "fracture {}",
        p.energy()
    );
    let viscous = p.state[slot::VISCOUS];
    assert!(viscous > 0.0, "viscous energy {viscous}");
}

#[test]
fn turon_consistency_warning() {
    // AS4/PEEK: S = 100 against N sqrt(G_IIc/G_Ic) = 106.6 (BENCHMARKS 4)
    let w = build("bilinear", "").warnings();
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(
        w[0].contains("1.0655e2") && w[0].contains("turon2018"),
        "{}",
        w[0]
    );
    assert!(build("bilinear", "shear_penalty = \"turon2018\"")
        .warnings()
        .is_empty());
    // the mode-dependent penalty of Turon 2018
    let law = build("bilinear", "shear_penalty = \"turon2018\"");
    let k = law.initial_stiffness();
    let expected = K * (GIC / GIIC) * (S / N) * (S / N);
    assert!((k[0] - expected).abs() < 1e-9 * expected && k[2] == K);
}

#[test]
fn bad_parameters_name_the_key() {
    let base = "K = 1e6\nN = 80.0\nS = 100.0\nG_Ic = 0.969\nG_IIc = 1.719\neta = 2.284\n";
    let cases = [
        (base.replace("G_Ic = 0.969", "G_Ic = 0.0"), "`G_Ic` = 0"),
        (
            base.replace("G_IIc = 1.719", "G_IIc = -1.0"),
            "`G_IIc` = -1",
        ),
        (base.replace("N = 80.0", "N = -5.0"), "`N` = -5"),
        (base.replace("S = 100.0", "S = 0.0"), "`S` = 0"),
        (base.replace("eta = 2.284", "eta = -1.0"), "`eta` = -1"),
        (base.replace("eta = 2.284\n", ""), "missing `eta`"),
        (
            format!("{base}propagation = \"linear\"\n"),
            "`propagation` = \"linear\"",
        ),
        (format!("{base}onset = \"nope\"\n"), "`onset`"),
        (format!("{base}viscosity = -1.0\n"), "`viscosity`"),
        (format!("{base}Gc = 1.0\n"), "Gc"),
        // toughness too small to soften: G_Ic <= N^2 / (2 K) = 3.2e-3
        (
            base.replace("G_Ic = 0.969", "G_Ic = 0.003"),
            "G_Ic > N^2 / (2 K)",
        ),
    ];
    for (text, needle) in cases {
        let e = build_err("bilinear", &text);
        assert!(e.contains(needle), "expected `{needle}` in: {e}");
        assert!(e.contains("bilinear"), "{e}");
    }
}

/// In an element, a softening law's tangent (unsymmetric where the mode
/// ratio changes with the jump) is assembled as its symmetric part: the
/// element matrix is symmetric, as the symmetric storage needs.
#[test]
fn element_assembles_the_symmetric_part_of_a_mixed_mode_tangent() {
    use junta_core::element::{Element, ElementContext};
    use junta_core::topology::CellShape;
    use junta_interface::{InterfaceElement, InterfaceRule};
    let law = build("bilinear", "");
    let el = InterfaceElement::new(CellShape::Inter8, InterfaceRule::Gauss, law.clone()).unwrap();
    let face = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    ];
    let coords: Vec<[f64; 3]> = face.iter().chain(face.iter()).copied().collect();
    // top face slid and opened, more at one corner: mixed mode, softening
    let mut disp = vec![0.0; 24];
    for a in 0..4 {
        let s = 1.0 + a as f64;
        disp[3 * (4 + a)] = 0.6e-4 * s;
        disp[3 * (4 + a) + 2] = 0.5e-4 * s;
    }
    let mut state = vec![0.0; el.state_len()];
    el.init_state(&mut state);
    let mut trial = vec![0.0; el.state_len()];
    let mut f = vec![0.0; 24];
    let mut k = vec![0.0; 24 * 24];
    el.compute(
        &ElementContext {
            coords: &coords,
            disp: &disp,
            state_committed: &state,
            step: StepInfo::at(1, 1.0, 1.0),
            law_responses: None,
            temperature: None,
        },
        &mut trial,
        &mut f,
        Some(&mut k),
    )
    .unwrap();
    // the points soften in mixed mode
    let damaged = trial
        .chunks(slot::STATE_LEN)
        .filter(|s| s[slot::DAMAGE] > 0.0 && s[slot::MODE_RATIO] > 0.1)
        .count();
    assert!(damaged > 0, "no mixed-mode softening point");
    // ... where the law's own tangent is not symmetric
    let raw = Point::new(law).trial([1.5e-4, 0.0, 1.25e-4], 1.0).0.tangent;
    let asym = (raw[0][2] - raw[2][0]).abs();
    assert!(asym > 1e-3 * raw[2][2].abs(), "law tangent {raw:?}");
    let kmax = k.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    for i in 0..24 {
        for j in 0..24 {
            assert!(
                (k[i * 24 + j] - k[j * 24 + i]).abs() <= 1e-12 * kmax,
                "K[{i}][{j}] = {} against K[{j}][{i}] = {}",
                k[i * 24 + j],
                k[j * 24 + i]
            );
        }
    }
}

/// On the damage surface itself (the converged state an increment starts
/// from: the committed damage equals the damage of the current jump) the
/// tangent is the loading one: the one-sided derivative towards more
/// opening, not the secant. Mode I, bilinear: the loading slope of the
/// normal traction is `-N / (delta_f - delta_0)` (BENCHMARKS.md section 4).
#[test]
fn tangent_on_the_damage_surface_is_the_loading_one() {
    for key in ["bilinear", "exponential"] {
        let mut p = Point::new(build(key, ""));
        let d0 = N / K;
        let jump = [0.0, 0.0, 3.0 * d0];
        p.step(jump);
        assert!(p.damage() > 0.0);
        // same jump again, from the committed state it produced
        let (r, _) = p.trial(jump, 0.0);
        let h = 1e-5 * d0;
        let (rp, _) = p.trial([0.0, 0.0, jump[2] + h], 0.0);
        let forward = (rp.traction[2] - r.traction[2]) / h;
        assert!(forward < 0.0, "{key}: loading slope {forward}");
        assert!(
            (r.tangent[2][2] - forward).abs() < 1e-4 * forward.abs(),
            "{key}: tangent {} against the one-sided difference {forward}",
            r.tangent[2][2]
        );
        if key == "bilinear" {
            let df = 2.0 * GIC / N;
            let exact = -N / (df - d0);
            assert!(
                (r.tangent[2][2] / exact - 1.0).abs() < 1e-9,
                "{}",
                r.tangent[2][2]
            );
        }
    }
}

/// `tangent = "exact"`: the law declares a general tangent, the element
/// assembles the full (nonsymmetric in mixed mode) matrix, and it equals
/// the finite-difference derivative of the element forces; a bad value is
/// a clear error.
#[test]
fn exact_tangent_option_assembles_the_nonsymmetric_tangent() {
    use junta_core::element::{Element, ElementContext};
    use junta_core::topology::CellShape;
    use junta_core::MatrixKind;
    use junta_interface::{InterfaceElement, InterfaceRule};
    assert_eq!(
        build("bilinear", "").tangent_kind(),
        MatrixKind::SymmetricIndefinite
    );
    let law = build("bilinear", "tangent = \"exact\"");
    assert_eq!(law.tangent_kind(), MatrixKind::General);
    let err = build_err(
        "bilinear",
        "K = 1e6\nN = 80\nS = 100\nG_Ic = 1\nG_IIc = 2\neta = 2\ntangent = \"full\"",
    );
    assert!(err.contains("tangent") && err.contains("exact"), "{err}");
    let el = InterfaceElement::new(CellShape::Inter8, InterfaceRule::Gauss, law).unwrap();
    let face = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    ];
    let coords: Vec<[f64; 3]> = face.iter().chain(face.iter()).copied().collect();
    let mut disp = vec![0.0; 24];
    for a in 0..4 {
        let s = 1.0 + a as f64;
        disp[3 * (4 + a)] = 0.6e-4 * s;
        disp[3 * (4 + a) + 2] = 0.5e-4 * s;
    }
    let mut state = vec![0.0; el.state_len()];
    el.init_state(&mut state);
    let eval = |u: &[f64], k: Option<&mut [f64]>| {
        let mut trial = vec![0.0; state.len()];
        let mut f = vec![0.0; 24];
        el.compute(
            &ElementContext {
                coords: &coords,
                disp: u,
                state_committed: &state,
                step: StepInfo::at(1, 1.0, 1.0),
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
    let mut k = vec![0.0; 24 * 24];
    eval(&disp, Some(&mut k));
    let (mut asym, mut scale, mut err) = (0.0f64, 0.0f64, 0.0f64);
    let h = 1e-10;
    for j in 0..24 {
        let (mut up, mut dn) = (disp.clone(), disp.clone());
        up[j] += h;
        dn[j] -= h;
        let (fp, fm) = (eval(&up, None), eval(&dn, None));
        for i in 0..24 {
            let fd = (fp[i] - fm[i]) / (2.0 * h);
            err = err.max((k[i * 24 + j] - fd).abs());
            scale = scale.max(k[i * 24 + j].abs());
            asym = asym.max((k[i * 24 + j] - k[j * 24 + i]).abs());
        }
    }
    assert!(
        err < 1e-5 * scale,
        "tangent against FD: {err:e} (scale {scale:e})"
    );
    assert!(
        asym > 1e-6 * scale,
        "the mixed-mode tangent is not symmetric: {asym:e}"
    );
}

/// INTER6 / INTER12 (and INTER8 for comparison) with the bilinear law:
/// the element tangent against central differences of the element forces
/// in the elastic regime (every point below onset) and in the softening
/// regime (every point past onset, mixed mode, undamaged committed state),
/// with the exact (nonsymmetric) tangent. Skewed, non-planar faces.
#[test]
fn triangle_interfaces_tangent_matches_fd_elastic_and_softening() {
    use junta_core::element::{Element, ElementContext};
    use junta_core::topology::{CellShape, TRI6_NODES};
    use junta_interface::{InterfaceElement, InterfaceRule};
    // a skewed, warped face over the natural triangle / square
    let map = |x: f64, y: f64| -> [f64; 3] {
        [
            1.0 * x + 0.3 * y,
            0.2 * x + 0.8 * y,
            0.05 * x * x - 0.04 * y + 0.03 * x * y,
        ]
    };
    let quad = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]];
    let d0 = N / K;
    for (shape, rule) in [
        (CellShape::Inter6, InterfaceRule::Gauss),
        (CellShape::Inter6, InterfaceRule::Lobatto),
        (CellShape::Inter12, InterfaceRule::Gauss),
        (CellShape::Inter8, InterfaceRule::Gauss),
    ] {
        let face: Vec<[f64; 3]> = if shape == CellShape::Inter8 {
            quad.iter().map(|p| map(p[0], p[1])).collect()
        } else {
            TRI6_NODES[..shape.num_nodes() / 2]
                .iter()
                .map(|p| map(2.0 * p[0] - 1.0, 2.0 * p[1] - 1.0))
                .collect()
        };
        let m = face.len();
        let nd = 6 * m;
        let coords: Vec<[f64; 3]> = face.iter().chain(face.iter()).copied().collect();
        for (regime, tangent, amp, shear) in [
            ("elastic", "tangent = \"exact\"", 0.3, 0.7),
            ("softening", "tangent = \"exact\"", 3.0, 0.7),
        ] {
            let name = format!("{} {rule:?} {regime}", shape.name());
            let el = InterfaceElement::new(shape, rule, build("bilinear", tangent)).unwrap();
            // top face opened (and slid) by about amp x onset, varying
            // from node to node
            let mut disp = vec![0.0; nd];
            for a in 0..m {
                let s = 1.0 + 0.1 * a as f64;
                disp[3 * (m + a)] = shear * amp * d0 * s;
                disp[3 * (m + a) + 2] = amp * d0 * s;
            }
            let mut state = vec![0.0; el.state_len()];
            el.init_state(&mut state);
            let eval = |u: &[f64], k: Option<&mut [f64]>| {
                let mut trial = vec![0.0; state.len()];
                let mut f = vec![0.0; nd];
                el.compute(
                    &ElementContext {
                        coords: &coords,
                        disp: u,
                        state_committed: &state,
                        step: StepInfo::at(1, 1.0, 1.0),
                        law_responses: None,
                        temperature: None,
                    },
                    &mut trial,
                    &mut f,
                    k,
                )
                .unwrap();
                (f, trial)
            };
            let mut k = vec![0.0; nd * nd];
            let (_, trial) = eval(&disp, Some(&mut k));
            let damaged = trial
                .chunks(slot::STATE_LEN)
                .filter(|s| s[slot::DAMAGE] > 0.0)
                .count();
            if regime == "elastic" {
                assert_eq!(damaged, 0, "{name}");
            } else {
                assert_eq!(damaged, el.num_points(), "{name}");
            }
            let (mut scale, mut err) = (0.0f64, 0.0f64);
            let h = 1e-6 * d0;
            for j in 0..nd {
                let (mut up, mut dn) = (disp.clone(), disp.clone());
                up[j] += h;
                dn[j] -= h;
                let (fp, fm) = (eval(&up, None).0, eval(&dn, None).0);
                for i in 0..nd {
                    let fd = (fp[i] - fm[i]) / (2.0 * h);
                    err = err.max((k[i * nd + j] - fd).abs());
                    scale = scale.max(k[i * nd + j].abs());
                }
            }
            assert!(scale > 0.0, "{name}");
            assert!(
                err < 1e-6 * scale,
                "{name}: tangent against FD {err:e} (scale {scale:e})"
            );
        }
    }
}

/// Which laws' penalties are constraints (the paper's error analysis and
/// its d_op apply) and which are part of a cohesive model (Turon's bound
/// applies): every registered law says so.
#[test]
fn each_law_declares_its_penalty_role() {
    use junta_core::PenaltyRole::{Cohesive, Constraint};
    let cohesive =
        format!("K = {K:e}\nN = {N}\nS = {S}\nG_Ic = {GIC}\nG_IIc = {GIIC}\neta = {ETA}\n");
    let cases = [
        ("linear_penalty", "d = 1e14".to_string(), Constraint),
        (
            "paper_debond",
            "d = 1e14\ncriterion = { type = \"quadratic\", sigma_lim = 2.0e6, tau_lim = 4.0e6 }"
                .to_string(),
            Constraint,
        ),
        ("contact", "K = 1e6".to_string(), Constraint),
        (
            "coulomb_friction",
            "K = 1e5\nmu = 0.4".to_string(),
            Constraint,
        ),
        (
            "mohr_coulomb",
            "K = 1e5\nc = 0.5\nphi = 30.0".to_string(),
            Constraint,
        ),
        ("bilinear", cohesive.clone(), Cohesive),
        ("exponential", cohesive.clone(), Cohesive),
        ("bilinear_friction", format!("{cohesive}mu = 0.3"), Cohesive),
    ];
    for (key, text, role) in cases {
        let t: toml::Table = toml::from_str(&text).unwrap();
        let law =
            (find::<LawEntry>(key).unwrap().build)(&t).unwrap_or_else(|e| panic!("{key}: {e}"));
        assert_eq!(law.penalty_role(), role, "{key}");
    }
}
