//! The one definition of a failed point ([`PointStage`], issue 37 item 1):
//! one point of every softening law driven along a monotone proportional
//! path at mode ratios B = 0 (mode I), 0.5 and 1 (mode II) counts as
//! failed exactly when the energy it has dissipated reaches its
//! toughness for that mode mix, and not before.
//!
//! The dissipated energy is integrated independently of the law's own
//! bookkeeping: the work `sum (t_k + t_{k+1}) / 2 . (delta_{k+1} - delta_k)`
//! (trapezoid rule) less the recoverable elastic energy `t . delta / 2`
//! (these laws unload along the secant to the origin). The toughness of
//! the mode mix is Benzeggagh & Kenane's `G_c = G_Ic + (G_IIc - G_Ic)
//! B^eta` (Compos. Sci. Technol. 56, 1996), with one penalty
//! `B = sin^2` of the angle between the jump and the normal (Camanho &
//! Davila 2002, NASA/TM-2002-211737). Material: the stiff penalty of
//! issue 37 (K = 3e7, N = 30, G_Ic = 0.26), where the former secant
//! threshold (damage >= 0.99) came at 0.6 % of the final opening.

use junta_core::element::StepInfo;
use junta_core::law::{InterfaceLaw, LawContext};
use junta_core::registry::{find, LawEntry};
use junta_core::PointStage;
use junta_interface as _;
use std::sync::Arc;

const K: f64 = 3e7;
const N: f64 = 30.0;
const GIC: f64 = 0.26;
const GIIC: f64 = 1.002;
const ETA: f64 = 2.0;
/// Relative tolerance on the energy at failure (the trapezoid rule's
/// error at the kinks of the path is far below it).
const TOL: f64 = 2e-3;

/// `S` consistent with one penalty (Turon et al. 2010): `N sqrt(G_IIc/G_Ic)`.
fn s_consistent() -> f64 {
    N * (GIIC / GIC).sqrt()
}

fn bilinear_text(k: f64, n: f64, g1: f64, g2: f64) -> String {
    let s = n * (g2 / g1).sqrt();
    format!("K = {k:e}\nN = {n}\nS = {s}\nG_Ic = {g1}\nG_IIc = {g2}\neta = {ETA}\n")
}

fn build(key: &str, text: &str) -> Arc<dyn InterfaceLaw> {
    let t: toml::Table = toml::from_str(text).unwrap();
    (find::<LawEntry>(key).unwrap().build)(&t).unwrap()
}

fn bk(b: f64, g1: f64, g2: f64) -> f64 {
    g1 + (g2 - g1) * b.powf(ETA)
}

/// What one monotone path met: per step the stage and the dissipated
/// energy (work less recoverable), and the traction magnitude.
struct PathRecord {
    stages: Vec<PointStage>,
    dissipated: Vec<f64>,
    traction: Vec<f64>,
}

/// Drive a fresh point of `law` along `jump = lam [sqrt(B), 0, sqrt(1-B)]`
/// for `lam` from 0 to `lam_end` in `steps` equal steps, committing each.
fn drive(law: &Arc<dyn InterfaceLaw>, b: f64, lam_end: f64, steps: usize) -> PathRecord {
    let mut state = vec![0.0; law.state_len()];
    law.init_state(&mut state);
    let dir = [b.sqrt(), 0.0, (1.0 - b).sqrt()];
    let (mut t_old, mut j_old) = ([0.0; 3], [0.0; 3]);
    let mut work = 0.0;
    let mut rec = PathRecord {
        stages: vec![],
        dissipated: vec![],
        traction: vec![],
    };
    for k in 1..=steps {
        let lam = lam_end * k as f64 / steps as f64;
        let jump = dir.map(|c| c * lam);
        let mut trial = vec![f64::NAN; state.len()];
        let r = law
            .evaluate(
                &LawContext {
                    jump,
                    state_committed: &state,
                    step: StepInfo::at(k, lam / lam_end, 1.0 / steps as f64),
                },
                &mut trial,
            )
            .unwrap();
        state = trial;
        let t = r.traction;
        work += (0..3)
            .map(|a| 0.5 * (t[a] + t_old[a]) * (jump[a] - j_old[a]))
            .sum::<f64>();
        let elastic = 0.5 * (0..3).map(|a| t[a] * jump[a]).sum::<f64>();
        rec.stages.push(law.stage(&state));
        rec.dissipated.push(work - elastic);
        rec.traction
            .push((t[0] * t[0] + t[1] * t[1] + t[2] * t[2]).sqrt());
        (t_old, j_old) = (t, jump);
    }
    rec
}

/// The point fails exactly when its dissipated energy reaches `target`:
/// every failed step has dissipated at least `target (1 - TOL)`, the first
/// failed step at most `target (1 + TOL)`, every earlier step less than
/// `target` and with traction left; damage starts (process zone) before.
fn assert_fails_at(rec: &PathRecord, target: f64, what: &str) {
    let first = rec
        .stages
        .iter()
        .position(|&s| s == PointStage::Failed)
        .unwrap_or_else(|| panic!("{what}: never failed"));
    let at = rec.dissipated[first];
    assert!(
        (at - target).abs() <= TOL * target,
        "{what}: failed at step {first} with {at:.6e} dissipated, G_c {target:.6e}"
    );
    for k in 0..first {
        assert!(
            rec.dissipated[k] < target * (1.0 + 1e-9) && rec.traction[k] > 0.0,
            "{what}: step {k} before failure: {:.6e} dissipated, traction {:.3e}",
            rec.dissipated[k],
            rec.traction[k]
        );
    }
    for k in first..rec.stages.len() {
        assert_eq!(rec.stages[k], PointStage::Failed, "{what}: step {k} healed");
        assert!(
            rec.dissipated[k] >= target * (1.0 - TOL),
            "{what}: step {k}"
        );
    }
    // half way to failure (in energy) the point is in the process zone
    let half = rec
        .dissipated
        .iter()
        .position(|&w| w > 0.5 * target)
        .unwrap();
    assert_eq!(rec.stages[half], PointStage::ProcessZone, "{what}");
}

/// Below the onset the point is intact.
fn assert_intact_below_onset(law: &Arc<dyn InterfaceLaw>, b: f64, what: &str) {
    let rec = drive(law, b, 0.9 * onset(b, N, s_consistent()), 5);
    assert!(
        rec.stages.iter().all(|&s| s == PointStage::Intact),
        "{what}: {:?}",
        rec.stages
    );
}

/// Onset jump along mode ratio `b` with the quadratic criterion and one
/// penalty: `(K lam cos / N)^2 + (K lam sin / S)^2 = 1`.
fn onset(b: f64, n: f64, s: f64) -> f64 {
    let (sb, cb) = (b.sqrt(), (1.0 - b).sqrt());
    1.0 / (K * ((cb / n).powi(2) + (sb / s).powi(2)).sqrt())
}

/// Final equivalent opening of the bilinear curve at mode ratio `b` with
/// the quadratic onset and one penalty (Camanho & Davila 2002:
/// `delta_0m`, `delta_fm = 2 G_c / (K delta_0m)`).
fn final_opening(b: f64, n: f64, s: f64, g_c: f64) -> f64 {
    2.0 * g_c / (K * onset(b, n, s))
}

const MODES: [f64; 3] = [0.0, 0.5, 1.0];

#[test]
fn bilinear_point_fails_when_it_has_dissipated_g_c_of_its_mode_mix() {
    let law = build("bilinear", &bilinear_text(K, N, GIC, GIIC));
    for b in MODES {
        let g_c = bk(b, GIC, GIIC);
        let lam_f = final_opening(b, N, s_consistent(), g_c);
        let rec = drive(&law, b, 1.2 * lam_f, 3000);
        assert_fails_at(&rec, g_c, &format!("bilinear B = {b}"));
        assert_intact_below_onset(&law, b, "bilinear");
    }
}

#[test]
fn exponential_point_fails_at_its_stated_energy_fraction() {
    use junta_interface::law::exponential::FAILED_ENERGY_FRACTION;
    let law = build("exponential", &bilinear_text(K, N, GIC, GIIC));
    for b in MODES {
        let g_c = bk(b, GIC, GIIC);
        // the decay length is below 2 G_c / tau_0; 12 of them reach far
        // past the 99 % of G_c
        let lam_end = 12.0 * final_opening(b, N, s_consistent(), g_c);
        let rec = drive(&law, b, lam_end, 20000);
        assert_fails_at(
            &rec,
            FAILED_ENERGY_FRACTION * g_c,
            &format!("exponential B = {b}"),
        );
        assert_intact_below_onset(&law, b, "exponential");
    }
}

#[test]
fn fatigue_laws_under_static_load_fail_when_their_energy_damage_reaches_1() {
    let paris = "C_I = 0.02\nm_I = 5.0\nC_II = 0.05\nm_II = 4.0\nl_cz = 1.0\n";
    let cf20 = "epsilon = 0.3\nbrittleness = 0.9\n";
    for (key, extra) in [("fatigue_bilinear", paris), ("fatigue_cf20", cf20)] {
        let law = build(key, &format!("{}{extra}", bilinear_text(K, N, GIC, GIIC)));
        for b in MODES {
            let g_c = bk(b, GIC, GIIC);
            let lam_f = final_opening(b, N, s_consistent(), g_c);
            let rec = drive(&law, b, 1.2 * lam_f, 3000);
            assert_fails_at(&rec, g_c, &format!("{key} B = {b}"));
            assert_intact_below_onset(&law, b, key);
        }
    }
}

#[test]
fn bilinear_friction_point_fails_with_its_cohesive_part() {
    // an opening or a slip without pressure: no friction, the cohesive
    // part alone dissipates
    let law = build(
        "bilinear_friction",
        &format!("mu = 0.5\n{}", bilinear_text(K, N, GIC, GIIC)),
    );
    for b in MODES {
        let g_c = bk(b, GIC, GIIC);
        let lam_f = final_opening(b, N, s_consistent(), g_c);
        let rec = drive(&law, b, 1.2 * lam_f, 3000);
        assert_fails_at(&rec, g_c, &format!("bilinear_friction B = {b}"));
        assert_intact_below_onset(&law, b, "bilinear_friction");
    }
}

#[test]
fn superposed_point_fails_when_both_laws_have_dissipated_their_toughness() {
    // an initiation law and a bridging law of a tenth of its strength and
    // the same onset (Davila, Rose & Camanho 2009): the point has failed
    // once the sum of the toughnesses is dissipated
    let (n2, g1, g2) = (3.0, 0.26, 0.4);
    let k2 = K * n2 / N;
    let text = format!(
        "[[laws]]\ntype = \"bilinear\"\n{}[[laws]]\ntype = \"bilinear\"\n{}",
        bilinear_text(K, N, g1, 4.0 * g1),
        bilinear_text(k2, n2, g2, 4.0 * g2)
    );
    let law = build("superposed", &text);
    for b in MODES {
        let (ga, gb) = (bk(b, g1, 4.0 * g1), bk(b, g2, 4.0 * g2));
        // the bridging law fails last (same onset, far lower strength)
        let lam_f2 = {
            let (sb, cb) = (b.sqrt(), (1.0 - b).sqrt());
            let s2 = n2 * 2.0;
            let lam0 = 1.0 / (k2 * ((cb / n2).powi(2) + (sb / s2).powi(2)).sqrt());
            2.0 * gb / (k2 * lam0)
        };
        let rec = drive(&law, b, 1.2 * lam_f2, 20000);
        assert_fails_at(&rec, ga + gb, &format!("superposed B = {b}"));
        assert_intact_below_onset(&law, b, "superposed");
    }
}

#[test]
fn laws_without_fracture_never_fail() {
    for (key, text) in [
        ("linear_penalty", "d = 1e6\n".to_string()),
        ("contact", "K = 1e6\n".to_string()),
    ] {
        let law = build(key, &text);
        let rec = drive(&law, 0.5, 1.0, 10);
        assert!(rec.stages.iter().all(|&s| s == PointStage::Intact), "{key}");
    }
}
