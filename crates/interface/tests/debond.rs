//! Tests of the paper's debonding law `paper_debond` (PAPER.md section 4),
//! driven directly with a sequence of jumps over increments; the driver is
//! emulated by copying trial -> committed after each converged increment.
//!
//! 1. failure in tension, release 3/4, 1/2, 1/4, 0 of t_f (normal and shear);
//! 2. failure in compression by shear: shear released, normal stays contact;
//! 3. opening and closing after failure (and while still releasing);
//! 4. the criterion index stored in the state against hand values;
//! 5. finite-difference tangent in every regime;
//! 6. cut-back: a discarded failing trial leaves no trace;
//! 7. `wants_small_increments` exactly while releasing;
//! 8. parameter checks and the registry entry;
//! 9. one INTER8 with the top face pulled uniformly: all points fail in the
//!    same increment and the nodal forces follow 3/4, 1/2, 1/4, 0.

use junta_core::element::{Element, ElementContext, StepInfo};
use junta_core::law::{InterfaceLaw, LawContext, LawResponse};
use junta_core::registry::{find, LawEntry};
use junta_core::topology::CellShape;
use junta_criteria::{CompressionRule, MaxStress, Quadratic};
use junta_interface as _;
use junta_interface::law::paper_debond::{
    debond_status, slot, DebondMode, DebondPhase, PaperDebond,
};
use junta_interface::{InterfaceElement, InterfaceRule};
use std::sync::Arc;

const D: f64 = 1e12;

fn law_with(rule: CompressionRule) -> PaperDebond {
    PaperDebond::new([D; 3], 4, Arc::new(Quadratic::new(2e6, 4e6, rule).unwrap())).unwrap()
}

fn law() -> PaperDebond {
    law_with(CompressionRule::PositivePart)
}

fn ctx(jump: [f64; 3], committed: &[f64], increment: usize) -> LawContext<'_> {
    LawContext {
        jump,
        state_committed: committed,
        step: StepInfo::at(increment, 0.0, 0.0),
    }
}

/// One integration point and its committed state, driven like the driver.
struct Point<'a> {
    law: &'a PaperDebond,
    committed: Vec<f64>,
}

impl<'a> Point<'a> {
    fn new(law: &'a PaperDebond) -> Self {
        let mut committed = vec![f64::NAN; law.state_len()];
        law.init_state(&mut committed);
        Point { law, committed }
    }

    /// Evaluate without committing (a Newton iterate).
    fn trial(&self, jump: [f64; 3], inc: usize) -> (LawResponse, Vec<f64>) {
        let mut trial = vec![f64::NAN; self.law.state_len()];
        let r = self
            .law
            .evaluate(&ctx(jump, &self.committed, inc), &mut trial)
            .unwrap();
        (r, trial)
    }

    /// Evaluate and commit (a converged increment).
    fn step(&mut self, jump: [f64; 3], inc: usize) -> LawResponse {
        let (r, trial) = self.trial(jump, inc);
        self.committed = trial;
        r
    }
}

fn diag(a: f64, b: f64, c: f64) -> [[f64; 3]; 3] {
    [[a, 0.0, 0.0], [0.0, b, 0.0], [0.0, 0.0, c]]
}

// ------------------------------------------------------------------- 1

#[test]
fn failure_in_tension_releases_over_four_increments() {
    let law = law();
    let mut p = Point::new(&law);
    // ramp delta_3 by 0.5e-6: index 1/16, 1/4, 9/16, then exactly 1 at 2e-6
    let expected_index = [0.0625, 0.25, 0.5625, 1.0];
    for (inc, idx) in expected_index.iter().enumerate() {
        let d3 = 0.5e-6 * (inc + 1) as f64;
        let r = p.step([0.0, 0.0, d3], inc);
        // the failing increment (inc 3) still answers t = D delta
        assert_eq!(r.traction, [0.0, 0.0, D * d3]);
        assert_eq!(r.tangent, diag(D, D, D));
        let st = debond_status(&p.committed);
        assert_eq!(st.failure_index, *idx);
        let phase = if inc < 3 {
            DebondPhase::Intact
        } else {
            DebondPhase::Releasing
        };
        assert_eq!(st.phase, phase, "increment {inc}");
    }
    let st = debond_status(&p.committed);
    assert_eq!(st.mode, Some(DebondMode::Tension));
    assert_eq!(st.failed_at, Some(3));
    let tf = 2e6;
    assert_eq!(st.failure_traction, Some([0.0, 0.0, tf]));
    // the opening keeps growing; the traction is prescribed
    for (k, frac) in [0.75, 0.5, 0.25, 0.0].iter().enumerate() {
        let inc = 4 + k;
        let r = p.step([0.0, 0.0, 2e-6 + 0.5e-6 * (k + 1) as f64], inc);
        assert_eq!(r.traction, [0.0, 0.0, frac * tf], "increment {inc}");
        assert_eq!(r.tangent, [[0.0; 3]; 3], "increment {inc}");
        let st = debond_status(&p.committed);
        assert_eq!(st.release_step, k + 1);
        let phase = if k < 3 {
            DebondPhase::Releasing
        } else {
            DebondPhase::Failed
        };
        assert_eq!(st.phase, phase);
        assert_eq!(st.failure_index, 1.0, "index kept at its failure value");
    }
    for inc in 8..11 {
        let r = p.step([0.0, 0.0, 5e-6], inc);
        assert_eq!(r.traction, [0.0; 3]);
        assert_eq!(debond_status(&p.committed).phase, DebondPhase::Failed);
    }
}

#[test]
fn failure_in_tension_with_shear_releases_shear_and_normal() {
    let law = law();
    let mut p = Point::new(&law);
    // t = i [1e6, -0.5e6, 0.5e6]: index 0.140625, 0.5625, 1.265625
    let base = [1e-6, -0.5e-6, 0.5e-6];
    let idx = [0.140625, 0.5625, 1.265625];
    for (inc, index) in idx.iter().enumerate() {
        let s = (inc + 1) as f64;
        let r = p.step(base.map(|v| s * v), inc);
        assert_eq!(r.traction, base.map(|v| D * s * v));
        assert_eq!(debond_status(&p.committed).failure_index, *index);
    }
    let tf = [3e6, -1.5e6, 1.5e6];
    let st = debond_status(&p.committed);
    assert_eq!(st.failure_traction, Some(tf));
    assert_eq!(st.mode, Some(DebondMode::Tension));
    assert_eq!(st.failed_at, Some(2));
    // the released tractions do not depend on the (changing) slips
    for (k, frac) in [0.75, 0.5, 0.25, 0.0].iter().enumerate() {
        let r = p.step([7e-6 * k as f64, 2e-6, 4e-6], 3 + k);
        assert_eq!(r.traction, tf.map(|v| frac * v), "k = {}", k + 1);
        assert_eq!(r.tangent, [[0.0; 3]; 3]);
    }
}

// ------------------------------------------------------------------- 2

#[test]
fn failure_in_compression_by_shear_keeps_the_normal_contact() {
    let law = law();
    let mut p = Point::new(&law);
    // sigma_33 = -1e6 (ignored by the positive part), tau = 1e6 .. 4e6
    for inc in 0..4 {
        let s = (inc + 1) as f64;
        let r = p.step([s * 1e-6, 0.0, -1e-6], inc);
        assert_eq!(r.traction, [s * 1e6, 0.0, -1e6]);
        assert_eq!(debond_status(&p.committed).failure_index, s * s / 16.0);
    }
    let st = debond_status(&p.committed);
    assert_eq!(st.phase, DebondPhase::Releasing);
    assert_eq!(st.mode, Some(DebondMode::Compression));
    assert_eq!(st.failed_at, Some(3));
    assert!(st.closed);
    let tf = [4e6, 0.0, -1e6];
    assert_eq!(st.failure_traction, Some(tf));
    for (k, frac) in [0.75, 0.5, 0.25, 0.0].iter().enumerate() {
        // the closure varies: the normal traction follows d3 delta_3
        let d3 = -1e-6 - 0.25e-6 * k as f64;
        let r = p.step([5e-6, 1e-6, d3], 4 + k);
        assert_eq!(r.traction, [frac * 4e6, 0.0, D * d3], "k = {}", k + 1);
        assert_eq!(r.tangent, diag(0.0, 0.0, D));
    }
    assert_eq!(debond_status(&p.committed).phase, DebondPhase::Failed);
    // compression-failed point that opens: nothing
    let r = p.step([5e-6, 1e-6, 1e-6], 8);
    assert_eq!(r.traction, [0.0; 3]);
    assert_eq!(r.tangent, [[0.0; 3]; 3]);
}

// ------------------------------------------------------------------- 3

/// A point failed in tension at increment 0 (t_f = [0, 0, 2e6]).
fn failed_in_tension(law: &PaperDebond) -> Point<'_> {
    let mut p = Point::new(law);
    p.step([0.0, 0.0, 2e-6], 0);
    assert_eq!(debond_status(&p.committed).phase, DebondPhase::Releasing);
    p
}

/// (jump, expected traction, expected tangent, closed)
type Expect = ([f64; 3], [f64; 3], [[f64; 3]; 3], bool);

#[test]
fn opening_and_closing_after_full_failure() {
    let law = law();
    let mut p = failed_in_tension(&law);
    for inc in 1..=4 {
        p.step([0.0, 0.0, 3e-6], inc);
    }
    assert_eq!(debond_status(&p.committed).phase, DebondPhase::Failed);
    let seq: [Expect; 5] = [
        ([1e-6, 2e-6, 1e-6], [0.0; 3], [[0.0; 3]; 3], false),
        (
            [1e-6, 2e-6, -1e-6],
            [0.0, 0.0, -1e6],
            diag(0.0, 0.0, D),
            true,
        ),
        (
            [3e-6, 0.0, -2.5e-6],
            [0.0, 0.0, -2.5e6],
            diag(0.0, 0.0, D),
            true,
        ),
        ([1e-6, 2e-6, 0.5e-6], [0.0; 3], [[0.0; 3]; 3], false),
        ([1e-6, 2e-6, 0.0], [0.0; 3], [[0.0; 3]; 3], false),
    ];
    for (i, (jump, t, k, closed)) in seq.iter().enumerate() {
        let r = p.step(*jump, 5 + i);
        assert_eq!(r.traction, *t, "step {i}");
        assert_eq!(r.tangent, *k, "step {i}");
        let st = debond_status(&p.committed);
        assert_eq!(st.closed, *closed);
        assert_eq!(st.phase, DebondPhase::Failed);
    }
}

#[test]
fn tension_failed_point_that_closes_while_releasing_adds_contact() {
    let law = law();
    let mut p = failed_in_tension(&law);
    // k = 1: remaining 3/4 t_f plus contact d3 delta_3
    let r = p.step([0.0, 0.0, -1e-6], 1);
    assert_eq!(r.traction, [0.0, 0.0, 1.5e6 - 1e6]);
    assert_eq!(r.tangent, diag(0.0, 0.0, D));
    assert!(debond_status(&p.committed).closed);
    // k = 2: open again, only the remainder
    let r = p.step([0.0, 0.0, 1e-6], 2);
    assert_eq!(r.traction, [0.0, 0.0, 1e6]);
    assert_eq!(r.tangent, [[0.0; 3]; 3]);
    assert!(!debond_status(&p.committed).closed);
}

// ------------------------------------------------------------------- 4

#[test]
fn criterion_index_through_the_law() {
    let law_pos = law();
    let law_lit = law_with(CompressionRule::AsWritten);
    let cases: [([f64; 3], f64, f64); 5] = [
        ([2e-6, 0.0, 1e-6], 0.5, 0.5),
        ([0.0, 2e-6, 0.0], 0.25, 0.25),
        ([2e-6, 0.0, -1e-6], 0.25, 0.5),
        ([0.0, 0.0, -1.5e-6], 0.0, 0.5625),
        ([0.0, 0.0, 1.5e-6], 0.5625, 0.5625),
    ];
    for (jump, pos, lit) in cases {
        let (_, s) = Point::new(&law_pos).trial(jump, 0);
        assert_eq!(s[slot::INDEX], pos, "{jump:?}");
        assert_eq!(debond_status(&s).phase, DebondPhase::Intact);
        let (_, s) = Point::new(&law_lit).trial(jump, 0);
        assert_eq!(s[slot::INDEX], lit, "{jump:?}");
    }
    // as written, pure compression at sigma_lim fails the point (in compression)
    let (_, s) = Point::new(&law_lit).trial([0.0, 0.0, -3e-6], 0);
    assert_eq!(s[slot::INDEX], 2.25);
    assert_eq!(debond_status(&s).mode, Some(DebondMode::Compression));
    let (_, s) = Point::new(&law_pos).trial([0.0, 0.0, -3e-6], 0);
    assert_eq!(s[slot::INDEX], 0.0);
    assert_eq!(debond_status(&s).phase, DebondPhase::Intact);
    // max_stress
    let ms = PaperDebond::new(
        [D; 3],
        4,
        Arc::new(MaxStress::new(2e6, 4e6, CompressionRule::PositivePart).unwrap()),
    )
    .unwrap();
    let (_, s) = Point::new(&ms).trial([3e-6, 0.0, 1e-6], 0);
    assert_eq!(s[slot::INDEX], 0.75);
    let (_, s) = Point::new(&ms).trial([2e-6, 0.0, 2e-6], 0);
    assert_eq!(s[slot::INDEX], 1.0);
    assert_eq!(debond_status(&s).phase, DebondPhase::Releasing);
}

// ------------------------------------------------------------------- 5

fn check_tangent(law: &PaperDebond, committed: &[f64], jump: [f64; 3], inc: usize, name: &str) {
    let eval = |j: [f64; 3]| {
        let mut trial = vec![0.0; law.state_len()];
        law.evaluate(&ctx(j, committed, inc), &mut trial).unwrap()
    };
    let r = eval(jump);
    let h = 1e-10;
    for k in 0..3 {
        let (mut a, mut b) = (jump, jump);
        a[k] += h;
        b[k] -= h;
        let (ta, tb) = (eval(a).traction, eval(b).traction);
        for i in 0..3 {
            let fd = (ta[i] - tb[i]) / (2.0 * h);
            assert!(
                (fd - r.tangent[i][k]).abs() <= 1e-6 * D,
                "{name}: d t{i} / d delta{k}: fd {fd} vs {}",
                r.tangent[i][k]
            );
        }
    }
}

#[test]
fn tangent_matches_finite_differences_in_every_regime() {
    let law = law();
    // intact, open and closed
    let p = Point::new(&law);
    check_tangent(&law, &p.committed, [1e-7, -2e-7, 3e-7], 0, "intact open");
    check_tangent(&law, &p.committed, [1e-7, -2e-7, -3e-7], 0, "intact closed");
    // failed in tension at increment 0
    let p = failed_in_tension(&law);
    check_tangent(
        &law,
        &p.committed,
        [1e-6, 1e-6, 1e-6],
        0,
        "failing increment",
    );
    check_tangent(&law, &p.committed, [1e-6, 1e-6, 1e-6], 2, "releasing open");
    check_tangent(
        &law,
        &p.committed,
        [1e-6, 1e-6, -1e-6],
        2,
        "releasing closed",
    );
    check_tangent(&law, &p.committed, [1e-6, 1e-6, 1e-6], 9, "failed open");
    check_tangent(&law, &p.committed, [1e-6, 1e-6, -1e-6], 9, "failed closed");
    // failed in compression
    let mut p = Point::new(&law);
    p.step([5e-6, 0.0, -1e-6], 0);
    assert_eq!(
        debond_status(&p.committed).mode,
        Some(DebondMode::Compression)
    );
    check_tangent(
        &law,
        &p.committed,
        [1e-6, 1e-6, -1e-6],
        1,
        "compression releasing closed",
    );
    check_tangent(
        &law,
        &p.committed,
        [1e-6, 1e-6, 1e-6],
        1,
        "compression releasing open",
    );
}

// ------------------------------------------------------------------- 6

#[test]
fn cut_back_leaves_no_trace_of_a_discarded_failing_trial() {
    let law = law();
    let mut p = Point::new(&law);
    p.step([0.0, 0.0, 1e-6], 0);
    let before = p.committed.clone();
    // trial that fails ...
    let (r, trial) = p.trial([0.0, 0.0, 2e-6], 1);
    assert_eq!(r.traction, [0.0, 0.0, 2e6]);
    assert_eq!(debond_status(&trial).phase, DebondPhase::Releasing);
    // ... not converged: the driver cuts back; committed state untouched
    assert_eq!(p.committed, before);
    let (r, trial) = p.trial([0.0, 0.0, 1.5e-6], 1);
    assert_eq!(r.traction, [0.0, 0.0, 1.5e6]);
    assert_eq!(r.tangent, diag(D, D, D));
    let st = debond_status(&trial);
    assert_eq!(st.phase, DebondPhase::Intact);
    assert_eq!(st.failed_at, None);
    assert_eq!(st.failure_index, 0.5625);
    // a Newton iterate that fails followed by one that does not, in the
    // same increment: the last one decides
    let mut trial = vec![0.0; law.state_len()];
    law.evaluate(&ctx([0.0, 0.0, 2e-6], &p.committed, 1), &mut trial)
        .unwrap();
    law.evaluate(&ctx([0.0, 0.0, 1.5e-6], &p.committed, 1), &mut trial)
        .unwrap();
    assert_eq!(debond_status(&trial).phase, DebondPhase::Intact);
    // commit the smaller step, then fail at the next increment
    p.step([0.0, 0.0, 1.5e-6], 1);
    p.step([0.0, 0.0, 2e-6], 2);
    assert_eq!(debond_status(&p.committed).failed_at, Some(2));
}

// ------------------------------------------------------------------- 7

#[test]
fn wants_small_increments_exactly_while_releasing() {
    let law = law();
    let mut p = Point::new(&law);
    assert!(!law.wants_small_increments(&p.committed));
    let mut flags = Vec::new();
    for inc in 0..10 {
        let d3 = if inc < 2 {
            1e-6
        } else {
            2e-6 + 1e-6 * inc as f64
        };
        p.step([0.0, 0.0, d3], inc);
        flags.push(law.wants_small_increments(&p.committed));
    }
    // fails at 2, released at 3, 4, 5, 6 (zero at 6)
    assert_eq!(
        flags,
        [false, false, true, true, true, true, false, false, false, false]
    );
    // also through release_increments = 1
    let one = PaperDebond::new([D; 3], 1, law.criterion().clone()).unwrap();
    let mut p = Point::new(&one);
    p.step([0.0, 0.0, 3e-6], 0);
    assert!(one.wants_small_increments(&p.committed));
    let r = p.step([0.0, 0.0, 3e-6], 1);
    assert_eq!(r.traction, [0.0; 3]);
    assert!(!one.wants_small_increments(&p.committed));
}

// ------------------------------------------------------------------- 8

fn from_toml(src: &str) -> Result<PaperDebond, String> {
    PaperDebond::from_table(&src.parse().unwrap()).map_err(|e| e.to_string())
}

const CRIT: &str = r#"criterion = { type = "quadratic", sigma_lim = 2e6, tau_lim = 4e6 }"#;

#[test]
fn parameters_are_checked() {
    let ok = from_toml(&format!("d = 1e12\n{CRIT}")).unwrap();
    assert_eq!(ok.d, [D; 3]);
    assert_eq!(ok.release_increments, 4);
    assert_eq!(ok.criterion().key(), "quadratic");
    let ok = from_toml(
        "d = 1e12\nd3 = 2e12\nrelease_increments = 6\ncriterion = { type = \"max_stress\", sigma_lim = 1.0, tau_lim = 2.0, compression = \"as_written\" }",
    )
    .unwrap();
    assert_eq!(ok.d, [D, D, 2e12]);
    assert_eq!(ok.release_increments, 6);
    assert_eq!(ok.criterion().key(), "max_stress");

    let e = from_toml("d = 1e12").unwrap_err();
    assert!(
        e.contains("missing `criterion`") && e.contains("quadratic"),
        "{e}"
    );
    let e = from_toml("d = 1e12\ncriterion = { type = \"hashin\" }").unwrap_err();
    assert!(
        e.contains("hashin") && e.contains("quadratic") && e.contains("max_stress"),
        "{e}"
    );
    let e = from_toml("d = 1e12\ncriterion = { sigma_lim = 1.0 }").unwrap_err();
    assert!(
        e.contains("needs `type`") && e.contains("max_stress"),
        "{e}"
    );
    let e = from_toml("d = 1e12\ncriterion = \"quadratic\"").unwrap_err();
    assert!(e.contains("must be a table"), "{e}");
    let e =
        from_toml("d = 1e12\ncriterion = { type = \"quadratic\", sigma_lim = 2e6 }").unwrap_err();
    assert!(e.contains("criterion") && e.contains("tau_lim"), "{e}");
    let e = from_toml(
        "d = 1e12\ncriterion = { type = \"quadratic\", sigma_lim = 2e6, tau_lim = 4e6, sigma_max = 1.0 }",
    )
    .unwrap_err();
    assert!(e.contains("sigma_max"), "{e}");
    for bad in ["0.0", "-1e12"] {
        let e = from_toml(&format!("d = {bad}\n{CRIT}")).unwrap_err();
        assert!(e.contains("d1") && e.contains("positive"), "{e}");
    }
    let e = from_toml(&format!("d = 1e12\nd2 = -1.0\n{CRIT}")).unwrap_err();
    assert!(e.contains("d2"), "{e}");
    let e = from_toml(&format!("d1 = 1e12\n{CRIT}")).unwrap_err();
    assert!(e.contains("d2"), "{e}");
    for bad in ["0", "-2"] {
        let e = from_toml(&format!("d = 1e12\nrelease_increments = {bad}\n{CRIT}")).unwrap_err();
        assert!(
            e.contains("release_increments") && e.contains("at least 1"),
            "{e}"
        );
    }
    let e = from_toml(&format!("d = 1e12\nrelease_steps = 4\n{CRIT}")).unwrap_err();
    assert!(
        e.contains("release_steps") && e.contains("release_increments"),
        "{e}"
    );
    let c = Arc::new(Quadratic::new(1.0, 1.0, CompressionRule::PositivePart).unwrap());
    assert!(PaperDebond::new([D; 3], 0, c.clone()).is_err());
    assert!(PaperDebond::new([D, f64::NAN, D], 4, c).is_err());
}

#[test]
fn registry_entry_builds_the_law() {
    let entry = find::<LawEntry>("paper_debond").unwrap_or_else(|e| panic!("{e}"));
    for name in ["d", "release_increments", "criterion"] {
        assert!(entry.params.iter().any(|p| p.name == name), "{name}");
    }
    let t: toml::Table = format!("d = 1e12\n{CRIT}").parse().unwrap();
    let law = (entry.build)(&t).unwrap();
    assert_eq!(law.key(), "paper_debond");
    assert_eq!(law.state_len(), slot::STATE_LEN);
    assert_eq!(law.initial_stiffness(), [D; 3]);
    let mut s = vec![f64::NAN; law.state_len()];
    law.init_state(&mut s);
    assert_eq!(debond_status(&s).phase.code(), 0);
    assert!(s.iter().all(|v| v.is_finite()));
}

// ------------------------------------------------------------------- 9

#[test]
fn inter8_top_face_pulled_uniformly() {
    let law = Arc::new(law());
    let el = InterfaceElement::new(CellShape::Inter8, InterfaceRule::Lobatto, law.clone()).unwrap();
    // 2 x 2 square: |V_xi x V_eta| = 1, Lobatto weights 1: dA = 1 per point
    let sq = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]];
    let coords: Vec<[f64; 3]> = (0..8).map(|i| [sq[i % 4][0], sq[i % 4][1], 0.0]).collect();
    let mut committed = vec![f64::NAN; el.state_len()];
    el.init_state(&mut committed);
    let sl = law.state_len();
    let mut forces = Vec::new();
    for inc in 0..9 {
        let w = 0.5e-6 * (inc + 1) as f64; // fails at inc 3 (w = 2e-6)
        let mut disp = vec![0.0; 24];
        for a in 4..8 {
            disp[3 * a + 2] = w;
            disp[3 * a] = 0.25 * w; // some slip along e1 too
        }
        let mut trial = vec![0.0; el.state_len()];
        let mut f = vec![0.0; 24];
        let mut k = vec![0.0; 24 * 24];
        el.compute(
            &ElementContext {
                coords: &coords,
                disp: &disp,
                state_committed: &committed,
                step: StepInfo::at(inc, 0.0, 0.0),
                law_responses: None,
                temperature: None,
            },
            &mut trial,
            &mut f,
            Some(&mut k),
        )
        .unwrap();
        committed = trial;
        // every top node carries the same force, the bottom the opposite
        for a in 0..4 {
            for c in 0..3 {
                assert_eq!(f[3 * (4 + a) + c], f[12 + c], "inc {inc}");
                assert_eq!(f[3 * a + c], -f[12 + c], "inc {inc}");
            }
        }
        let phases: Vec<_> = committed
            .chunks(sl)
            .map(|s| debond_status(s).phase)
            .collect();
        assert!(phases.windows(2).all(|p| p[0] == p[1]), "{phases:?}");
        forces.push((
            [f[12], f[13], f[14]],
            phases[0],
            el.wants_small_increments(&committed),
        ));
        if inc >= 4 {
            // released: the normal and shear rows of K are zero (open)
            assert!(k.iter().all(|v| *v == 0.0), "inc {inc}");
        }
    }
    // failure at inc 3: t_f = [0.5e6, 0, 2e6] (index 1 + 1/64 >= 1)
    let tf = [0.5e6, 0.0, 2e6];
    assert_eq!(forces[2].1, DebondPhase::Intact);
    assert_eq!(forces[3], (tf, DebondPhase::Releasing, true));
    for (k, frac) in [0.75, 0.5, 0.25].iter().enumerate() {
        assert_eq!(
            forces[4 + k],
            (tf.map(|v| frac * v), DebondPhase::Releasing, true)
        );
    }
    assert_eq!(forces[7], ([0.0; 3], DebondPhase::Failed, false));
    assert_eq!(forces[8], ([0.0; 3], DebondPhase::Failed, false));
    for s in committed.chunks(sl) {
        assert_eq!(debond_status(s).failed_at, Some(3));
        assert!(law.is_failed(s));
        assert_eq!(law.failure_index(s), Some(1.015625));
    }
    let mut fresh = vec![0.0; sl];
    law.init_state(&mut fresh);
    assert!(!law.is_failed(&fresh));
    assert_eq!(law.failure_index(&fresh), Some(0.0));
}
