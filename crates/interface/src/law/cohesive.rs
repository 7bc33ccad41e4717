//! The mixed-mode damage machinery shared by the fracture-energy laws
//! (`bilinear`, `exponential`): equivalent jump, mode ratio, onset through a
//! [`FailureCriterion`], propagation toughness (BK or power law), an
//! irreversible damage history, exact dissipated energy, penalty contact,
//! optional viscous regularisation. The softening *shape* (what damage a
//! given jump gives between onset and full separation) is the only thing
//! the two laws differ in; it lives in their own files as a [`Softening`].
//!
//! # Mixed mode (Camanho & Davila 2002; Turon et al. 2006, 2018)
//!
//! Penalties `K_n` (normal) and `K_s` (both slips): `K_s = K_n` (`shear_penalty
//! = "equal"`) or Turon 2018's `K_s = K_n (G_Ic / G_IIc) (S / N)^2`
//! (`"turon2018"`). With the jump `delta = [delta_1, delta_2, delta_n]` and
//! only the opening part `<delta_n> = max(delta_n, 0)` driving damage:
//!
//! ```text
//! 2 psi = K_s (delta_1^2 + delta_2^2) + K_n <delta_n>^2     twice the undamaged elastic energy
//! B     = K_s (delta_1^2 + delta_2^2) / (2 psi)             mode ratio G_II / G_T, from energies
//! K_B   = (1 - B) K_n + B K_s                               equivalent penalty
//! lam   = 2 psi / |t0|,  t0 = [K_s delta_1, K_s delta_2, K_n <delta_n>]
//! ```
//!
//! so that `2 psi = K_B lam^2`: the point moves on an equivalent
//! one-dimensional law `tau = (1 - d) K_B lam` whose area is the toughness.
//! With one penalty, `lam = sqrt(delta_1^2 + delta_2^2 + <delta_n>^2)`, the
//! usual equivalent jump.
//!
//! **Onset** from the criterion: its index `I(delta)` of the undamaged
//! traction is homogeneous of degree `p` in the jump, so the onset jump
//! along the current direction is `lam_0 = lam I^(-1/p)` (quadratic: the
//! Camanho-Davila `delta_0m`; `bk`: Turon's energy form).
//!
//! **Propagation** toughness `G_c(B)`:
//!
//! ```text
//! bk          G_c = G_Ic + (G_IIc - G_Ic) B^eta                         (Benzeggagh & Kenane 1996)
//! power_law   G_c = [ ((1 - B) / G_Ic)^alpha + (B / G_IIc)^alpha ]^(-1/alpha)
//! ```
//!
//! **Damage**: the shape gives `d_B(lam)` for the current mode ratio,
//! increasing from 0 at `lam_0` to 1 at full separation, with
//! `int tau dlam = G_c(B)` over the whole curve. The history variable is the
//! damage itself: `d = max(d_committed, d_B(lam))`. Damage is a normalised
//! threshold (it fixes the fraction of the stiffness lost, whatever the
//! mode): a change of mixity can never lower it (no healing), and a point
//! reloads elastically until its jump reaches the curve of the current mode
//! at the damage it already has.
//!
//! **Dissipated energy** per unit area, exact for any increment size: on
//! the curve of the current mode, the energy dissipated from the undamaged
//! state to damage `d` by a monotone path is `F_B(d)` (closed form per
//! shape, `F_B(1) = G_c(B)`); an increment that raises the damage from `d_0`
//! to `d_1` dissipates `F_B(d_1) - F_B(d_0)` with the mode of that
//! increment. A proportional path dissipates exactly `G_c(B)`; a path whose
//! mode turns dissipates the sum of its pieces, never less than the
//! smallest and never more than the largest `G_c` it met.
//!
//! **Traction** (compression never damages; contact keeps the penalty,
//! even after full separation):
//!
//! ```text
//! t_i = (1 - d) K_s delta_i                  (i = 1, 2)
//! t_n = (1 - d) K_n delta_n   if delta_n > 0,   K_n delta_n   otherwise
//! ```
//!
//! **Viscous regularisation** (Abaqus `*DAMAGE STABILIZATION`, MOOSE's
//! `viscosity`): with viscosity `mu > 0` the traction uses `d_v`, relaxed
//! towards the rate-independent `d` by `d_v' = (d - d_v) / mu`, integrated by
//! backward Euler over the load-factor increment `dt`:
//! `d_v = (mu d_v,0 + dt d) / (mu + dt)`. The fracture energy is then
//! `F_B(d_v)` accumulated as above, and the viscous energy is the rest of
//! what the regularised law dissipates, `sum psi (d_v,1 - d_v,0) - (F_B(d_v,1)
//! - F_B(d_v,0))` (reported separately; it can be slightly negative in an
//! increment where the point unloads while `d_v` still catches up).
//!
//! **Tangent**: the whole evaluation runs in forward-mode dual numbers
//! ([`Dual3`]) seeded on the jump, so the tangent is the exact derivative of
//! the branch taken (loading: `d` depends on the jump; unloading,
//! reloading below the curve and full separation: `d` fixed). On the damage
//! surface itself (`d_B = d_committed`: the converged state an increment
//! starts from) it is the loading branch, the one-sided derivative towards
//! more damage, so that the first iteration of an increment, and the
//! dissipation constraint of path following, see the softening. With a mode
//! ratio that changes with the jump, the exact tangent is not symmetric;
//! the interface element assembles its symmetric part (the tangent of a
//! symmetric storage), which keeps Newton's convergence quadratic in pure
//! modes and fixed-mode loading, and slows it slightly where the mixity
//! turns. When the driver asks for it ([`StepInfo::secant`], after Newton
//! with the consistent tangent stopped reducing the residual), the law
//! returns its secant stiffness `diag((1-d) K_s, (1-d) K_s, (1-d) K_n or K_n)`
//! instead: positive definite, linear convergence, no cycling between the
//! loading and unloading branches.
//!
//! [`StepInfo::secant`]: junta_core::element::StepInfo::secant

use junta_core::law::{
    output, FractureProperties, InterfaceLaw, LawContext, LawError, LawResponse, PointStage,
};
use junta_core::registry::{entries, find, parse_params, CriterionEntry};
use junta_core::{CoreError, Dual3, FailureCriterion, MatrixKind, OnsetInput};
use serde::Deserialize;
use std::sync::Arc;

// Keep the criteria crate linked so that its registry entries are present.
use junta_criteria as _;

/// State layout of one integration point.
pub mod slot {
    /// Rate-independent damage history `d` (max over the path).
    pub const DAMAGE_HISTORY: usize = 0;
    /// Damage the traction uses (`d`, or the viscous `d_v`).
    pub const DAMAGE: usize = 1;
    /// Fracture energy dissipated per unit area.
    pub const ENERGY: usize = 2;
    /// Viscous energy per unit area.
    pub const VISCOUS: usize = 3;
    /// Mode ratio B of the last evaluation with an opening (or slip).
    pub const MODE_RATIO: usize = 4;
    /// Onset index of the last evaluation (`>= 1`: at or past onset).
    pub const INDEX: usize = 5;
    /// Number of state values per point.
    pub const STATE_LEN: usize = 6;
}

/// Damage above which a damage value is taken as exactly 1.
const FULL: f64 = 1.0 - 1e-12;

/// A softening shape on the equivalent one-dimensional law: undamaged
/// slope `k_b` up to `lam_0`, then a descending branch of total area `g_c`.
pub trait Softening: Send + Sync + std::fmt::Debug {
    /// Name of the shape, for messages.
    fn name(&self) -> &'static str;
    /// Damage `d_B(lam)` for `lam > lam_0` (values in `[0, 1]`), as a dual
    /// number (the arguments carry their gradients).
    fn damage(&self, lam: Dual3, lam0: Dual3, g_c: Dual3, k_b: Dual3) -> Dual3;
    /// Energy dissipated per unit area by a monotone path from the
    /// undamaged state to damage `d` on this curve (`F(1) = g_c`).
    fn dissipated(&self, d: f64, lam0: f64, g_c: f64, k_b: f64) -> f64;
    /// The fraction of `g_c` a point has dissipated when it counts as
    /// failed ([`junta_core::PointStage::Failed`]). 1 (the default): the
    /// point fails where the curve reaches zero traction, having
    /// dissipated all of `g_c`; a shape whose traction never reaches zero
    /// states a fraction below 1 in its doc.
    fn failed_energy_fraction(&self) -> f64 {
        1.0
    }
}

/// Propagation criterion: the toughness at mode ratio B.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Propagation {
    /// Benzeggagh-Kenane: `G_c = G_Ic + (G_IIc - G_Ic) B^eta`.
    Bk {
        /// BK exponent `eta > 0` (AS4/PEEK: 2.284).
        eta: f64,
    },
    /// Power law: `G_c = [((1 - B) / G_Ic)^alpha + (B / G_IIc)^alpha]^(-1/alpha)`.
    PowerLaw {
        /// Exponent `alpha > 0` (1 linear, 2 quadratic).
        alpha: f64,
    },
}

impl Propagation {
    /// `G_c(B)`.
    pub fn toughness(&self, b: Dual3, g1: f64, g2: f64) -> Dual3 {
        match *self {
            Propagation::Bk { eta } => b.powf(eta) * (g2 - g1) + g1,
            Propagation::PowerLaw { alpha } => {
                let s = ((1.0 - b) / g1).powf(alpha) + (b / g2).powf(alpha);
                s.powf(-1.0 / alpha)
            }
        }
    }
}

/// Choice of the shear penalty.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum ShearPenalty {
    /// `K_s = K_n`.
    #[default]
    Equal,
    /// Turon et al. 2018: `K_s = K_n (G_Ic / G_IIc) (S / N)^2`.
    Turon2018,
}

/// A mixed-mode fracture-energy law with a softening shape.
#[derive(Debug, Clone)]
pub struct CohesiveLaw {
    key: &'static str,
    shape: Arc<dyn Softening>,
    /// Normal penalty K_n.
    pub k_n: f64,
    /// Shear penalty K_s.
    pub k_s: f64,
    /// Normal strength N.
    pub n: f64,
    /// Shear strength S.
    pub s: f64,
    /// Mode I toughness.
    pub g_ic: f64,
    /// Mode II toughness.
    pub g_iic: f64,
    /// Propagation criterion.
    pub propagation: Propagation,
    /// Shear penalty rule.
    pub shear_penalty: ShearPenalty,
    /// Viscosity (load-factor units; 0 = none).
    pub viscosity: f64,
    /// Assemble the exact (nonsymmetric in mixed mode) tangent instead of
    /// its symmetric part (`tangent = "exact"`; needs the `lu` back end).
    pub exact_tangent: bool,
    criterion: Arc<dyn FailureCriterion>,
    warnings: Vec<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Params {
    #[serde(rename = "K")]
    k: Option<f64>,
    #[serde(rename = "N")]
    n: Option<f64>,
    #[serde(rename = "S")]
    s: Option<f64>,
    #[serde(rename = "G_Ic")]
    g_ic: Option<f64>,
    #[serde(rename = "G_IIc")]
    g_iic: Option<f64>,
    propagation: Option<String>,
    eta: Option<f64>,
    alpha: Option<f64>,
    onset: Option<toml::Value>,
    shear_penalty: Option<ShearPenalty>,
    viscosity: Option<f64>,
    tangent: Option<String>,
}

/// Parameter documentation shared by the fracture-energy laws.
pub const PARAMS: &[junta_core::registry::ParamDoc] = &[
    junta_core::registry::ParamDoc { name: "K", doc: "normal penalty stiffness K_n > 0 [force/length^3] (Turon: K = 50 E_33 / t_ply or more)" },
    junta_core::registry::ParamDoc { name: "N", doc: "normal (mode I) strength > 0 [stress]" },
    junta_core::registry::ParamDoc { name: "S", doc: "shear (mode II) strength > 0 [stress]" },
    junta_core::registry::ParamDoc { name: "G_Ic", doc: "mode I toughness > 0 [energy/area]" },
    junta_core::registry::ParamDoc { name: "G_IIc", doc: "mode II toughness > 0 [energy/area]" },
    junta_core::registry::ParamDoc { name: "propagation", doc: "\"bk\" (default; needs eta) or \"power_law\" (needs alpha)" },
    junta_core::registry::ParamDoc { name: "eta", doc: "BK exponent > 0 (AS4/PEEK: 2.284); also used by onset = \"bk\"" },
    junta_core::registry::ParamDoc { name: "alpha", doc: "power-law exponent > 0 (1 linear, 2 quadratic)" },
    junta_core::registry::ParamDoc { name: "onset", doc: "damage-onset criterion: \"quadratic\" (default, Abaqus QUADS), \"max_stress\" (MAXS), \"bk\" (Turon), given N and S (and eta); or a table { type = .., .. } with its own parameters" },
    junta_core::registry::ParamDoc { name: "shear_penalty", doc: "\"equal\" (default: K_s = K) or \"turon2018\" (K_s = K (G_Ic/G_IIc)(S/N)^2)" },
    junta_core::registry::ParamDoc { name: "viscosity", doc: "viscous regularisation mu >= 0 in load-factor units (default 0: none); its energy is reported apart from the fracture energy" },
    junta_core::registry::ParamDoc { name: "tangent", doc: "\"symmetric\" (default: the interface element assembles the symmetric part of the mixed-mode tangent; cholesky/ldlt) or \"exact\" (the full, nonsymmetric tangent where the mode ratio changes; quadratic convergence in mixed mode; solved by lu)" },
];

fn criterion_keys() -> String {
    entries::<CriterionEntry>()
        .iter()
        .map(|e| e.key)
        .collect::<Vec<_>>()
        .join(", ")
}

impl CohesiveLaw {
    /// Build from a TOML table (see [`PARAMS`]) with the softening `shape`;
    /// `key` names the law in errors.
    pub fn from_table(
        key: &'static str,
        shape: Arc<dyn Softening>,
        t: &toml::Table,
    ) -> Result<Self, CoreError> {
        let invalid = |message: String| CoreError::InvalidParameters {
            kind: "law",
            key: key.into(),
            message,
        };
        let p: Params = parse_params("law", key, t)?;
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
        let k = positive(p.k, "K", "normal penalty stiffness, force/length^3")?;
        let n = positive(p.n, "N", "normal strength, stress")?;
        let s = positive(p.s, "S", "shear strength, stress")?;
        let g_ic = positive(p.g_ic, "G_Ic", "mode I toughness, energy/area")?;
        let g_iic = positive(p.g_iic, "G_IIc", "mode II toughness, energy/area")?;
        let propagation = match p.propagation.as_deref().unwrap_or("bk") {
            "bk" => Propagation::Bk {
                eta: positive(p.eta, "eta", "BK exponent, e.g. 2.284")?,
            },
            "power_law" => Propagation::PowerLaw {
                alpha: positive(p.alpha, "alpha", "power-law exponent, e.g. 1 or 2")?,
            },
            other => {
                return Err(invalid(format!(
                    "`propagation` = \"{other}\"; valid: \"bk\", \"power_law\""
                )))
            }
        };
        let viscosity = match p.viscosity {
            None => 0.0,
            Some(v) if v >= 0.0 && v.is_finite() => v,
            Some(v) => {
                return Err(invalid(format!(
                    "`viscosity` = {v} must be >= 0 and finite (load-factor units)"
                )))
            }
        };
        let shear_penalty = p.shear_penalty.unwrap_or_default();
        let k_s = match shear_penalty {
            ShearPenalty::Equal => k,
            ShearPenalty::Turon2018 => k * (g_ic / g_iic) * (s / n).powi(2),
        };
        let criterion = build_onset(key, p.onset.as_ref(), n, s, p.eta)?;
        let exact_tangent = match p.tangent.as_deref() {
            None | Some("symmetric") => false,
            Some("exact") => true,
            Some(other) => {
                return Err(invalid(format!(
                    "`tangent` = \"{other}\": use \"symmetric\" or \"exact\""
                )))
            }
        };
        let mut law = CohesiveLaw {
            key,
            shape,
            k_n: k,
            k_s,
            n,
            s,
            g_ic,
            g_iic,
            propagation,
            shear_penalty,
            viscosity,
            exact_tangent,
            criterion,
            warnings: Vec::new(),
        };
        law.check_consistency().map_err(invalid)?;
        Ok(law)
    }

    /// The [`PointStage`] of a point's state (the first
    /// [`slot::STATE_LEN`] values), see [`InterfaceLaw::stage`] above.
    pub fn stage_of(&self, state: &[f64]) -> PointStage {
        let d = state.get(slot::DAMAGE).copied().unwrap_or(0.0);
        if d <= 0.0 {
            return PointStage::Intact;
        }
        if d >= FULL {
            return PointStage::Failed;
        }
        let fraction = self.shape.failed_energy_fraction();
        if fraction < 1.0 {
            let b = state.get(slot::MODE_RATIO).copied().unwrap_or(0.0);
            let (lam0, g_c, k_b) = self.mode_properties(b);
            if self.shape.dissipated(d, lam0, g_c, k_b) >= fraction * g_c {
                return PointStage::Failed;
            }
        }
        PointStage::ProcessZone
    }

    /// The onset criterion.
    pub fn criterion(&self) -> &Arc<dyn FailureCriterion> {
        &self.criterion
    }

    /// Onset jump `lam_0`, toughness and equivalent penalty at mode ratio
    /// `b` (for checks and advice).
    pub fn mode_properties(&self, b: f64) -> (f64, f64, f64) {
        // a unit-energy jump with this mode ratio
        let ds = (b / self.k_s).sqrt();
        let dn = ((1.0 - b) / self.k_n).sqrt();
        let jump = Dual3::seeds([ds, 0.0, dn]);
        let t0 = [jump[0] * self.k_s, jump[1] * self.k_s, jump[2] * self.k_n];
        let idx = self
            .criterion
            .onset_index(&OnsetInput {
                traction: t0,
                jump,
                penalty: [self.k_s, self.k_s, self.k_n],
            })
            .map(|d| d.v)
            .unwrap_or(f64::NAN);
        let k_b = (1.0 - b) * self.k_n + b * self.k_s;
        let lam = (1.0 / k_b).sqrt(); // 2 psi = 1 = K_B lam^2
        let lam0 = lam * idx.powf(-1.0 / self.criterion.degree());
        let g_c = self
            .propagation
            .toughness(Dual3::cst(b), self.g_ic, self.g_iic)
            .v;
        (lam0, g_c, k_b)
    }

    /// Errors for modes where the toughness cannot hold the elastic energy
    /// at onset (`G_c <= K_B lam_0^2 / 2`: no descending branch), warnings
    /// for Turon's 2010 consistency condition.
    fn check_consistency(&mut self) -> Result<(), String> {
        for i in 0..=20 {
            let b = i as f64 / 20.0;
            let (lam0, g_c, k_b) = self.mode_properties(b);
            let elastic = 0.5 * k_b * lam0 * lam0;
            if !(lam0.is_finite() && lam0 > 0.0) {
                return Err(format!(
                    "onset criterion `{}` gives no finite onset at mode ratio B = {b}",
                    self.criterion.key()
                ));
            }
            if g_c <= elastic {
                return Err(format!(
                    "at mode ratio B = {b:.2} the toughness G_c = {g_c:.4e} does not exceed the elastic energy at onset K_B lam_0^2 / 2 = {elastic:.4e}: raise G_Ic/G_IIc or K, or lower N/S (mode I needs G_Ic > N^2 / (2 K))"
                ));
            }
        }
        if self.shear_penalty == ShearPenalty::Equal {
            let s_consistent = self.n * (self.g_iic / self.g_ic).sqrt();
            if ((self.s - s_consistent) / s_consistent).abs() > 0.01 {
                self.warnings.push(format!(
                    "law `{}`: with one penalty K for all modes, S = {:.4e} breaks Turon's 2010 consistency condition S = N sqrt(G_IIc/G_Ic) = {:.4e}: mixed-mode onset and propagation disagree; set shear_penalty = \"turon2018\" (K_s = K (G_Ic/G_IIc)(S/N)^2 = {:.4e}) or S = {:.4e}",
                    self.key,
                    self.s,
                    s_consistent,
                    self.k_n * (self.g_ic / self.g_iic) * (self.s / self.n).powi(2),
                    s_consistent
                ));
            }
        }
        Ok(())
    }
}

/// Build the onset criterion from the law's `onset` value: a registry key
/// (given the law's `N`, `S` and, when it takes one, `eta`) or a full table.
fn build_onset(
    key: &str,
    onset: Option<&toml::Value>,
    n: f64,
    s: f64,
    eta: Option<f64>,
) -> Result<Arc<dyn FailureCriterion>, CoreError> {
    let invalid = |message: String| CoreError::InvalidParameters {
        kind: "law",
        key: key.into(),
        message,
    };
    let (ty, table) = match onset {
        None => ("quadratic".to_string(), None),
        Some(toml::Value::String(s)) => (s.clone(), None),
        Some(toml::Value::Table(t)) => match t.get("type") {
            Some(toml::Value::String(s)) => (s.clone(), Some(t.clone())),
            _ => {
                return Err(invalid(format!(
                    "`onset` table needs `type` (a string); valid types: {}",
                    criterion_keys()
                )))
            }
        },
        Some(other) => {
            return Err(invalid(format!(
                "`onset` must be a criterion name or a table, not {other}; valid: {}",
                criterion_keys()
            )))
        }
    };
    let entry = find::<CriterionEntry>(&ty).map_err(|e| invalid(format!("`onset`: {e}")))?;
    let table = match table {
        Some(mut t) => {
            t.remove("type");
            t
        }
        None => {
            let mut t = toml::Table::new();
            for p in entry.params {
                match p.name {
                    "sigma_lim" => {
                        t.insert("sigma_lim".into(), n.into());
                    }
                    "tau_lim" => {
                        t.insert("tau_lim".into(), s.into());
                    }
                    "eta" => {
                        let eta = eta.ok_or_else(|| {
                            invalid(format!(
                                "onset criterion `{ty}` needs the law's `eta` (BK exponent)"
                            ))
                        })?;
                        t.insert("eta".into(), eta.into());
                    }
                    _ => {}
                }
            }
            t
        }
    };
    let c = (entry.build)(&table).map_err(|e| invalid(format!("`onset`: {e}")))?;
    // can it drive a softening law?
    let probe = Dual3::seeds([1e-3, 0.0, 1e-3]);
    if c.onset_index(&OnsetInput {
        traction: probe,
        jump: probe,
        penalty: [1.0; 3],
    })
    .is_none()
    {
        return Err(invalid(format!(
            "criterion `{ty}` gives no onset index of a jump, so it cannot start damage in a softening law; use one of: {}",
            entries::<CriterionEntry>()
                .iter()
                .filter(|e| (e.build)(&default_table(e.params)).is_ok_and(|c| c
                    .onset_index(&OnsetInput {
                        traction: probe,
                        jump: probe,
                        penalty: [1.0; 3]
                    })
                    .is_some()))
                .map(|e| e.key)
                .collect::<Vec<_>>()
                .join(", ")
        )));
    }
    Ok(c)
}

/// A table giving 1.0 to every documented parameter (to probe a criterion).
fn default_table(params: &[junta_core::registry::ParamDoc]) -> toml::Table {
    let mut t = toml::Table::new();
    for p in params {
        if p.name != "compression" {
            t.insert(p.name.into(), 1.0.into());
        }
    }
    t
}

impl InterfaceLaw for CohesiveLaw {
    fn key(&self) -> &'static str {
        self.key
    }

    fn state_len(&self) -> usize {
        slot::STATE_LEN
    }

    fn init_state(&self, state: &mut [f64]) {
        state.iter_mut().for_each(|v| *v = 0.0);
    }

    fn evaluate(&self, ctx: &LawContext<'_>, trial: &mut [f64]) -> Result<LawResponse, LawError> {
        let (t, d) = self.evaluate_dual(ctx, trial)?;
        let (ks, kn) = (self.k_s, self.k_n);
        let mut tangent = t.map(|x| x.d);
        if ctx.step.secant {
            // secant stiffness of the damaged point (positive definite)
            let s = 1.0 - d.v;
            tangent = [[s * ks, 0.0, 0.0], [0.0, s * ks, 0.0], [0.0, 0.0, 0.0]];
            tangent[2][2] = if ctx.jump[2] > 0.0 { s * kn } else { kn };
        }
        Ok(LawResponse {
            traction: t.map(|x| x.v),
            tangent,
        })
    }

    fn initial_stiffness(&self) -> [f64; 3] {
        [self.k_s, self.k_s, self.k_n]
    }

    /// `K` is the cohesive law's initial stiffness: it adds compliance
    /// and sets the onset opening (Turon et al. 2007: `K >= 50 E_33 / t`).
    fn penalty_role(&self) -> junta_core::PenaltyRole {
        junta_core::PenaltyRole::Cohesive
    }

    /// Failed once the damage the traction uses reaches 1 (the point is
    /// traction-free: the equivalent jump has reached `lam_f` and `G_c(B)`
    /// is dissipated), or, for a shape whose traction never reaches zero,
    /// once a monotone path to that damage at the last mode ratio has
    /// dissipated [`Softening::failed_energy_fraction`] of `G_c(B)`;
    /// process zone while `0 < d` short of that.
    fn stage(&self, state: &[f64]) -> PointStage {
        self.stage_of(state)
    }

    fn failure_index(&self, state: &[f64]) -> Option<f64> {
        state.get(slot::INDEX).copied()
    }

    fn tangent_kind(&self) -> MatrixKind {
        if self.exact_tangent {
            MatrixKind::General
        } else {
            MatrixKind::SymmetricIndefinite
        }
    }

    fn tangent_is_symmetrised(&self) -> bool {
        // mixed mode: the mode ratio changes with the jump
        !self.exact_tangent
    }

    fn output_names(&self) -> &'static [&'static str] {
        &[
            output::DAMAGE,
            output::DISSIPATED_ENERGY,
            output::VISCOUS_ENERGY,
            output::MODE_RATIO,
        ]
    }

    fn outputs(&self, state: &[f64], out: &mut [f64]) {
        use slot::*;
        if state.len() == STATE_LEN && out.len() == 4 {
            out[0] = state[DAMAGE];
            out[1] = state[ENERGY];
            out[2] = state[VISCOUS];
            out[3] = state[MODE_RATIO];
        }
    }

    fn fracture_properties(&self) -> Option<FractureProperties> {
        Some(FractureProperties {
            strength_normal: self.n,
            strength_shear: self.s,
            toughness_mode_i: self.g_ic,
            toughness_mode_ii: self.g_iic,
            penalty: self.initial_stiffness(),
        })
    }

    fn warnings(&self) -> Vec<String> {
        self.warnings.clone()
    }
}

/// The equivalent one-dimensional law at a jump (see the module doc), in
/// dual numbers seeded on the jump: what [`CohesiveLaw::equivalent`]
/// returns for laws built on this machinery (`fatigue_bilinear`).
#[derive(Debug, Clone, Copy)]
pub struct Equivalent {
    /// Twice the undamaged elastic energy `2 psi = K_B lam^2`.
    pub two_psi: Dual3,
    /// Mode ratio `B = G_II / G_T`.
    pub b: Dual3,
    /// Onset index `I` of the undamaged traction (`>= 1`: past onset).
    pub index: Dual3,
    /// Equivalent jump `lam`.
    pub lam: Dual3,
    /// Onset jump `lam_0` along the current direction.
    pub lam0: Dual3,
    /// Equivalent penalty `K_B`.
    pub k_b: Dual3,
    /// Toughness `G_c(B)`.
    pub g_c: Dual3,
}

impl CohesiveLaw {
    /// The equivalent one-dimensional law at the jump `dj` (dual numbers):
    /// `None` when nothing drives damage (`2 psi = 0`: closed and no slip).
    pub fn equivalent(&self, dj: [Dual3; 3]) -> Result<Option<Equivalent>, LawError> {
        let (ks, kn) = (self.k_s, self.k_n);
        let dn_pos = dj[2].pos();
        let t0 = [dj[0] * ks, dj[1] * ks, dn_pos * kn];
        let shear2 = (dj[0] * dj[0] + dj[1] * dj[1]) * ks;
        let two_psi = shear2 + dn_pos * dn_pos * kn;
        if two_psi.v <= 0.0 {
            return Ok(None);
        }
        let b = shear2 / two_psi;
        let index = self
            .criterion
            .onset_index(&OnsetInput {
                traction: t0,
                jump: [dj[0], dj[1], dn_pos],
                penalty: [ks, ks, kn],
            })
            .ok_or_else(|| {
                LawError::Failed(format!(
                    "{}: criterion `{}` gives no onset index",
                    self.key,
                    self.criterion.key()
                ))
            })?;
        let t0_norm = (t0[0] * t0[0] + t0[1] * t0[1] + t0[2] * t0[2]).sqrt();
        let lam = two_psi / t0_norm;
        let lam0 = lam * index.powf(-1.0 / self.criterion.degree());
        let k_b = (1.0 - b) * kn + b * ks;
        let g_c = self.propagation.toughness(b, self.g_ic, self.g_iic);
        Ok(Some(Equivalent {
            two_psi,
            b,
            index,
            lam,
            lam0,
            k_b,
            g_c,
        }))
    }
}

impl CohesiveLaw {
    /// The law in dual numbers seeded on the jump: the traction and the
    /// damage the traction uses (`d`, or the viscous `d_v`), each with its
    /// derivatives in the jump; trial state into `trial`. Laws built on
    /// this one (`bilinear_friction`) combine these.
    pub fn evaluate_dual(
        &self,
        ctx: &LawContext<'_>,
        trial: &mut [f64],
    ) -> Result<([Dual3; 3], Dual3), LawError> {
        use slot::*;
        let c = ctx.state_committed;

        if c.len() != STATE_LEN || trial.len() != STATE_LEN {
            return Err(LawError::Failed(format!(
                "{}: state slices of length {} (committed) and {} (trial), expected {STATE_LEN}",
                self.key,
                c.len(),
                trial.len()
            )));
        }
        if !ctx.jump.iter().all(|v| v.is_finite()) {
            return Err(LawError::Failed(format!(
                "{}: jump is not finite: {:?}",
                self.key, ctx.jump
            )));
        }
        trial.copy_from_slice(c);
        let (ks, kn) = (self.k_s, self.k_n);
        let dj = Dual3::seeds(ctx.jump);
        let d_hist = c[DAMAGE_HISTORY];
        let mut d = Dual3::cst(d_hist);
        if let Some(eq) = self.equivalent(dj)? {
            let Equivalent {
                two_psi,
                b,
                index: idx,
                lam,
                lam0,
                k_b,
                g_c,
            } = eq;
            trial[MODE_RATIO] = b.v;
            trial[INDEX] = idx.v;
            if idx.v > 1.0 && d_hist < 1.0 {
                let mut d_b = self.shape.damage(lam, lam0, g_c, k_b);
                if d_b.v >= FULL {
                    d_b = Dual3::cst(1.0);
                }
                // On the damage surface itself (`d_B = d_committed`, e.g.
                // at the converged point an increment starts from) the
                // tangent is the loading one: the one-sided derivative in
                // the direction of further damage. The secant one there
                // would hide the softening from the first iteration (and
                // make the dissipation constraint of path following
                // singular).
                if d_b.v > d_hist || (d_b.v == d_hist && d_hist > 0.0) {
                    d = d_b;
                    trial[DAMAGE_HISTORY] = d.v;
                }
                // energy on the curve of this increment's mode
                let f = |x: f64| self.shape.dissipated(x, lam0.v, g_c.v, k_b.v);
                if self.viscosity == 0.0 {
                    if d.v > d_hist {
                        trial[ENERGY] = c[ENERGY] + f(d.v) - f(d_hist);
                    }
                    trial[DAMAGE] = d.v;
                } else {
                    let dt = ctx.step.delta_load_factor.max(0.0);
                    let mu = self.viscosity;
                    let dv0 = c[DAMAGE];
                    let dv = (d * dt + dv0 * mu) / (mu + dt);
                    trial[DAMAGE] = dv.v;
                    let frac = f(dv.v) - f(dv0);
                    trial[ENERGY] = c[ENERGY] + frac;
                    trial[VISCOUS] = c[VISCOUS] + 0.5 * two_psi.v * (dv.v - dv0) - frac;
                    d = dv;
                }
            } else if self.viscosity > 0.0 {
                d = self.relax_viscous(c, ctx.step.delta_load_factor, two_psi.v, trial);
            }
        } else if self.viscosity > 0.0 {
            d = self.relax_viscous(c, ctx.step.delta_load_factor, 0.0, trial);
        }
        let one_m_d = 1.0 - d;
        let t = [
            one_m_d * dj[0] * ks,
            one_m_d * dj[1] * ks,
            if dj[2].v > 0.0 {
                one_m_d * dj[2] * kn
            } else {
                dj[2] * kn
            },
        ];
        Ok((t, d))
    }

    /// Viscous damage relaxing towards the (unchanged) history while the
    /// point does not load: `d_v = (mu d_v,0 + dt d) / (mu + dt)`, constant
    /// in the jump. Books its energy like a loading increment.
    fn relax_viscous(&self, c: &[f64], dt: f64, two_psi: f64, trial: &mut [f64]) -> Dual3 {
        use slot::*;
        let dt = dt.max(0.0);
        let mu = self.viscosity;
        let dv0 = c[DAMAGE];
        let dv = (mu * dv0 + dt * c[DAMAGE_HISTORY]) / (mu + dt);
        if dv > dv0 {
            let b = c[MODE_RATIO];
            let (lam0, g_c, k_b) = self.mode_properties(b);
            let frac = self.shape.dissipated(dv, lam0, g_c, k_b)
                - self.shape.dissipated(dv0, lam0, g_c, k_b);
            trial[ENERGY] = c[ENERGY] + frac;
            trial[VISCOUS] = c[VISCOUS] + 0.5 * two_psi * (dv - dv0) - frac;
        }
        trial[DAMAGE] = dv;
        Dual3::cst(dv)
    }
}
