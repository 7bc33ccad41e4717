//! `fatigue_cf20`: the mixed-mode bilinear law of [`super::bilinear`] with
//! the local cohesive fatigue damage of the CF20 model (C.G. Davila,
//! "From S-N to the Paris law with a new mixed-mode cohesive fatigue model
//! for delamination in composites", Theor. Appl. Fract. Mech. 106 (2020)
//! 102499; as implemented in NASA's CompDam, whose `cohesive.for` we read
//! to fix the details). No energy release rate and no process-zone length:
//! every point accumulates damage per cycle from its own jump, so damage
//! also initiates in a pristine interface.
//!
//! # Static part
//!
//! Exactly the `bilinear` law (equivalent jump `lam`, mode ratio `B`,
//! onset `lam_0`, toughness `G_c(B)`, `lam_f = 2 G_c / (K_B lam_0)`,
//! stiffness damage `d`, contact penalty): with `delta_cycles = 0` the two
//! laws agree bit for bit.
//!
//! # Fatigue damage
//!
//! The damage variable of the fatigue part is the energy damage
//! `D = d lam_0 / (lam_f (1 - d) + d lam_0)` (CompDam's "R form"). On the
//! static bilinear curve the point with energy damage `D` sits at the jump
//! `lam_D = (1 - D) lam_0 + D lam_f`, so the jump relative to the
//! current (damaged) strength envelope is
//!
//! ```text
//! lambda = lam / ((1 - D) lam_0 + D lam_f)           (1 at the static envelope)
//! ```
//!
//! The endurance limit `epsilon` (the relative jump, i.e. relative
//! stress of the undamaged point, below which a cycle at load ratio
//! R = -1 does no damage) depends on the mode ratio and on the load ratio
//! `R` of the cycle (Davila 2020; Goodman-like in `R`):
//!
//! ```text
//! eps_B = epsilon (1 - 0.42 B)
//! eps_R = 2 eps_B / (eps_B + 1 + R (eps_B - 1))
//! ```
//!
//! The brittleness `eta` sets the S-N slope through
//! `beta = -7 eta / log10(eps_R)` (the exponent that takes a point from
//! failure in one cycle at `lambda = 1` to the endurance limit at 1e7
//! cycles), and `p = beta + p_mod`. Per cycle, for `lambda >= eps_R`,
//!
//! ```text
//! dD/dN = (1 - D)^(beta - p) (lambda / eps_R)^beta / ((p + 1) gamma)
//! ```
//!
//! and 0 under the endurance limit; `gamma` is the model's cycle scale
//! (CompDam's `fatigue_gamma`).
//!
//! # Integration over an increment of `dN` cycles
//!
//! Backward Euler in `D`, with the jump at the end of the increment
//! (CompDam steps forward, from the committed `D_0`):
//!
//! ```text
//! D_2 = D_0 + dN dD/dN(D_2, lam)    (the root in [D_0, 1]),   d_fatigue = d(D_2)
//! d   = max(d_committed, d_static(lam), d_fatigue)
//! ```
//!
//! The relative jump falls fast as `D` grows (`lam_f / lam_0` is some
//! hundreds), so under a held jump the damage arrests where `lambda`
//! reaches the endurance limit, `D* = (lam / eps_R - lam_0) / (lam_f -
//! lam_0)`; a forward step overshoots that arrest by up to a whole
//! increment's growth, the backward step stops on it for any `dN`. The
//! root is found by bisection with Newton steps; its derivative in the
//! jump by the implicit-function theorem (`dD_2/dx = dN dr/dx / (1 - dN
//! dr/dD)`), or that of `D*` where the root sits on the limit. The rest of
//! the tangent is exact (dual numbers seeded on the jump: through
//! `lambda`, `eps_B` and `beta` in the mode ratio, `lam_0`, `lam_f`).
//!
//! # Parameters (besides `bilinear`'s, without `viscosity`)
//!
//! `epsilon` (endurance limit at R = -1, 0 < epsilon < 1), `eta`
//! brittleness (> 0; CF20's "eta", here `brittleness` since `eta` is the
//! BK exponent), `p_mod` (default 0) and `gamma` (default 1e7 cycles).
//!
//! # Outputs
//!
//! `damage`, `dissipated_energy`, `mode_ratio`, `fatigue_damage` (the part
//! of `D` grown by cycles), `damage_rate` (`dD/dN` at the end of the last
//! evaluation, the next increment's rate: the driver sizes `dN` with it)
//! and `energy_damage` (`D`).
//!
//! # Step information read
//!
//! `StepInfo::delta_cycles` (`dN >= 0`) and `StepInfo::load_ratio`
//! (`-1 <= R < 1`, checked when `dN > 0`).

use super::bilinear::LinearSoftening;
use super::cohesive::{CohesiveLaw, Equivalent, Softening};
use super::fatigue_paris::{
    damaged_traction, energy_damage_at, energy_of_stiffness, fatigue_base, fatigue_law_common,
    static_damage, stiffness_of_energy,
};
use junta_core::law::{output, InterfaceLaw, LawContext, LawError};
use junta_core::registry::{LawEntry, ParamDoc};
use junta_core::{CoreError, Dual3};
use std::sync::Arc;

/// Registry key.
pub const KEY: &str = "fatigue_cf20";

/// State layout of one integration point: the `bilinear` law's slots then
/// the fatigue ones.
pub mod slot {
    pub use crate::law::cohesive::slot::{
        DAMAGE, DAMAGE_HISTORY, ENERGY, INDEX, MODE_RATIO, VISCOUS,
    };
    /// Energy damage grown by fatigue, `sum dN dD/dN`.
    pub const FATIGUE_DAMAGE: usize = 6;
    /// `dD/dN` of the last evaluation.
    pub const DAMAGE_RATE: usize = 7;
    /// Number of state values per point.
    pub const STATE_LEN: usize = 8;
}

/// The mode-ratio factor of the endurance limit, `eps_B = eps (1 - 0.42 B)`
/// (Davila 2020, as CompDam uses it).
const ENDURANCE_MODE_FACTOR: f64 = 0.42;

/// The fatigue keys of the parameter table (the rest is `bilinear`'s).
const FATIGUE_KEYS: &[&str] = &["epsilon", "brittleness", "p_mod", "gamma"];

/// Parameter documentation.
pub const PARAMS: &[ParamDoc] = &[
    ParamDoc { name: "K", doc: "normal penalty stiffness K_n > 0 [force/length^3]" },
    ParamDoc { name: "N", doc: "normal (mode I) strength > 0 [stress]" },
    ParamDoc { name: "S", doc: "shear (mode II) strength > 0 [stress]" },
    ParamDoc { name: "G_Ic", doc: "mode I toughness > 0 [energy/area]" },
    ParamDoc { name: "G_IIc", doc: "mode II toughness > 0 [energy/area]" },
    ParamDoc { name: "propagation", doc: "\"bk\" (default; needs eta) or \"power_law\" (needs alpha)" },
    ParamDoc { name: "eta", doc: "BK exponent > 0 (AS4/PEEK: 2.284); also used by onset = \"bk\"" },
    ParamDoc { name: "alpha", doc: "power-law exponent > 0 (1 linear, 2 quadratic)" },
    ParamDoc { name: "onset", doc: "damage-onset criterion, as for `bilinear`" },
    ParamDoc { name: "shear_penalty", doc: "\"equal\" (default: K_s = K) or \"turon2018\"" },
    ParamDoc { name: "tangent", doc: "\"symmetric\" (default) or \"exact\" (nonsymmetric mixed-mode tangent; lu)" },
    ParamDoc { name: "epsilon", doc: "endurance limit 0 < epsilon < 1: the relative jump (stress) under which a fully reversed cycle (R = -1) does no damage (Davila 2020; eps_B = epsilon (1 - 0.42 B))" },
    ParamDoc { name: "brittleness", doc: "CF20's brittleness eta > 0: the S-N exponent beta = -7 eta / log10(eps_R)" },
    ParamDoc { name: "p_mod", doc: "CF20's p = beta + p_mod (default 0): how the rate falls with the damage, (1 - D)^(beta - p)" },
    ParamDoc { name: "gamma", doc: "cycle scale gamma > 0 of the rate dD/dN = (1 - D)^(beta - p) (lambda / eps_R)^beta / ((p + 1) gamma) (default 1e7)" },
];

/// The `fatigue_cf20` law.
#[derive(Debug, Clone)]
pub struct FatigueCf20 {
    /// The static part (the `bilinear` law with this key).
    pub base: CohesiveLaw,
    /// Endurance limit at R = -1.
    pub epsilon: f64,
    /// Brittleness `eta`.
    pub brittleness: f64,
    /// `p - beta`.
    pub p_mod: f64,
    /// Cycle scale.
    pub gamma: f64,
}

impl FatigueCf20 {
    /// Build from a TOML table (see [`PARAMS`]).
    pub fn from_table(t: &toml::Table) -> Result<Self, CoreError> {
        let invalid = |message: String| CoreError::InvalidParameters {
            kind: "law",
            key: KEY.into(),
            message,
        };
        let (base, numbers) = fatigue_base(KEY, t, FATIGUE_KEYS)?;
        let num = |name: &str| numbers.get(name).copied().flatten();
        let epsilon = num("epsilon").ok_or_else(|| {
            invalid("missing `epsilon` (endurance limit, 0 < epsilon < 1)".into())
        })?;
        if !(epsilon > 0.0 && epsilon < 1.0) {
            return Err(invalid(format!(
                "`epsilon` = {epsilon}: the endurance limit is a relative stress, 0 < epsilon < 1"
            )));
        }
        let brittleness = num("brittleness")
            .ok_or_else(|| invalid("missing `brittleness` (CF20's eta > 0)".into()))?;
        if !(brittleness > 0.0 && brittleness.is_finite()) {
            return Err(invalid(format!(
                "`brittleness` = {brittleness} must be positive and finite"
            )));
        }
        let p_mod = num("p_mod").unwrap_or(0.0);
        if !p_mod.is_finite() {
            return Err(invalid(format!("`p_mod` = {p_mod} must be finite")));
        }
        let gamma = num("gamma").unwrap_or(1e7);
        if !(gamma > 0.0 && gamma.is_finite()) {
            return Err(invalid(format!(
                "`gamma` = {gamma} must be positive and finite (cycles)"
            )));
        }
        Ok(FatigueCf20 {
            base,
            epsilon,
            brittleness,
            p_mod,
            gamma,
        })
    }

    /// `(eps_R, beta, p)` at mode ratio `b` and load ratio `r_ratio`.
    fn exponents(&self, b: Dual3, r_ratio: f64) -> (Dual3, Dual3, Dual3) {
        let eps_b = (1.0 - b * ENDURANCE_MODE_FACTOR) * self.epsilon;
        let eps_r = eps_b * 2.0 / (eps_b + 1.0 + (eps_b - 1.0) * r_ratio);
        let beta = (-7.0 * self.brittleness * std::f64::consts::LN_10) / eps_r.ln();
        (eps_r, beta, beta + self.p_mod)
    }

    /// `dD/dN` at the energy damage `big_d` and the jump of `eq`; 0 under
    /// the endurance limit. Also `d ln(dD/dN) / dD` (at fixed jump).
    pub fn damage_rate(&self, eq: &Equivalent, big_d: f64, r_ratio: f64) -> (Dual3, f64) {
        let lam_f = eq.g_c * 2.0 / (eq.k_b * eq.lam0);
        let envelope = eq.lam0 * (1.0 - big_d) + lam_f * big_d;
        let lambda = eq.lam / envelope;
        let (eps_r, beta, p) = self.exponents(eq.b, r_ratio);
        if lambda.v < eps_r.v || big_d >= 1.0 {
            return (Dual3::cst(0.0), 0.0);
        }
        let ln_rate = (beta - p) * (1.0 - big_d).ln() + beta * (lambda / eps_r).ln()
            - ((p + 1.0) * self.gamma).ln();
        let dln_dd = -(beta.v - p.v) / (1.0 - big_d) - beta.v * (lam_f.v - eq.lam0.v) / envelope.v;
        (ln_rate.exp(), dln_dd)
    }

    /// The energy damage at the end of `dn` cycles from `big_d0` at the
    /// jump of `eq`, by backward Euler: the root of
    /// `g(D) = D - D_0 - dN dD/dN(D)` in `[D_0, 1]` (`g(D_0) <= 0`,
    /// `g(1) = 1 - D_0 > 0`), found by bisection and Newton. Its
    /// derivative in the jump by the implicit-function theorem (`D_0`
    /// carries the derivatives of the mode ratio's map), or, where
    /// the root sits on the endurance limit (the rate drops to 0 there:
    /// the damage that brings the relative jump down to `eps_R`), that of
    /// `D* = (lam / eps_R - lam_0) / (lam_f - lam_0)`.
    fn implicit_update(&self, eq: &Equivalent, d0: Dual3, r_ratio: f64, dn: f64) -> Dual3 {
        let big_d0 = d0.v;
        let g = |d: f64| d - big_d0 - dn * self.damage_rate(eq, d, r_ratio).0.v;
        let (mut lo, mut hi) = (big_d0, 1.0);
        for _ in 0..200 {
            let d = 0.5 * (lo + hi);
            // a Newton step from d where it stays in the bracket
            let (r, dln) = self.damage_rate(eq, d, r_ratio);
            let gd = d - big_d0 - dn * r.v;
            if gd <= 0.0 {
                lo = d;
            } else {
                hi = d;
            }
            let slope = 1.0 - dn * r.v * dln;
            if slope > 0.0 {
                let next = d - gd / slope;
                if next > lo && next < hi {
                    if g(next) <= 0.0 {
                        lo = next;
                    } else {
                        hi = next;
                    }
                }
            }
            if hi - lo <= 1e-15 * hi.max(1e-300) {
                break;
            }
        }
        let d = hi.min(1.0);
        if d >= 1.0 {
            return Dual3::cst(1.0);
        }
        let (r, dln) = self.damage_rate(eq, d, r_ratio);
        if r.v > 0.0 {
            let slope = 1.0 - dn * r.v * dln;
            let mut out = Dual3::cst(d);
            for i in 0..3 {
                out.d[i] = (d0.d[i] + dn * r.d[i]) / slope;
            }
            out
        } else {
            // on the endurance limit
            let lam_f = eq.g_c * 2.0 / (eq.k_b * eq.lam0);
            let (eps_r, _, _) = self.exponents(eq.b, r_ratio);
            let on_limit = (eq.lam / eps_r - eq.lam0) / (lam_f - eq.lam0);
            Dual3 {
                v: d,
                d: on_limit.d,
            }
        }
    }

    /// The law in dual numbers seeded on the jump: traction and damage;
    /// trial state into `trial`.
    fn evaluate_dual(
        &self,
        ctx: &LawContext<'_>,
        trial: &mut [f64],
    ) -> Result<([Dual3; 3], Dual3), LawError> {
        use slot::*;
        let c = ctx.state_committed;
        if c.len() != STATE_LEN || trial.len() != STATE_LEN {
            return Err(LawError::Failed(format!(
                "{KEY}: state slices of length {} (committed) and {} (trial), expected {STATE_LEN}",
                c.len(),
                trial.len()
            )));
        }
        let dn = ctx.step.delta_cycles;
        let r_ratio = ctx.step.load_ratio;
        if !ctx.jump.iter().all(|v| v.is_finite()) || dn < 0.0 || !dn.is_finite() {
            return Err(LawError::Failed(format!(
                "{KEY}: jump {:?} and delta_cycles {dn} must be finite, delta_cycles >= 0",
                ctx.jump
            )));
        }
        if dn > 0.0 && !(-1.0..1.0).contains(&r_ratio) {
            return Err(LawError::Failed(format!(
                "{KEY}: load ratio R = {r_ratio} outside [-1, 1)"
            )));
        }
        trial.copy_from_slice(c);
        trial[DAMAGE_RATE] = 0.0;
        let dj = Dual3::seeds(ctx.jump);
        let d_hist = c[DAMAGE_HISTORY];
        let mut d = Dual3::cst(d_hist);
        if let Some(eq) = self.base.equivalent(dj)? {
            trial[MODE_RATIO] = eq.b.v;
            trial[INDEX] = eq.index.v;
            let lam_f = eq.g_c * 2.0 / (eq.k_b * eq.lam0);
            d = static_damage(&eq, d_hist);
            if d_hist < 1.0 {
                // the committed damage in energy form at the current mode
                // (it moves with the mode ratio, so it carries derivatives)
                let d0 = energy_of_stiffness(Dual3::cst(d_hist), eq.lam0, lam_f);
                let big_d0 = d0.v;
                let (rate, _) = self.damage_rate(&eq, big_d0, r_ratio);
                if dn > 0.0 && rate.v > 0.0 {
                    let big_d2 = self.implicit_update(&eq, d0, r_ratio, dn);
                    let d_fatigue = if big_d2.v >= 1.0 {
                        Dual3::cst(1.0)
                    } else {
                        stiffness_of_energy(big_d2, eq.lam0, lam_f)
                    };
                    if d_fatigue.v > d.v {
                        d = d_fatigue;
                        trial[FATIGUE_DAMAGE] = c[FATIGUE_DAMAGE] + (big_d2.v - big_d0);
                    }
                    trial[DAMAGE_RATE] = self.damage_rate(&eq, big_d2.v.min(1.0), r_ratio).0.v;
                } else {
                    trial[DAMAGE_RATE] = rate.v;
                }
            }
            if d.v > d_hist {
                let f = |x: f64| LinearSoftening.dissipated(x, eq.lam0.v, eq.g_c.v, eq.k_b.v);
                trial[ENERGY] = c[ENERGY] + f(d.v) - f(d_hist);
            }
            trial[DAMAGE_HISTORY] = d.v.max(d_hist);
            trial[DAMAGE] = trial[DAMAGE_HISTORY];
        }
        Ok((damaged_traction(d, dj, self.base.k_s, self.base.k_n), d))
    }
}

impl InterfaceLaw for FatigueCf20 {
    fatigue_law_common!(KEY, slot);

    fn output_names(&self) -> &'static [&'static str] {
        &[
            output::DAMAGE,
            output::DISSIPATED_ENERGY,
            output::MODE_RATIO,
            output::FATIGUE_DAMAGE,
            output::DAMAGE_RATE,
            output::ENERGY_DAMAGE,
        ]
    }

    fn outputs(&self, state: &[f64], out: &mut [f64]) {
        use slot::*;
        if state.len() == STATE_LEN && out.len() == 6 {
            out[0] = state[DAMAGE];
            out[1] = state[ENERGY];
            out[2] = state[MODE_RATIO];
            out[3] = state[FATIGUE_DAMAGE];
            out[4] = state[DAMAGE_RATE];
            out[5] = energy_damage_at(&self.base, state[DAMAGE], state[MODE_RATIO]);
        }
    }
}

inventory::submit! {
    LawEntry {
        key: KEY,
        description: "bilinear mixed-mode law with the local CF20 cohesive fatigue damage (Davila 2020: endurance limit, brittleness, R ratio; no energy release rate; initiates in a pristine interface)",
        params: PARAMS,
        build: |t| Ok(Arc::new(FatigueCf20::from_table(t)?)),
    }
}
