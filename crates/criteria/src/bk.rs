//! `bk`: Turon's energy-consistent damage-onset criterion, built on the
//! Benzeggagh-Kenane (BK) mode interpolation (Turon, Camanho, Costa &
//! Davila 2006; Turon, Camanho, Costa & Renart 2010).
//!
//! With the undamaged penalties `K_s` (shear) and `K_n` (normal), the
//! opening part of the jump and the undamaged traction `t0 = K delta`:
//!
//! ```text
//! 2 psi   = t0_1 delta_1 + t0_2 delta_2 + <t0_n> <delta_n>       (twice the elastic energy)
//! B       = (t0_1 delta_1 + t0_2 delta_2) / (2 psi)              (mode ratio G_II / G_T, from energies)
//! 2 psi_0 = N^2 / K_n + (S^2 / K_s - N^2 / K_n) B^eta            (twice the onset energy)
//! index   = psi / psi_0,                  damage starts when index >= 1
//! ```
//!
//! Degree 2 in the jump. With one penalty `K` this is Turon 2006's
//! `delta_0^2 = delta_0n^2 + (delta_0s^2 - delta_0n^2) B^eta` with
//! `delta_0n = N/K`, `delta_0s = S/K`. With Turon 2018's shear penalty
//! `K_s = K (G_Ic/G_IIc)(S/N)^2` the onset energy is proportional to the
//! BK toughness `G_c(B)`, which keeps onset and propagation consistent for
//! every mode ratio.
//!
//! Traction-only evaluation ([`FailureCriterion::evaluate`], used by laws
//! that keep no jump, e.g. `paper_debond`) assumes one penalty for all
//! directions: `B = tau^2 / (tau^2 + <sigma_33>^2)`,
//! `index = (tau^2 + <sigma_33>^2) / (N^2 + (S^2 - N^2) B^eta)`.
//! Compression never contributes (`<.>` is the positive part).
//!
//! Parameters: `sigma_lim` (N), `tau_lim` (S), `eta` (BK exponent, > 0).

use crate::{check_limit, mode_of};
use junta_core::registry::{parse_params, CriterionEntry, ParamDoc};
use junta_core::{CoreError, Dual3, FailureCriterion, FailureResult, OnsetInput};
use serde::Deserialize;
use std::sync::Arc;

/// Turon's BK onset criterion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bk {
    /// Normal strength N.
    pub sigma_lim: f64,
    /// Shear strength S.
    pub tau_lim: f64,
    /// BK exponent eta.
    pub eta: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Params {
    sigma_lim: Option<f64>,
    tau_lim: Option<f64>,
    eta: Option<f64>,
}

impl Bk {
    /// A criterion with strengths `sigma_lim`, `tau_lim` (positive, finite)
    /// and BK exponent `eta` (positive, finite).
    pub fn new(sigma_lim: f64, tau_lim: f64, eta: f64) -> Result<Self, CoreError> {
        Ok(Bk {
            sigma_lim: check_limit("bk", "sigma_lim", sigma_lim)?,
            tau_lim: check_limit("bk", "tau_lim", tau_lim)?,
            eta: check_exponent("bk", "eta", eta)?,
        })
    }

    /// From a TOML table: `sigma_lim`, `tau_lim`, `eta`.
    pub fn from_table(t: &toml::Table) -> Result<Self, CoreError> {
        let p: Params = parse_params("criterion", "bk", t)?;
        let need = |v: Option<f64>, name: &str, what: &str| {
            v.ok_or_else(|| CoreError::InvalidParameters {
                kind: "criterion",
                key: "bk".into(),
                message: format!("missing `{name}` ({what})"),
            })
        };
        Self::new(
            need(p.sigma_lim, "sigma_lim", "normal strength N, > 0")?,
            need(p.tau_lim, "tau_lim", "shear strength S, > 0")?,
            need(p.eta, "eta", "BK exponent, > 0, e.g. 2.284 for AS4/PEEK")?,
        )
    }
}

/// Check an exponent: positive and finite; the error names the key.
pub(crate) fn check_exponent(criterion: &str, name: &str, v: f64) -> Result<f64, CoreError> {
    if v > 0.0 && v.is_finite() {
        Ok(v)
    } else {
        Err(CoreError::InvalidParameters {
            kind: "criterion",
            key: criterion.into(),
            message: format!("`{name}` = {v} must be positive and finite (an exponent)"),
        })
    }
}

impl FailureCriterion for Bk {
    fn key(&self) -> &'static str {
        "bk"
    }

    fn evaluate(&self, t: [f64; 3]) -> FailureResult {
        let tau2 = t[0] * t[0] + t[1] * t[1];
        let sn = t[2].max(0.0);
        let total = tau2 + sn * sn;
        let index = if total > 0.0 {
            let b = tau2 / total;
            let (n2, s2) = (self.sigma_lim.powi(2), self.tau_lim.powi(2));
            total / (n2 + (s2 - n2) * b.powf(self.eta))
        } else {
            0.0
        };
        FailureResult {
            index,
            mode: mode_of(t[2]),
        }
    }

    fn onset_index(&self, p: &OnsetInput) -> Option<Dual3> {
        let (t, d) = (p.traction, p.jump);
        let shear = t[0] * d[0] + t[1] * d[1];
        let two_psi = shear + t[2].pos() * d[2].pos();
        if two_psi.v <= 0.0 {
            return Some(Dual3::cst(0.0));
        }
        let b = shear / two_psi;
        let en = self.sigma_lim.powi(2) / p.penalty[2];
        let es = self.tau_lim.powi(2) / (0.5 * (p.penalty[0] + p.penalty[1]));
        Some(two_psi / ((es - en) * b.powf(self.eta) + en))
    }

    fn degree(&self) -> f64 {
        2.0
    }
}

inventory::submit! {
    CriterionEntry {
        key: "bk",
        description: "Turon's energy-consistent onset: psi / psi_0(B), 2 psi_0 = N^2/K_n + (S^2/K_s - N^2/K_n) B^eta (mode ratio B from energies)",
        params: &[
            ParamDoc { name: "sigma_lim", doc: "normal strength N, > 0 [stress]" },
            ParamDoc { name: "tau_lim", doc: "shear strength S, > 0 [stress]" },
            ParamDoc { name: "eta", doc: "BK exponent, > 0 (AS4/PEEK: 2.284)" },
        ],
        build: |t| Ok(Arc::new(Bk::from_table(t)?)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One penalty K: the onset jump reproduces Turon 2006's closed form
    /// delta_0^2 = delta_0n^2 + (delta_0s^2 - delta_0n^2) B^eta.
    #[test]
    fn onset_jump_is_turons_closed_form() {
        let (n, s, eta, k) = (80.0, 100.0, 2.284, 1e6);
        let c = Bk::new(n, s, eta).unwrap();
        for &(ds, dn) in &[(0.0, 1e-5), (1e-5, 0.0), (1e-5, 1e-5), (3e-5, 1e-5)] {
            let d = Dual3::seeds([ds, 0.0, dn]);
            let t = d.map(|x| x * k);
            let idx = c
                .onset_index(&OnsetInput {
                    traction: t,
                    jump: d,
                    penalty: [k; 3],
                })
                .unwrap();
            let b: f64 = ds * ds / (ds * ds + dn * dn);
            let (d0n, d0s) = (n / k, s / k);
            let d0sq = d0n * d0n + (d0s * d0s - d0n * d0n) * b.powf(eta);
            let expected = (ds * ds + dn * dn) / d0sq;
            assert!((idx.v - expected).abs() < 1e-12 * expected, "{ds} {dn}");
            // traction-only form agrees with one penalty
            let e2 = c.evaluate([k * ds, 0.0, k * dn]).index;
            assert!((e2 - expected).abs() < 1e-12 * expected);
        }
    }
}
