//! Total-Lagrangian kinematics for the solid elements under `nlgeom`
//! ([`junta_core::Kinematics::Finite`]): Green strain, second
//! Piola-Kirchhoff stress, and the consistent tangent with its geometric
//! stiffness, one integration point at a time.
//!
//! ## Kinematics
//!
//! Everything is written on the reference configuration. With the
//! reference gradients `g_a = ∂N_a/∂X` of the shape functions and the
//! nodal displacements `u_a`,
//!
//! ```text
//! F = I + Σ_a u_a ⊗ g_a                     (deformation gradient)
//! E = (F^T F - I) / 2                         (Green-Lagrange strain)
//! S = C E                                     (St. Venant-Kirchhoff)
//! ```
//!
//! in Voigt order `[11, 22, 33, 12, 23, 31]` with engineering shear
//! (`2 E_12`, ...), `C` the material's elasticity matrix in the reference
//! frame. The material axes of an orthotropic or anisotropic material are
//! therefore carried with the body: `S` and `E` are measured in the
//! reference frame, so a rigid rotation leaves them unchanged. The same
//! `C` gives the small-strain element back when `F -> I`.
//!
//! ## Internal force and tangent
//!
//! The variation of `E` is `δE = sym(F^T δF)`, i.e. `δE = Σ_a B_a δu_a`
//! with the 6 x 3 matrix whose column `i` is the Voigt form of
//! `sym(F_i ⊗ g_a)` (`F_i` the `i`-th row of `F`):
//!
//! ```text
//! B_a[:, i] = [F_i1 g1, F_i2 g2, F_i3 g3,
//!              F_i1 g2 + F_i2 g1, F_i2 g3 + F_i3 g2, F_i3 g1 + F_i1 g3]
//! ```
//!
//! The internal force is `f_a = ∫ B_a^T S dV0 = ∫ P g_a dV0` with the first
//! Piola-Kirchhoff stress `P = F S`, and the consistent tangent
//!
//! ```text
//! K_ab = ∫ B_a^T C B_b dV0 + ∫ (g_a · S g_b) I dV0
//!        (material)           (geometric, or initial-stress, stiffness)
//! ```
//!
//! is symmetric; the geometric term makes it indefinite under compressive
//! stress (buckling). At `u = 0` it is the small-strain `K`.
//!
//! ## Stress output
//!
//! Cauchy `sigma = F S F^T / det F` on the current configuration, and `S`
//! itself.
//!
//! The functions here take any number of "nodes" with a gradient each, so
//! that `h8i` can pass its incompatible modes as extra gradients.

use junta_core::Voigt6;
use nalgebra::{Matrix3, SMatrix, Vector6};

/// `F = I + Σ_a u_a ⊗ g_a` for the gradients `g` and the displacements
/// `disp` (node-major, 3 per gradient).
#[inline]
pub fn deformation_gradient(g: &[[f64; 3]], disp: &[f64]) -> Matrix3<f64> {
    let mut f = Matrix3::identity();
    for (a, ga) in g.iter().enumerate() {
        for i in 0..3 {
            let u = disp[3 * a + i];
            for j in 0..3 {
                f[(i, j)] += u * ga[j];
            }
        }
    }
    f
}

/// Green-Lagrange strain `(F^T F - I) / 2` in Voigt form (engineering shear).
#[inline]
pub fn green_strain(f: &Matrix3<f64>) -> Vector6<f64> {
    let c = f.transpose() * f;
    Vector6::new(
        0.5 * (c[(0, 0)] - 1.0),
        0.5 * (c[(1, 1)] - 1.0),
        0.5 * (c[(2, 2)] - 1.0),
        c[(0, 1)],
        c[(1, 2)],
        c[(2, 0)],
    )
}

/// The symmetric 3 x 3 tensor of a Voigt stress.
#[inline]
pub fn tensor(s: &Vector6<f64>) -> Matrix3<f64> {
    Matrix3::new(s[0], s[3], s[5], s[3], s[1], s[4], s[5], s[4], s[2])
}

/// Cauchy stress `F S F^T / det F` in Voigt form.
pub fn cauchy_stress(f: &Matrix3<f64>, s: &Vector6<f64>) -> [f64; 6] {
    let sig = f * tensor(s) * f.transpose() / f.determinant();
    [
        sig[(0, 0)],
        sig[(1, 1)],
        sig[(2, 2)],
        sig[(0, 1)],
        sig[(1, 2)],
        sig[(2, 0)],
    ]
}

/// Column `i` of `B_a` for the gradient `ga`: the Voigt form of
/// `sym(F_i ⊗ g_a)` (engineering shear).
#[inline(always)]
fn b_column(f: &Matrix3<f64>, ga: &[f64; 3], i: usize) -> [f64; 6] {
    let r = [f[(i, 0)], f[(i, 1)], f[(i, 2)]];
    [
        r[0] * ga[0],
        r[1] * ga[1],
        r[2] * ga[2],
        r[0] * ga[1] + r[1] * ga[0],
        r[1] * ga[2] + r[2] * ga[1],
        r[2] * ga[0] + r[0] * ga[2],
    ]
}

/// Add `dv P g_a` (`P = F S`) to `f_int[3a..3a + 3]` for every gradient.
#[inline]
pub fn add_internal_force(
    g: &[[f64; 3]],
    f: &Matrix3<f64>,
    s: &Vector6<f64>,
    dv: f64,
    f_int: &mut [f64],
) {
    let p = f * tensor(s);
    for (a, ga) in g.iter().enumerate() {
        for i in 0..3 {
            f_int[3 * a + i] += dv * (p[(i, 0)] * ga[0] + p[(i, 1)] * ga[1] + p[(i, 2)] * ga[2]);
        }
    }
}

/// Most gradients one point carries (H27's 27 nodes; h8i's 8 + 3 modes).
pub const MAX_GRADIENTS: usize = 27;

/// Add `dv (B_a^T C B_b + (g_a · S g_b) I)` to the row-major `k` of
/// leading dimension `ld` (at least `3 g.len()`), full (both triangles).
///
/// The element sizes in use (8, 11 = h8i's 8 + 3 modes, 20 and 27
/// gradients) go through fixed-size matrix products, `K = B^T (dv C B)`
/// with `B` the `6 x 3n` matrix of the columns `B_a[:, i]`; any other
/// count through the same sums written out ([`add_tangent_any`]).
pub fn add_tangent(
    g: &[[f64; 3]],
    f: &Matrix3<f64>,
    s: &Vector6<f64>,
    c: &Voigt6,
    dv: f64,
    k: &mut [f64],
    ld: usize,
) {
    debug_assert!(g.len() <= MAX_GRADIENTS && ld >= 3 * g.len());
    let p = PointTangent { g, f, s, c, dv };
    match g.len() {
        8 => add_tangent_fixed::<24>(&p, k, ld),
        11 => add_tangent_fixed::<33>(&p, k, ld),
        20 => add_tangent_fixed::<60>(&p, k, ld),
        27 => add_tangent_fixed::<81>(&p, k, ld),
        _ => add_tangent_any(&p, k, ld),
    }
}

/// What one point's tangent is built from ([`add_tangent`]).
struct PointTangent<'a> {
    g: &'a [[f64; 3]],
    f: &'a Matrix3<f64>,
    s: &'a Vector6<f64>,
    c: &'a Voigt6,
    dv: f64,
}

/// [`add_tangent`] for `D = 3 g.len()` dofs with fixed-size products: `B`
/// and `dv C B` (`6 x D`), then the `3 x 3` blocks `B_a^T (dv C B_b)` of
/// the upper block triangle (`b >= a`: the matrix is symmetric, so half the
/// product of `B^T (dv C B)` in full), each written with the geometric
/// `dv (g_a . S g_b) I` to block `(a, b)` and its transpose to `(b, a)`.
fn add_tangent_fixed<const D: usize>(p: &PointTangent<'_>, k: &mut [f64], ld: usize) {
    let PointTangent { g, f, s, c, dv } = *p;
    let mut b = SMatrix::<f64, 6, D>::zeros();
    for (a, ga) in g.iter().enumerate() {
        for i in 0..3 {
            b.set_column(3 * a + i, &Vector6::from(b_column(f, ga, i)));
        }
    }
    let cb = (c * dv) * b;
    let st = tensor(s) * dv;
    for (a, ga) in g.iter().enumerate() {
        let ba = b.fixed_columns::<3>(3 * a);
        let sga = st * nalgebra::Vector3::from(*ga);
        for (bn, gb) in g.iter().enumerate().skip(a) {
            let block = ba.transpose() * cb.fixed_columns::<3>(3 * bn);
            let geo = sga[0] * gb[0] + sga[1] * gb[1] + sga[2] * gb[2];
            for i in 0..3 {
                for j in 0..3 {
                    let v = block[(i, j)] + if i == j { geo } else { 0.0 };
                    k[(3 * a + i) * ld + 3 * bn + j] += v;
                    if bn != a {
                        k[(3 * bn + j) * ld + 3 * a + i] += v;
                    }
                }
            }
        }
    }
}

/// [`add_tangent`] for any number of gradients: the upper triangle
/// (dof `r = 3a + i` against `c = 3b + j`, `c >= r`) computed once as `B_r
/// · (dv C B_c)` plus the geometric `dv g_a · S g_b` where `i = j`, and
/// written to both triangles.
fn add_tangent_any(p: &PointTangent<'_>, k: &mut [f64], ld: usize) {
    let PointTangent { g, f, s, c, dv } = *p;
    let nd = 3 * g.len();
    // by dof r = 3a + i: the column B_r and dv C B_r (Voigt 6-vectors)
    let mut bcol = [[0.0; 6]; 3 * MAX_GRADIENTS];
    let mut cbcol = [[0.0; 6]; 3 * MAX_GRADIENTS];
    // by gradient: dv S g_a
    let mut sg = [[0.0; 3]; MAX_GRADIENTS];
    let st = tensor(s);
    for (a, ga) in g.iter().enumerate() {
        for i in 0..3 {
            let col = b_column(f, ga, i);
            bcol[3 * a + i] = col;
            cbcol[3 * a + i] = (c * Vector6::from(col) * dv).into();
        }
        sg[a] = (st * nalgebra::Vector3::from(*ga) * dv).into();
    }
    for r in 0..nd {
        let (a, i) = (r / 3, r % 3);
        let br = &bcol[r];
        for col in r..nd {
            let cb = &cbcol[col];
            let mut v: f64 = (0..6).map(|x| br[x] * cb[x]).sum();
            if col % 3 == i {
                let gb = &g[col / 3];
                v += sg[a][0] * gb[0] + sg[a][1] * gb[1] + sg[a][2] * gb[2];
            }
            k[r * ld + col] += v;
            if col != r {
                k[col * ld + r] += v;
            }
        }
    }
}
