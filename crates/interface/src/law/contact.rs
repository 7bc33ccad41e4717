//! `contact`: frictionless penalty contact of an open (cracked) surface,
//! e.g. the precrack of an ENF or MMB specimen, whose faces press on each
//! other and must not interpenetrate, but carry no tension and no shear.
//!
//! ```text
//! t = [0, 0, K min(delta_n, 0)],     dt/ddelta = diag(0, 0, K if delta_n < 0 else 0)
//! ```
//!
//! The penalty `K` [force/length^3] plays the role of the normal penalty
//! of a cohesive law (use the same value). No state.

use junta_core::law::{InterfaceLaw, LawContext, LawError, LawResponse};
use junta_core::registry::{parse_params, LawEntry, ParamDoc};
use junta_core::CoreError;
use serde::Deserialize;
use std::sync::Arc;

/// Frictionless penalty contact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Contact {
    /// Normal penalty.
    pub k: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Params {
    #[serde(rename = "K")]
    k: Option<f64>,
}

impl Contact {
    /// From a TOML table: `K` (positive, finite).
    pub fn from_table(t: &toml::Table) -> Result<Self, CoreError> {
        let p: Params = parse_params("law", "contact", t)?;
        match p.k {
            Some(k) if k > 0.0 && k.is_finite() => Ok(Contact { k }),
            Some(k) => Err(CoreError::InvalidParameters {
                kind: "law",
                key: "contact".into(),
                message: format!(
                    "`K` = {k} must be positive and finite (normal penalty, force/length^3)"
                ),
            }),
            None => Err(CoreError::InvalidParameters {
                kind: "law",
                key: "contact".into(),
                message: "missing `K` (normal penalty, force/length^3)".into(),
            }),
        }
    }
}

impl InterfaceLaw for Contact {
    fn key(&self) -> &'static str {
        "contact"
    }

    fn evaluate(&self, ctx: &LawContext<'_>, _trial: &mut [f64]) -> Result<LawResponse, LawError> {
        let mut r = LawResponse::default();
        if ctx.jump[2] < 0.0 {
            r.traction[2] = self.k * ctx.jump[2];
            r.tangent[2][2] = self.k;
        }
        Ok(r)
    }

    fn initial_stiffness(&self) -> [f64; 3] {
        [0.0, 0.0, self.k]
    }

    /// Non-interpenetration of the closed faces: a constraint penalty.
    fn penalty_role(&self) -> junta_core::PenaltyRole {
        junta_core::PenaltyRole::Constraint
    }
}

inventory::submit! {
    LawEntry {
        key: "contact",
        description: "frictionless penalty contact of a cracked surface: t_n = K min(delta_n, 0), no shear, no tension",
        params: &[ParamDoc { name: "K", doc: "normal penalty > 0 [force/length^3]" }],
        build: |t| Ok(Arc::new(Contact::from_table(t)?)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use junta_core::element::StepInfo;

    #[test]
    fn presses_but_never_pulls_or_shears() {
        let c = Contact { k: 1e6 };
        let eval = |j: [f64; 3]| {
            c.evaluate(
                &LawContext {
                    jump: j,
                    state_committed: &[],
                    step: StepInfo::default(),
                },
                &mut [],
            )
            .unwrap()
        };
        let r = eval([1e-3, 2e-3, -1e-5]);
        assert_eq!(r.traction, [0.0, 0.0, -10.0]);
        assert_eq!(r.tangent[2][2], 1e6);
        let r = eval([1e-3, 2e-3, 1e-5]);
        assert_eq!(r, LawResponse::default());
    }
}
