//! `puck`: Puck's action-plane criterion, fibre fracture and inter-fibre
//! fracture in 3D.
//!
//! A. Puck, H. Schürmann, "Failure analysis of FRP laminates by means of
//! physically based phenomenological models", Compos. Sci. Technol. 58
//! (1998) 1045-1067 and 62 (2002) 1633-1662; parameters after A. Puck,
//! J. Kopp, M. Knops, Compos. Sci. Technol. 62 (2002) 371-378.
//!
//! Stress `[s11, s22, s33, t12, t23, t31]` in the ply axes. Fibre fracture
//! (FF), by maximum stress on `s11`: `f_FF = s11/Xt` (`s11 >= 0`) or
//! `-s11/Xc`. Inter-fibre fracture (IFF) on the action plane, the plane
//! parallel to the fibres whose normal makes the angle `theta` with axis 2
//! about axis 1:
//!
//! ```text
//! s_n(theta)  =  s22 cos^2 + s33 sin^2 + 2 t23 sin cos
//! t_nt(theta) = (s33 - s22) sin cos + t23 (cos^2 - sin^2)
//! t_n1(theta) =  t31 sin + t12 cos
//!
//! s_n >= 0:  f_E = sqrt( ((1/R_t - p+/R_psi) s_n)^2 + (t_nt/R_A)^2 + (t_n1/R_par)^2 ) + p+/R_psi s_n
//! s_n <  0:  f_E = sqrt( (t_nt/R_A)^2 + (t_n1/R_par)^2 + (p-/R_psi s_n)^2 ) + p-/R_psi s_n
//! p/R_psi  = p_perp_perp/R_A cos^2 psi + p_perp_par/R_par sin^2 psi,
//! cos^2 psi = t_nt^2 / (t_nt^2 + t_n1^2)        (cos^2 psi = 1 when both vanish)
//! R_t = Yt,  R_par = S12,  R_A = R_perp_perp_A = Yc / (2 (1 + p_perp_perp_minus))
//!
//! f_IFF = max over theta in [-90, 90) degrees of f_E(theta),   index = max(f_FF, f_IFF)
//! ```
//!
//! Both exposures are positively homogeneous of degree 1 in the stress, so
//! `strength_ratio = 1 / index`. The search over `theta` scans 180 planes
//! one degree apart, then refines each local maximum of the scan by
//! golden-section search on the two degrees around it to `1e-10` rad (see
//! [`Puck::action_plane`]); `f_E` is smooth near its maximum, so its value
//! is exact to rounding.
//!
//! Mode reported: fibre tension or compression when `f_FF >= f_IFF`, else
//! matrix tension when `s_n >= 0` on the fracture plane and matrix
//! compression otherwise (Puck's IFF mode A is matrix tension, B and C
//! matrix compression); `Interaction` for a zero stress.
//!
//! Parameters: strengths `Xt`, `Xc`, `Yt`, `Yc`, `S12` (stress units,
//! positive, finite); inclinations `p_perp_par_plus` (default 0.3),
//! `p_perp_par_minus` (default 0.25), `p_perp_perp_minus` and
//! `p_perp_perp_plus` (default `p_perp_perp_minus`, as Puck, Kopp and Knops
//! recommend), each in `[0, 1)`. Without `p_perp_perp_minus` it is derived
//! as Puck recommends, so that the 3D criterion reproduces his 2D mode-C
//! envelope: `R_A = S12/(2 p-par) (sqrt(1 + 2 p-par Yc/S12) - 1)`,
//! `p_perp_perp_minus = p-par R_A / S12` (then `p_perp_perp/R_A =
//! p_perp_par/R_par` in compression, for any `psi`). The tension terms
//! need `p_perp_par_plus <= S12/Yt` and `p_perp_perp_plus <= R_A/Yt`
//! (else a pure `s_n` would not fail at `Yt`); other values are refused.

use crate::ply_common::{check_range, check_strength, governing, invalid, KIND};
use junta_core::ply_criterion::has_nan;
use junta_core::registry::{parse_params, ParamDoc, PlyCriterionEntry};
use junta_core::{CoreError, PlyCriterion, PlyFailure, PlyFailureMode};
use serde::Deserialize;
use std::f64::consts::FRAC_PI_2;
use std::sync::Arc;

const KEY: &str = "puck";

/// Number of planes of the coarse scan over `theta` in `[-90, 90)` degrees.
const SCAN_PLANES: usize = 180;
/// Width of the bracket the golden-section search stops at, radians.
const ANGLE_TOLERANCE: f64 = 1e-10;

/// Puck's criterion with its parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Puck {
    /// Tensile strength along the fibres.
    pub xt: f64,
    /// Compressive strength along the fibres (positive).
    pub xc: f64,
    /// Transverse tensile strength `R_perp_t`.
    pub yt: f64,
    /// Transverse compressive strength `R_perp_c` (positive).
    pub yc: f64,
    /// In-plane shear strength `R_perp_par`.
    pub s12: f64,
    /// Inclination `p_perp_par^(+)`.
    pub p_perp_par_plus: f64,
    /// Inclination `p_perp_par^(-)`.
    pub p_perp_par_minus: f64,
    /// Inclination `p_perp_perp^(+)`.
    pub p_perp_perp_plus: f64,
    /// Inclination `p_perp_perp^(-)`.
    pub p_perp_perp_minus: f64,
    /// Fracture resistance of the action plane against its transverse
    /// shear, `R_perp_perp_A = Yc / (2 (1 + p_perp_perp_minus))`.
    pub r_perp_perp_a: f64,
}

/// The fracture plane of inter-fibre fracture.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ActionPlane {
    /// Stress exposure `f_E` on the plane (the largest over `theta`).
    pub exposure: f64,
    /// Fracture angle `theta_fp`, radians, in `[-pi/2, pi/2]` (about).
    pub angle: f64,
    /// Normal stress `s_n` on the plane.
    pub normal_stress: f64,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Params {
    #[serde(rename = "Xt")]
    xt: f64,
    #[serde(rename = "Xc")]
    xc: f64,
    #[serde(rename = "Yt")]
    yt: f64,
    #[serde(rename = "Yc")]
    yc: f64,
    #[serde(rename = "S12")]
    s12: f64,
    p_perp_par_plus: Option<f64>,
    p_perp_par_minus: Option<f64>,
    p_perp_perp_minus: Option<f64>,
    p_perp_perp_plus: Option<f64>,
}

/// Stresses `(s_n, t_nt, t_n1)` on the plane at `theta`.
#[inline]
fn plane_stresses(s: &[f64; 6], theta: f64) -> (f64, f64, f64) {
    let (sin, cos) = theta.sin_cos();
    let (sin2, cos2) = (2.0 * theta).sin_cos();
    let mean = 0.5 * (s[1] + s[2]);
    let half_difference = 0.5 * (s[1] - s[2]);
    let normal = mean + half_difference * cos2 + s[4] * sin2;
    let transverse_shear = -half_difference * sin2 + s[4] * cos2;
    let axial_shear = s[5] * sin + s[3] * cos;
    (normal, transverse_shear, axial_shear)
}

/// Maximise `f` on `[a, b]` by golden-section search: `(theta, f(theta))`.
fn golden_section_max(f: impl Fn(f64) -> f64, mut a: f64, mut b: f64) -> (f64, f64) {
    const INV_PHI: f64 = 0.618_033_988_749_894_8;
    let mut x1 = b - INV_PHI * (b - a);
    let mut x2 = a + INV_PHI * (b - a);
    let (mut f1, mut f2) = (f(x1), f(x2));
    for _ in 0..200 {
        if b - a <= ANGLE_TOLERANCE {
            break;
        }
        if f1 < f2 {
            a = x1;
            (x1, f1) = (x2, f2);
            x2 = a + INV_PHI * (b - a);
            f2 = f(x2);
        } else {
            b = x2;
            (x2, f2) = (x1, f1);
            x1 = b - INV_PHI * (b - a);
            f1 = f(x1);
        }
    }
    if f1 >= f2 {
        (x1, f1)
    } else {
        (x2, f2)
    }
}

/// `R_perp_perp_A` and `p_perp_perp_minus` derived from `p_perp_par_minus`
/// (Puck's consistency with the 2D mode C).
fn derived_transverse(yc: f64, s12: f64, p_par_minus: f64) -> (f64, f64) {
    if p_par_minus == 0.0 {
        return (0.5 * yc, 0.0);
    }
    let r_a = s12 / (2.0 * p_par_minus) * ((1.0 + 2.0 * p_par_minus * yc / s12).sqrt() - 1.0);
    (r_a, p_par_minus * r_a / s12)
}

impl Puck {
    /// From a TOML table (see the module documentation).
    pub fn from_table(t: &toml::Table) -> Result<Self, CoreError> {
        let p: Params = parse_params(KIND, KEY, t)?;
        let xt = check_strength(KEY, "Xt", p.xt)?;
        let xc = check_strength(KEY, "Xc", p.xc)?;
        let yt = check_strength(KEY, "Yt", p.yt)?;
        let yc = check_strength(KEY, "Yc", p.yc)?;
        let s12 = check_strength(KEY, "S12", p.s12)?;
        let inclination = |v: Option<f64>, name: &str, default: f64| {
            check_range(KEY, name, v.unwrap_or(default), 0.0, 1.0)
        };
        let p_par_plus = inclination(p.p_perp_par_plus, "p_perp_par_plus", 0.3)?;
        let p_par_minus = inclination(p.p_perp_par_minus, "p_perp_par_minus", 0.25)?;
        let (r_a, p_perp_minus) = match p.p_perp_perp_minus {
            None => derived_transverse(yc, s12, p_par_minus),
            Some(v) => {
                let v = check_range(KEY, "p_perp_perp_minus", v, 0.0, 1.0)?;
                (yc / (2.0 * (1.0 + v)), v)
            }
        };
        let p_perp_plus = inclination(p.p_perp_perp_plus, "p_perp_perp_plus", p_perp_minus)?;
        let puck = Puck {
            xt,
            xc,
            yt,
            yc,
            s12,
            p_perp_par_plus: p_par_plus,
            p_perp_par_minus: p_par_minus,
            p_perp_perp_plus: p_perp_plus,
            p_perp_perp_minus: p_perp_minus,
            r_perp_perp_a: r_a,
        };
        puck.check_tension_terms()
    }

    fn check_tension_terms(self) -> Result<Self, CoreError> {
        if self.p_perp_par_plus * self.yt > self.s12 {
            return Err(invalid(
                KEY,
                format!(
                    "`p_perp_par_plus` = {} must not exceed S12/Yt = {}",
                    self.p_perp_par_plus,
                    self.s12 / self.yt
                ),
            ));
        }
        if self.p_perp_perp_plus * self.yt > self.r_perp_perp_a {
            return Err(invalid(
                KEY,
                format!(
                    "`p_perp_perp_plus` = {} must not exceed R_perp_perp_A/Yt = {}",
                    self.p_perp_perp_plus,
                    self.r_perp_perp_a / self.yt
                ),
            ));
        }
        Ok(self)
    }

    /// Stress exposure `f_E` of a plane with stresses `s_n, t_nt, t_n1`.
    pub fn plane_exposure(&self, normal: f64, transverse_shear: f64, axial_shear: f64) -> f64 {
        let shear_squared = transverse_shear * transverse_shear + axial_shear * axial_shear;
        let cos2_psi = if shear_squared > 0.0 {
            transverse_shear * transverse_shear / shear_squared
        } else {
            1.0
        };
        let (p_perp, p_par) = if normal >= 0.0 {
            (self.p_perp_perp_plus, self.p_perp_par_plus)
        } else {
            (self.p_perp_perp_minus, self.p_perp_par_minus)
        };
        let p = p_perp / self.r_perp_perp_a * cos2_psi + p_par / self.s12 * (1.0 - cos2_psi);
        let shear =
            (transverse_shear / self.r_perp_perp_a).powi(2) + (axial_shear / self.s12).powi(2);
        let normal_term = if normal >= 0.0 {
            (1.0 / self.yt - p) * normal
        } else {
            p * normal
        };
        (normal_term * normal_term + shear).sqrt() + p * normal
    }

    /// Stress exposure of the plane at `theta` (radians).
    pub fn exposure_at(&self, stress: &[f64; 6], theta: f64) -> f64 {
        let (n, nt, n1) = plane_stresses(stress, theta);
        self.plane_exposure(n, nt, n1)
    }

    /// The fracture plane: the largest `f_E` over `theta` (a scan of
    /// 180 planes one degree apart, each local maximum refined by golden-section
    /// search on the scan's step either side).
    pub fn action_plane(&self, stress: &[f64; 6]) -> ActionPlane {
        let step = 2.0 * FRAC_PI_2 / SCAN_PLANES as f64;
        let angle_of = |k: usize| -FRAC_PI_2 + step * k as f64;
        let mut scan = [0.0; SCAN_PLANES];
        for (k, value) in scan.iter_mut().enumerate() {
            *value = self.exposure_at(stress, angle_of(k));
        }
        let mut best = (angle_of(0), scan[0]);
        for k in 0..SCAN_PLANES {
            let before = scan[(k + SCAN_PLANES - 1) % SCAN_PLANES];
            let after = scan[(k + 1) % SCAN_PLANES];
            if scan[k] > best.1 {
                best = (angle_of(k), scan[k]);
            }
            if scan[k] > before && scan[k] >= after {
                let centre = angle_of(k);
                let refined = golden_section_max(
                    |t| self.exposure_at(stress, t),
                    centre - step,
                    centre + step,
                );
                if refined.1 > best.1 {
                    best = refined;
                }
            }
        }
        ActionPlane {
            exposure: best.1,
            angle: best.0,
            normal_stress: plane_stresses(stress, best.0).0,
        }
    }

    /// Fibre-fracture exposure and its mode.
    fn fibre_fracture(&self, s11: f64) -> (f64, PlyFailureMode) {
        if s11 >= 0.0 {
            (s11 / self.xt, PlyFailureMode::FibreTension)
        } else {
            (-s11 / self.xc, PlyFailureMode::FibreCompression)
        }
    }
}

impl PlyCriterion for Puck {
    fn key(&self) -> &'static str {
        KEY
    }

    fn evaluate(&self, stress: [f64; 6]) -> PlyFailure {
        if has_nan(&stress) {
            return PlyFailure::NAN;
        }
        let plane = self.action_plane(&stress);
        let matrix_mode = if plane.normal_stress >= 0.0 {
            PlyFailureMode::MatrixTension
        } else {
            PlyFailureMode::MatrixCompression
        };
        let (index, mode) = governing(&[
            self.fibre_fracture(stress[0]),
            (plane.exposure, matrix_mode),
        ]);
        PlyFailure::homogeneous(index, mode)
    }
}

inventory::submit! {
    PlyCriterionEntry {
        key: KEY,
        description: "Puck (1998/2002): fibre fracture by max stress, inter-fibre fracture on the action plane (3D fracture-angle search)",
        params: &[
            ParamDoc { name: "Xt", doc: "tensile strength along the fibres, > 0 [stress]" },
            ParamDoc { name: "Xc", doc: "compressive strength along the fibres, a positive number [stress]" },
            ParamDoc { name: "Yt", doc: "transverse tensile strength R_perp_t, > 0 [stress]" },
            ParamDoc { name: "Yc", doc: "transverse compressive strength R_perp_c, a positive number [stress]" },
            ParamDoc { name: "S12", doc: "in-plane shear strength R_perp_par, > 0 [stress]" },
            ParamDoc { name: "p_perp_par_plus", doc: "optional inclination p_perp_par(+), in [0, S12/Yt] (default 0.3)" },
            ParamDoc { name: "p_perp_par_minus", doc: "optional inclination p_perp_par(-), in [0, 1) (default 0.25)" },
            ParamDoc { name: "p_perp_perp_minus", doc: "optional inclination p_perp_perp(-), in [0, 1); R_perp_perp_A = Yc/(2 (1 + p_perp_perp_minus)); default derived from p_perp_par_minus (Puck's 2D mode-C consistency)" },
            ParamDoc { name: "p_perp_perp_plus", doc: "optional inclination p_perp_perp(+), in [0, R_perp_perp_A/Yt] (default p_perp_perp_minus)" },
        ],
        build: |t| Ok(Arc::new(Puck::from_table(t)?)),
    }
}
