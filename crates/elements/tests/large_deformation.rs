//! The solid elements under `nlgeom` (total-Lagrangian, `Kinematics::Finite`):
//! the tangent and the internal force against finite differences in
//! rotated, stretched and compressed states, objectivity under a rigid
//! rotation, and the Cauchy stress of a homogeneous stretch against the
//! closed form of the St. Venant-Kirchhoff material.

use junta_core::element::{ElementContext, StepInfo};
use junta_core::registry::{self, ElementBuild, ElementEntry};
use junta_core::topology::{CellShape, HEX27_NODES, WEDGE15_NODES};
use junta_core::{Element, Kinematics, Material};
use junta_elements::{EngineeringConstants, Isotropic, Orientation, Orthotropic};
use nalgebra::{Matrix3, Rotation3, Vector3};
use std::sync::Arc;

const KEYS: [&str; 9] = [
    "h8", "h8i", "h20", "h20r", "h27", "h27r", "wedge6", "wedge6r", "wedge15",
];

fn isotropic() -> Arc<dyn Material> {
    Arc::new(Isotropic::new(70e3, 0.3).unwrap())
}

fn laminate() -> Arc<dyn Material> {
    let c = EngineeringConstants {
        e1: 135e3,
        e2: 9e3,
        e3: 8e3,
        nu12: 0.3,
        nu13: 0.28,
        nu23: 0.45,
        g12: 5e3,
        g13: 4.8e3,
        g23: 3.1e3,
    };
    let axes = Orientation::rectangular([1.0, 0.5, 0.2], [-0.3, 1.0, 0.4]);
    Arc::new(Orthotropic::new(c, Some(axes)).unwrap())
}

fn element(key: &str, material: Arc<dyn Material>, kinematics: Kinematics) -> Arc<dyn Element> {
    let entry = registry::find::<ElementEntry>(key).unwrap();
    (entry.build)(&ElementBuild {
        material: Some(material),
        law: None,
        options: &toml::Table::new(),
        kinematics,
    })
    .unwrap()
}

/// A skewed reference cell of the element's shape (mid-nodes moved off
/// their midpoints by a deterministic pattern), about 2 x 1.5 x 1.
fn reference_coords(shape: CellShape) -> Vec<[f64; 3]> {
    let natural: Vec<[f64; 3]> = match shape {
        CellShape::Wedge6 | CellShape::Wedge15 => WEDGE15_NODES[..shape.num_nodes()]
            .iter()
            .map(|p| [2.0 * p[0], 1.5 * p[1], 0.5 * (p[2] + 1.0)])
            .collect(),
        _ => HEX27_NODES[..shape.num_nodes()]
            .iter()
            .map(|p| [p[0] + 1.0, 0.75 * (p[1] + 1.0), 0.5 * (p[2] + 1.0)])
            .collect(),
    };
    natural
        .iter()
        .enumerate()
        .map(|(a, x)| {
            let t = a as f64;
            [
                x[0] + 0.2 * x[1] + 0.03 * (1.3 * t).sin(),
                x[1] + 0.1 * x[2] + 0.03 * (2.1 * t).cos(),
                x[2] + 0.04 * (0.7 * t).sin(),
            ]
        })
        .collect()
}

/// Displacements `u = R (U X + w) - X`: a stretch/shear `U`, a rotation `R`
/// and a nodal ripple `w` of relative size `ripple`.
fn deformed(coords: &[[f64; 3]], u: Matrix3<f64>, r: Matrix3<f64>, ripple: f64) -> Vec<f64> {
    let mut d = Vec::with_capacity(3 * coords.len());
    for (a, x) in coords.iter().enumerate() {
        let t = a as f64;
        let w = Vector3::new((0.9 * t).sin(), (1.7 * t).cos(), (2.3 * t).sin()) * ripple;
        let x0 = Vector3::from(*x);
        let y = r * (u * x0 + w);
        d.extend((y - x0).iter());
    }
    d
}

/// The states the checks run through: a large rotation with a stretch, a
/// compression (negative geometric stiffness), and a pure shear.
fn states() -> Vec<(&'static str, Matrix3<f64>, Matrix3<f64>)> {
    let axis = Vector3::new(1.0, -2.0, 0.7).normalize();
    let rot70 =
        *Rotation3::from_axis_angle(&nalgebra::Unit::new_normalize(axis), 70f64.to_radians())
            .matrix();
    vec![
        (
            "rotated 70 deg and stretched",
            Matrix3::new(1.15, 0.05, 0.0, 0.0, 0.95, 0.08, 0.02, 0.0, 1.05),
            rot70,
        ),
        (
            "compressed 12 %",
            Matrix3::new(0.88, 0.0, 0.0, 0.0, 1.03, 0.0, 0.0, 0.0, 1.02),
            Matrix3::identity(),
        ),
        (
            "sheared 0.3",
            Matrix3::new(1.0, 0.3, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0),
            *Rotation3::from_axis_angle(&Vector3::z_axis(), 0.4).matrix(),
        ),
    ]
}

struct Kernel {
    el: Arc<dyn Element>,
    coords: Vec<[f64; 3]>,
    state: Vec<f64>,
}

impl Kernel {
    fn new(key: &str, material: Arc<dyn Material>) -> Self {
        let el = element(key, material, Kinematics::Finite);
        let coords = reference_coords(el.shape());
        let mut state = vec![0.0; el.state_len()];
        el.init_state(&mut state);
        Kernel { el, coords, state }
    }
    fn ctx<'a>(&'a self, disp: &'a [f64]) -> ElementContext<'a> {
        ElementContext {
            coords: &self.coords,
            disp,
            state_committed: &self.state,
            step: StepInfo::default(),
            law_responses: None,
            temperature: None,
        }
    }
    /// Internal force and, if asked, the tangent at `disp`.
    fn eval(&self, disp: &[f64], with_k: bool) -> (Vec<f64>, Vec<f64>) {
        let n = disp.len();
        let mut f = vec![0.0; n];
        let mut k = vec![0.0; if with_k { n * n } else { 0 }];
        let mut trial = vec![0.0; self.state.len()];
        self.el
            .compute(
                &self.ctx(disp),
                &mut trial,
                &mut f,
                with_k.then_some(k.as_mut_slice()),
            )
            .unwrap();
        (f, k)
    }
    /// Strain energy `Σ_q ½ E · S dV0` from the point outputs.
    fn energy(&self, disp: &[f64]) -> f64 {
        let pts = self.el.point_outputs(&self.ctx(disp)).unwrap();
        pts.iter()
            .map(|p| {
                let e = p.get("strain").unwrap();
                let s = p.get("pk2_stress").unwrap();
                let dv = p.get("volume").unwrap()[0];
                0.5 * dv * e.iter().zip(s).map(|(a, b)| a * b).sum::<f64>()
            })
            .sum()
    }
}

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

/// Central differences of the internal force against the tangent, and of
/// the strain energy against the internal force, for every solid element,
/// two materials and three states.
#[test]
fn tangent_and_force_match_finite_differences_under_nlgeom() {
    for key in KEYS {
        for (mname, material) in [("isotropic", isotropic()), ("laminate", laminate())] {
            let kernel = Kernel::new(key, material);
            for (sname, u, r) in states() {
                let d = deformed(&kernel.coords, u, r, 0.02);
                let (f, k) = kernel.eval(&d, true);
                let n = d.len();
                let h = 1e-6;
                let (mut err_k, mut err_f) = (0.0f64, 0.0f64);
                for j in 0..n {
                    let mut dp = d.clone();
                    let mut dm = d.clone();
                    dp[j] += h;
                    dm[j] -= h;
                    let (fp, _) = kernel.eval(&dp, false);
                    let (fm, _) = kernel.eval(&dm, false);
                    for i in 0..n {
                        let fd = (fp[i] - fm[i]) / (2.0 * h);
                        err_k = err_k.max((fd - k[i * n + j]).abs());
                    }
                    let dw = (kernel.energy(&dp) - kernel.energy(&dm)) / (2.0 * h);
                    err_f = err_f.max((dw - f[j]).abs());
                }
                let rel_k = err_k / max_abs(&k);
                let rel_f = err_f / max_abs(&f);
                assert!(
                    rel_k < 2e-6,
                    "{key} {mname} {sname}: tangent vs finite differences {rel_k:.2e}"
                );
                assert!(
                    rel_f < 2e-6,
                    "{key} {mname} {sname}: force vs energy differences {rel_f:.2e}"
                );
            }
        }
    }
}

/// A rigid rotation by 90 degrees strains nothing under `nlgeom`, while the
/// small-strain element sees a strain of order 1 in it.
#[test]
fn rigid_rotation_is_stress_free_under_nlgeom_only() {
    let r = *Rotation3::from_axis_angle(
        &nalgebra::Unit::new_normalize(Vector3::new(0.3, 1.0, -0.5)),
        std::f64::consts::FRAC_PI_2,
    )
    .matrix();
    for key in KEYS {
        let finite = Kernel::new(key, laminate());
        let d = deformed(&finite.coords, Matrix3::identity(), r, 0.0);
        // force scale: the tangent at rest times the displacement size
        let (_, k0) = finite.eval(&vec![0.0; d.len()], true);
        let scale = max_abs(&k0) * max_abs(&d);
        let (f, _) = finite.eval(&d, false);
        assert!(
            max_abs(&f) < 1e-12 * scale,
            "{key}: rigid rotation gives forces {:.2e} (scale {scale:.2e})",
            max_abs(&f)
        );
        let small = element(key, laminate(), Kinematics::Small);
        let mut fs = vec![0.0; d.len()];
        let mut trial = vec![0.0; small.state_len()];
        small
            .compute(&finite.ctx(&d), &mut trial, &mut fs, None)
            .unwrap();
        assert!(
            max_abs(&fs) > 0.05 * scale,
            "{key}: the small-strain element should see the rotation as strain"
        );
    }
}

/// A homogeneous uniaxial stretch `lambda` with the lateral stretch `mu`
/// of uniaxial second Piola-Kirchhoff stress. St. Venant-Kirchhoff is
/// linear between `E` and `S`, so `E_22 = -nu E_11`, `S_11 = Y E_11`
/// (`E_11 = (lambda^2 - 1)/2`, `mu = sqrt(1 - nu (lambda^2 - 1))`), and the
/// Cauchy stress is `sigma_11 = lambda S_11 / mu^2`, the others zero.
/// Every element reproduces it at every point, rotated by 40 degrees.
#[test]
fn homogeneous_stretch_gives_the_closed_form_cauchy_stress() {
    let (young, nu) = (70e3, 0.3);
    let lambda: f64 = 1.3;
    let e11 = 0.5 * (lambda * lambda - 1.0);
    let mu = (1.0 - nu * (lambda * lambda - 1.0)).sqrt();
    let sigma11 = lambda * young * e11 / (mu * mu);
    let r = *Rotation3::from_axis_angle(&Vector3::z_axis(), 40f64.to_radians()).matrix();
    let u = Matrix3::new(lambda, 0.0, 0.0, 0.0, mu, 0.0, 0.0, 0.0, mu);
    // the Cauchy stress rotates with the body: R diag(sigma11, 0, 0) R^T
    let expect = r * Matrix3::new(sigma11, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0) * r.transpose();
    let voigt = [(0, 0), (1, 1), (2, 2), (0, 1), (1, 2), (2, 0)];
    for key in KEYS {
        let kernel = Kernel::new(key, Arc::new(Isotropic::new(young, nu).unwrap()));
        let d = deformed(&kernel.coords, u, r, 0.0);
        for p in kernel.el.point_outputs(&kernel.ctx(&d)).unwrap() {
            let s = p.get("stress").unwrap();
            for (v, &(i, j)) in voigt.iter().enumerate() {
                assert!(
                    (s[v] - expect[(i, j)]).abs() < 1e-9 * sigma11,
                    "{key}: stress[{v}] = {} against {}",
                    s[v],
                    expect[(i, j)]
                );
            }
            let pk2 = p.get("pk2_stress").unwrap();
            assert!(
                (pk2[0] - young * e11).abs() < 1e-9 * young * e11,
                "{key}: S_11 {}",
                pk2[0]
            );
        }
    }
}
