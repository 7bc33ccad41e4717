//! `linear_penalty`: the paper's penalty law (eqs. 33-35).
//!
//! ```text
//! tau_13 = d1 delta_1,   tau_23 = d2 delta_2,   sigma_33 = d3 delta_3
//! D = d t / d delta = diag(d1, d2, d3)          [N/m^3]
//! ```
//!
//! No state. `d1, d2, d3` must be positive and finite.

use junta_core::law::{InterfaceLaw, LawContext, LawError, LawResponse};
use junta_core::registry::{parse_params, LawEntry, ParamDoc};
use junta_core::CoreError;
use serde::Deserialize;
use std::sync::Arc;

/// Linear penalty law `t = diag(d1, d2, d3) delta`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearPenalty {
    /// Penalty stiffness per direction `[d1, d2, d3]` (slips, normal).
    pub d: [f64; 3],
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Params {
    d: Option<f64>,
    d1: Option<f64>,
    d2: Option<f64>,
    d3: Option<f64>,
}

impl LinearPenalty {
    /// A law with stiffness `[d1, d2, d3]`; each must be positive and finite.
    pub fn new(d: [f64; 3]) -> Result<Self, CoreError> {
        let d = super::penalty_stiffness("linear_penalty", None, d.map(Some))?;
        Ok(LinearPenalty { d })
    }

    /// From a TOML table: `d` for all three directions, or `d1`, `d2`, `d3`
    /// (each overrides `d`).
    pub fn from_table(t: &toml::Table) -> Result<Self, CoreError> {
        let p: Params = parse_params("law", "linear_penalty", t)?;
        Self::new(super::penalty_stiffness(
            "linear_penalty",
            p.d,
            [p.d1, p.d2, p.d3],
        )?)
    }
}

impl InterfaceLaw for LinearPenalty {
    fn key(&self) -> &'static str {
        "linear_penalty"
    }

    fn evaluate(&self, ctx: &LawContext<'_>, _state: &mut [f64]) -> Result<LawResponse, LawError> {
        let mut r = LawResponse::default();
        for i in 0..3 {
            r.traction[i] = self.d[i] * ctx.jump[i];
            r.tangent[i][i] = self.d[i];
        }
        Ok(r)
    }

    fn initial_stiffness(&self) -> [f64; 3] {
        self.d
    }

    /// The paper's `D` bonds the faces (sections 3 and 5): a constraint
    /// penalty, judged by the paper's error analysis.
    fn penalty_role(&self) -> junta_core::PenaltyRole {
        junta_core::PenaltyRole::Constraint
    }
}

inventory::submit! {
    LawEntry {
        key: "linear_penalty",
        description: "linear penalty D = diag(d1, d2, d3) (paper eqs. 33-35)",
        params: &[
            ParamDoc { name: "d", doc: "penalty stiffness for all three directions [force/length^3]" },
            ParamDoc { name: "d1", doc: "slip stiffness along e1 (overrides d)" },
            ParamDoc { name: "d2", doc: "slip stiffness along e2 (overrides d)" },
            ParamDoc { name: "d3", doc: "normal stiffness (overrides d)" },
        ],
        build: |t| Ok(Arc::new(LinearPenalty::from_table(t)?)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use junta_core::element::StepInfo;

    #[test]
    fn tangent_matches_finite_differences_and_bad_d_is_rejected() {
        let law = LinearPenalty::new([1e10, 2e10, 3e10]).unwrap();
        let jump = [1e-6, -2e-6, 3e-7];
        let eval = |j: [f64; 3]| {
            law.evaluate(
                &LawContext {
                    jump: j,
                    state_committed: &[],
                    step: StepInfo::default(),
                },
                &mut [],
            )
            .unwrap()
        };
        let r = eval(jump);
        let h = 1e-9;
        for k in 0..3 {
            let (mut a, mut b) = (jump, jump);
            a[k] += h;
            b[k] -= h;
            let (ta, tb) = (eval(a).traction, eval(b).traction);
            for i in 0..3 {
                let fd = (ta[i] - tb[i]) / (2.0 * h);
                assert!(
                    (fd - r.tangent[i][k]).abs() <= 1e-6 * 3e10,
                    "d t{i}/d delta{k}: {fd} vs {}",
                    r.tangent[i][k]
                );
            }
        }
        assert_eq!(r.traction, [1e4, -4e4, 9e3]);
        assert!(LinearPenalty::new([1.0, 0.0, 1.0]).is_err());
        let mut t = toml::Table::new();
        t.insert("d".into(), toml::Value::Float(-1.0));
        assert!(LinearPenalty::from_table(&t).is_err());
        t.insert("d".into(), toml::Value::Float(5.0));
        t.insert("d3".into(), toml::Value::Float(7.0));
        assert_eq!(LinearPenalty::from_table(&t).unwrap().d, [5.0, 5.0, 7.0]);
        t.insert("dn".into(), toml::Value::Float(7.0));
        let e = LinearPenalty::from_table(&t).unwrap_err().to_string();
        assert!(e.contains("dn"), "{e}");
    }
}
