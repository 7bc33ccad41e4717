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
//!
//! **Open at a zero jump.** The traction is continuous at `delta_n = 0`
//! but its derivative jumps from `K` to 0; the law takes the open branch
//! there (a jump exactly zero carries nothing either way). Taking the
//! closed one instead was tried (issue 37): it helps nothing on an ENF
//! and keeps the precrack of an MMB, which opens, from starting.
//!
//! **Grazing contact: the status walk.** Both arms of an ENF bend alike
//! over the precrack, so the whole precrack sits at a gap of order 1e-4 of
//! the deflection (beam theory: no pressure between the arms except where
//! the shear enters the upper arm, at its free end), whose sign is set by
//! shear, Poisson and support terms. Newton on this law is a semi-smooth
//! Newton on the contact status: each iteration solves with the status of
//! the last iterate, and on slender arms (a beam on the penalty foundation
//! of decay length `(4 E I / (K b))^(1/4)`, a fraction of a millimetre)
//! the status changes only a few points beyond the last change: from "all
//! open" (or all closed) to the few closed points at the support end the
//! status walks along the precrack by one element or so per iteration
//! (measured on 0.5 mm elements, 1 mm wide arms 1.55 mm thick, a0 =
//! 0.75 L, K = 3e7: 11 iterations on a 150 mm span, 74 on 200 mm, 169 on
//! 300 mm, against the 25 of `max_iterations`). Since the
//! problem is positively homogeneous in the load until the bonded zone
//! damages, a smaller increment repeats the same walk: the run could not
//! start. The law declares its switch ([`InterfaceLaw::contact_closed`])
//! so that the Newton driver counts such iterations as *contact
//! iterations*, which do not count against the iteration limit (the
//! severe discontinuity iterations of Abaqus/Standard): see the `newton`
//! module of the solvers. Once the walk is done, the status carries over
//! to the next increments, which converge in one or two iterations.

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

    fn has_contact_switch(&self) -> bool {
        true
    }

    /// Closed where [`InterfaceLaw::evaluate`] takes the closed branch.
    fn contact_closed(&self, jump: [f64; 3], _state: &[f64]) -> bool {
        jump[2] < 0.0
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

    /// At a zero jump the law is open, and says so to the driver.
    #[test]
    fn open_at_zero_jump() {
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
        assert_eq!(r, LawResponse::default());
        assert!(c.has_contact_switch());
        assert!(!c.contact_closed([0.0; 3], &[]));
        assert!(c.contact_closed([1.0, 0.0, -1e-12], &[]));
    }

    /// The tangent against central differences, open and closed; at zero the
    /// one-sided difference towards opening.
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
        let fd_opening = (t(h).traction[2] - t(0.0).traction[2]) / h;
        assert!((fd_opening - t(0.0).tangent[2][2]).abs() <= 1e-6 * 3e7);
    }
}
