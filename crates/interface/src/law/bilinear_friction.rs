//! `bilinear_friction`: the `bilinear` mixed-mode cohesive law with
//! Coulomb friction on the damaged fraction of the surface (Alfano &
//! Sacco 2006, Int. J. Numer. Meth. Engng 68:542-582), so that a
//! delaminated interface under pressure keeps a friction resistance.
//!
//! # Law
//!
//! A point is split into an undamaged fraction `1 - d`, which carries the
//! cohesive law, and a damaged fraction `d`, which carries contact and
//! Coulomb friction:
//!
//! ```text
//! t = t_coh(delta; d) + d [tau_f(delta_s, sigma_c; s_p), 0]
//! ```
//!
//! - `t_coh` is [`super::bilinear`] exactly (the same code:
//!   [`CohesiveLaw::evaluate_dual`]): `(1 - d) K_s delta_s` in shear,
//!   `(1 - d) K_n delta_n` in opening and `K_n delta_n` in compression,
//!   which is already `(1 - d) K_n delta_n + d sigma_c` with the contact
//!   pressure of the damaged part `sigma_c = K_n min(delta_n, 0)`.
//! - `tau_f` is the Coulomb friction of [`super::coulomb_friction`] with
//!   the stick stiffness `K_s` of the cohesive law, the contact pressure
//!   `sigma_c` and its own plastic slip `s_p` (closed-form return to the
//!   cone `|tau_f| <= -mu sigma_c`; open when `delta_n >= 0`).
//!
//! With `d = 0` the law is `bilinear`; with `d = 1` it is
//! `coulomb_friction` (pure contact and friction), and the residual shear
//! resistance of a fully debonded surface under a pressure `p` is `mu p`.
//!
//! # Consistent tangent
//!
//! ```text
//! dt/d delta = d t_coh / d delta + d (d tau_f / d delta) + tau_f (d d / d delta)^T
//! ```
//!
//! with the cohesive tangent (damage loading or not), the friction tangent
//! of [`super::coulomb_friction`] (nonsymmetric when slipping) and the
//! damage gradient (non-zero while damage grows). All three come from one
//! evaluation in dual numbers ([`Dual3`]). Tangent kind: general.
//!
//! Frictional dissipation per unit area: `D += d tau_f . (s_p - s_p,n)`
//! (never negative), reported apart from the fracture energy of the
//! cohesive part.
//!
//! State: the 6 values of the cohesive law, then `[s_p1, s_p2, kappa, D,
//! slip_state]`.

use super::bilinear::bilinear_from_table;
use super::cohesive::{self, CohesiveLaw};
use super::coulomb_friction::{check_state, coulomb_return, friction_coefficient};
use junta_core::law::{
    output, FractureProperties, InterfaceLaw, LawContext, LawError, LawResponse,
};
use junta_core::registry::{LawEntry, ParamDoc};
use junta_core::{CoreError, Dual3, MatrixKind};
use std::sync::Arc;

/// State layout of one point (after the cohesive law's values).
pub mod slot {
    use super::cohesive;
    /// Plastic slip of the friction, first direction.
    pub const SLIP_1: usize = cohesive::slot::STATE_LEN;
    /// Plastic slip, second direction.
    pub const SLIP_2: usize = SLIP_1 + 1;
    /// Accumulated slip.
    pub const ACCUMULATED: usize = SLIP_1 + 2;
    /// Frictional dissipation per unit area.
    pub const DISSIPATION: usize = SLIP_1 + 3;
    /// 0 stick, 1 slip, 2 open.
    pub const STATE: usize = SLIP_1 + 4;
    /// Number of state values.
    pub const STATE_LEN: usize = SLIP_1 + 5;
}

/// Bilinear cohesive law with friction on the damaged fraction.
#[derive(Debug, Clone)]
pub struct BilinearFriction {
    /// The cohesive part (`bilinear`).
    pub cohesive: CohesiveLaw,
    /// Friction coefficient of the damaged part.
    pub mu: f64,
}

/// Parameters of `bilinear_friction`: `mu` and those of `bilinear`.
pub const PARAMS: &[ParamDoc] = &[
    ParamDoc { name: "mu", doc: "friction coefficient >= 0 of the damaged fraction" },
    ParamDoc { name: "K", doc: "normal penalty stiffness K_n > 0 [force/length^3]; the shear penalty is also the stick stiffness of the friction" },
    ParamDoc { name: "N", doc: "normal (mode I) strength > 0 [stress]" },
    ParamDoc { name: "S", doc: "shear (mode II) strength > 0 [stress]" },
    ParamDoc { name: "G_Ic", doc: "mode I toughness > 0 [energy/area]" },
    ParamDoc { name: "G_IIc", doc: "mode II toughness > 0 [energy/area]" },
    ParamDoc { name: "(others)", doc: "propagation, eta, alpha, onset, shear_penalty, viscosity: as for `bilinear`" },
];

impl BilinearFriction {
    /// From a TOML table: `mu` and the parameters of `bilinear`.
    pub fn from_table(t: &toml::Table) -> Result<Self, CoreError> {
        const KEY: &str = "bilinear_friction";
        let mu = match t.get("mu") {
            None => None,
            Some(toml::Value::Float(v)) => Some(*v),
            Some(toml::Value::Integer(i)) => Some(*i as f64),
            Some(other) => {
                return Err(CoreError::InvalidParameters {
                    kind: "law",
                    key: KEY.into(),
                    message: format!("`mu` = {other}: the friction coefficient is a number >= 0"),
                })
            }
        };
        let mu = friction_coefficient(KEY, mu)?;
        let mut rest = t.clone();
        rest.remove("mu");
        let cohesive = bilinear_from_table(&rest).map_err(|e| match e {
            CoreError::InvalidParameters { kind, message, .. } => CoreError::InvalidParameters {
                kind,
                key: KEY.into(),
                message,
            },
            other => other,
        })?;
        Ok(BilinearFriction { cohesive, mu })
    }
}

impl InterfaceLaw for BilinearFriction {
    fn key(&self) -> &'static str {
        "bilinear_friction"
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
        let nc = cohesive::slot::STATE_LEN;
        trial.copy_from_slice(c);
        let coh_ctx = LawContext {
            jump: ctx.jump,
            state_committed: &c[..nc],
            step: ctx.step,
        };
        let (tc, d) = self.cohesive.evaluate_dual(&coh_ctx, &mut trial[..nc])?;
        let (ks, kn) = (self.cohesive.k_s, self.cohesive.k_n);
        let dj = Dual3::seeds(ctx.jump);
        let sigma_c = dj[2].min(Dual3::cst(0.0)) * kn;
        let r = coulomb_return([dj[0], dj[1]], sigma_c, [c[SLIP_1], c[SLIP_2]], ks, self.mu);
        trial[SLIP_1] = r.slip[0];
        trial[SLIP_2] = r.slip[1];
        trial[ACCUMULATED] = c[ACCUMULATED] + r.dgamma;
        trial[DISSIPATION] = c[DISSIPATION] + d.v * r.dissipation;
        trial[STATE] = r.state;
        let t = [tc[0] + d * r.tau[0], tc[1] + d * r.tau[1], tc[2]];
        let mut tangent = t.map(|x| x.d);
        if ctx.step.secant {
            // cohesive secant plus the friction of the damaged part without
            // its couplings (damage gradient, pressure): positive semi-definite
            let s = 1.0 - d.v;
            tangent = [[s * ks, 0.0, 0.0], [0.0, s * ks, 0.0], [0.0, 0.0, 0.0]];
            tangent[2][2] = if ctx.jump[2] > 0.0 { s * kn } else { kn };
            for (row, tau) in tangent.iter_mut().zip(&r.tau) {
                for (k, dk) in row.iter_mut().zip(&tau.d).take(2) {
                    *k += d.v * dk;
                }
            }
        }
        Ok(LawResponse {
            traction: t.map(|x| x.v),
            tangent,
        })
    }

    fn initial_stiffness(&self) -> [f64; 3] {
        self.cohesive.initial_stiffness()
    }

    /// The `bilinear` cohesive law's `K` (see [`CohesiveLaw`]).
    fn penalty_role(&self) -> junta_core::PenaltyRole {
        junta_core::PenaltyRole::Cohesive
    }

    fn wants_small_increments(&self, state: &[f64]) -> bool {
        self.cohesive
            .wants_small_increments(&state[..cohesive::slot::STATE_LEN.min(state.len())])
    }

    /// The cohesive part's stage: failed once it is traction-free and
    /// has dissipated `G_c(B)` (friction goes on; it is not fracture).
    fn stage(&self, state: &[f64]) -> junta_core::PointStage {
        self.cohesive.stage_of(state)
    }

    fn failure_index(&self, state: &[f64]) -> Option<f64> {
        self.cohesive.failure_index(state)
    }

    fn tangent_kind(&self) -> MatrixKind {
        MatrixKind::General
    }

    fn output_names(&self) -> &'static [&'static str] {
        &[
            output::DAMAGE,
            output::DISSIPATED_ENERGY,
            output::VISCOUS_ENERGY,
            output::MODE_RATIO,
            output::PLASTIC_SLIP_1,
            output::PLASTIC_SLIP_2,
            output::ACCUMULATED_SLIP,
            output::SLIP_STATE,
            output::FRICTIONAL_DISSIPATION,
        ]
    }

    fn outputs(&self, state: &[f64], out: &mut [f64]) {
        use slot::*;
        if state.len() == STATE_LEN && out.len() == 9 {
            self.cohesive
                .outputs(&state[..cohesive::slot::STATE_LEN], &mut out[..4]);
            out[4] = state[SLIP_1];
            out[5] = state[SLIP_2];
            out[6] = state[ACCUMULATED];
            out[7] = state[STATE];
            out[8] = state[DISSIPATION];
        }
    }

    fn fracture_properties(&self) -> Option<FractureProperties> {
        self.cohesive.fracture_properties()
    }

    fn warnings(&self) -> Vec<String> {
        self.cohesive.warnings()
    }
}

inventory::submit! {
    LawEntry {
        key: "bilinear_friction",
        description: "bilinear mixed-mode cohesive law with Coulomb friction on the damaged fraction (Alfano-Sacco 2006): a debonded surface under pressure keeps the friction mu p; nonsymmetric tangent (solver lu)",
        params: PARAMS,
        build: |t| Ok(Arc::new(BilinearFriction::from_table(t)?)),
    }
}
