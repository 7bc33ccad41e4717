//! INTER8 / INTER16 / INTER18 and INTER6 / INTER12: zero-thickness
//! isoparametric interface elements (paper section 3, eqs. 15-39), one
//! kernel generic over the face shape (Q4 / Q8 / Q9 quadrilaterals, Tri3 /
//! Tri6 triangles).
//!
//! Nodes: the `m` nodes of the bottom face, then the `m` nodes of the top
//! face, each in the face shape's order (`junta_core::topology`:
//! quadrilaterals with natural coordinates (xi, eta) in [-1, 1]^2,
//! triangles with (xi, eta) = (r, s), r, s >= 0, r + s <= 1, corners then
//! mid-edges 0-1, 1-2, 2-0 as a wedge's bottom triangle). At each
//! integration point (xi, eta), with face shape functions N_a
//! (`junta_elements::shape::surface_shape`):
//!
//! ```text
//! mid-surface     x(xi, eta) = sum_a N_a (x_bot,a + x_top,a) / 2
//! tangents        V_xi = dx/dxi,  V_eta = dx/deta
//! normal          e3 = (V_xi x V_eta) / |V_xi x V_eta|   (erratum to eq. 26)
//! frame           e1 = V_xi / |V_xi|,  e2 = e3 x e1,  theta = [e1 e2 e3]
//! jump            delta = theta^T sum_a N_a (u_top,a - u_bot,a) = B U_e
//!                 B = theta^T [-N_bot, N_top]                 (3 x 6m)
//! traction        t = law(delta),  D = dt/ddelta (local frame)
//! internal force  f = int B^T t dA,   K = int B^T D B dA,
//!                 dA = |V_xi x V_eta| dxi deta.
//! ```
//!
//! On a triangle the same formulas hold with the tangents along the
//! natural edges 0-1 (V_r) and 0-2 (V_s): e1 follows edge 0-1, the normal
//! points to the side from which 0-1-2 turns counter-clockwise, and the
//! reference area is `int dA = sum_q w_q |V_r x V_s|` with weights summing
//! to 1/2.
//!
//! Node blocks of K are `s_a s_b N_a N_b (theta D theta^T) dA` with
//! `s = -1` on the bottom face and `+1` on the top face: the kernel sums
//! the `3m x 3m` block `B = sum_q N_a N_b (theta D theta^T) dA` over the
//! points and writes `K = [[B, -B], [-B, B]]` once (fixed-size arrays, no
//! allocation).
//!
//! Integration (`integration` option):
//!
//! * `gauss` (default): 2x2 for INTER8, 3x3 for INTER16/18 (the paper's);
//!   INTER6 the 3-point rule (degree 2) and INTER12 the 6-point rule
//!   (degree 4) of `junta_elements::quadrature::triangle_rule`. On a flat
//!   face `dA` is constant, so the integrand of K, `N_a N_b`, has the
//!   degree of the face's mass matrix: 2 for Tri3, 4 for Tri6; both rules
//!   integrate the consistent stiffness (and, for a linear law, the forces)
//!   exactly, as the 2x2 / 3x3 Gauss rules do on Q4 / Q9.
//! * `lobatto` (nodal): 2x2 / 3x3 Gauss-Lobatto points for quadrilaterals
//!   (nodal integration for INTER8 and INTER18, which decouples the node
//!   pairs and removes the traction oscillations of Schellekens & de Borst
//!   1993); for INTER6 the vertex rule (corners, weights 1/6: nodal, the
//!   same decoupling). INTER12 refuses it: the nodal rule of the quadratic
//!   triangle (mid-edges, weights 1/6) gives the corners zero weight, so
//!   the corner node pairs would carry no stiffness at all.
//!
//! # Kinematics
//!
//! Small displacements ([`Kinematics::Small`], the default): the frame and
//! the area factor are built on the reference geometry, so `B` is constant
//! and the element is linear in the displacements for a linear law.
//!
//! Large rotation ([`Kinematics::Finite`], scene `[analysis] nlgeom =
//! true`, deck `*STEP, NLGEOM`): the same formulas on the *current*
//! mid-surface. With `x_a = X_a + u_a`,
//!
//! ```text
//! mid-surface     x(xi, eta) = sum_a N_a (x_bot,a + x_top,a) / 2
//! tangents        V_xi = dx/dxi,  V_eta = dx/deta       (current)
//! frame           e1, e2, e3, theta as above, on V_xi, V_eta
//! gap             g = sum_a N_a (u_top,a - u_bot,a)     (global)
//! jump            delta = theta^T g
//! area factor     j = |V_xi x V_eta|                    (current area)
//! force           F = j theta t(delta)                  (global, per point)
//!                 f_top,a = + sum_q w_q N_a F,   f_bot,a = - sum_q w_q N_a F
//! ```
//!
//! so a rigid rotation `R` of the loaded element leaves `delta` and `t`
//! unchanged and turns the forces by `R`. The law still sees `[s1, s2, n]`
//! and never knows the kinematics. The point outputs give the current
//! `area` and the `reference_area` (on the undeformed mid-surface); crack
//! areas and dissipated energies are integrated over the reference one
//! (a peeled-off point's current mid-surface shrinks as its faces part).
//!
//! Tangent. `V_xi, V_eta` depend on both faces with weight 1/2
//! (`dV_xi = sum_b dN_b/dxi (du_bot,b + du_top,b) / 2`), `g` on their
//! difference. Writing `de_i = A_i dV_xi + C_i dV_eta` for the frame,
//!
//! ```text
//! A_1 = (I - e1 e1^T) / |V_xi|                      C_1 = 0
//! A_3 = -(I - e3 e3^T) [V_eta]x / j                 C_3 = (I - e3 e3^T) [V_xi]x / j
//! A_2 = -[e1]x A_3 + [e3]x A_1                      C_2 = -[e1]x C_3
//! dj  = (V_eta x e3) . dV_xi + (e3 x V_xi) . dV_eta
//! ```
//!
//! (`[v]x` the cross-product matrix, `e2 = e3 x e1`), and with `D = dt /
//! ddelta` the law's exact tangent, the derivative of `F` is
//!
//! ```text
//! dF    = Q dg + P_xi dV_xi + P_eta dV_eta
//! Q     = j theta D theta^T
//! P_xi  = j (sum_i t_i A_i + theta D G_xi) + (theta t) (V_eta x e3)^T,  (G_xi)_k = g^T A_k
//! P_eta = j (sum_i t_i C_i + theta D G_eta) + (theta t) (e3 x V_xi)^T,  (G_eta)_k = g^T C_k
//! ```
//!
//! Summed over the points into the `3m x 3m` blocks `B_ab = sum_q w_q N_a
//! N_b Q` and `H_ab = sum_q w_q N_a (P_xi dN_b/dxi + P_eta dN_b/deta) / 2`,
//! the element tangent is
//!
//! ```text
//! K = [[ B - H,  -B - H ],
//!      [ H - B,   B + H ]]        over (bottom, top) nodes.
//! ```
//!
//! `H` (the frame and area terms) is not symmetric. Unless the law's
//! tangent is general or [`junta_core::StepInfo::exact_tangent`] asks for the exact
//! one, the element stores the symmetric part `(K + K^T) / 2` of this
//! exact `K` (built with the law's exact `D`) and reports the law's
//! symmetric kind, so that `ldlt` and its inertia stay in use; it records
//! the largest scaled skew `max |K_ij - K_ji| / sqrt(|K_ii K_jj|)` of what
//! it symmetrised, which the driver reads after each converged increment
//! ([`Element::take_symmetrised_skew`]) and, above its limit (0.1), turns
//! to the exact tangent for the rest of the run. Measured on a DCB
//! (`dcb_h8.toml` under nlgeom): 3e-6 while the bond is elastic, 2e-2 with
//! a process zone, where Newton on the symmetric part takes the exact
//! tangent's iterations. `check_geometry` still checks the
//! reference geometry; a current surface that degenerates (crushed to a
//! line) is a [`ElementError::DegenerateSurface`] at that iteration.
//!
//! Tangent storage (small kinematics): unless the law declares a general
//! (nonsymmetric) tangent, the element assembles the symmetric part `(D +
//! D^T) / 2` of the law's tangent (mixed-mode softening laws have a
//! slightly nonsymmetric exact tangent where the mode ratio changes with
//! the jump).
//!
//! # Line interfaces (2D: LINE_INTER4, LINE_INTER6)
//!
//! Between the edges of plane cells the sides are lines (Line2 / Line3,
//! natural coordinate xi). The same kernel runs with the second tangent
//! set to the out-of-plane direction scaled by the width `s` the line
//! stands for,
//!
//! ```text
//! V_eta = s e_z,    s = t (plane strain / stress: option `thickness`, default 1)
//!                   s = 2 pi r (axisymmetric: option `axisymmetric = true`, the full ring,
//!                               r the mid-line's x at the point)
//! ```
//!
//! so that `e1` follows the line, `e2 = e_z` and `e3 = e1 x e_z` (the right
//! of the bottom line, from its node 0 to node 1: the outward normal of the
//! edge of a counter-clockwise plane cell below it, as for the faces of
//! solids), `dA = s |V_xi| dxi`, and
//! the law sees `[s1, s2, n]` with `s2 = 0` (the `z` components are not
//! the model's: [`Element::active_components`]). Rules: `gauss` 2 points
//! (LINE_INTER4) or 3 (LINE_INTER6); `lobatto` 2 or 3 points, which are
//! also the closed Newton-Cotes rules of 2 and 3 points (trapezoid,
//! Simpson): nodal integration. Under finite kinematics `V_eta` is
//! constant for a plane line (the tangent above holds with `dV_eta = 0`);
//! an axisymmetric line's `V_eta = 2 pi r e_z` follows the current
//! radius `r = sum_b N_b x_b` of the mid-line, so `dV_eta / du_{b,x} =
//! pi N_b e_z` for each face's node `b` (the ring's area grows as it
//! moves outward).
//!
//! Point outputs: `jump`, `traction`, `frame`, `area`, `state`, `failed`,
//! `failure_index`, then every scalar the law names in
//! [`InterfaceLaw::output_names`] (e.g. `damage`, `dissipated_energy`).
//! Under finite kinematics the frame and the area are the current ones; the
//! output position is on the reference mid-surface.

use junta_core::element::{Element, ElementContext, ElementError, PlaneWidth, PointOutput};
use junta_core::law::{InterfaceLaw, LawContext, LawResponse, PointStage};
use junta_core::registry::{parse_params, ElementBuild, ElementEntry, ParamDoc};
use junta_core::topology::CellShape;
use junta_core::{CoreError, Kinematics, MatrixKind};
use junta_elements::quadrature::{
    gauss_legendre, gauss_legendre_2d, gauss_lobatto, gauss_lobatto_2d, triangle_rule,
    triangle_vertex_rule, Rule, Rule1D,
};
use junta_elements::shape::surface_shape;
use serde::Deserialize;
use std::sync::Arc;

/// Integration rule of an interface element.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum InterfaceRule {
    /// Gauss points (2x2 INTER8, 3x3 INTER16/18, 3 INTER6, 6 INTER12).
    Gauss,
    /// Nodal points: Gauss-Lobatto 2x2 / 3x3 on quadrilaterals, the
    /// vertices on INTER6 (none on INTER12: an error).
    Lobatto,
}

/// An interface element type bound to its traction law.
#[derive(Debug, Clone)]
pub struct InterfaceElement {
    shape: CellShape,
    face: CellShape,
    rule: InterfaceRule,
    points: Vec<[f64; 2]>,
    weights: Vec<f64>,
    law: Arc<dyn InterfaceLaw>,
    key: &'static str,
    kinematics: Kinematics,
    /// The width a line interface stands for (`None` for surfaces).
    line: Option<PlaneWidth>,
    /// Largest scaled skew of a tangent this element stored as its
    /// symmetric part since the driver last asked ([`SkewRecord`]).
    skew: SkewRecord,
}

/// A 1D rule as points `(xi, 0)` of the surface kernel.
fn line_rule(r: Rule1D) -> Rule<2> {
    Rule {
        points: r.points.iter().map(|&x| [x, 0.0]).collect(),
        weights: r.weights.to_vec(),
    }
}

/// The largest scaled skew `max |k_ij - k_ji| / sqrt(|k_ii k_jj|)` of the
/// element tangents a block stored symmetrised under finite kinematics,
/// shared by the assembly threads (the bits of a non-negative `f64`
/// order as the `f64`: `fetch_max` on them is the maximum).
#[derive(Debug, Default)]
struct SkewRecord(std::sync::atomic::AtomicU64);

impl SkewRecord {
    fn record(&self, skew: f64) {
        self.0
            .fetch_max(skew.to_bits(), std::sync::atomic::Ordering::Relaxed);
    }
    fn take(&self) -> f64 {
        f64::from_bits(self.0.swap(0, std::sync::atomic::Ordering::Relaxed))
    }
}

impl Clone for SkewRecord {
    fn clone(&self) -> Self {
        SkewRecord(std::sync::atomic::AtomicU64::new(
            self.0.load(std::sync::atomic::Ordering::Relaxed),
        ))
    }
}

/// Local frame and area factor at one point.
#[derive(Debug, Clone, Copy)]
struct Frame {
    /// Rows: e1, e2, e3.
    e: M3,
    /// |V_xi x V_eta|.
    jac: f64,
    /// The tangents V_xi, V_eta.
    v: [[f64; 3]; 2],
}

/// A 3 x 3 matrix, rows first.
type M3 = [[f64; 3]; 3];

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn norm(a: [f64; 3]) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}
fn mat_mul(a: &M3, b: &M3) -> M3 {
    let mut c = [[0.0; 3]; 3];
    for (ci, ai) in c.iter_mut().zip(a) {
        for (k, bk) in b.iter().enumerate() {
            for (x, y) in ci.iter_mut().zip(bk) {
                *x += ai[k] * y;
            }
        }
    }
    c
}
/// `[v]x`: the matrix of `w -> v x w`.
fn skew(v: [f64; 3]) -> M3 {
    [[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]]
}
/// `(I - e e^T) / len`: the derivative of `v / |v|` with `e = v / |v|`,
/// `len = |v|`.
fn unit_derivative(e: [f64; 3], len: f64) -> M3 {
    let mut p = [[0.0; 3]; 3];
    for (i, row) in p.iter_mut().enumerate() {
        for (j, x) in row.iter_mut().enumerate() {
            let delta = if i == j { 1.0 } else { 0.0 };
            *x = (delta - e[i] * e[j]) / len;
        }
    }
    p
}

/// Derivatives of the frame rows and of the area factor with respect to
/// one tangent vector `V` (V_xi or V_eta): `de_i = de[i] dV`, `dj = dj . dV`.
struct FrameDerivative {
    de: [M3; 3],
    dj: [f64; 3],
}

/// The frame's derivatives with respect to V_xi and V_eta (module docs:
/// `A_i`, `C_i` and the area terms).
fn frame_derivatives(fr: &Frame) -> [FrameDerivative; 2] {
    let [e1, _, e3] = fr.e;
    let [vxi, veta] = fr.v;
    let neg = |m: M3| m.map(|r| r.map(|x| -x));
    // e1 = V_xi / |V_xi|; e3 = n / j with dn = -[V_eta]x dV_xi + [V_xi]x dV_eta
    let a1 = unit_derivative(e1, norm(vxi));
    let d3 = unit_derivative(e3, fr.jac);
    let a3 = neg(mat_mul(&d3, &skew(veta)));
    let c3 = mat_mul(&d3, &skew(vxi));
    // e2 = e3 x e1: de2 = -[e1]x de3 + [e3]x de1
    let (s1, s3) = (skew(e1), skew(e3));
    let (s1a3, s3a1) = (mat_mul(&s1, &a3), mat_mul(&s3, &a1));
    let a2 = [0, 1, 2].map(|i| [0, 1, 2].map(|j| s3a1[i][j] - s1a3[i][j]));
    let c2 = neg(mat_mul(&s1, &c3));
    [
        FrameDerivative {
            de: [a1, a2, a3],
            dj: cross(veta, e3),
        },
        FrameDerivative {
            de: [[[0.0; 3]; 3], c2, c3],
            dj: cross(e3, vxi),
        },
    ]
}

/// `P = j (sum_i t_i de_i + theta D G) + (theta t) dj^T` with `G_k = g^T
/// de_k`: the derivative of the point force `F = j theta t` with respect to
/// one tangent vector (module docs), for traction `t`, law tangent `d` and
/// global gap `g`.
fn frame_force_derivative(
    fr: &Frame,
    fd: &FrameDerivative,
    t: [f64; 3],
    d: &M3,
    g: [f64; 3],
) -> M3 {
    let e = &fr.e;
    // G_k = g^T de_k, then D G
    let gk = fd
        .de
        .map(|a| [0, 1, 2].map(|c| g[0] * a[0][c] + g[1] * a[1][c] + g[2] * a[2][c]));
    let dg = mat_mul(d, &gk);
    let tg = [0, 1, 2].map(|c| e[0][c] * t[0] + e[1][c] * t[1] + e[2][c] * t[2]);
    let mut p = [[0.0; 3]; 3];
    for (c, row) in p.iter_mut().enumerate() {
        for (k, x) in row.iter_mut().enumerate() {
            let mut s = 0.0;
            for i in 0..3 {
                s += t[i] * fd.de[i][c][k] + e[i][c] * dg[i][k];
            }
            *x = fr.jac * s + tg[c] * fd.dj[k];
        }
    }
    p
}

impl InterfaceElement {
    /// Element of `shape` (Inter8/16/18, Inter6/12) with `rule` and `law`.
    ///
    /// Errors: a shape that is not an interface, or `Lobatto` on INTER12
    /// (no nodal rule: see the [module docs](self)).
    pub fn new(
        shape: CellShape,
        rule: InterfaceRule,
        law: Arc<dyn InterfaceLaw>,
    ) -> Result<Self, CoreError> {
        let (face, n, key) = match shape {
            CellShape::Inter8 => (CellShape::Quad4, 2, "inter8"),
            CellShape::Inter16 => (CellShape::Quad8, 3, "inter16"),
            CellShape::Inter18 => (CellShape::Quad9, 3, "inter18"),
            CellShape::Inter6 => (CellShape::Tri3, 3, "inter6"),
            CellShape::Inter12 => (CellShape::Tri6, 6, "inter12"),
            CellShape::LineInter4 => (CellShape::Line2, 2, "line_inter4"),
            CellShape::LineInter6 => (CellShape::Line3, 3, "line_inter6"),
            s => {
                return Err(CoreError::Invalid(format!(
                    "{} is not an interface shape",
                    s.name()
                )))
            }
        };
        let triangle = matches!(face, CellShape::Tri3 | CellShape::Tri6);
        let line = matches!(face, CellShape::Line2 | CellShape::Line3);
        let r = match (rule, triangle) {
            (InterfaceRule::Gauss, _) if line => gauss_legendre(n).map(line_rule),
            (InterfaceRule::Lobatto, _) if line => gauss_lobatto(n).map(line_rule),
            (InterfaceRule::Gauss, false) => gauss_legendre_2d(n),
            (InterfaceRule::Lobatto, false) => gauss_lobatto_2d(n),
            (InterfaceRule::Gauss, true) => triangle_rule(n),
            (InterfaceRule::Lobatto, true) if face == CellShape::Tri3 => Ok(triangle_vertex_rule()),
            (InterfaceRule::Lobatto, true) => {
                return Err(CoreError::InvalidParameters {
                    kind: "element",
                    key: key.into(),
                    message: "integration = \"lobatto\" (nodal) is not available for inter12: the nodal rule of the quadratic triangle gives its corners zero weight, so the corner node pairs would carry no stiffness; use integration = \"gauss\" (6 points), or inter6 for nodal integration".into(),
                })
            }
        }
        .map_err(|e| CoreError::Invalid(e.to_string()))?;
        Ok(InterfaceElement {
            shape,
            face,
            rule,
            points: r.points,
            weights: r.weights,
            law,
            key,
            kinematics: Kinematics::Small,
            line: line.then_some(PlaneWidth::Thickness(1.0)),
            skew: SkewRecord::default(),
        })
    }

    /// A line interface with the width `w` (a thickness, or the full ring
    /// axisymmetric). Errors: not a line interface, or a thickness that is
    /// not positive and finite.
    pub fn with_line_width(mut self, w: PlaneWidth) -> Result<Self, CoreError> {
        if self.line.is_none() {
            return Err(CoreError::InvalidParameters {
                kind: "element",
                key: self.key.into(),
                message: "thickness and axisymmetric apply to line interfaces only (line_inter4, line_inter6)".into(),
            });
        }
        if let PlaneWidth::Thickness(t) = w {
            if !(t.is_finite() && t > 0.0) {
                return Err(CoreError::InvalidParameters {
                    kind: "element",
                    key: self.key.into(),
                    message: format!(
                        "thickness = {t}: the out-of-plane thickness must be positive"
                    ),
                });
            }
        }
        self.line = Some(w);
        Ok(self)
    }

    /// The same element with kinematics `k` (small by default; finite
    /// frames the jump on the current mid-surface: see the
    /// [module docs](self)).
    pub fn with_kinematics(mut self, k: Kinematics) -> Self {
        self.kinematics = k;
        self
    }

    /// The traction law.
    pub fn law(&self) -> &Arc<dyn InterfaceLaw> {
        &self.law
    }

    /// The integration rule.
    pub fn rule(&self) -> InterfaceRule {
        self.rule
    }

    /// Natural coordinates of the integration points.
    pub fn points(&self) -> &[[f64; 2]] {
        &self.points
    }

    fn m(&self) -> usize {
        self.face.num_nodes()
    }

    /// Shape functions `n` and their derivatives `dn` at point `q`.
    fn shape_at(&self, q: usize, n: &mut [f64; 9], dn: &mut [[f64; 2]; 9]) {
        let m = self.m();
        surface_shape(self.face, self.points[q], &mut n[..m], &mut dn[..m]);
    }

    /// Shape functions and frame at point `q` on the reference geometry.
    fn frame(
        &self,
        coords: &[[f64; 3]],
        q: usize,
        n: &mut [f64; 9],
    ) -> Result<Frame, ElementError> {
        let mut dn = [[0.0; 2]; 9];
        self.shape_at(q, n, &mut dn);
        self.frame_on(q, n, &dn, |a, c| coords[a][c])
    }

    /// Shape functions and frame at point `q` in the element's kinematics:
    /// on the reference geometry (small) or on the current one (finite).
    fn point_frame(
        &self,
        ctx: &ElementContext<'_>,
        q: usize,
        n: &mut [f64; 9],
        dn: &mut [[f64; 2]; 9],
    ) -> Result<Frame, ElementError> {
        self.shape_at(q, n, dn);
        let (x, u) = (ctx.coords, ctx.disp);
        match self.kinematics {
            Kinematics::Small => self.frame_on(q, n, dn, |a, c| x[a][c]),
            Kinematics::Finite => self.frame_on(q, n, dn, |a, c| x[a][c] + u[3 * a + c]),
        }
    }

    /// Frame at point `q` (shape functions `n`, derivatives `dn`) of the
    /// mid-surface of the nodal positions `pos(node, component)`; a line's
    /// `V_eta` is `s e_z` (see the module docs).
    fn frame_on(
        &self,
        q: usize,
        n: &[f64; 9],
        dn: &[[f64; 2]; 9],
        pos: impl Fn(usize, usize) -> f64,
    ) -> Result<Frame, ElementError> {
        let m = self.m();
        let mut vxi = [0.0; 3];
        let mut veta = [0.0; 3];
        let mut r = 0.0;
        for (a, d) in dn.iter().enumerate().take(m) {
            for c in 0..3 {
                let xm = 0.5 * (pos(a, c) + pos(m + a, c));
                vxi[c] += d[0] * xm;
                veta[c] += d[1] * xm;
            }
            r += n[a] * 0.5 * (pos(a, 0) + pos(m + a, 0));
        }
        if let Some(w) = self.line {
            veta = [0.0, 0.0, w.at([r, 0.0, 0.0])];
        }
        let nv = cross(vxi, veta);
        let jac = norm(nv);
        let scale = norm(vxi) * norm(veta);
        if !jac.is_finite() || !scale.is_finite() || jac <= 1e-12 * scale {
            return Err(ElementError::DegenerateSurface {
                point: q,
                area: jac,
            });
        }
        let e3 = nv.map(|v| v / jac);
        let l1 = norm(vxi);
        let e1 = vxi.map(|v| v / l1);
        let e2 = cross(e3, e1);
        Ok(Frame {
            e: [e1, e2, e3],
            jac,
            v: [vxi, veta],
        })
    }

    /// Reference mid-surface position at shape functions `n`.
    fn reference_position(&self, coords: &[[f64; 3]], n: &[f64; 9]) -> [f64; 3] {
        let m = self.m();
        let mut x = [0.0; 3];
        for a in 0..m {
            for c in 0..3 {
                x[c] += n[a] * (0.5 * (coords[a][c] + coords[m + a][c]));
            }
        }
        x
    }

    /// Global gap `g = sum_a N_a (u_top,a - u_bot,a)` at shape functions `n`.
    fn gap(&self, n: &[f64; 9], disp: &[f64]) -> [f64; 3] {
        let m = self.m();
        let mut g = [0.0; 3];
        for a in 0..m {
            for c in 0..3 {
                g[c] += n[a] * (disp[3 * (m + a) + c] - disp[3 * a + c]);
            }
        }
        g
    }

    /// Local jump at a point (frame `f`, shape functions `n`).
    fn jump(&self, f: &Frame, n: &[f64; 9], disp: &[f64]) -> [f64; 3] {
        let g = self.gap(n, disp);
        [0, 1, 2].map(|i| f.e[i][0] * g[0] + f.e[i][1] * g[1] + f.e[i][2] * g[2])
    }
    /// The law's response at point `q` (frame `fr`, shape functions `n`),
    /// its trial state into `trial`.
    fn evaluate_point(
        &self,
        ctx: &ElementContext<'_>,
        q: usize,
        fr: &Frame,
        n: &[f64; 9],
        trial: &mut [f64],
    ) -> Result<LawResponse, ElementError> {
        let sl = self.law.state_len();
        self.law
            .evaluate(
                &LawContext {
                    jump: self.jump(fr, n, ctx.disp),
                    state_committed: &ctx.state_committed[q * sl..(q + 1) * sl],
                    step: ctx.step,
                },
                trial,
            )
            .map_err(|e| ElementError::Law {
                point: q,
                message: e.to_string(),
            })
    }

    /// The responses of a batched law at every point: the assembler's
    /// (block evaluated at once; trial states already written), or else
    /// this element's points evaluated in one batch into `own` (trial
    /// states into `trial`). `None` for a law evaluated point by point.
    fn batch_responses<'b>(
        &self,
        ctx: &ElementContext<'b>,
        trial: &mut [f64],
        own: &'b mut [LawResponse; MAX_POINTS],
    ) -> Result<Option<&'b [LawResponse]>, ElementError> {
        if let Some(rs) = ctx.law_responses {
            return Ok(Some(rs));
        }
        if !self.law.is_batched() {
            return Ok(None);
        }
        let np = self.points.len();
        let mut jumps = [[0.0; 3]; MAX_POINTS];
        self.jumps_into(ctx, &mut jumps[..np])?;
        self.law
            .evaluate_batch(
                &jumps[..np],
                ctx.state_committed,
                ctx.step,
                trial,
                &mut own[..np],
            )
            .map_err(|e| ElementError::Law {
                point: 0,
                message: e.to_string(),
            })?;
        Ok(Some(&own[..np]))
    }

    /// [`Element::compute`] with the face blocks in `N x N` arrays
    /// ([`FaceBlock`]).
    fn compute_sized<const N: usize>(
        &self,
        ctx: &ElementContext<'_>,
        state_trial: &mut [f64],
        f_int: &mut [f64],
        k: Option<&mut [f64]>,
    ) -> Result<(), ElementError> {
        let m = self.m();
        f_int[..6 * m].iter_mut().for_each(|v| *v = 0.0);
        // K = [[B - H, -B - H], [H - B, B + H]] over (bottom, top) nodes,
        // with the 3m x 3m blocks B = sum_q N_a N_b G_q da and (finite
        // kinematics only) H, the frame and area terms, accumulated first
        let want_k = k.is_some();
        let finite = self.kinematics == Kinematics::Finite;
        // the blocks only where they are used: zeroing both costs about as
        // much as a small element's whole residual
        let mut bk: Option<FaceBlock<N>> = want_k.then(|| [[0.0; N]; N]);
        let mut hk: Option<FaceBlock<N>> = (want_k && finite).then(|| [[0.0; N]; N]);
        let sl = self.law.state_len();
        let symmetric =
            !finite && self.law.tangent_kind() != MatrixKind::General && !ctx.step.exact_tangent;
        let mut n = [0.0; 9];
        let mut dn = [[0.0; 2]; 9];
        let mut own = [LawResponse::default(); MAX_POINTS];
        let batch = self.batch_responses(ctx, state_trial, &mut own)?;
        for q in 0..self.points.len() {
            let fr = self.point_frame(ctx, q, &mut n, &mut dn)?;
            let r = match batch {
                Some(rs) => rs[q],
                None => {
                    self.evaluate_point(ctx, q, &fr, &n, &mut state_trial[q * sl..(q + 1) * sl])?
                }
            };
            let da = fr.jac * self.weights[q];
            let e = &fr.e;
            // global traction t_g = theta t
            let tg = [0, 1, 2].map(|c| {
                e[0][c] * r.traction[0] + e[1][c] * r.traction[1] + e[2][c] * r.traction[2]
            });
            // f = [-N t_g, N t_g] da over (bottom, top)
            for a in 0..m {
                for c in 0..3 {
                    let v = n[a] * tg[c] * da;
                    f_int[3 * a + c] -= v;
                    f_int[3 * (m + a) + c] += v;
                }
            }
            if let Some(bk) = bk.as_mut() {
                // symmetric storage: assemble the symmetric part of the
                // law's tangent (the tangent itself for symmetric laws)
                let mut dt = r.tangent;
                if symmetric {
                    for (i, j) in [(0, 1), (0, 2), (1, 2)] {
                        let a = 0.5 * (dt[i][j] + dt[j][i]);
                        dt[i][j] = a;
                        dt[j][i] = a;
                    }
                }
                self.add_jump_block(bk, &n, &fr, &dt, da);
                if let Some(hk) = hk.as_mut() {
                    let g = self.gap(&n, ctx.disp);
                    let [dx, de] = frame_derivatives(&fr);
                    let px = frame_force_derivative(&fr, &dx, r.traction, &dt, g);
                    let pe = frame_force_derivative(&fr, &de, r.traction, &dt, g);
                    self.add_frame_block(hk, &n, &dn, [&px, &pe], self.weights[q]);
                }
            }
        }
        if let (Some(k), Some(bk)) = (k, &bk) {
            self.write_tangent(k, bk, hk.as_ref());
            if finite && self.law.tangent_kind() != MatrixKind::General && !ctx.step.exact_tangent {
                self.skew.record(scaled_skew(k, 6 * m));
                symmetrise(k, 6 * m);
            }
        }
        Ok(())
    }

    /// `B += N_a N_b theta D theta^T da`, the jump block of one point.
    fn add_jump_block<const N: usize>(
        &self,
        bk: &mut FaceBlock<N>,
        n: &[f64; 9],
        fr: &Frame,
        dt: &M3,
        da: f64,
    ) {
        let m = self.m();
        let e = &fr.e;
        // G = theta D theta^T (global 3x3)
        let mut g = [[0.0; 3]; 3];
        for c in 0..3 {
            for d in 0..3 {
                let mut s = 0.0;
                for i in 0..3 {
                    for j in 0..3 {
                        s += e[i][c] * dt[i][j] * e[j][d];
                    }
                }
                g[c][d] = s * da;
            }
        }
        for a in 0..m {
            if n[a] == 0.0 {
                continue;
            }
            for b in 0..m {
                let w = n[a] * n[b];
                for (c, gc) in g.iter().enumerate() {
                    let row = &mut bk[3 * a + c][3 * b..3 * b + 3];
                    for (x, gcd) in row.iter_mut().zip(gc) {
                        *x += w * gcd;
                    }
                }
            }
        }
    }

    /// `H += w N_a (P_xi dN_b/dxi + P_eta dN_b/deta) / 2`, the frame and
    /// area block of one point (finite kinematics; weight `w`).
    fn add_frame_block<const N: usize>(
        &self,
        hk: &mut FaceBlock<N>,
        n: &[f64; 9],
        dn: &[[f64; 2]; 9],
        p: [&M3; 2],
        w: f64,
    ) {
        let m = self.m();
        // an axisymmetric line's V_eta = 2 pi r e_z moves with the radius
        // r = sum_b N_b x_b (mid-line): dV_eta / du_{b,x} = pi N_b e_z per face
        let ring = self.line == Some(PlaneWidth::Axisymmetric);
        for a in 0..m {
            if n[a] == 0.0 {
                continue;
            }
            let s = 0.5 * w * n[a];
            for b in 0..m {
                let (sx, se) = (s * dn[b][0], s * dn[b][1]);
                for c in 0..3 {
                    let row = &mut hk[3 * a + c][3 * b..3 * b + 3];
                    for (d, x) in row.iter_mut().enumerate() {
                        *x += sx * p[0][c][d] + se * p[1][c][d];
                    }
                    if ring {
                        row[0] += s * std::f64::consts::TAU * n[b] * p[1][c][2];
                    }
                }
            }
        }
    }

    /// Write `K = [[B - H, -B - H], [H - B, B + H]]` (row-major, 6m x 6m);
    /// `H = 0` (`None`) under small kinematics.
    fn write_tangent<const N: usize>(
        &self,
        k: &mut [f64],
        bk: &FaceBlock<N>,
        hk: Option<&FaceBlock<N>>,
    ) {
        let h = 3 * self.m();
        let nd = 2 * h;
        for i in 0..h {
            let (top, bottom) = (i * nd, (h + i) * nd);
            for j in 0..h {
                let v = bk[i][j];
                match hk {
                    None => {
                        k[top + j] = v;
                        k[top + h + j] = -v;
                        k[bottom + j] = -v;
                        k[bottom + h + j] = v;
                    }
                    Some(hk) => {
                        let g = hk[i][j];
                        k[top + j] = v - g;
                        k[top + h + j] = -v - g;
                        k[bottom + j] = g - v;
                        k[bottom + h + j] = v + g;
                    }
                }
            }
        }
    }
}

/// The largest `|k_ij - k_ji| / sqrt(|k_ii k_jj|)` of a row-major `n x n`.
fn scaled_skew(k: &[f64], n: usize) -> f64 {
    let mut largest: f64 = 0.0;
    for i in 0..n {
        for j in i + 1..n {
            let scale = (k[i * n + i] * k[j * n + j]).abs().sqrt();
            if scale > 0.0 {
                largest = largest.max((k[i * n + j] - k[j * n + i]).abs() / scale);
            }
        }
    }
    largest
}

/// `k = (k + k^T) / 2` in place, row-major `n x n`.
fn symmetrise(k: &mut [f64], n: usize) {
    for i in 0..n {
        for j in i + 1..n {
            let a = 0.5 * (k[i * n + j] + k[j * n + i]);
            k[i * n + j] = a;
            k[j * n + i] = a;
        }
    }
}

/// Most dofs of one face (INTER18: 9 nodes).
const MAX_FACE_DOFS: usize = 3 * 9;

/// A `3m x 3m` block over one face's dofs, in an `N x N` array with
/// `3m <= N`: [`InterfaceElement::compute`] takes the smallest of 12, 18
/// and [`MAX_FACE_DOFS`] that holds it (zeroing the largest costs a small
/// element as much as its whole residual).
type FaceBlock<const N: usize> = [[f64; N]; N];

/// Most integration points of an interface element (INTER18: 9).
const MAX_POINTS: usize = 16;

impl Element for InterfaceElement {
    fn key(&self) -> &'static str {
        self.key
    }
    fn shape(&self) -> CellShape {
        self.shape
    }
    fn num_points(&self) -> usize {
        self.points.len()
    }
    fn state_len(&self) -> usize {
        self.points.len() * self.law.state_len()
    }
    fn init_state(&self, state: &mut [f64]) {
        self.law.init_states(state);
    }

    fn compute(
        &self,
        ctx: &ElementContext<'_>,
        state_trial: &mut [f64],
        f_int: &mut [f64],
        k: Option<&mut [f64]>,
    ) -> Result<(), ElementError> {
        match 3 * self.m() {
            0..=12 => self.compute_sized::<12>(ctx, state_trial, f_int, k),
            13..=18 => self.compute_sized::<18>(ctx, state_trial, f_int, k),
            _ => self.compute_sized::<MAX_FACE_DOFS>(ctx, state_trial, f_int, k),
        }
    }

    fn batch_law(&self) -> Option<&dyn InterfaceLaw> {
        self.law.is_batched().then_some(&*self.law)
    }

    fn jumps_into(
        &self,
        ctx: &ElementContext<'_>,
        out: &mut [[f64; 3]],
    ) -> Result<(), ElementError> {
        let mut n = [0.0; 9];
        let mut dn = [[0.0; 2]; 9];
        for (q, j) in out.iter_mut().enumerate().take(self.points.len()) {
            let fr = self.point_frame(ctx, q, &mut n, &mut dn)?;
            *j = self.jump(&fr, &n, ctx.disp);
        }
        Ok(())
    }

    fn check_geometry(&self, coords: &[[f64; 3]]) -> Result<(), ElementError> {
        let mut n = [0.0; 9];
        for q in 0..self.points.len() {
            self.frame(coords, q, &mut n)?;
        }
        Ok(())
    }

    fn point_outputs(&self, ctx: &ElementContext<'_>) -> Result<Vec<PointOutput>, ElementError> {
        let sl = self.law.state_len();
        let mut trial = vec![0.0; sl];
        let mut n = [0.0; 9];
        let mut dn = [[0.0; 2]; 9];
        let mut out = Vec::with_capacity(self.points.len());
        let mut own = [LawResponse::default(); MAX_POINTS];
        let mut trial_all = vec![0.0; sl * self.points.len()];
        let batch = self.batch_responses(ctx, &mut trial_all, &mut own)?;
        for q in 0..self.points.len() {
            let fr = self.point_frame(ctx, q, &mut n, &mut dn)?;
            let jump = self.jump(&fr, &n, ctx.disp);
            let committed = &ctx.state_committed[q * sl..(q + 1) * sl];
            let r = match batch {
                Some(rs) => rs[q],
                None => self.evaluate_point(ctx, q, &fr, &n, &mut trial)?,
            };
            let stage = self.law.stage(committed);
            let names = self.law.output_names();
            let mut law_out = [0.0; 16];
            let nl = names.len().min(law_out.len());
            self.law.outputs(committed, &mut law_out[..nl]);
            let mut values = vec![
                ("jump", jump.to_vec()),
                ("traction", r.traction.to_vec()),
                ("frame", fr.e.iter().flatten().copied().collect()),
                ("area", vec![fr.jac * self.weights[q]]),
                ("state", committed.to_vec()),
                (
                    "failed",
                    vec![if stage == PointStage::Failed {
                        1.0
                    } else {
                        0.0
                    }],
                ),
                ("stage", vec![stage.code()]),
                (
                    "failure_index",
                    vec![self.law.failure_index(committed).unwrap_or(0.0)],
                ),
            ];
            if self.kinematics == Kinematics::Finite {
                // the point's area on the reference mid-surface: what the
                // crack areas and the dissipated energies are integrated
                // over (a failed point's energy does not change when its
                // faces move apart and the current mid-surface shrinks)
                let fr0 = self.frame(ctx.coords, q, &mut [0.0; 9])?;
                values.push(("reference_area", vec![fr0.jac * self.weights[q]]));
            }
            values.extend(
                names[..nl]
                    .iter()
                    .zip(&law_out)
                    .map(|(n, v)| (*n, vec![*v])),
            );
            out.push(PointOutput {
                position: self.reference_position(ctx.coords, &n),
                values,
            });
        }
        Ok(out)
    }

    /// The laws' dissipated and viscous energies per area times each
    /// point's reference area (the mid-surface of the reference
    /// coordinates, as `area` under small strain and `reference_area`
    /// under nlgeom in [`Element::point_outputs`]), without the other
    /// outputs.
    fn dissipated_energy(&self, ctx: &ElementContext<'_>) -> Result<f64, ElementError> {
        use junta_core::law::output::{DISSIPATED_ENERGY, VISCOUS_ENERGY};
        let names = self.law.output_names();
        let nl = names.len().min(16);
        // in the order point_outputs' readers add them, so that the sum is
        // the same to the last bit
        let wanted: Vec<usize> = [DISSIPATED_ENERGY, VISCOUS_ENERGY]
            .iter()
            .filter_map(|w| names[..nl].iter().position(|n| n == w))
            .collect();
        if wanted.is_empty() {
            return Ok(0.0);
        }
        let sl = self.law.state_len();
        let mut law_out = [0.0; 16];
        let mut total = 0.0;
        for q in 0..self.points.len() {
            let area = self.frame(ctx.coords, q, &mut [0.0; 9])?.jac * self.weights[q];
            self.law.outputs(
                &ctx.state_committed[q * sl..(q + 1) * sl],
                &mut law_out[..nl],
            );
            for &i in &wanted {
                total += law_out[i] * area;
            }
        }
        Ok(total)
    }

    /// The law's outputs of the committed states only, as
    /// [`Element::point_outputs`] lists them (the first 16 of the law's
    /// names), without the element's own (jump, traction, frame).
    fn max_law_output(&self, ctx: &ElementContext<'_>, name: &str) -> Result<f64, ElementError> {
        let names = self.law.output_names();
        let mut law_out = [0.0; 16];
        let nl = names.len().min(law_out.len());
        let Some(i) = names[..nl].iter().position(|n| *n == name) else {
            return Ok(0.0);
        };
        let sl = self.law.state_len();
        let mut max = 0.0f64;
        for q in 0..self.points.len() {
            self.law.outputs(
                &ctx.state_committed[q * sl..(q + 1) * sl],
                &mut law_out[..nl],
            );
            max = max.max(law_out[i]);
        }
        Ok(max)
    }

    fn interface_stiffness(&self) -> Option<[f64; 3]> {
        Some(self.law.initial_stiffness())
    }

    fn tangent_kind(&self) -> MatrixKind {
        // under finite kinematics too: the symmetric part is stored
        self.law.tangent_kind()
    }

    fn symmetrises_tangent(&self) -> bool {
        self.law.tangent_kind() != MatrixKind::General
            && (self.kinematics == Kinematics::Finite || self.law.tangent_is_symmetrised())
    }

    fn take_symmetrised_skew(&self) -> f64 {
        self.skew.take()
    }

    /// `[x, y]` only for a line interface (its `z` jump is not the
    /// model's), all three otherwise.
    fn active_components(&self) -> [bool; 3] {
        [true, true, self.line.is_none()]
    }
    fn plane_width(&self) -> Option<PlaneWidth> {
        self.line
    }
    fn kinematics(&self) -> Kinematics {
        self.kinematics
    }

    fn fracture_properties(&self) -> Option<junta_core::FractureProperties> {
        self.law.fracture_properties()
    }

    fn fatigue_growth_rate(&self, g_max: f64, b: f64, r: f64) -> Option<(f64, f64)> {
        self.law.fatigue_growth_rate(g_max, b, r)
    }

    fn penalty_role(&self) -> Option<junta_core::PenaltyRole> {
        Some(self.law.penalty_role())
    }

    fn warnings(&self) -> Vec<String> {
        self.law.warnings()
    }

    fn has_contact_switch(&self) -> bool {
        self.law.has_contact_switch()
    }

    fn contact_closed_into(
        &self,
        ctx: &ElementContext<'_>,
        out: &mut [bool],
    ) -> Result<(), ElementError> {
        let sl = self.law.state_len();
        let mut n = [0.0; 9];
        let mut dn = [[0.0; 2]; 9];
        for (q, closed) in out.iter_mut().enumerate().take(self.points.len()) {
            let fr = self.point_frame(ctx, q, &mut n, &mut dn)?;
            let jump = self.jump(&fr, &n, ctx.disp);
            let committed = &ctx.state_committed[q * sl..(q + 1) * sl];
            *closed = self.law.contact_closed(jump, committed);
        }
        Ok(())
    }

    fn wants_small_increments(&self, state_committed: &[f64]) -> bool {
        let sl = self.law.state_len();
        sl > 0
            && state_committed
                .chunks(sl)
                .any(|s| self.law.wants_small_increments(s))
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Options {
    integration: Option<InterfaceRule>,
    /// Out-of-plane thickness of a plane line interface (default 1).
    thickness: Option<f64>,
    /// A line interface of an axisymmetric model (the full ring).
    axisymmetric: Option<bool>,
}

/// The width of a line interface from its options (see the module docs).
fn line_width(key: &str, o: &Options) -> Result<PlaneWidth, CoreError> {
    let bad = |message: &str| CoreError::InvalidParameters {
        kind: "element",
        key: key.into(),
        message: message.into(),
    };
    match (o.axisymmetric.unwrap_or(false), o.thickness) {
        (true, Some(_)) => Err(bad(
            "an axisymmetric line interface takes no thickness: it models the full ring",
        )),
        (true, None) => Ok(PlaneWidth::Axisymmetric),
        (false, t) => Ok(PlaneWidth::Thickness(t.unwrap_or(1.0))),
    }
}

fn build(shape: CellShape, key: &str, b: &ElementBuild<'_>) -> Result<Arc<dyn Element>, CoreError> {
    let o: Options = parse_params("element", key, b.options)?;
    if shape.face_shape().is_some_and(|f| f.dimension() == 2) {
        let w = line_width(key, &o)?;
        let law = b.law.clone().ok_or_else(|| CoreError::InvalidParameters {
            kind: "element",
            key: key.into(),
            message: "an interface element needs a traction law (e.g. `law = \"linear_penalty\"`)"
                .into(),
        })?;
        let el = InterfaceElement::new(shape, o.integration.unwrap_or(InterfaceRule::Gauss), law)?
            .with_kinematics(b.kinematics)
            .with_line_width(w)?;
        return Ok(Arc::new(el));
    }
    if o.thickness.is_some() || o.axisymmetric.is_some() {
        return Err(CoreError::InvalidParameters {
            kind: "element",
            key: key.into(),
            message: "thickness and axisymmetric apply to line interfaces only (line_inter4, line_inter6)".into(),
        });
    }
    let law = b.law.clone().ok_or_else(|| CoreError::InvalidParameters {
        kind: "element",
        key: key.into(),
        message: "an interface element needs a traction law (e.g. `law = \"linear_penalty\"`)"
            .into(),
    })?;
    Ok(Arc::new(
        InterfaceElement::new(shape, o.integration.unwrap_or(InterfaceRule::Gauss), law)?
            .with_kinematics(b.kinematics),
    ))
}

const OPTIONS: &[ParamDoc] = &[ParamDoc {
    name: "integration",
    doc: "\"gauss\" (default; the paper's 3x3 for INTER18, 3 points INTER6, 6 points INTER12) or \"lobatto\" (nodal: Gauss-Lobatto on quadrilaterals, the vertices on INTER6; not available for INTER12)",
}];

const LINE_OPTIONS: &[ParamDoc] = &[
    ParamDoc {
        name: "integration",
        doc: "\"gauss\" (default; 2 points line_inter4, 3 line_inter6) or \"lobatto\" (nodal: 2 or 3 Gauss-Lobatto points, the closed Newton-Cotes rules)",
    },
    ParamDoc {
        name: "thickness",
        doc: "out-of-plane thickness of a plane strain / plane stress model (default 1)",
    },
    ParamDoc {
        name: "axisymmetric",
        doc: "true in an axisymmetric model: the full ring, width 2 pi r (default false)",
    },
];

inventory::submit! {
    ElementEntry {
        key: "line_inter4",
        description: "4-node zero-thickness line interface (2+2), matches the edges of linear plane cells (Abaqus COH2D4, COHAX4)",
        params: LINE_OPTIONS,
        shape: CellShape::LineInter4,
        build: |b| build(CellShape::LineInter4, "line_inter4", b),
    }
}
inventory::submit! {
    ElementEntry {
        key: "line_inter6",
        description: "6-node zero-thickness line interface (3+3), matches the edges of quadratic plane cells",
        params: LINE_OPTIONS,
        shape: CellShape::LineInter6,
        build: |b| build(CellShape::LineInter6, "line_inter6", b),
    }
}

inventory::submit! {
    ElementEntry {
        key: "inter8",
        description: "8-node zero-thickness interface (4+4), matches H8 faces",
        params: OPTIONS,
        shape: CellShape::Inter8,
        build: |b| build(CellShape::Inter8, "inter8", b),
    }
}
inventory::submit! {
    ElementEntry {
        key: "inter16",
        description: "16-node zero-thickness interface (8+8), matches H20 faces",
        params: OPTIONS,
        shape: CellShape::Inter16,
        build: |b| build(CellShape::Inter16, "inter16", b),
    }
}
inventory::submit! {
    ElementEntry {
        key: "inter18",
        description: "18-node zero-thickness interface (9+9), matches H27 faces (the paper's INTER18)",
        params: OPTIONS,
        shape: CellShape::Inter18,
        build: |b| build(CellShape::Inter18, "inter18", b),
    }
}
inventory::submit! {
    ElementEntry {
        key: "inter6",
        description: "6-node zero-thickness interface (3+3 triangles), matches wedge6 triangular faces (Abaqus COH3D6)",
        params: OPTIONS,
        shape: CellShape::Inter6,
        build: |b| build(CellShape::Inter6, "inter6", b),
    }
}
inventory::submit! {
    ElementEntry {
        key: "inter12",
        description: "12-node zero-thickness interface (6+6 quadratic triangles), matches wedge15 triangular faces",
        params: OPTIONS,
        shape: CellShape::Inter12,
        build: |b| build(CellShape::Inter12, "inter12", b),
    }
}
