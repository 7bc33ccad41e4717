//! `coulomb_friction`: penalty contact in the normal direction and Coulomb
//! friction in the tangential plane, for surfaces that start unbonded
//! (a crack, a block resting on a base).
//!
//! # Law
//!
//! Jump `delta = [delta_s, delta_n]` (`delta_s` the two slips), plastic slip
//! `s_p` (state), penalties `K_n` (normal) and `K_s` (stick stiffness),
//! friction coefficient `mu`:
//!
//! ```text
//! sigma = K_n min(delta_n - g_0, 0)                   (no tension)
//! tau   = K_s (delta_s - s_p)                         stick:  |tau| + mu sigma <= 0
//! ```
//!
//! `g_0 >= 0` is an optional interference (Abaqus' interference fit): the
//! faces overlap by `g_0` at zero jump, so a constrained joint keeps the
//! contact pressure `K_n g_0` whatever the load factor (a preload, e.g. a
//! clamp or a shrink fit, under a proportional load program).
//!
//! # Return mapping (backward Euler, closed form)
//!
//! Trial `tau_tr = K_s (delta_s - s_p,n)`, `f_tr = |tau_tr| + mu sigma`.
//!
//! - **open** (`sigma >= 0`): `tau = 0`, `s_p = delta_s` (the faces slide
//!   freely; they stick again where they close), no dissipation.
//! - **stick** (`f_tr <= 0`): `tau = tau_tr`.
//! - **slip** (`f_tr > 0`): with `n = tau_tr / |tau_tr|`,
//!   `dgamma = f_tr / K_s`, `s_p = s_p,n + dgamma n`,
//!   `tau = -mu sigma n` (on the cone `|tau| = -mu sigma`, same direction
//!   as the trial: the radial return is exact for this cone).
//!
//! Accumulated slip `kappa += dgamma`; frictional dissipation per unit area
//! `D += tau . (s_p - s_p,n) = -mu sigma dgamma >= 0`.
//!
//! # Consistent tangent
//!
//! ```text
//! stick:  d tau/d delta_s = K_s I,   d tau/d delta_n = 0,   d sigma/d delta_n = K_n (closed)
//! slip:   d tau/d delta_s = (-mu sigma / |tau_tr|) K_s (I - n n^T)
//!         d tau/d delta_n = -mu K_n n                (nonsymmetric: d sigma / d delta_s = 0)
//! open:   0
//! ```
//!
//! The slip tangent is nonsymmetric, so the law declares a general tangent
//! ([`MatrixKind::General`]) and the driver picks the `lu` back end. The
//! code evaluates the return in forward-mode dual numbers ([`Dual3`]), which
//! gives exactly these derivatives.
//!
//! State: `[s_p1, s_p2, kappa, D, slip_state]` (`slip_state`: 0 stick,
//! 1 slip, 2 open).

use junta_core::law::{output, InterfaceLaw, LawContext, LawError, LawResponse};
use junta_core::registry::{parse_params, LawEntry, ParamDoc};
use junta_core::{CoreError, Dual3, MatrixKind};
use serde::Deserialize;
use std::sync::Arc;

/// State layout of one point.
pub mod slot {
    /// Plastic slip, first direction.
    pub const SLIP_1: usize = 0;
    /// Plastic slip, second direction.
    pub const SLIP_2: usize = 1;
    /// Accumulated slip.
    pub const ACCUMULATED: usize = 2;
    /// Frictional dissipation per unit area.
    pub const DISSIPATION: usize = 3;
    /// 0 stick, 1 slip, 2 open.
    pub const STATE: usize = 4;
    /// Number of state values.
    pub const STATE_LEN: usize = 5;
}

/// Result of the Coulomb return mapping of one point.
#[derive(Debug, Clone, Copy)]
pub struct CoulombReturn {
    /// Shear traction (with its derivatives in the jump).
    pub tau: [Dual3; 2],
    /// New plastic slip.
    pub slip: [f64; 2],
    /// Slip increment magnitude `dgamma` (0 when sticking or open).
    pub dgamma: f64,
    /// Dissipation increment per unit area `tau . (s_p - s_p,n)`.
    pub dissipation: f64,
    /// [`output::STICK`], [`output::SLIP`] or [`output::OPEN`].
    pub state: f64,
}

/// The closed-form Coulomb return of the module documentation: slips `ds`
/// and normal traction `sigma` (duals seeded on the jump), committed
/// plastic slip `slip_n`, stick stiffness `ks`, friction coefficient `mu`.
pub fn coulomb_return(
    ds: [Dual3; 2],
    sigma: Dual3,
    slip_n: [f64; 2],
    ks: f64,
    mu: f64,
) -> CoulombReturn {
    if sigma.v >= 0.0 {
        return CoulombReturn {
            tau: [Dual3::cst(0.0); 2],
            slip: [ds[0].v, ds[1].v],
            dgamma: 0.0,
            dissipation: 0.0,
            state: output::OPEN,
        };
    }
    let tr = [(ds[0] - slip_n[0]) * ks, (ds[1] - slip_n[1]) * ks];
    let norm = (tr[0] * tr[0] + tr[1] * tr[1]).sqrt();
    let f = norm + sigma * mu;
    if f.v <= 0.0 || norm.v == 0.0 {
        return CoulombReturn {
            tau: tr,
            slip: slip_n,
            dgamma: 0.0,
            dissipation: 0.0,
            state: output::STICK,
        };
    }
    let n = [tr[0] / norm, tr[1] / norm];
    let bound = -(sigma * mu);
    let dgamma = f.v / ks;
    let tau = [n[0] * bound, n[1] * bound];
    CoulombReturn {
        tau,
        slip: [slip_n[0] + dgamma * n[0].v, slip_n[1] + dgamma * n[1].v],
        dgamma,
        dissipation: bound.v * dgamma,
        state: output::SLIP,
    }
}

/// Coulomb friction with penalty contact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CoulombFriction {
    /// Normal penalty `K_n`.
    pub k_n: f64,
    /// Stick (tangential) penalty `K_s`.
    pub k_s: f64,
    /// Friction coefficient `mu`.
    pub mu: f64,
    /// Interference `g_0 >= 0` (overlap of the faces at zero jump).
    pub interference: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Params {
    #[serde(rename = "K")]
    k: Option<f64>,
    #[serde(rename = "K_s")]
    k_s: Option<f64>,
    mu: Option<f64>,
    interference: Option<f64>,
}

/// Parameters of `coulomb_friction`.
pub const PARAMS: &[ParamDoc] = &[
    ParamDoc {
        name: "K",
        doc: "normal penalty > 0 [force/length^3]",
    },
    ParamDoc {
        name: "K_s",
        doc: "stick (tangential) penalty > 0 [force/length^3] (default K)",
    },
    ParamDoc {
        name: "mu",
        doc: "friction coefficient >= 0",
    },
    ParamDoc {
        name: "interference",
        doc: "overlap g_0 >= 0 of the faces at zero jump [length] (default 0): a contact preload K g_0 that does not scale with the load factor",
    },
];

/// A positive, finite parameter or an error naming the law and the key.
pub(crate) fn positive(
    key: &str,
    name: &str,
    v: Option<f64>,
    what: &str,
) -> Result<f64, CoreError> {
    let invalid = |message: String| CoreError::InvalidParameters {
        kind: "law",
        key: key.into(),
        message,
    };
    let v = v.ok_or_else(|| invalid(format!("missing `{name}` ({what})")))?;
    if v > 0.0 && v.is_finite() {
        Ok(v)
    } else {
        Err(invalid(format!(
            "`{name}` = {v} must be positive and finite ({what})"
        )))
    }
}

/// A friction coefficient: `>= 0` and finite.
pub(crate) fn friction_coefficient(key: &str, v: Option<f64>) -> Result<f64, CoreError> {
    let v = v.ok_or_else(|| CoreError::InvalidParameters {
        kind: "law",
        key: key.into(),
        message: "missing `mu` (friction coefficient >= 0)".into(),
    })?;
    if v >= 0.0 && v.is_finite() {
        Ok(v)
    } else {
        Err(CoreError::InvalidParameters {
            kind: "law",
            key: key.into(),
            message: format!("`mu` = {v}: the friction coefficient must be >= 0 and finite"),
        })
    }
}

impl CoulombFriction {
    /// From a TOML table (see [`PARAMS`]).
    pub fn from_table(t: &toml::Table) -> Result<Self, CoreError> {
        const KEY: &str = "coulomb_friction";
        let p: Params = parse_params("law", KEY, t)?;
        let k_n = positive(KEY, "K", p.k, "normal penalty, force/length^3")?;
        let k_s = positive(
            KEY,
            "K_s",
            p.k_s.or(Some(k_n)),
            "stick penalty, force/length^3",
        )?;
        let mu = friction_coefficient(KEY, p.mu)?;
        let interference = p.interference.unwrap_or(0.0);
        if !(interference >= 0.0 && interference.is_finite()) {
            return Err(CoreError::InvalidParameters {
                kind: "law",
                key: KEY.into(),
                message: format!(
                    "`interference` = {interference} must be >= 0 and finite (length)"
                ),
            });
        }
        Ok(CoulombFriction {
            k_n,
            k_s,
            mu,
            interference,
        })
    }
}

/// Check the state slices of a law with `len` state values.
pub(crate) fn check_state(
    key: &str,
    ctx: &LawContext<'_>,
    trial: &[f64],
    len: usize,
) -> Result<(), LawError> {
    if ctx.state_committed.len() != len || trial.len() != len {
        return Err(LawError::Failed(format!(
            "{key}: state slices of length {} (committed) and {} (trial), expected {len}",
            ctx.state_committed.len(),
            trial.len()
        )));
    }
    if !ctx.jump.iter().all(|v| v.is_finite()) {
        return Err(LawError::Failed(format!(
            "{key}: jump is not finite: {:?}",
            ctx.jump
        )));
    }
    Ok(())
}

impl InterfaceLaw for CoulombFriction {
    fn key(&self) -> &'static str {
        "coulomb_friction"
    }

    fn state_len(&self) -> usize {
        slot::STATE_LEN
    }

    fn init_state(&self, state: &mut [f64]) {
        state.iter_mut().for_each(|v| *v = 0.0);
    }

    fn evaluate(&self, ctx: &LawContext<'_>, trial: &mut [f64]) -> Result<LawResponse, LawError> {
        use slot::*;
        check_state(self.key(), ctx, trial, STATE_LEN)?;
        let c = ctx.state_committed;
        trial.copy_from_slice(c);
        let dj = Dual3::seeds(ctx.jump);
        let sigma = (dj[2] - self.interference).min(Dual3::cst(0.0)) * self.k_n;
        let r = coulomb_return(
            [dj[0], dj[1]],
            sigma,
            [c[SLIP_1], c[SLIP_2]],
            self.k_s,
            self.mu,
        );
        trial[SLIP_1] = r.slip[0];
        trial[SLIP_2] = r.slip[1];
        trial[ACCUMULATED] = c[ACCUMULATED] + r.dgamma;
        trial[DISSIPATION] = c[DISSIPATION] + r.dissipation;
        trial[STATE] = r.state;
        let t = [r.tau[0], r.tau[1], sigma];
        let mut tangent = t.map(|x| x.d);
        if ctx.step.secant {
            // positive semi-definite: drop the normal coupling of the slip
            tangent[0][2] = 0.0;
            tangent[1][2] = 0.0;
        }
        Ok(LawResponse {
            traction: t.map(|x| x.v),
            tangent,
        })
    }

    fn initial_stiffness(&self) -> [f64; 3] {
        [self.k_s, self.k_s, self.k_n]
    }

    /// The stick and contact stiffnesses enforce sticking and
    /// non-interpenetration: constraint penalties.
    fn penalty_role(&self) -> junta_core::PenaltyRole {
        junta_core::PenaltyRole::Constraint
    }

    fn tangent_kind(&self) -> MatrixKind {
        MatrixKind::General
    }

    fn output_names(&self) -> &'static [&'static str] {
        &[
            output::PLASTIC_SLIP_1,
            output::PLASTIC_SLIP_2,
            output::ACCUMULATED_SLIP,
            output::SLIP_STATE,
            output::FRICTIONAL_DISSIPATION,
        ]
    }

    fn outputs(&self, state: &[f64], out: &mut [f64]) {
        use slot::*;
        if state.len() == STATE_LEN && out.len() == 5 {
            out[0] = state[SLIP_1];
            out[1] = state[SLIP_2];
            out[2] = state[ACCUMULATED];
            out[3] = state[STATE];
            out[4] = state[DISSIPATION];
        }
    }
}

inventory::submit! {
    LawEntry {
        key: "coulomb_friction",
        description: "penalty contact with Coulomb friction (stick penalty, closed-form return to the slip cone; nonsymmetric tangent: solver lu) for unbonded surfaces",
        params: PARAMS,
        build: |t| Ok(Arc::new(CoulombFriction::from_table(t)?)),
    }
}
