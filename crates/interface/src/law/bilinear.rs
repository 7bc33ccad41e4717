//! `bilinear`: mixed-mode bilinear softening (Camanho & Davila 2002,
//! NASA/TM-2002-211737; Turon, Camanho, Costa & Davila 2006), the law of
//! Abaqus' `*DAMAGE EVOLUTION, TYPE=ENERGY, SOFTENING=LINEAR`.
//!
//! On the equivalent one-dimensional law of [`super::cohesive`] (equivalent
//! jump `lam`, penalty `K_B`, onset `lam_0` from the criterion, toughness
//! `G_c(B)`), the traction rises linearly to `tau_0 = K_B lam_0` and falls
//! linearly to zero at
//!
//! ```text
//! lam_f = 2 G_c / (K_B lam_0)                          (area of the triangle = G_c)
//! d(lam) = lam_f (lam - lam_0) / (lam (lam_f - lam_0)),   lam_0 <= lam <= lam_f;  1 beyond
//! ```
//!
//! which is `tau = (1 - d) K_B lam = tau_0 (lam_f - lam) / (lam_f - lam_0)`.
//! Dissipated energy of a monotone path to damage `d` (the area swept
//! under the curve minus the elastic energy left, `int psi dd`):
//!
//! ```text
//! lam(d) = lam_f lam_0 / (lam_f - d (lam_f - lam_0))
//! F(d)   = G_c (lam(d) - lam_0) / (lam_f - lam_0)          F(1) = G_c
//! ```
//!
//! With one penalty and the quadratic criterion, `lam_0` and `lam_f` are
//! Camanho & Davila's `delta_0m` and `delta_fm` (BENCHMARKS.md section 4).
//! Parameters, mixed mode, irreversibility, contact and viscosity: see
//! [`super::cohesive`].

use super::cohesive::{CohesiveLaw, Softening, PARAMS};
use junta_core::registry::LawEntry;
use junta_core::{CoreError, Dual3};
use std::sync::Arc;

/// Linear softening.
#[derive(Debug, Clone, Copy, Default)]
pub struct LinearSoftening;

impl Softening for LinearSoftening {
    fn name(&self) -> &'static str {
        "linear"
    }

    fn damage(&self, lam: Dual3, lam0: Dual3, g_c: Dual3, k_b: Dual3) -> Dual3 {
        let lam_f = g_c * 2.0 / (k_b * lam0);
        if lam.v >= lam_f.v {
            return Dual3::cst(1.0);
        }
        (lam_f * (lam - lam0) / (lam * (lam_f - lam0))).max(Dual3::cst(0.0))
    }

    fn dissipated(&self, d: f64, lam0: f64, g_c: f64, k_b: f64) -> f64 {
        if d <= 0.0 {
            return 0.0;
        }
        if d >= 1.0 {
            return g_c;
        }
        let lam_f = 2.0 * g_c / (k_b * lam0);
        let lam = lam_f * lam0 / (lam_f - d * (lam_f - lam0));
        g_c * (lam - lam0) / (lam_f - lam0)
    }
}

/// The `bilinear` law: [`CohesiveLaw`] with [`LinearSoftening`].
pub fn bilinear_from_table(t: &toml::Table) -> Result<CohesiveLaw, CoreError> {
    CohesiveLaw::from_table("bilinear", Arc::new(LinearSoftening), t)
}

inventory::submit! {
    LawEntry {
        key: "bilinear",
        description: "mixed-mode bilinear softening with fracture energies G_Ic, G_IIc (Camanho-Davila 2002 / Turon 2006; Abaqus SOFTENING=LINEAR)",
        params: PARAMS,
        build: |t| Ok(Arc::new(bilinear_from_table(t)?)),
    }
}
