//! `fatigue_bilinear`: the mixed-mode bilinear law of [`super::bilinear`]
//! with high-cycle fatigue damage driven by a Paris law (Turon, Costa,
//! Camanho & Davila 2007, "Simulation of delamination in composites under
//! high-cycle fatigue", Composites Part A 38, 2270-2282; mixed-mode Paris
//! coefficients after Blanco, Gamstedt, Asp & Costa 2004, "Mixed-mode
//! delamination growth in carbon-fibre composite laminates under cyclic
//! loading", Int. J. Solids Struct. 41, 4219-4235).
//!
//! # Static part
//!
//! Exactly the `bilinear` law (equivalent jump `lam`, mode ratio `B`,
//! penalty `K_B`, onset `lam_0`, toughness `G_c(B)` by BK or the power law,
//! `lam_f = 2 G_c / (K_B lam_0)`, stiffness damage `d`, contact penalty):
//! with `delta_cycles = 0` the two laws give the same traction, tangent and
//! state, bit for bit. Viscous regularisation is not offered (a cycle jump
//! is not a time).
//!
//! # Energy damage
//!
//! Turon's fatigue rate acts on the *energy* damage `D`, the fraction of
//! `G_c` a monotone path to `d` dissipates on the bilinear curve (the
//! damaged-area fraction of the point). For the bilinear shape, at the
//! current mode,
//!
//! ```text
//! D(d) = d lam_0 / (lam_f (1 - d) + d lam_0)         d(D) = lam_f D / (lam_0 + D (lam_f - lam_0))
//! dd/dD = (lam_f (1 - d) + d lam_0)^2 / (lam_f lam_0)
//! ```
//!
//! and the dissipated energy `F_B(d) = G_c(B) D(d)`.
//!
//! # Fatigue damage rate (Turon et al. 2007)
//!
//! A crack advancing by `dA` moves every point of the cohesive zone
//! (area `A_cz`) by the fraction `dA / A_cz` of its way from onset to
//! full separation, so `dD/dN = (1 / A_cz) dA/dN`; per unit width (the law
//! sees a point, not an element),
//!
//! ```text
//! dD/dN = (da/dN) / l_cz                 dd/dN = dd/dD dD/dN   (Turon 2007's d-form)
//! da/dN = C(B) (DG / G_c(B))^m(B)       if DG > G_th, else 0
//! DG    = (1 - R^2) G_max               (R = load ratio of the constant-amplitude cycle)
//! ```
//!
//! **Mixed mode** (Blanco et al. 2004), quadratic in `B` on log scale:
//!
//! ```text
//! m(B)     = m_I + m_m B + (m_II - m_I - m_m) B^2
//! log C(B) = log C_I + B log C_m + B^2 log(C_II / (C_I C_m))
//! ```
//!
//! `C_m`, `m_m` are the mixed-mode fitting parameters; left out, they
//! default to `C_m = C_II / C_I` and `m_m = m_II - m_I`, which makes
//! `log C` and `m` linear in `B`.
//!
//! **Energy release rate and zone length: measured on the crack** (the
//! default of a scene's fatigue step, `[fatigue] energy_release_rate =
//! "crack_front"`). The driver measures at the start of each fatigue
//! increment, from the converged state ([`junta_core::crack_drive`]), the
//! J integral of the cohesive tractions along the line of interface points
//! with the largest one (Rice 1968: J around a cohesive zone is `-int t .
//! d delta/ds ds` over it, whatever the tractions' shape), its mode ratio
//! `B_J = G_II / G` from the shear part of the integral, and the length
//! `L` of that line's process zone (the points past onset or damaged at
//! the start of the increment). Every point of the zone then gets the same
//! rate
//!
//! ```text
//! dD/dN = C(B_J) ((1 - R^2) J / G_c(B_J))^m(B_J) / L
//! ```
//!
//! the measured-zone form of Bak, Turon, Lindgaard & Lund 2016 (Int. J.
//! Numer. Meth. Eng. 106, 163-191): a zone of length `L` whose points all
//! go from onset to failure at the rate `dD/dN` moves by `L dD/dN` per
//! cycle. `l_cz`, `E` and `M` are not used. Measured against the Paris
//! law on DCBs and split beams (docs/verification.md): mode I and mode II
//! within -6 .. +10 %; at `G_II / G = 0.5` the crack grows +8 % fast at
//! `G/G_c = 0.3` and +24 % at 0.4, because a quarter of each point's damage
//! then comes from the static law as the zone's tractions redistribute,
//! on top of the fatigue rate that alone would move the zone at the Paris
//! rate.
//!
//! **Energy release rate and zone length: the point's own estimate**
//! (`energy_release_rate = "local"`, a single point or a model without a
//! crack line). `G_max` is the area under the static bilinear curve up to
//! the point's current equivalent jump (the J integral of the part of a
//! cohesive zone ahead of the point, on its static curve),
//!
//! ```text
//! G_max(lam) = K_B lam^2 / 2                                   lam <= lam_0
//!            = G_c - tau_0 (lam_f - lam)^2 / (2 (lam_f - lam_0))  lam_0 < lam < lam_f
//!            = G_c                                              lam >= lam_f
//! ```
//!
//! and the zone length `l_cz` is given, or `l_cz = M E G_c(B) / tau_0(B)^2`
//! with `tau_0 = K_B lam_0`, `E` the modulus the user gives (Turon: the
//! transverse modulus E_33 of the arms) and `M` a model factor (default 1,
//! Hillerborg's length; Rice's slender-body estimate is 9 pi / 32). On a
//! DCB this estimate grows the crack at 0.07 .. 0.13 of the Paris rate:
//! the points at the zone's leading edge see a small local `G_max` and
//! barely damage, which holds the zone back. It is exact for a single
//! point under a held jump (the closed form of the tests).
//!
//! **Where fatigue acts**: in the process zone only, that is at a point
//! past onset at the start of the increment (committed `I >= 1`) or
//! already damaged (`d > 0`), with an opening or a slip (`2 psi > 0`). The
//! zone is frozen over the increment: a point that passes onset inside it
//! gets static damage only until the next one (taking the current index
//! would switch the measured-crack rate on and off between Newton
//! iterations, a jump in the traction that stalls Newton). A pristine point below onset gets
//! no fatigue damage (no initiation from a pristine interface; the rate
//! jumps from 0 to its onset value at `lam = lam_0`).
//!
//! # Integration over an increment of `dN = delta_cycles` cycles
//!
//! With `d_1` the static update of the increment (the `bilinear` law's
//! `max(d_committed, d_B(lam))`),
//!
//! ```text
//! D_2 = min(1, D(d_1) + dN r(lam, B)),    d = d(D_2)
//! ```
//!
//! with the rate `r = dD/dN` evaluated at the jump at the **end** of the
//! increment (the one Newton iterates on; with a measured crack it is the
//! increment's constant): a backward-Euler step. The rate
//! does not depend on the damage (`G_max` depends on the jump only), so
//! for a jump held over the increment (the cycle jump holds the load at
//! the envelope maximum) the step is exact: `D` grows linearly in `N`, the
//! result does not depend on how the cycles are split into increments, and
//! `d(N)` solves Turon's ODE `dd/dN = dd/dD r` exactly. When the jump
//! changes within the increment, it is a backward-Euler (first-order)
//! step in `N`. Damage never decreases (`dN >= 0`, `r >= 0`).
//!
//! **Tangent**: the whole update runs in dual numbers seeded on the jump,
//! so the tangent includes `d(d)/d(jump)` through `d_1` (static loading),
//! the mode ratio (the map `D <-> d` and `l_cz`, `C`, `m`, `G_c` change with
//! `B`), and the fatigue increment, `dN dr/d(jump)` with
//! `dr/dG_max = m r / G_max` and `dG_max/dlam = tau_static(lam)` (the
//! static traction: the slope of an area is its height). The fatigue
//! increment makes the tangent softer than the static one, and
//! nonsymmetric in mixed mode like the static one (the element assembles
//! its symmetric part unless `tangent = "exact"`).
//!
//! **Dissipated energy**: `dissipated_energy = sum G_c(B) dD` over
//! increments (the static law's bookkeeping, `F_B(d_1) - F_B(d_0)` with the
//! mode of the increment), fatigue increments included. It is the
//! fracture energy of the damaged-area fraction: `dissipated / G_c` is the
//! point's share of crack area, and a point that fails under a
//! proportional path has dissipated exactly `G_c(B)`, however many cycles
//! it took. It is not the hysteresis energy of the load cycles, which a
//! model held at the envelope maximum does not resolve.
//!
//! # Outputs
//!
//! `damage` (d), `dissipated_energy`, `mode_ratio`, `fatigue_damage` (the
//! part of `D` grown by fatigue, `sum dN r`), `energy_release_rate` (the
//! `G_max` of the last evaluation, measured or local), `damage_rate` (`r = dD/dN`
//! of the last evaluation, per cycle, 0 outside the process zone or
//! under the threshold; a cycle-jump driver bounds `dN` with it:
//! `dN <= dD_max / max r`) and `energy_damage` (the point's `D`).
//!
//! # Step information read
//!
//! `StepInfo::delta_cycles` (`dN >= 0`; 0: the static law),
//! `StepInfo::load_ratio` (`0 <= R < 1`, checked when `dN > 0`) and
//! `StepInfo::crack_drive` (the measured crack; `None`: the local
//! estimate).
//!
//! What a cycle-jump driver must do: load to the envelope maximum in
//! ordinary increments (`delta_cycles = 0`), then hold the load and give
//! each fatigue increment `delta_cycles = dN > 0`, `cycles = N` at its end
//! and the step's `load_ratio`, the same on every Newton iteration and
//! cut-back retry of the increment (the law starts from the committed
//! state each time, so a cut-back is a smaller `dN`). A bound on the
//! damage growth per increment is `dN = dD_max / max r` over the committed
//! `damage_rate` outputs; `N` itself is the driver's to checkpoint (the
//! law's state holds no cycle count).

use super::bilinear::LinearSoftening;
use super::cohesive::{CohesiveLaw, Equivalent, Softening};
use junta_core::law::{output, InterfaceLaw, LawContext, LawError};
use junta_core::registry::{LawEntry, ParamDoc};
use junta_core::{CoreError, CrackDrive, Dual3};
use std::sync::Arc;

/// Registry key.
pub const KEY: &str = "fatigue_bilinear";

/// State layout of one integration point: the `bilinear` law's slots
/// ([`super::cohesive::slot`]; `VISCOUS` stays 0) then the fatigue ones.
pub mod slot {
    pub use crate::law::cohesive::slot::{
        DAMAGE, DAMAGE_HISTORY, ENERGY, INDEX, MODE_RATIO, VISCOUS,
    };
    /// Energy damage grown by fatigue, `sum dN r`.
    pub const FATIGUE_DAMAGE: usize = 6;
    /// Local `G_max` of the last evaluation.
    pub const ENERGY_RELEASE_RATE: usize = 7;
    /// `r = dD/dN` of the last evaluation.
    pub const DAMAGE_RATE: usize = 8;
    /// Number of state values per point.
    pub const STATE_LEN: usize = 9;
}

/// Damage above which a damage value is taken as exactly 1 (as in
/// [`super::cohesive`]).
const FULL: f64 = 1.0 - 1e-12;

/// Paris-law parameters, mixed mode after Blanco et al. 2004.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Paris {
    /// Mode I coefficient `C_I` [length/cycle].
    pub c_i: f64,
    /// Mode II coefficient `C_II`.
    pub c_ii: f64,
    /// Mixed-mode coefficient `C_m` (dimensionless factor).
    pub c_m: f64,
    /// Mode I exponent `m_I`.
    pub m_i: f64,
    /// Mode II exponent `m_II`.
    pub m_ii: f64,
    /// Mixed-mode exponent term `m_m`.
    pub m_m: f64,
    /// Threshold `G_th` on `DG` (energy/area; 0: none).
    pub g_th: f64,
}

impl Paris {
    /// `m(B)`.
    pub fn exponent<T>(&self, b: T) -> T
    where
        T: Copy
            + std::ops::Mul<f64, Output = T>
            + std::ops::Mul<T, Output = T>
            + std::ops::Add<f64, Output = T>
            + std::ops::Add<T, Output = T>,
    {
        b * self.m_m + b * b * (self.m_ii - self.m_i - self.m_m) + self.m_i
    }
    /// `ln C(B)`.
    pub fn ln_coefficient<T>(&self, b: T) -> T
    where
        T: Copy
            + std::ops::Mul<f64, Output = T>
            + std::ops::Mul<T, Output = T>
            + std::ops::Add<f64, Output = T>
            + std::ops::Add<T, Output = T>,
    {
        b * self.c_m.ln() + b * b * (self.c_ii / (self.c_i * self.c_m)).ln() + self.c_i.ln()
    }
}

/// How the cohesive-zone length is obtained.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ZoneLength {
    /// A given length `l_cz`, the same in every mode.
    Given(f64),
    /// `l_cz = M E G_c(B) / tau_0(B)^2`.
    Modulus {
        /// Modulus `E` (stress).
        e: f64,
        /// Model factor `M`.
        m: f64,
    },
    /// Neither given: the process-zone length the driver measures on the
    /// interface ([`CrackDrive::process_zone_length`]); the local estimate
    /// (without a measured crack) cannot be used.
    Measured,
}

/// The `fatigue_bilinear` law.
#[derive(Debug, Clone)]
pub struct FatigueBilinear {
    /// The static part (the `bilinear` law with this key).
    pub base: CohesiveLaw,
    /// Paris-law parameters.
    pub paris: Paris,
    /// Cohesive-zone length rule.
    pub zone: ZoneLength,
}

/// The fatigue keys of the parameter table (the rest is `bilinear`'s).
const FATIGUE_KEYS: &[&str] = &[
    "C_I", "C_II", "m_I", "m_II", "C_m", "m_m", "G_th", "l_cz", "E", "M",
];

/// The static `bilinear` part of a fatigue law `key` from its table `t`,
/// and the numbers of its fatigue keys `keys` (absent: `None`). Refuses
/// `viscosity` (a cycle jump is not a time) and a fatigue key that is not
/// a number; an unknown key's message lists the fatigue keys too.
pub(crate) fn fatigue_base(
    key: &'static str,
    t: &toml::Table,
    keys: &[&str],
) -> Result<(CohesiveLaw, std::collections::BTreeMap<String, Option<f64>>), CoreError> {
    let invalid = |message: String| CoreError::InvalidParameters {
        kind: "law",
        key: key.into(),
        message,
    };
    let mut rest = t.clone();
    if rest.contains_key("viscosity") {
        return Err(invalid(format!(
            "`viscosity` is not supported by {key} (a cycle jump is not a time); remove it"
        )));
    }
    let mut numbers = std::collections::BTreeMap::new();
    for &name in keys {
        let v = match rest.remove(name) {
            None => None,
            Some(toml::Value::Float(v)) => Some(v),
            Some(toml::Value::Integer(v)) => Some(v as f64),
            Some(other) => return Err(invalid(format!("`{name}` must be a number, not {other}"))),
        };
        numbers.insert(name.to_string(), v);
    }
    let base =
        CohesiveLaw::from_table(key, Arc::new(LinearSoftening), &rest).map_err(
            |err| match err {
                CoreError::InvalidParameters { kind, key, message }
                    if message.contains("unknown field") =>
                {
                    CoreError::InvalidParameters {
                        kind,
                        key,
                        message: format!("{message}; or a fatigue key: {}", keys.join(", ")),
                    }
                }
                other => other,
            },
        )?;
    Ok((base, numbers))
}

/// The static update of a fatigue law's point: the `bilinear` law's
/// `max(d_committed, d_B(lam))` past onset, in dual numbers (`d_hist`
/// itself, constant, where the static law does not damage).
pub(crate) fn static_damage(eq: &Equivalent, d_hist: f64) -> Dual3 {
    if eq.index.v > 1.0 && d_hist < 1.0 {
        let mut d_b = LinearSoftening.damage(eq.lam, eq.lam0, eq.g_c, eq.k_b);
        if d_b.v >= FULL {
            d_b = Dual3::cst(1.0);
        }
        if d_b.v > d_hist || (d_b.v == d_hist && d_hist > 0.0) {
            return d_b;
        }
    }
    Dual3::cst(d_hist)
}

/// Traction of the damaged penalty law with contact: `(1 - d) K jump`,
/// the full normal penalty in compression.
pub(crate) fn damaged_traction(d: Dual3, dj: [Dual3; 3], ks: f64, kn: f64) -> [Dual3; 3] {
    let one_m_d = 1.0 - d;
    [
        one_m_d * dj[0] * ks,
        one_m_d * dj[1] * ks,
        if dj[2].v > 0.0 {
            one_m_d * dj[2] * kn
        } else {
            dj[2] * kn
        },
    ]
}

/// The energy damage `D = d lam_0 / (lam_f (1 - d) + d lam_0)` of the
/// stiffness damage `d` on the bilinear curve, and back.
pub(crate) fn energy_of_stiffness(d: Dual3, lam0: Dual3, lam_f: Dual3) -> Dual3 {
    d * lam0 / (lam_f * (1.0 - d) + d * lam0)
}

/// The energy damage of a point of the static law `base` with stiffness
/// damage `d` at mode ratio `b` (1 when failed).
pub(crate) fn energy_damage_at(base: &CohesiveLaw, d: f64, b: f64) -> f64 {
    if d >= 1.0 {
        return 1.0;
    }
    let (lam0, g_c, k_b) = base.mode_properties(b);
    let lam_f = 2.0 * g_c / (k_b * lam0);
    d * lam0 / (lam_f * (1.0 - d) + d * lam0)
}

/// Energy damage `D` from which a fatigue point counts as failed: the
/// fraction of its toughness left is below 1e-9.
pub const FAILED_ENERGY_DAMAGE: f64 = 1.0 - 1e-9;

/// The [`junta_core::PointStage`] of a fatigue point built on `base` (its
/// state starts with `base`'s slots): failed once its energy damage `D`
/// reaches [`FAILED_ENERGY_DAMAGE`], process zone while `0 < d` short of it.
pub(crate) fn fatigue_stage(base: &CohesiveLaw, state: &[f64]) -> junta_core::PointStage {
    let d = state.get(slot::DAMAGE).copied().unwrap_or(0.0);
    let b = state.get(slot::MODE_RATIO).copied().unwrap_or(0.0);
    if d <= 0.0 {
        junta_core::PointStage::Intact
    } else if energy_damage_at(base, d, b) >= FAILED_ENERGY_DAMAGE {
        junta_core::PointStage::Failed
    } else {
        junta_core::PointStage::ProcessZone
    }
}

/// The stiffness damage of the energy damage `big_d` ([`energy_of_stiffness`] inverted).
pub(crate) fn stiffness_of_energy(big_d: Dual3, lam0: Dual3, lam_f: Dual3) -> Dual3 {
    lam_f * big_d / (lam0 + big_d * (lam_f - lam0))
}

/// Parameter documentation.
pub const PARAMS: &[ParamDoc] = &[
    ParamDoc { name: "K", doc: "normal penalty stiffness K_n > 0 [force/length^3] (Turon: K = 50 E_33 / t_ply or more)" },
    ParamDoc { name: "N", doc: "normal (mode I) strength > 0 [stress]" },
    ParamDoc { name: "S", doc: "shear (mode II) strength > 0 [stress]" },
    ParamDoc { name: "G_Ic", doc: "mode I toughness > 0 [energy/area]" },
    ParamDoc { name: "G_IIc", doc: "mode II toughness > 0 [energy/area]" },
    ParamDoc { name: "propagation", doc: "\"bk\" (default; needs eta) or \"power_law\" (needs alpha)" },
    ParamDoc { name: "eta", doc: "BK exponent > 0 (AS4/PEEK: 2.284); also used by onset = \"bk\"" },
    ParamDoc { name: "alpha", doc: "power-law exponent > 0 (1 linear, 2 quadratic)" },
    ParamDoc { name: "onset", doc: "damage-onset criterion, as for `bilinear`: \"quadratic\" (default), \"max_stress\", \"bk\", or a table { type = .., .. }" },
    ParamDoc { name: "shear_penalty", doc: "\"equal\" (default: K_s = K) or \"turon2018\" (K_s = K (G_Ic/G_IIc)(S/N)^2)" },
    ParamDoc { name: "tangent", doc: "\"symmetric\" (default) or \"exact\" (nonsymmetric mixed-mode tangent; lu)" },
    ParamDoc { name: "C_I", doc: "mode I Paris coefficient C_I > 0 [length/cycle] in da/dN = C (DG/G_c)^m" },
    ParamDoc { name: "m_I", doc: "mode I Paris exponent m_I > 0" },
    ParamDoc { name: "C_II", doc: "mode II Paris coefficient C_II > 0 [length/cycle]" },
    ParamDoc { name: "m_II", doc: "mode II Paris exponent m_II > 0" },
    ParamDoc { name: "C_m", doc: "mixed-mode coefficient factor C_m > 0 of Blanco et al. 2004 (default C_II/C_I: log C linear in B)" },
    ParamDoc { name: "m_m", doc: "mixed-mode exponent term m_m of Blanco et al. 2004 (default m_II - m_I: m linear in B); m(B) must stay > 0" },
    ParamDoc { name: "G_th", doc: "fatigue threshold G_th >= 0 [energy/area] on DG = (1 - R^2) G_max (default 0: none)" },
    ParamDoc { name: "l_cz", doc: "cohesive-zone length [length] of the local estimate (`[fatigue] energy_release_rate = \"local\"`), the same in every mode; or give E (and M) instead; unused when the crack is measured (the default)" },
    ParamDoc { name: "E", doc: "modulus E > 0 [stress] for the local estimate's l_cz = M E G_c(B) / tau_0(B)^2 (Turon 2007: transverse modulus E_33 of the arms); not with l_cz" },
    ParamDoc { name: "M", doc: "cohesive-zone length factor M > 0 of the local estimate (default 1: Hillerborg's E G_c / tau_0^2; Rice: 0.88); only with E" },
];

impl FatigueBilinear {
    /// Build from a TOML table (see [`PARAMS`]).
    pub fn from_table(t: &toml::Table) -> Result<Self, CoreError> {
        let invalid = |message: String| CoreError::InvalidParameters {
            kind: "law",
            key: KEY.into(),
            message,
        };
        let (base, mut numbers) = fatigue_base(KEY, t, FATIGUE_KEYS)?;
        let mut num = |name: &str| numbers.remove(name).flatten();
        let c_i = num("C_I");
        let c_ii = num("C_II");
        let m_i = num("m_I");
        let m_ii = num("m_II");
        let c_m = num("C_m");
        let m_m = num("m_m");
        let g_th = num("G_th");
        let l_cz = num("l_cz");
        let e = num("E");
        let m_factor = num("M");
        let positive = |v: Option<f64>, name: &str, what: &str| -> Result<f64, CoreError> {
            let v = v.ok_or_else(|| invalid(format!("missing `{name}` ({what})")))?;
            if v > 0.0 && v.is_finite() {
                Ok(v)
            } else {
                Err(invalid(format!(
                    "`{name}` = {v} must be positive and finite ({what})"
                )))
            }
        };
        let c_i = positive(c_i, "C_I", "mode I Paris coefficient, length/cycle")?;
        let c_ii = positive(c_ii, "C_II", "mode II Paris coefficient, length/cycle")?;
        let m_i = positive(m_i, "m_I", "mode I Paris exponent")?;
        let m_ii = positive(m_ii, "m_II", "mode II Paris exponent")?;
        let c_m = match c_m {
            None => c_ii / c_i,
            v => positive(
                v,
                "C_m",
                "mixed-mode coefficient factor of Blanco et al. 2004",
            )?,
        };
        let m_m = match m_m {
            None => m_ii - m_i,
            Some(v) if v.is_finite() => v,
            Some(v) => return Err(invalid(format!("`m_m` = {v} must be finite"))),
        };
        let g_th = match g_th {
            None => 0.0,
            Some(v) if v >= 0.0 && v.is_finite() => v,
            Some(v) => {
                return Err(invalid(format!(
                    "`G_th` = {v} must be >= 0 and finite (fatigue threshold, energy/area)"
                )))
            }
        };
        let zone = match (l_cz, e, m_factor) {
            (Some(_), Some(_), _) | (Some(_), _, Some(_)) => return Err(invalid(
                "give either `l_cz` (cohesive-zone length) or `E` (and optionally `M`), not both"
                    .into(),
            )),
            (Some(l), None, None) => {
                ZoneLength::Given(positive(Some(l), "l_cz", "cohesive-zone length")?)
            }
            (None, None, Some(_)) => {
                return Err(invalid(
                    "`M` scales l_cz = M E G_c / tau_0^2: give `E` with it (or leave both out: the crack-front fatigue step measures the zone)".into(),
                ))
            }
            (None, None, None) => ZoneLength::Measured,
            (None, e, m) => {
                ZoneLength::Modulus {
                    e: positive(e, "E", "modulus for l_cz = M E G_c / tau_0^2, stress")?,
                    m: match m {
                        None => 1.0,
                        v => positive(v, "M", "cohesive-zone length factor")?,
                    },
                }
            }
        };
        let paris = Paris {
            c_i,
            c_ii,
            c_m,
            m_i,
            m_ii,
            m_m,
            g_th,
        };
        for i in 0..=20 {
            let b = i as f64 / 20.0;
            let m = paris.exponent(b);
            if m.is_nan() || m <= 0.0 {
                return Err(invalid(format!(
                    "`m_m` = {m_m} makes the Paris exponent m(B) = {m:.4} <= 0 at mode ratio B = {b:.2}; valid m_m keep m_I + m_m B + (m_II - m_I - m_m) B^2 > 0 on [0, 1]"
                )));
            }
        }
        Ok(FatigueBilinear { base, paris, zone })
    }

    /// Cohesive-zone length at the mode of `eq` (`None`: to be measured).
    fn zone_length(&self, eq: &Equivalent) -> Option<Dual3> {
        match self.zone {
            ZoneLength::Given(l) => Some(Dual3::cst(l)),
            ZoneLength::Modulus { e, m } => {
                let tau0 = eq.k_b * eq.lam0;
                Some(eq.g_c * (m * e) / (tau0 * tau0))
            }
            ZoneLength::Measured => None,
        }
    }

    /// Energy damage `D(d)` of a point with stiffness damage `d` at mode
    /// ratio `b` (the bilinear map of the module docs).
    pub fn energy_damage(&self, d: f64, b: f64) -> f64 {
        energy_damage_at(&self.base, d, b)
    }

    /// Local `G_max`: the area under the static bilinear curve up to `lam`.
    pub fn energy_release_rate(eq: &Equivalent) -> Dual3 {
        let Equivalent {
            lam,
            lam0,
            k_b,
            g_c,
            ..
        } = *eq;
        let lam_f = g_c * 2.0 / (k_b * lam0);
        if lam.v <= lam0.v {
            lam * lam * k_b * 0.5
        } else if lam.v < lam_f.v {
            let tau0 = k_b * lam0;
            let r = lam_f - lam;
            g_c - tau0 * r * r / ((lam_f - lam0) * 2.0)
        } else {
            g_c
        }
    }

    /// Fatigue rate `r = dD/dN` at the mode and jump of `eq` for the load
    /// ratio `r_ratio`; also `G_max`. Zero under the threshold.
    pub fn damage_rate(
        &self,
        eq: &Equivalent,
        r_ratio: f64,
        drive: Option<CrackDrive>,
    ) -> Result<(Dual3, Dual3), LawError> {
        match drive {
            Some(c) => {
                let rate = self.crack_damage_rate(c, r_ratio);
                Ok((Dual3::cst(rate), Dual3::cst(c.energy_release_rate)))
            }
            None => self.local_damage_rate(eq, r_ratio),
        }
    }

    /// `dD/dN` from the point's own `G_max` and mode ratio.
    fn local_damage_rate(&self, eq: &Equivalent, r_ratio: f64) -> Result<(Dual3, Dual3), LawError> {
        let g_max = Self::energy_release_rate(eq);
        let dg = g_max * (1.0 - r_ratio * r_ratio);
        if dg.v.is_nan() || dg.v <= 0.0 || dg.v <= self.paris.g_th {
            return Ok((Dual3::cst(0.0), g_max));
        }
        let l_cz = self.zone_length(eq).ok_or_else(|| {
            LawError::Failed(format!(
                "{KEY}: the local estimate of G_max needs the cohesive-zone length: give `l_cz` or `E` in the law, or measure the crack (`[fatigue] energy_release_rate = \"crack_front\"`, the default)"
            ))
        })?;
        let x = dg / eq.g_c;
        let m = self.paris.exponent(eq.b);
        let ln_c = self.paris.ln_coefficient(eq.b);
        let da_dn = (ln_c + m * x.ln()).exp();
        Ok((da_dn / l_cz, g_max))
    }

    /// `dD/dN` from the crack's measured energy release rate, mode ratio
    /// and process-zone length: the same at every point of the zone.
    fn crack_damage_rate(&self, c: CrackDrive, r_ratio: f64) -> f64 {
        let Some((_, da_dn)) =
            self.fatigue_growth_rate(c.energy_release_rate, c.mode_ratio, r_ratio)
        else {
            return 0.0;
        };
        if c.process_zone_length > 0.0 {
            da_dn / c.process_zone_length
        } else {
            0.0
        }
    }

    /// The law in dual numbers seeded on the jump: traction and the damage
    /// it uses; trial state into `trial`.
    pub fn evaluate_dual(
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
        if !ctx.jump.iter().all(|v| v.is_finite()) {
            return Err(LawError::Failed(format!(
                "{KEY}: jump is not finite: {:?}",
                ctx.jump
            )));
        }
        let dn = ctx.step.delta_cycles;
        let r_ratio = ctx.step.load_ratio;
        if dn < 0.0 || !dn.is_finite() {
            return Err(LawError::Failed(format!(
                "{KEY}: delta_cycles = {dn} must be >= 0 and finite"
            )));
        }
        if dn > 0.0 && !(0.0..1.0).contains(&r_ratio) {
            return Err(LawError::Failed(format!(
                "{KEY}: load ratio R = {r_ratio} outside [0, 1) (DG = (1 - R^2) G_max holds for 0 <= R < 1)"
            )));
        }
        trial.copy_from_slice(c);
        trial[ENERGY_RELEASE_RATE] = 0.0;
        trial[DAMAGE_RATE] = 0.0;
        let (ks, kn) = (self.base.k_s, self.base.k_n);
        let dj = Dual3::seeds(ctx.jump);
        let d_hist = c[DAMAGE_HISTORY];
        let mut d = Dual3::cst(d_hist);
        if let Some(eq) = self.base.equivalent(dj)? {
            trial[MODE_RATIO] = eq.b.v;
            trial[INDEX] = eq.index.v;
            let Equivalent { lam0, k_b, g_c, .. } = eq;
            let f = |x: f64| LinearSoftening.dissipated(x, lam0.v, g_c.v, k_b.v);
            // static part: the bilinear law's update
            d = static_damage(&eq, d_hist);
            // fatigue part, in the process zone
            if (c[INDEX] >= 1.0 || d_hist > 0.0) && d.v < 1.0 {
                let (rate, g_max) = match self.damage_rate(&eq, r_ratio, ctx.step.crack_drive) {
                    Ok(v) => v,
                    Err(e) if dn > 0.0 => return Err(e),
                    // a static evaluation needs no rate
                    Err(_) => (Dual3::cst(0.0), Self::energy_release_rate(&eq)),
                };
                trial[ENERGY_RELEASE_RATE] = g_max.v;
                trial[DAMAGE_RATE] = rate.v;
                if dn > 0.0 && rate.v > 0.0 {
                    let lam_f = g_c * 2.0 / (k_b * lam0);
                    let big_d1 = energy_of_stiffness(d, lam0, lam_f);
                    let big_d2 = big_d1 + rate * dn;
                    if big_d2.v >= FULL {
                        trial[FATIGUE_DAMAGE] = c[FATIGUE_DAMAGE] + (1.0 - big_d1.v);
                        d = Dual3::cst(1.0);
                    } else {
                        trial[FATIGUE_DAMAGE] = c[FATIGUE_DAMAGE] + rate.v * dn;
                        d = stiffness_of_energy(big_d2, lam0, lam_f);
                    }
                }
            }
            if d.v > d_hist {
                trial[ENERGY] = c[ENERGY] + f(d.v) - f(d_hist);
            }
            trial[DAMAGE_HISTORY] = d.v.max(d_hist);
            trial[DAMAGE] = trial[DAMAGE_HISTORY];
        }
        let t = damaged_traction(d, dj, ks, kn);
        Ok((t, d))
    }
}

/// The parts of [`InterfaceLaw`] every fatigue law built on a static
/// `bilinear` part (`self.base`) and the `bilinear` slots (`$slot::DAMAGE`,
/// `$slot::INDEX`, `$slot::STATE_LEN`) shares: the key, the state, the
/// response of `self.evaluate_dual` (with the secant tangent the drivers
/// may ask for), the penalty, failure and tangent-kind queries, fracture
/// properties and warnings.
macro_rules! fatigue_law_common {
    ($key:expr, $slot:ident) => {
        fn key(&self) -> &'static str {
            $key
        }

        fn state_len(&self) -> usize {
            $slot::STATE_LEN
        }

        fn init_state(&self, state: &mut [f64]) {
            state.iter_mut().for_each(|v| *v = 0.0);
        }

        fn evaluate(
            &self,
            ctx: &junta_core::law::LawContext<'_>,
            trial: &mut [f64],
        ) -> Result<junta_core::law::LawResponse, junta_core::law::LawError> {
            let (t, d) = self.evaluate_dual(ctx, trial)?;
            let (ks, kn) = (self.base.k_s, self.base.k_n);
            let mut tangent = t.map(|x| x.d);
            if ctx.step.secant {
                let s = 1.0 - d.v;
                tangent = [[s * ks, 0.0, 0.0], [0.0, s * ks, 0.0], [0.0, 0.0, 0.0]];
                tangent[2][2] = if ctx.jump[2] > 0.0 { s * kn } else { kn };
            }
            Ok(junta_core::law::LawResponse {
                traction: t.map(|x| x.v),
                tangent,
            })
        }

        fn initial_stiffness(&self) -> [f64; 3] {
            self.base.initial_stiffness()
        }

        fn penalty_role(&self) -> junta_core::PenaltyRole {
            junta_core::PenaltyRole::Cohesive
        }

        /// Failed once the energy damage `D` (the fraction of `G_c(B)`
        /// dissipated) reaches 1 (to within `FAILED_ENERGY_DAMAGE`);
        /// process zone while `0 < d` short of that.
        fn stage(&self, state: &[f64]) -> junta_core::PointStage {
            $crate::law::fatigue_paris::fatigue_stage(&self.base, state)
        }

        fn failure_index(&self, state: &[f64]) -> Option<f64> {
            state.get($slot::INDEX).copied()
        }

        fn tangent_kind(&self) -> junta_core::MatrixKind {
            self.base.tangent_kind()
        }

        fn tangent_is_symmetrised(&self) -> bool {
            self.base.tangent_is_symmetrised()
        }

        fn fracture_properties(&self) -> Option<junta_core::FractureProperties> {
            self.base.fracture_properties()
        }

        fn warnings(&self) -> Vec<String> {
            self.base.warnings()
        }
    };
}
pub(crate) use fatigue_law_common;

impl InterfaceLaw for FatigueBilinear {
    fatigue_law_common!(KEY, slot);

    fn output_names(&self) -> &'static [&'static str] {
        &[
            output::DAMAGE,
            output::DISSIPATED_ENERGY,
            output::MODE_RATIO,
            output::FATIGUE_DAMAGE,
            output::ENERGY_RELEASE_RATE,
            output::DAMAGE_RATE,
            output::ENERGY_DAMAGE,
        ]
    }

    fn outputs(&self, state: &[f64], out: &mut [f64]) {
        use slot::*;
        if state.len() == STATE_LEN && out.len() == 7 {
            out[0] = state[DAMAGE];
            out[1] = state[ENERGY];
            out[2] = state[MODE_RATIO];
            out[3] = state[FATIGUE_DAMAGE];
            out[4] = state[ENERGY_RELEASE_RATE];
            out[5] = state[DAMAGE_RATE];
            out[6] = self.energy_damage(state[DAMAGE], state[MODE_RATIO]);
        }
    }

    fn fatigue_growth_rate(&self, g_max: f64, b: f64, r_ratio: f64) -> Option<(f64, f64)> {
        let (_, g_c, _) = self.base.mode_properties(b);
        let dg = (1.0 - r_ratio * r_ratio) * g_max;
        let rate = if dg > self.paris.g_th && dg > 0.0 {
            (self.paris.ln_coefficient(b) + self.paris.exponent(b) * (dg / g_c).ln()).exp()
        } else {
            0.0
        };
        Some((g_c, rate))
    }
}

inventory::submit! {
    LawEntry {
        key: KEY,
        description: "bilinear mixed-mode law with Paris-law high-cycle fatigue damage (Turon et al. 2007; mixed-mode C, m after Blanco et al. 2004; threshold, R-ratio)",
        params: PARAMS,
        build: |t| Ok(Arc::new(FatigueBilinear::from_table(t)?)),
    }
}
