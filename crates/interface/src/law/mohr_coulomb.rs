//! `mohr_coulomb`: elasto-plastic bonded interface with a Mohr-Coulomb
//! yield surface, non-associated flow (dilatancy angle `psi`), an optional
//! tension cut-off, and linear softening or hardening of the cohesion with
//! the accumulated plastic slip.
//!
//! # Law
//!
//! Jump `delta = [delta_s, delta_n]`, plastic jump `delta_p = [s_p, n_p]`
//! (state), elastic tractions `tau = K_s (delta_s - s_p)`,
//! `sigma = K_n (delta_n - n_p)` (compression negative). With
//! `q = |tau|`, `tan phi = t_phi`, `tan psi = t_psi` and the cohesion
//! `c(kappa) = max(c_0 + H kappa, c_r)` (`kappa` the accumulated slip,
//! `H < 0` softening, `H > 0` hardening, `c_r` the residual cohesion):
//!
//! ```text
//! F_1 = q + sigma t_phi - c(kappa) <= 0                 shear face
//! F_2 = sigma - r c(kappa)        <= 0                  tension cut-off, r = sigma_t / c_0
//! G_1 = q + sigma t_psi                                 plastic potential (psi <= phi)
//! d s_p = dlam_1 n,  d n_p = dlam_1 t_psi + dlam_2,  d kappa = dlam_1,  n = tau / q
//! ```
//!
//! (the cut-off strength `sigma_t` scales with the cohesion, so it stays
//! below the apex `c / t_phi`; without a cut-off the tensile strength is the
//! apex).
//!
//! # Return mapping (backward Euler, closed form)
//!
//! Trial `tau_tr = K_s (delta_s - s_p,n)`, `sigma_tr = K_n (delta_n - n_p,n)`,
//! `q_tr = |tau_tr|`, `c_n = c(kappa_n)`; the return keeps the direction
//! `n = tau_tr / q_tr` (the yield function depends on `|tau|` only).
//!
//! - **elastic** (`F_1,tr <= 0`, `F_2,tr <= 0`): the trial state.
//! - **face**: `dlam = F_1,tr / (K_s + K_n t_phi t_psi + H)`,
//!   `q = q_tr - K_s dlam`, `sigma = sigma_tr - K_n t_psi dlam`; valid when
//!   `q >= 0` and `F_2 <= 0`. (If `c` reaches `c_r`, the same with `H = 0`
//!   and `c_n = c_r`.)
//! - **cut-off** (`F_1(q_tr, r c_n) <= 0`): `sigma = r c_n`, `tau = tau_tr`,
//!   `n_p += (sigma_tr - sigma) / K_n`.
//! - **corner** (face and cut-off): `dlam_1 = (q_tr - c_n (1 - r t_phi)) /
//!   (K_s + H (1 - r t_phi))`, `c = c_n + H dlam_1`, `sigma = r c`,
//!   `q = c (1 - r t_phi)`, `dlam_2 = (sigma_tr - K_n t_psi dlam_1 - sigma) / K_n`.
//! - **apex** (no cut-off, `q < 0` from the face return, `phi > 0`):
//!   `tau = 0`, `s_p += tau_tr / K_s` (`dlam = q_tr / K_s`), `sigma = c(kappa_n
//!   + dlam) / t_phi`, `n_p += (sigma_tr - sigma) / K_n`.
//!
//! Plastic dissipation per unit area `D += tau . d s_p + sigma d n_p`
//! (end-of-step tractions); on the face it is `dlam (c + |sigma| (t_phi -
//! t_psi))` in compression, never negative because `psi <= phi`.
//!
//! # Consistent tangent
//!
//! Face return (`A = K_s + K_n t_phi t_psi + H`, `P = I - n n^T`):
//!
//! ```text
//! d tau / d delta_s   = K_s [ (q / q_tr) P + (1 - K_s / A) n n^T ]
//! d tau / d delta_n   = -(K_s K_n t_phi / A) n
//! d sigma / d delta_s = -(K_n t_psi K_s / A) n^T
//! d sigma / d delta_n = K_n (1 - K_n t_phi t_psi / A)
//! ```
//!
//! nonsymmetric unless `psi = phi` (`t_phi` and `t_psi` swap between the
//! off-diagonal blocks). Cut-off: `d sigma = 0`, `d tau / d delta_s = K_s I`.
//! Apex: `d tau = 0`, `d sigma / d delta_s = (H / (K_s t_phi)) K_s n^T`.
//! Corner: `d q / d delta_s = (1 - r t_phi) H / (K_s + H (1 - r t_phi))
//! K_s n^T`, `d sigma / d delta_s = r H / (K_s + H (1 - r t_phi)) K_s n^T`.
//! The code evaluates the return in forward-mode dual numbers
//! ([`Dual3`]), which gives exactly these derivatives of the branch taken;
//! the law declares a general tangent ([`MatrixKind::General`]).
//!
//! State: `[s_p1, s_p2, n_p, kappa, D, slip_state]` (`slip_state`: 0
//! elastic, 1 on the shear face, 2 on the cut-off, the corner or the apex).

use super::coulomb_friction::{check_state, positive};
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
    /// Plastic opening.
    pub const OPENING: usize = 2;
    /// Accumulated slip `kappa`.
    pub const ACCUMULATED: usize = 3;
    /// Plastic dissipation per unit area.
    pub const DISSIPATION: usize = 4;
    /// 0 elastic, 1 face, 2 cut-off / corner / apex.
    pub const STATE: usize = 5;
    /// Number of state values.
    pub const STATE_LEN: usize = 6;
}

/// Mohr-Coulomb interface plasticity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MohrCoulomb {
    /// Normal penalty `K_n`.
    pub k_n: f64,
    /// Shear penalty `K_s`.
    pub k_s: f64,
    /// Initial cohesion `c_0`.
    pub c: f64,
    /// Friction angle (radians).
    pub phi: f64,
    /// Dilatancy angle (radians), `0 <= psi <= phi`.
    pub psi: f64,
    /// Tension cut-off strength `sigma_t` at `c_0` (`None`: the apex).
    pub tension: Option<f64>,
    /// Softening (< 0) or hardening (> 0) modulus `H = dc / dkappa`.
    pub hardening: f64,
    /// Residual cohesion `c_r`.
    pub residual_cohesion: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Params {
    #[serde(rename = "K")]
    k: Option<f64>,
    #[serde(rename = "K_s")]
    k_s: Option<f64>,
    c: Option<f64>,
    phi: Option<f64>,
    psi: Option<f64>,
    tension: Option<f64>,
    hardening: Option<f64>,
    residual_cohesion: Option<f64>,
}

/// Parameters of `mohr_coulomb`.
pub const PARAMS: &[ParamDoc] = &[
    ParamDoc { name: "K", doc: "normal penalty > 0 [force/length^3]" },
    ParamDoc { name: "K_s", doc: "shear penalty > 0 [force/length^3] (default K)" },
    ParamDoc { name: "c", doc: "cohesion >= 0 [stress]" },
    ParamDoc { name: "phi", doc: "friction angle in degrees, 0 <= phi < 90" },
    ParamDoc { name: "psi", doc: "dilatancy angle in degrees, 0 <= psi <= phi (default 0; psi = phi: associated flow)" },
    ParamDoc { name: "tension", doc: "tension cut-off strength 0 <= sigma_t <= c / tan(phi) [stress] at the initial cohesion; scales with the cohesion (default: none, the apex c / tan(phi) limits the tension)" },
    ParamDoc { name: "hardening", doc: "H = dc / d(accumulated slip) [stress/length]: < 0 softening, > 0 hardening (default 0)" },
    ParamDoc { name: "residual_cohesion", doc: "cohesion floor 0 <= c_r <= c under softening [stress] (default 0)" },
];

impl MohrCoulomb {
    /// From a TOML table (see [`PARAMS`]); every inconsistency is an error
    /// naming the key and what would be valid.
    pub fn from_table(t: &toml::Table) -> Result<Self, CoreError> {
        const KEY: &str = "mohr_coulomb";
        let invalid = |message: String| CoreError::InvalidParameters {
            kind: "law",
            key: KEY.into(),
            message,
        };
        let p: Params = parse_params("law", KEY, t)?;
        let k_n = positive(KEY, "K", p.k, "normal penalty, force/length^3")?;
        let k_s = positive(
            KEY,
            "K_s",
            p.k_s.or(Some(k_n)),
            "shear penalty, force/length^3",
        )?;
        let c =
            p.c.ok_or_else(|| invalid("missing `c` (cohesion >= 0, stress)".into()))?;
        if !(c >= 0.0 && c.is_finite()) {
            return Err(invalid(format!(
                "`c` = {c}: the cohesion must be >= 0 and finite"
            )));
        }
        let phi_deg = p.phi.ok_or_else(|| {
            invalid("missing `phi` (friction angle in degrees, 0 <= phi < 90)".into())
        })?;
        if !(0.0..90.0).contains(&phi_deg) {
            return Err(invalid(format!(
                "`phi` = {phi_deg}: the friction angle must be in [0, 90) degrees"
            )));
        }
        let psi_deg = p.psi.unwrap_or(0.0);
        if !(psi_deg >= 0.0 && psi_deg <= phi_deg) {
            return Err(invalid(format!(
                "`psi` = {psi_deg}: the dilatancy angle must be in [0, phi = {phi_deg}] degrees (psi > phi would create energy)"
            )));
        }
        let (phi, psi) = (phi_deg.to_radians(), psi_deg.to_radians());
        let hardening = p.hardening.unwrap_or(0.0);
        if !hardening.is_finite() {
            return Err(invalid(format!("`hardening` = {hardening} must be finite")));
        }
        let residual_cohesion = p.residual_cohesion.unwrap_or(0.0);
        if !(residual_cohesion >= 0.0 && residual_cohesion <= c) {
            return Err(invalid(format!(
                "`residual_cohesion` = {residual_cohesion} must be in [0, c = {c}]"
            )));
        }
        let (tp, tq) = (phi.tan(), psi.tan());
        let tension = match p.tension {
            None => None,
            Some(st) => {
                let apex = if tp > 0.0 { c / tp } else { f64::INFINITY };
                if !(st >= 0.0 && st <= apex * (1.0 + 1e-12)) || c == 0.0 {
                    return Err(invalid(format!(
                        "`tension` = {st} must be in [0, c / tan(phi) = {apex}] and needs c > 0"
                    )));
                }
                Some(st)
            }
        };
        if k_s + k_n * tp * tq + hardening <= 0.0 {
            return Err(invalid(format!(
                "`hardening` = {hardening} is steeper than the elastic stiffness (K_s + K tan(phi) tan(psi) + H = {} <= 0): the point would snap back; use a smaller softening modulus",
                k_s + k_n * tp * tq + hardening
            )));
        }
        let law = MohrCoulomb {
            k_n,
            k_s,
            c,
            phi,
            psi,
            tension,
            hardening,
            residual_cohesion,
        };
        if k_s + hardening * (1.0 - law.ratio() * tp) <= 0.0 {
            return Err(invalid(format!(
                "`hardening` = {hardening} is steeper than the shear stiffness at the cut-off corner: use a smaller softening modulus"
            )));
        }
        Ok(law)
    }

    /// `r = sigma_t / c_0` (0 without a cut-off).
    fn ratio(&self) -> f64 {
        match self.tension {
            Some(st) if self.c > 0.0 => st / self.c,
            _ => 0.0,
        }
    }

    /// Cohesion at accumulated slip `kappa` and its slope there.
    pub fn cohesion(&self, kappa: f64) -> (f64, f64) {
        let c = self.c + self.hardening * kappa;
        if self.hardening < 0.0 && c <= self.residual_cohesion {
            (self.residual_cohesion, 0.0)
        } else {
            (c, self.hardening)
        }
    }
}

impl InterfaceLaw for MohrCoulomb {
    fn key(&self) -> &'static str {
        "mohr_coulomb"
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
        let (ks, kn) = (self.k_s, self.k_n);
        let (tp, tq) = (self.phi.tan(), self.psi.tan());
        let r = self.ratio();
        let has_cutoff = self.tension.is_some();
        let dj = Dual3::seeds(ctx.jump);
        let tr = [(dj[0] - c[SLIP_1]) * ks, (dj[1] - c[SLIP_2]) * ks];
        let s_tr = (dj[2] - c[OPENING]) * kn;
        let q_tr = (tr[0] * tr[0] + tr[1] * tr[1]).sqrt();
        let n = if q_tr.v > 0.0 {
            [tr[0] / q_tr, tr[1] / q_tr]
        } else {
            [Dual3::cst(1.0), Dual3::cst(0.0)]
        };
        let kappa_n = c[ACCUMULATED];
        let (c_n, h) = self.cohesion(kappa_n);
        let f1 = q_tr + s_tr * tp - c_n;
        let f2 = s_tr - r * c_n;
        // (tau, sigma, dlam_1 (slip), state)
        let mut result: Option<([Dual3; 2], Dual3, Dual3, f64)> = None;
        if f1.v <= 0.0 && (!has_cutoff || f2.v <= 0.0) {
            result = Some((tr, s_tr, Dual3::cst(0.0), output::STICK));
        }
        if result.is_none() && f1.v > 0.0 {
            // face return, then the floor of the cohesion if it is passed
            let mut dl = f1 / (ks + kn * tp * tq + h);
            if h < 0.0 && c_n + h * dl.v < self.residual_cohesion {
                let cr = self.residual_cohesion;
                dl = (q_tr + s_tr * tp - cr) / (ks + kn * tp * tq);
            }
            let q = q_tr - dl * ks;
            let sigma = s_tr - dl * (kn * tq);
            let (c_new, _) = self.cohesion(kappa_n + dl.v);
            if q.v >= 0.0 && (!has_cutoff || sigma.v <= r * c_new * (1.0 + 1e-14)) {
                result = Some(([n[0] * q, n[1] * q], sigma, dl, output::SLIP));
            }
        }
        if result.is_none() && has_cutoff {
            let st = r * c_n;
            if f2.v > 0.0 && q_tr.v + st * tp - c_n <= 0.0 {
                // cut-off only: the shear stays elastic
                result = Some((tr, Dual3::cst(st), Dual3::cst(0.0), output::OPEN));
            } else {
                // corner: on the face and the cut-off
                let a = 1.0 - r * tp;
                let mut dl = (q_tr - c_n * a) / (ks + h * a);
                let mut cc = dl * h + c_n;
                if h < 0.0 && cc.v < self.residual_cohesion {
                    let cr = self.residual_cohesion;
                    dl = (q_tr - cr * a) / ks;
                    cc = Dual3::cst(cr);
                }
                let q = cc * a;
                result = Some(([n[0] * q, n[1] * q], cc * r, dl, output::OPEN));
            }
        }
        let (tau, sigma, dl, state) = match result {
            Some(x) => x,
            None => {
                // apex (phi > 0: else the face return is always valid)
                let dl = q_tr / ks;
                let mut cc = dl * h + c_n;
                if h < 0.0 && cc.v < self.residual_cohesion {
                    cc = Dual3::cst(self.residual_cohesion);
                }
                ([Dual3::cst(0.0); 2], cc / tp, dl, output::OPEN)
            }
        };
        // plastic jump = jump - elastic jump
        let sp = [
            ctx.jump[0] - tau[0].v / ks,
            ctx.jump[1] - tau[1].v / ks,
            ctx.jump[2] - sigma.v / kn,
        ];
        let d_work = tau[0].v * (sp[0] - c[SLIP_1])
            + tau[1].v * (sp[1] - c[SLIP_2])
            + sigma.v * (sp[2] - c[OPENING]);
        trial[SLIP_1] = sp[0];
        trial[SLIP_2] = sp[1];
        trial[OPENING] = sp[2];
        trial[ACCUMULATED] = kappa_n + dl.v;
        trial[DISSIPATION] = c[DISSIPATION] + d_work;
        trial[STATE] = state;
        let t = [tau[0], tau[1], sigma];
        let mut tangent = t.map(|x| x.d);
        if ctx.step.secant {
            // symmetric part (a positive semi-definite secant-like tangent)
            let t0 = tangent;
            for (i, row) in tangent.iter_mut().enumerate() {
                for (j, v) in row.iter_mut().enumerate() {
                    *v = 0.5 * (t0[i][j] + t0[j][i]);
                }
            }
        }
        Ok(LawResponse {
            traction: t.map(|x| x.v),
            tangent,
        })
    }

    fn initial_stiffness(&self) -> [f64; 3] {
        [self.k_s, self.k_s, self.k_n]
    }

    /// The elastic jump before yield is a penalty on a bonded interface
    /// (no fracture energy; the yield surface, not `K`, sets the response):
    /// a constraint penalty.
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
            output::PLASTIC_OPENING,
            output::ACCUMULATED_SLIP,
            output::SLIP_STATE,
            output::FRICTIONAL_DISSIPATION,
        ]
    }

    fn outputs(&self, state: &[f64], out: &mut [f64]) {
        use slot::*;
        if state.len() == STATE_LEN && out.len() == 6 {
            out[0] = state[SLIP_1];
            out[1] = state[SLIP_2];
            out[2] = state[OPENING];
            out[3] = state[ACCUMULATED];
            out[4] = state[STATE];
            out[5] = state[DISSIPATION];
        }
    }

    fn warnings(&self) -> Vec<String> {
        let mut w = Vec::new();
        if self.hardening < 0.0 {
            w.push(format!(
                "mohr_coulomb: softening cohesion (H = {}): the tangent can be indefinite as well as nonsymmetric",
                self.hardening
            ));
        }
        w
    }
}

inventory::submit! {
    LawEntry {
        key: "mohr_coulomb",
        description: "elasto-plastic interface: Mohr-Coulomb F = |tau| + sigma tan(phi) - c, non-associated flow (dilatancy psi), tension cut-off, linear softening/hardening of c; closed-form return to the face, cut-off, corner or apex; nonsymmetric tangent (solver lu)",
        params: PARAMS,
        build: |t| Ok(Arc::new(MohrCoulomb::from_table(t)?)),
    }
}
