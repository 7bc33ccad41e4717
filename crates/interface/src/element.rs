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
//! Small displacements: the frame is built on the reference geometry.
//!
//! Tangent storage: unless the law declares a general (nonsymmetric)
//! tangent, the element assembles the symmetric part `(D + D^T) / 2` of the
//! law's tangent (mixed-mode softening laws have a slightly nonsymmetric
//! exact tangent where the mode ratio changes with the jump).
//!
//! Point outputs: `jump`, `traction`, `frame`, `area`, `state`, `failed`,
//! `failure_index`, then every scalar the law names in
//! [`InterfaceLaw::output_names`] (e.g. `damage`, `dissipated_energy`).

use junta_core::element::{Element, ElementContext, ElementError, PointOutput};
use junta_core::law::{InterfaceLaw, LawContext, LawResponse};
use junta_core::registry::{parse_params, ElementBuild, ElementEntry, ParamDoc};
use junta_core::topology::CellShape;
use junta_core::CoreError;
use junta_elements::quadrature::{
    gauss_legendre_2d, gauss_lobatto_2d, triangle_rule, triangle_vertex_rule,
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
}

/// Local frame and area factor at one point.
#[derive(Debug, Clone, Copy)]
struct Frame {
    /// Rows: e1, e2, e3.
    e: [[f64; 3]; 3],
    /// |V_xi x V_eta|.
    jac: f64,
    /// Mid-surface position.
    x: [f64; 3],
}

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
            s => {
                return Err(CoreError::Invalid(format!(
                    "{} is not an interface shape",
                    s.name()
                )))
            }
        };
        let triangle = matches!(face, CellShape::Tri3 | CellShape::Tri6);
        let r = match (rule, triangle) {
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
        })
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

    /// Shape functions and frame at point `q`.
    fn frame(
        &self,
        coords: &[[f64; 3]],
        q: usize,
        n: &mut [f64; 9],
    ) -> Result<Frame, ElementError> {
        let m = self.m();
        let mut dn = [[0.0; 2]; 9];
        surface_shape(self.face, self.points[q], &mut n[..m], &mut dn[..m]);
        let mut vxi = [0.0; 3];
        let mut veta = [0.0; 3];
        let mut x = [0.0; 3];
        for a in 0..m {
            for c in 0..3 {
                let xm = 0.5 * (coords[a][c] + coords[m + a][c]);
                x[c] += n[a] * xm;
                vxi[c] += dn[a][0] * xm;
                veta[c] += dn[a][1] * xm;
            }
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
            x,
        })
    }

    /// Local jump at point `q`.
    fn jump(&self, f: &Frame, n: &[f64; 9], disp: &[f64]) -> [f64; 3] {
        let m = self.m();
        let mut g = [0.0; 3];
        for a in 0..m {
            for c in 0..3 {
                g[c] += n[a] * (disp[3 * (m + a) + c] - disp[3 * a + c]);
            }
        }
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
}

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
        let s = self.law.state_len();
        if s > 0 {
            for chunk in state.chunks_mut(s) {
                self.law.init_state(chunk);
            }
        }
    }

    fn compute(
        &self,
        ctx: &ElementContext<'_>,
        state_trial: &mut [f64],
        f_int: &mut [f64],
        k: Option<&mut [f64]>,
    ) -> Result<(), ElementError> {
        let m = self.m();
        let nd = 6 * m;
        f_int[..nd].iter_mut().for_each(|v| *v = 0.0);
        // K = [[B, -B], [-B, B]] over (bottom, top) nodes, with the 3m x 3m
        // block B = sum_q N_a N_b G_q da accumulated first
        const MAX: usize = 3 * 9;
        let mut bk = [[0.0f64; MAX]; MAX];
        let want_k = k.is_some();
        let sl = self.law.state_len();
        let symmetric =
            self.law.tangent_kind() != junta_core::MatrixKind::General && !ctx.step.exact_tangent;
        let mut n = [0.0; 9];
        let mut own = [LawResponse::default(); MAX_POINTS];
        let batch = self.batch_responses(ctx, state_trial, &mut own)?;
        for q in 0..self.points.len() {
            let fr = self.frame(ctx.coords, q, &mut n)?;
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
            if want_k {
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
        }
        if let Some(k) = k {
            let h = 3 * m;
            for (i, row) in bk.iter().enumerate().take(h) {
                let src = &row[..h];
                let (top, bottom) = (i * nd, (h + i) * nd);
                for (j, &v) in src.iter().enumerate() {
                    k[top + j] = v;
                    k[top + h + j] = -v;
                    k[bottom + j] = -v;
                    k[bottom + h + j] = v;
                }
            }
        }
        Ok(())
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
        for (q, j) in out.iter_mut().enumerate().take(self.points.len()) {
            let fr = self.frame(ctx.coords, q, &mut n)?;
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
        let mut out = Vec::with_capacity(self.points.len());
        let mut own = [LawResponse::default(); MAX_POINTS];
        let mut trial_all = vec![0.0; sl * self.points.len()];
        let batch = self.batch_responses(ctx, &mut trial_all, &mut own)?;
        for q in 0..self.points.len() {
            let fr = self.frame(ctx.coords, q, &mut n)?;
            let jump = self.jump(&fr, &n, ctx.disp);
            let committed = &ctx.state_committed[q * sl..(q + 1) * sl];
            let r = match batch {
                Some(rs) => rs[q],
                None => self.evaluate_point(ctx, q, &fr, &n, &mut trial)?,
            };
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
                    vec![if self.law.is_failed(committed) {
                        1.0
                    } else {
                        0.0
                    }],
                ),
                (
                    "failure_index",
                    vec![self.law.failure_index(committed).unwrap_or(0.0)],
                ),
            ];
            values.extend(
                names[..nl]
                    .iter()
                    .zip(&law_out)
                    .map(|(n, v)| (*n, vec![*v])),
            );
            out.push(PointOutput {
                position: fr.x,
                values,
            });
        }
        Ok(out)
    }

    fn interface_stiffness(&self) -> Option<[f64; 3]> {
        Some(self.law.initial_stiffness())
    }

    fn tangent_kind(&self) -> junta_core::MatrixKind {
        self.law.tangent_kind()
    }

    fn symmetrises_tangent(&self) -> bool {
        self.law.tangent_kind() != junta_core::MatrixKind::General
            && self.law.tangent_is_symmetrised()
    }

    fn fracture_properties(&self) -> Option<junta_core::FractureProperties> {
        self.law.fracture_properties()
    }

    fn penalty_role(&self) -> Option<junta_core::PenaltyRole> {
        Some(self.law.penalty_role())
    }

    fn warnings(&self) -> Vec<String> {
        self.law.warnings()
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
}

fn build(shape: CellShape, key: &str, b: &ElementBuild<'_>) -> Result<Arc<dyn Element>, CoreError> {
    let o: Options = parse_params("element", key, b.options)?;
    junta_elements::small_strain_only(key, b.kinematics)?;
    let law = b.law.clone().ok_or_else(|| CoreError::InvalidParameters {
        kind: "element",
        key: key.into(),
        message: "an interface element needs a traction law (e.g. `law = \"linear_penalty\"`)"
            .into(),
    })?;
    Ok(Arc::new(InterfaceElement::new(
        shape,
        o.integration.unwrap_or(InterfaceRule::Gauss),
        law,
    )?))
}

const OPTIONS: &[ParamDoc] = &[ParamDoc {
    name: "integration",
    doc: "\"gauss\" (default; the paper's 3x3 for INTER18, 3 points INTER6, 6 points INTER12) or \"lobatto\" (nodal: Gauss-Lobatto on quadrilaterals, the vertices on INTER6; not available for INTER12)",
}];

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
