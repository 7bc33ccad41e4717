//! `exponential`: mixed-mode exponential softening with the same onset,
//! mode ratio and toughnesses as `bilinear` (a BK-weighted exponential, the
//! shape of Abaqus' `SOFTENING=EXPONENTIAL` with its area fixed to `G_c`).
//!
//! On the equivalent one-dimensional law of [`super::cohesive`]: linear up
//! to `tau_0 = K_B lam_0`, then
//!
//! ```text
//! tau(lam) = tau_0 exp(-(lam - lam_0) / l),     l = (G_c - K_B lam_0^2 / 2) / tau_0
//! d(lam)   = 1 - (lam_0 / lam) exp(-(lam - lam_0) / l)
//! ```
//!
//! so the area under the whole curve is `K_B lam_0^2 / 2 + tau_0 l = G_c`.
//! The traction never reaches zero: damage counts as 1 once it exceeds
//! `1 - 1e-12`. **Failed point**: since no finite jump dissipates all of
//! `G_c`, a point counts as failed ([`junta_core::PointStage::Failed`])
//! once a monotone path to its damage has dissipated 99 % of `G_c(B)`
//! (`F(d) >= 0.99 G_c`, [`FAILED_ENERGY_FRACTION`]): at `x = (lam -
//! lam_0) / l` of about 4.6 to 6.6 (depending on `K_B lam_0^2 / 2 G_c`),
//! where the traction has fallen below 1 % of `tau_0`. Dissipated energy of a monotone path to damage `d`:
//! `lam(d)` solves `ln(lam_0 / lam) - (lam - lam_0) / l = ln(1 - d)` (a
//! decreasing convex function of `lam`: Newton from `lam_0` converges
//! monotonically), and
//!
//! ```text
//! F(d) = K_B lam_0^2 / 2 + tau_0 l (1 - e^{-x}) - tau_0 e^{-x} lam / 2,   x = (lam - lam_0) / l
//! ```
//!
//! (work done minus the elastic energy left), `F(1) = G_c`.

use super::cohesive::{CohesiveLaw, Softening, PARAMS};
use junta_core::registry::LawEntry;
use junta_core::{CoreError, Dual3};
use std::sync::Arc;

/// Fraction of `G_c` an exponential point has dissipated when it counts
/// as failed (see the module doc).
pub const FAILED_ENERGY_FRACTION: f64 = 0.99;

/// Exponential softening.
#[derive(Debug, Clone, Copy, Default)]
pub struct ExponentialSoftening;

impl Softening for ExponentialSoftening {
    fn name(&self) -> &'static str {
        "exponential"
    }

    fn damage(&self, lam: Dual3, lam0: Dual3, g_c: Dual3, k_b: Dual3) -> Dual3 {
        let tau0 = k_b * lam0;
        let l = (g_c - k_b * lam0 * lam0 * 0.5) / tau0;
        (1.0 - lam0 / lam * (-(lam - lam0) / l).exp()).max(Dual3::cst(0.0))
    }

    fn failed_energy_fraction(&self) -> f64 {
        FAILED_ENERGY_FRACTION
    }

    fn dissipated(&self, d: f64, lam0: f64, g_c: f64, k_b: f64) -> f64 {
        if d <= 0.0 {
            return 0.0;
        }
        if d >= 1.0 - 1e-12 {
            return g_c;
        }
        let tau0 = k_b * lam0;
        let l = (g_c - 0.5 * k_b * lam0 * lam0) / tau0;
        let target = (1.0 - d).ln();
        let mut lam = lam0;
        for _ in 0..100 {
            let h = (lam0 / lam).ln() - (lam - lam0) / l - target;
            let dh = -1.0 / lam - 1.0 / l;
            let step = h / dh;
            lam -= step;
            if step.abs() <= 1e-15 * lam {
                break;
            }
        }
        let e = (-(lam - lam0) / l).exp();
        0.5 * k_b * lam0 * lam0 + tau0 * l * (1.0 - e) - 0.5 * tau0 * e * lam
    }
}

/// The `exponential` law: [`CohesiveLaw`] with [`ExponentialSoftening`].
pub fn exponential_from_table(t: &toml::Table) -> Result<CohesiveLaw, CoreError> {
    CohesiveLaw::from_table("exponential", Arc::new(ExponentialSoftening), t)
}

inventory::submit! {
    LawEntry {
        key: "exponential",
        description: "mixed-mode exponential softening with the same onset and fracture energies as `bilinear` (Abaqus SOFTENING=EXPONENTIAL)",
        params: PARAMS,
        build: |t| Ok(Arc::new(exponential_from_table(t)?)),
    }
}
