//! Lekhnitskii's cylindrically orthotropic curved beam (Anisotropic
//! Plates, 1968, sec. 31; the basis of ASTM D6415), derived here. With
//! the stress function `psi`, `sigma_r = psi / r`, `sigma_theta = psi'`,
//! and the plane-strain compliances `b_ij = S_ij - S_iz S_jz / S_zz` (1
//! hoop, 2 axis, 3 radius), compatibility with a rigid rotation of the
//! sections gives `r^2 psi'' + r psi' - k^2 psi = C r / b_tt`,
//! `k = sqrt(b_rr / b_tt)`, so under a pure moment
//!
//! ```text
//! sigma_r = A r^(k-1) + B r^(-k-1) + E,   sigma_theta = k A r^(k-1) - k B r^(-k-1) + E,
//! ```
//!
//! with `sigma_r(a) = sigma_r(b) = 0` and the section's moment about the
//! centre `int sigma_theta r dr = -int psi dr = m` (the moment per width).
#![allow(dead_code)]

/// `k` of a transversely isotropic ply with its fibre along the hoop, in
/// plane strain along the axis (`E_2 = E_3`, `nu_12 = nu_13`).
pub fn hoop_ply_k(e1: f64, e2: f64, nu12: f64, nu23: f64) -> f64 {
    let (s11, s22, s33) = (1.0 / e1, 1.0 / e2, 1.0 / e2);
    let (s12, s23) = (-nu12 / e1, -nu23 / e2);
    ((s33 - s23 * s23 / s22) / (s11 - s12 * s12 / s22)).sqrt()
}

/// The curved beam between radii `a` and `b` under the moment per width
/// `m` (module docs).
pub struct CurvedBeam {
    pub k: f64,
    /// `A`, `B`, `E`.
    pub coef: [f64; 3],
}

impl CurvedBeam {
    pub fn new(a: f64, b: f64, k: f64, m: f64) -> Self {
        let int = |p: f64| (b.powf(p) - a.powf(p)) / p;
        let mat = nalgebra::Matrix3::new(
            a.powf(k - 1.0),
            a.powf(-k - 1.0),
            1.0,
            b.powf(k - 1.0),
            b.powf(-k - 1.0),
            1.0,
            -int(k + 1.0),
            -int(1.0 - k),
            -0.5 * (b * b - a * a),
        );
        let c = mat
            .lu()
            .solve(&nalgebra::Vector3::new(0.0, 0.0, m))
            .expect("a < b");
        CurvedBeam {
            k,
            coef: [c[0], c[1], c[2]],
        }
    }

    pub fn sigma_r(&self, r: f64) -> f64 {
        let ([a, b, e], k) = (self.coef, self.k);
        a * r.powf(k - 1.0) + b * r.powf(-k - 1.0) + e
    }

    pub fn sigma_theta(&self, r: f64) -> f64 {
        let ([a, b, e], k) = (self.coef, self.k);
        k * a * r.powf(k - 1.0) - k * b * r.powf(-k - 1.0) + e
    }
}
