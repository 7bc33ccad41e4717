//! `paper_debond`: the paper's debonding procedure (section 4): a linear
//! penalty until a stress criterion fails the point, then a gradual release
//! of the traction over `N = release_increments` increments, with penalty
//! contact after failure.
//!
//! Per integration point, with `D = diag(d1, d2, d3)`, jump `delta` and
//! committed state (layout in [`slot`]):
//!
//! ```text
//! intact       t = D delta,  dt/ddelta = D.
//!              index = criterion(D delta); if index >= 1 the point FAILS in
//!              this increment i_f: the trial state records i_f, the mode
//!              (tension if sigma_33 > 0, else compression) and t_f = D delta.
//!              The traction of the failing increment is still D delta (k = 0).
//!
//! failed       k = min(i - i_f, N) at increment i, r = (N - k) / N,
//!              closed = delta_3 < 0, c = d3 delta_3 if closed else 0.
//!   k = 0      (only when re-evaluated within the failing increment) t = D delta, D.
//!   k >= 1     shear:   tau_13 = r t_f,1, tau_23 = r t_f,2     (tangent 0)
//!              tension:     sigma_33 = r t_f,3 + c             (tangent d3 if closed else 0)
//!              compression: sigma_33 = c                       (tangent d3 if closed else 0)
//!   k = N      the point is fully failed: t = [0, 0, c].
//! ```
//!
//! Decisions:
//!
//! - **Failing increment.** The state change happens *between* increments:
//!   the increment in which the index first reaches 1 converges with the
//!   intact `t = D delta` (the Newton iterations of that increment see a
//!   smooth law), and the release runs over increments `i_f + 1 ..= i_f + N`
//!   with `t = (1 - k/N) t_f`, reaching zero at `i_f + N`.
//! - **Released components are prescribed tractions**: their tangent is zero.
//! - **Mode.** Tension if `sigma_33 > 0` at failure, compression otherwise
//!   (`sigma_33 == 0` counts as compression: there is no normal traction to
//!   release, so both modes would give the same response). Tension releases
//!   shear and normal; compression releases the shear only and the normal
//!   traction stays as contact.
//! - **Contact** after failure (both modes, including the release
//!   increments): closed when `delta_3 < 0` strictly, then `sigma_33 = d3
//!   delta_3` with tangent `d3`; open (`delta_3 >= 0`) gives no contact
//!   traction. Open/closed is decided on the trial jump at every evaluation,
//!   with no increment counting.
//! - **A tension-failed point that closes while still releasing** carries
//!   the sum of the remaining prescribed tensile traction and the contact
//!   traction, `sigma_33 = (1 - k/N) t_f,3 + d3 delta_3`, tangent `d3`.
//! - **Criterion** evaluated on the trial traction `D delta` of intact points
//!   only; once failed, the stored failure index keeps its value at failure.
//! - **Increment counting** uses `step.increment` (the driver's increment
//!   index; a retry after a cut-back reuses the index of the increment it
//!   retries). `i < i_f` (e.g. a restart that renumbers) is taken as `k = 0`.
//! - **Cut-back safe.** Every evaluation starts from the committed state and
//!   rewrites the whole trial state, so a failing trial that is discarded
//!   leaves no trace.
//! - [`InterfaceLaw::wants_small_increments`] is true while the committed
//!   state is "releasing" (from the failing increment up to `i_f + N - 1`),
//!   the paper's rule to keep load increments small during release.

use junta_core::law::{InterfaceLaw, LawContext, LawError, LawResponse};
use junta_core::registry::{entries, find, parse_params, CriterionEntry, LawEntry, ParamDoc};
use junta_core::{CoreError, FailureCriterion};
use serde::Deserialize;
use std::sync::Arc;

// Keep the criteria crate linked so that its registry entries are present
// whenever this law is.
use junta_criteria as _;

/// State layout of one integration point (`STATE_LEN` values).
pub mod slot {
    /// Phase: 0 intact, 1 releasing, 2 fully failed (see [`super::DebondPhase`]).
    pub const STATUS: usize = 0;
    /// Increment index at failure (`-1` while intact).
    pub const FAILED_AT: usize = 1;
    /// Mode: 0 none (intact), 1 tension, 2 compression.
    pub const MODE: usize = 2;
    /// Traction at failure `t_f = [tau_13, tau_23, sigma_33]` (3 values).
    pub const T_FAIL: usize = 3;
    /// Release step `k` of the last evaluation (0 ..= N).
    pub const RELEASE_STEP: usize = 6;
    /// Last evaluated failure index (kept at its failure value once failed).
    pub const INDEX: usize = 7;
    /// 1 if the last evaluated jump was closed (`delta_3 < 0`), else 0.
    pub const CLOSED: usize = 8;
    /// Number of state values per point.
    pub const STATE_LEN: usize = 9;
}

/// Phase of a point.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DebondPhase {
    /// Bonded: linear penalty.
    Intact,
    /// Failed, traction being released.
    Releasing,
    /// Released completely: contact only.
    Failed,
}

impl DebondPhase {
    /// Output code: 0 intact, 1 releasing, 2 fully failed.
    pub fn code(self) -> u8 {
        match self {
            DebondPhase::Intact => 0,
            DebondPhase::Releasing => 1,
            DebondPhase::Failed => 2,
        }
    }
}

/// Mode in which a point failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DebondMode {
    /// `sigma_33 > 0` at failure: shear and normal released.
    Tension,
    /// `sigma_33 <= 0` at failure: shear released, normal kept as contact.
    Compression,
}

/// A point's status read from its state, for output.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DebondStatus {
    /// Intact / releasing / fully failed.
    pub phase: DebondPhase,
    /// Failure mode (`None` while intact).
    pub mode: Option<DebondMode>,
    /// Increment index at failure.
    pub failed_at: Option<usize>,
    /// Release step `k` of the last evaluation.
    pub release_step: usize,
    /// Traction at failure.
    pub failure_traction: Option<[f64; 3]>,
    /// Last evaluated failure index.
    pub failure_index: f64,
    /// Whether the last evaluated jump was closed (`delta_3 < 0`).
    pub closed: bool,
}

const INTACT: f64 = 0.0;
const RELEASING: f64 = 1.0;
const FAILED: f64 = 2.0;
const MODE_NONE: f64 = 0.0;
const MODE_TENSION: f64 = 1.0;
const MODE_COMPRESSION: f64 = 2.0;

/// The paper's debonding law: linear penalty, criterion, gradual release,
/// contact.
#[derive(Debug, Clone)]
pub struct PaperDebond {
    /// Penalty stiffness `[d1, d2, d3]` (slips, normal).
    pub d: [f64; 3],
    /// Number of increments `N` over which a failed point is released.
    pub release_increments: usize,
    criterion: Arc<dyn FailureCriterion>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Params {
    d: Option<f64>,
    d1: Option<f64>,
    d2: Option<f64>,
    d3: Option<f64>,
    release_increments: Option<i64>,
    criterion: Option<toml::Value>,
}

fn invalid(message: String) -> CoreError {
    CoreError::InvalidParameters {
        kind: "law",
        key: "paper_debond".into(),
        message,
    }
}

fn criterion_keys() -> String {
    entries::<CriterionEntry>()
        .iter()
        .map(|e| e.key)
        .collect::<Vec<_>>()
        .join(", ")
}

impl PaperDebond {
    /// Default number of release increments (the paper's four).
    pub const DEFAULT_RELEASE_INCREMENTS: usize = 4;

    /// A law with penalty `d` (each positive, finite), release over
    /// `release_increments >= 1` increments, and `criterion`.
    pub fn new(
        d: [f64; 3],
        release_increments: usize,
        criterion: Arc<dyn FailureCriterion>,
    ) -> Result<Self, CoreError> {
        let d = super::penalty_stiffness("paper_debond", None, d.map(Some))?;
        if release_increments == 0 {
            return Err(invalid(
                "`release_increments` = 0; it must be at least 1 (the paper uses 4)".into(),
            ));
        }
        Ok(PaperDebond {
            d,
            release_increments,
            criterion,
        })
    }

    /// From a TOML table: `d` or `d1`, `d2`, `d3`; `release_increments`
    /// (default 4); `criterion = { type = "quadratic", sigma_lim = ..,
    /// tau_lim = .. }` built through the criterion registry.
    pub fn from_table(t: &toml::Table) -> Result<Self, CoreError> {
        let p: Params = parse_params("law", "paper_debond", t)?;
        let d = super::penalty_stiffness("paper_debond", p.d, [p.d1, p.d2, p.d3])?;
        let n = match p.release_increments {
            None => Self::DEFAULT_RELEASE_INCREMENTS,
            Some(n) if n >= 1 => n as usize,
            Some(n) => {
                return Err(invalid(format!(
                    "`release_increments` = {n}; it must be at least 1 (the paper uses 4)"
                )))
            }
        };
        let criterion = match &p.criterion {
            None => {
                return Err(invalid(format!(
                    "missing `criterion`, e.g. criterion = {{ type = \"quadratic\", sigma_lim = 2e6, tau_lim = 4e6 }}; valid types: {}",
                    criterion_keys()
                )))
            }
            Some(v) => Self::build_criterion(v)?,
        };
        Self::new(d, n, criterion)
    }

    fn build_criterion(v: &toml::Value) -> Result<Arc<dyn FailureCriterion>, CoreError> {
        let table = v.as_table().ok_or_else(|| {
            invalid(format!(
                "`criterion` must be a table such as {{ type = \"quadratic\", sigma_lim = 2e6, tau_lim = 4e6 }}, not {v}; valid types: {}",
                criterion_keys()
            ))
        })?;
        let ty = match table.get("type") {
            Some(toml::Value::String(s)) => s.as_str(),
            Some(other) => {
                return Err(invalid(format!(
                    "`criterion.type` must be a string, not {other}; valid types: {}",
                    criterion_keys()
                )))
            }
            None => {
                return Err(invalid(format!(
                    "`criterion` needs `type`; valid types: {}",
                    criterion_keys()
                )))
            }
        };
        let entry =
            find::<CriterionEntry>(ty).map_err(|e| invalid(format!("`criterion.type`: {e}")))?;
        let mut rest = table.clone();
        rest.remove("type");
        (entry.build)(&rest).map_err(|e| invalid(format!("`criterion`: {e}")))
    }

    /// The failure criterion.
    pub fn criterion(&self) -> &Arc<dyn FailureCriterion> {
        &self.criterion
    }

    /// Status of a point from its state slice (committed or trial).
    pub fn status(state: &[f64]) -> DebondStatus {
        debond_status(state)
    }

    fn intact_response(&self, jump: [f64; 3]) -> LawResponse {
        let [d1, d2, d3] = self.d;
        LawResponse {
            traction: [d1 * jump[0], d2 * jump[1], d3 * jump[2]],
            tangent: [[d1, 0.0, 0.0], [0.0, d2, 0.0], [0.0, 0.0, d3]],
        }
    }
}

/// Status of a point from its state slice (layout in [`slot`]). A slice
/// shorter than [`slot::STATE_LEN`] reads as intact.
pub fn debond_status(state: &[f64]) -> DebondStatus {
    use slot::*;
    if state.len() < STATE_LEN {
        return DebondStatus {
            phase: DebondPhase::Intact,
            mode: None,
            failed_at: None,
            release_step: 0,
            failure_traction: None,
            failure_index: 0.0,
            closed: false,
        };
    }
    let phase = if state[STATUS] == RELEASING {
        DebondPhase::Releasing
    } else if state[STATUS] == FAILED {
        DebondPhase::Failed
    } else {
        DebondPhase::Intact
    };
    let failed = phase != DebondPhase::Intact;
    DebondStatus {
        phase,
        mode: if state[MODE] == MODE_TENSION {
            Some(DebondMode::Tension)
        } else if state[MODE] == MODE_COMPRESSION {
            Some(DebondMode::Compression)
        } else {
            None
        },
        failed_at: failed.then(|| state[FAILED_AT] as usize),
        release_step: state[RELEASE_STEP] as usize,
        failure_traction: failed.then(|| [state[T_FAIL], state[T_FAIL + 1], state[T_FAIL + 2]]),
        failure_index: state[INDEX],
        closed: state[CLOSED] != 0.0,
    }
}

impl InterfaceLaw for PaperDebond {
    fn key(&self) -> &'static str {
        "paper_debond"
    }

    fn state_len(&self) -> usize {
        slot::STATE_LEN
    }

    fn init_state(&self, state: &mut [f64]) {
        use slot::*;
        state.iter_mut().for_each(|v| *v = 0.0);
        state[STATUS] = INTACT;
        state[FAILED_AT] = -1.0;
        state[MODE] = MODE_NONE;
    }

    fn evaluate(
        &self,
        ctx: &LawContext<'_>,
        state_trial: &mut [f64],
    ) -> Result<LawResponse, LawError> {
        use slot::*;
        let c = ctx.state_committed;
        if c.len() != STATE_LEN || state_trial.len() != STATE_LEN {
            return Err(LawError::Failed(format!(
                "paper_debond: state slices of length {} (committed) and {} (trial), expected {STATE_LEN}",
                c.len(),
                state_trial.len()
            )));
        }
        state_trial.copy_from_slice(c);
        let jump = ctx.jump;
        let closed = jump[2] < 0.0;
        state_trial[CLOSED] = if closed { 1.0 } else { 0.0 };

        if c[STATUS] == INTACT {
            let r = self.intact_response(jump);
            let f = self.criterion.evaluate(r.traction);
            state_trial[INDEX] = f.index;
            if f.index >= 1.0 {
                state_trial[STATUS] = RELEASING;
                state_trial[FAILED_AT] = ctx.step.increment as f64;
                state_trial[MODE] = if r.traction[2] > 0.0 {
                    MODE_TENSION
                } else {
                    MODE_COMPRESSION
                };
                state_trial[T_FAIL..T_FAIL + 3].copy_from_slice(&r.traction);
                state_trial[RELEASE_STEP] = 0.0;
            }
            return Ok(r);
        }

        // Failed: release step k since the failing increment.
        let n = self.release_increments;
        let failed_at = c[FAILED_AT].max(0.0) as usize;
        let k = ctx.step.increment.saturating_sub(failed_at).min(n);
        state_trial[RELEASE_STEP] = k as f64;
        state_trial[STATUS] = if k >= n { FAILED } else { RELEASING };
        if k == 0 {
            return Ok(self.intact_response(jump));
        }
        let rf = (n - k) as f64 / n as f64;
        let tf = [c[T_FAIL], c[T_FAIL + 1], c[T_FAIL + 2]];
        let mut r = LawResponse::default();
        r.traction[0] = rf * tf[0];
        r.traction[1] = rf * tf[1];
        let released_n = if c[MODE] == MODE_TENSION {
            rf * tf[2]
        } else {
            0.0
        };
        let (contact, kn) = if closed {
            (self.d[2] * jump[2], self.d[2])
        } else {
            (0.0, 0.0)
        };
        r.traction[2] = released_n + contact;
        r.tangent[2][2] = kn;
        Ok(r)
    }

    fn initial_stiffness(&self) -> [f64; 3] {
        self.d
    }

    /// The paper's `D` bonds the intact faces and `d3` is the contact
    /// penalty after failure: constraint penalties (the paper's eqs. 41-55
    /// choose them); the stress criterion, not the penalty, sets failure.
    fn penalty_role(&self) -> junta_core::PenaltyRole {
        junta_core::PenaltyRole::Constraint
    }

    fn wants_small_increments(&self, state_committed: &[f64]) -> bool {
        state_committed.get(slot::STATUS) == Some(&RELEASING)
    }

    /// Intact while bonded, process zone while its traction is being
    /// released, failed once released completely (contact only: it
    /// carries no traction in tension).
    fn stage(&self, state: &[f64]) -> junta_core::PointStage {
        match debond_status(state).phase {
            DebondPhase::Intact => junta_core::PointStage::Intact,
            DebondPhase::Releasing => junta_core::PointStage::ProcessZone,
            DebondPhase::Failed => junta_core::PointStage::Failed,
        }
    }

    fn failure_index(&self, state: &[f64]) -> Option<f64> {
        state.get(slot::INDEX).copied()
    }

    fn output_names(&self) -> &'static [&'static str] {
        &[junta_core::law::output::DAMAGE]
    }

    /// `damage` = the released fraction `k / N` (0 intact, 1 fully
    /// released); this law has no fracture energy to report.
    fn outputs(&self, state: &[f64], out: &mut [f64]) {
        let st = debond_status(state);
        out[0] = match st.phase {
            DebondPhase::Intact => 0.0,
            DebondPhase::Releasing => st.release_step as f64 / self.release_increments as f64,
            DebondPhase::Failed => 1.0,
        };
    }
}

inventory::submit! {
    LawEntry {
        key: "paper_debond",
        description: "the paper's debonding: linear penalty until a criterion fails the point, release over N increments, penalty contact (section 4)",
        params: &[
            ParamDoc { name: "d", doc: "penalty stiffness for all three directions [force/length^3]" },
            ParamDoc { name: "d1", doc: "slip stiffness along e1 (overrides d)" },
            ParamDoc { name: "d2", doc: "slip stiffness along e2 (overrides d)" },
            ParamDoc { name: "d3", doc: "normal stiffness, also the contact penalty after failure (overrides d)" },
            ParamDoc { name: "release_increments", doc: "increments over which a failed point's traction goes linearly to zero, >= 1 (default 4, the paper's)" },
            ParamDoc { name: "criterion", doc: "inline table { type = \"quadratic\" | \"max_stress\", sigma_lim = .., tau_lim = .., compression = \"positive_part\" | \"as_written\" } (required)" },
        ],
        build: |t| Ok(Arc::new(PaperDebond::from_table(t)?)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use junta_core::element::StepInfo;
    use junta_criteria::{CompressionRule, Quadratic};

    fn law() -> PaperDebond {
        let c = Quadratic::new(2e6, 4e6, CompressionRule::PositivePart).unwrap();
        PaperDebond::new([1e12; 3], 4, Arc::new(c)).unwrap()
    }

    fn eval(
        law: &PaperDebond,
        committed: &[f64],
        jump: [f64; 3],
        inc: usize,
    ) -> (LawResponse, Vec<f64>) {
        let mut trial = vec![f64::NAN; slot::STATE_LEN];
        let r = law
            .evaluate(
                &LawContext {
                    jump,
                    state_committed: committed,
                    step: StepInfo {
                        increment: inc,
                        ..Default::default()
                    },
                },
                &mut trial,
            )
            .unwrap();
        (r, trial)
    }

    #[test]
    fn init_state_is_intact_and_failure_is_recorded() {
        let law = law();
        let mut s = vec![f64::NAN; law.state_len()];
        law.init_state(&mut s);
        let st = debond_status(&s);
        assert_eq!(st.phase, DebondPhase::Intact);
        assert_eq!(st.mode, None);
        assert_eq!(st.failed_at, None);
        assert!(!law.wants_small_increments(&s));
        let (r, trial) = eval(&law, &s, [4e-6, 0.0, 2e-6], 7);
        assert_eq!(r.traction, [4e6, 0.0, 2e6]);
        let st = debond_status(&trial);
        assert_eq!(st.phase, DebondPhase::Releasing);
        assert_eq!(st.mode, Some(DebondMode::Tension));
        assert_eq!(st.failed_at, Some(7));
        assert_eq!(st.failure_traction, Some([4e6, 0.0, 2e6]));
        assert_eq!(st.failure_index, 2.0);
        assert_eq!(st.release_step, 0);
        assert!(!st.closed);
        // re-evaluated in the failing increment: still the intact answer
        let (r, _) = eval(&law, &trial, [4e-6, 0.0, 2e-6], 7);
        assert_eq!(r.traction, [4e6, 0.0, 2e6]);
        // next increment: 3/4
        let (r, t2) = eval(&law, &trial, [4e-6, 0.0, 2e-6], 8);
        assert_eq!(r.traction, [3e6, 0.0, 1.5e6]);
        assert_eq!(debond_status(&t2).release_step, 1);
    }

    #[test]
    fn wrong_state_length_is_an_error() {
        let law = law();
        let mut trial = [0.0; 3];
        let e = law
            .evaluate(
                &LawContext {
                    jump: [0.0; 3],
                    state_committed: &[0.0; 3],
                    step: StepInfo::default(),
                },
                &mut trial,
            )
            .unwrap_err();
        assert!(e.to_string().contains("expected 9"), "{e}");
    }
}
