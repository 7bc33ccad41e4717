//! `contact`: frictionless penalty contact of an open (cracked) surface,
//! e.g. the precrack of an ENF or MMB specimen, whose faces press on each
//! other and must not interpenetrate, but carry no tension and no shear.
//!
//! ```text
//! t = [0, 0, K min(delta_n, 0)],     dt/ddelta = diag(0, 0, K if delta_n <= 0 else 0)
//! ```
//!
//! The penalty `K` [force/length^3] plays the role of the normal penalty
//! of a cohesive law (use the same value). No state.
//!
//! **Closed at a zero jump.** The traction is continuous at `delta_n = 0`
//! but its derivative jumps from `K` to 0; both one-sided derivatives are
//! valid there and the law takes the closed one (`K`). The open one made
//! the first Newton iteration of every run (all jumps exactly zero) see a
//! precrack without any normal stiffness: on an ENF (span 150 mm, a0 =
//! 0.75 L, 1 mm wide, K = 3e7) that predictor pushed the arms 0.59 mm into
//! each other, the line search cut the step to 1/32 and the driver fell
//! back to the secant tangent for the whole attempt. Closed at zero, the
//! first predictor is the "bonded in the normal direction" solution,
//! whose largest open gap is 5e-10 mm on that specimen.
//!
//! This does not by itself make that specimen start: both arms of an ENF
//! bend alike over the precrack, so the whole precrack sits at a gap of
//! order 1e-4 of the deflection whose sign is set by shear, Poisson and
//! support-indentation terms, and the active set walks from "all closed"
//! to the few points near the support by 6-10 points per Newton iteration
//! (measured: 152 closed of 452 after the first iteration, 70 after 23),
//! more than the 25 iterations allowed on a 150 mm span (100 mm: 8 of 300
//! closed after 7 iterations). Since the problem is linear in the load
//! until the bonded zone damages, a smaller increment repeats the same
//! walk (see the issue 37 report).

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
        if ctx.jump[2] <= 0.0 {
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

    /// At a zero jump the law is closed: the first Newton predictor of a
    /// run (all jumps zero) sees the contact stiffness, not a free precrack.
    #[test]
    fn closed_at_zero_jump() {
        let c = Contact { k: 3e7 };
        let r = c
            .evaluate(
                &LawContext {
                    jump: [0.0; 3],
                    state_committed: &[],
                    step: StepInfo::default(),
                },
                &mut [],
            )
            .unwrap();
        assert_eq!(r.traction, [0.0; 3]);
        assert_eq!(r.tangent[2][2], 3e7);
    }

    /// The tangent against central differences, open and closed; at zero the
    /// one-sided difference towards closing.
    #[test]
    fn tangent_matches_finite_differences() {
        let c = Contact { k: 3e7 };
        let t = |dn: f64| {
            c.evaluate(
                &LawContext {
                    jump: [1e-3, -2e-3, dn],
                    state_committed: &[],
                    step: StepInfo::default(),
                },
                &mut [],
            )
            .unwrap()
        };
        let h = 1e-9;
        for dn in [-1e-5, 1e-5] {
            let fd = (t(dn + h).traction[2] - t(dn - h).traction[2]) / (2.0 * h);
            assert!((fd - t(dn).tangent[2][2]).abs() <= 1e-6 * 3e7, "dn = {dn}");
        }
        let fd_closing = (t(0.0).traction[2] - t(-h).traction[2]) / h;
        assert!((fd_closing - t(0.0).tangent[2][2]).abs() <= 1e-6 * 3e7);
    }
}
