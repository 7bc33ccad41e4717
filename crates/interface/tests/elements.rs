//! Verification tests of the zero-thickness interface elements INTER8 /
//! INTER16 / INTER18 (paper section 3, eqs. 15-39) and their triangular
//! siblings INTER6 / INTER12, with both Gauss and Lobatto integration
//! (Lobatto = the vertex rule on INTER6; INTER12 has no nodal rule and is
//! tested with Gauss only, its Lobatto refusal in 8.):
//!
//! 1. stiffness symmetric, positive semi-definite, null space of dimension
//!    exactly 3m, rigid-body modes give zero force;
//! 2. constant-jump patch test on a skewed flat face in 3D (triangles: also
//!    the consistent nodal forces against their closed form);
//! 3. frame invariance under a rotation of the whole element;
//! 4. local frame orthonormal on skewed / curved faces (erratum to eq. 26);
//! 5. element tangent against central finite differences, linear law and a
//!    nonlinear, non-symmetric test law;
//! 6. Gauss vs Lobatto (equal resultants; nodal decoupling of Lobatto);
//! 7. degenerate surfaces rejected with `DegenerateSurface`;
//! 8. registry entries and their parameter checks.

use junta_core::element::{Element, ElementContext, ElementError, PointOutput};
use junta_core::law::{InterfaceLaw, LawContext, LawError, LawResponse};
use junta_core::registry::{find, ElementBuild, ElementEntry, LawEntry};
use junta_core::topology::{CellShape, QUAD9_NODES, TRI6_NODES};
use junta_elements::quadrature::{triangle_rule, triangle_vertex_rule};
use junta_elements::shape::surface_shape;
use junta_interface as _;
use junta_interface::{InterfaceElement, InterfaceRule, LinearPenalty};
use nalgebra::DMatrix;
use std::sync::Arc;

// ---------------------------------------------------------------- helpers

type V3 = [f64; 3];

const SHAPES: [CellShape; 5] = [
    CellShape::Inter8,
    CellShape::Inter16,
    CellShape::Inter18,
    CellShape::Inter6,
    CellShape::Inter12,
];
const RULES: [InterfaceRule; 2] = [InterfaceRule::Gauss, InterfaceRule::Lobatto];

/// True for the element / rule pairs that exist (INTER12 has no nodal rule).
fn exists(shape: CellShape, rule: InterfaceRule) -> bool {
    !(shape == CellShape::Inter12 && rule == InterfaceRule::Lobatto)
}

/// True for the triangular interfaces.
fn is_tri(shape: CellShape) -> bool {
    matches!(shape, CellShape::Inter6 | CellShape::Inter12)
}

fn face_of(shape: CellShape) -> CellShape {
    shape.face_shape().unwrap()
}

/// Number of nodes of one face.
fn m_of(shape: CellShape) -> usize {
    face_of(shape).num_nodes()
}

fn add(a: V3, b: V3) -> V3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn scale(s: f64, a: V3) -> V3 {
    [s * a[0], s * a[1], s * a[2]]
}
fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn norm(a: V3) -> f64 {
    dot(a, a).sqrt()
}
fn mat_vec(r: &[[f64; 3]; 3], a: V3) -> V3 {
    [dot(r[0], a), dot(r[1], a), dot(r[2], a)]
}

/// Rotation matrix from an axis (any length) and an angle (Rodrigues).
fn rotation(axis: V3, angle: f64) -> [[f64; 3]; 3] {
    let k = scale(1.0 / norm(axis), axis);
    let (s, c) = angle.sin_cos();
    let mut r = [[0.0; 3]; 3];
    for (i, row) in r.iter_mut().enumerate() {
        for (j, v) in row.iter_mut().enumerate() {
            let delta = if i == j { 1.0 } else { 0.0 };
            *v = c * delta + (1.0 - c) * k[i] * k[j];
        }
    }
    // + sin * [k]_x
    r[0][1] -= s * k[2];
    r[0][2] += s * k[1];
    r[1][0] += s * k[2];
    r[1][2] -= s * k[0];
    r[2][0] -= s * k[1];
    r[2][1] += s * k[0];
    r
}

/// Small deterministic generator (xorshift64*), values in [-1, 1].
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let v = self.0.wrapping_mul(0x2545_F491_4F6C_DD1D);
        (v >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }
    fn vec(&mut self, n: usize) -> Vec<f64> {
        (0..n).map(|_| self.next()).collect()
    }
}

/// Face nodes (Q or triangle order) of `shape`'s face, from a map of the
/// natural square: a triangle's natural (r, s) is the square's (2r - 1,
/// 2s - 1), so the triangle is the half of the mapped square on the side of
/// its corners 0, 1, 3.
fn face_nodes(shape: CellShape, map: impl Fn(f64, f64) -> V3) -> Vec<V3> {
    if is_tri(shape) {
        return TRI6_NODES[..m_of(shape)]
            .iter()
            .map(|p| map(2.0 * p[0] - 1.0, 2.0 * p[1] - 1.0))
            .collect();
    }
    QUAD9_NODES[..m_of(shape)]
        .iter()
        .map(|p| map(p[0], p[1]))
        .collect()
}

/// Affine map of the natural square onto the parallelogram spanned by
/// corners `c[0]`, `c[1]`, `c[3]` (flat triangles with straight edges and
/// mid-edge nodes at the midpoints).
fn affine(c: [V3; 4]) -> impl Fn(f64, f64) -> V3 {
    move |x, y| {
        add(
            c[0],
            add(
                scale(0.5 * (x + 1.0), sub(c[1], c[0])),
                scale(0.5 * (y + 1.0), sub(c[3], c[0])),
            ),
        )
    }
}

/// Bilinear map through 4 corners (Q order).
fn bilinear(c: [V3; 4]) -> impl Fn(f64, f64) -> V3 {
    move |x, y| {
        let n = [
            0.25 * (1.0 - x) * (1.0 - y),
            0.25 * (1.0 + x) * (1.0 - y),
            0.25 * (1.0 + x) * (1.0 + y),
            0.25 * (1.0 - x) * (1.0 + y),
        ];
        let mut p = [0.0; 3];
        for a in 0..4 {
            p = add(p, scale(n[a], c[a]));
        }
        p
    }
}

/// Interface coordinates: the face twice (bottom then top, zero thickness).
fn doubled(face: &[V3]) -> Vec<V3> {
    face.iter().chain(face.iter()).copied().collect()
}

/// A flat, skewed, trapezoidal quadrilateral (convex, counter-clockwise in
/// its own plane) placed in an arbitrary orientation in 3D. Returns the
/// corners and the rotation used (its third column is the normal).
fn skewed_corners() -> ([V3; 4], [[f64; 3]; 3]) {
    let r = rotation([0.3, -1.1, 0.7], 1.1);
    let o = [0.4, -0.2, 1.3];
    let plane = [
        [0.0, 0.0, 0.0],
        [1.3, 0.15, 0.0],
        [1.05, 0.95, 0.0],
        [0.2, 0.7, 0.0],
    ];
    (plane.map(|p| add(o, mat_vec(&r, p))), r)
}

/// A curved, distorted face: skewed corners, mid-side and centre nodes moved
/// in plane and lifted out of the plane (Q8/Q9); a warped Q4 for INTER8.
fn curved_face(shape: CellShape) -> Vec<V3> {
    let (c, r) = skewed_corners();
    let n = [r[0][2], r[1][2], r[2][2]];
    let base = bilinear(c);
    let t = sub(c[1], c[0]);
    let map = |x: f64, y: f64| {
        let lift = 0.12 * (1.0 - x * x) + 0.08 * (1.0 - y * y) + 0.03 * x * y;
        let shift = 0.04 * (1.0 - x * x) * y;
        add(add(base(x, y), scale(lift, n)), scale(shift, t))
    };
    let mut f = face_nodes(shape, map);
    if matches!(shape, CellShape::Inter8 | CellShape::Inter6) {
        // warp: lift one corner out of the plane (INTER6: tilt the triangle)
        f[2] = add(f[2], scale(0.1, n));
    }
    f
}

fn element(shape: CellShape, rule: InterfaceRule, d: V3) -> InterfaceElement {
    InterfaceElement::new(shape, rule, Arc::new(LinearPenalty::new(d).unwrap())).unwrap()
}

fn element_with(
    shape: CellShape,
    rule: InterfaceRule,
    law: Arc<dyn InterfaceLaw>,
) -> InterfaceElement {
    InterfaceElement::new(shape, rule, law).unwrap()
}

fn ctx<'a>(coords: &'a [V3], disp: &'a [f64], state: &'a [f64]) -> ElementContext<'a> {
    ElementContext {
        coords,
        disp,
        state_committed: state,
        step: Default::default(),
        law_responses: None,
        temperature: None,
    }
}

/// Internal force and tangent (row-major).
fn compute(el: &InterfaceElement, coords: &[V3], disp: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let nd = 3 * el.num_nodes();
    let committed = committed_state(el);
    let mut trial = vec![0.0; el.state_len()];
    let mut f = vec![f64::NAN; nd];
    let mut k = vec![f64::NAN; nd * nd];
    el.compute(
        &ctx(coords, disp, &committed),
        &mut trial,
        &mut f,
        Some(&mut k),
    )
    .unwrap();
    (f, k)
}

/// Internal force only.
fn force(el: &InterfaceElement, coords: &[V3], disp: &[f64]) -> Vec<f64> {
    let committed = committed_state(el);
    let mut trial = vec![0.0; el.state_len()];
    let mut f = vec![f64::NAN; 3 * el.num_nodes()];
    el.compute(&ctx(coords, disp, &committed), &mut trial, &mut f, None)
        .unwrap();
    f
}

fn committed_state(el: &InterfaceElement) -> Vec<f64> {
    let mut s = vec![0.0; el.state_len()];
    el.init_state(&mut s);
    s
}

fn outputs(el: &InterfaceElement, coords: &[V3], disp: &[f64]) -> Vec<PointOutput> {
    let committed = committed_state(el);
    el.point_outputs(&ctx(coords, disp, &committed)).unwrap()
}

fn get3(p: &PointOutput, name: &str) -> V3 {
    let v = p.get(name).unwrap_or_else(|| panic!("no output {name}"));
    assert_eq!(v.len(), 3, "{name}");
    [v[0], v[1], v[2]]
}

/// Rows e1, e2, e3 of the "frame" output.
fn frame(p: &PointOutput) -> [V3; 3] {
    let v = p.get("frame").expect("no frame output");
    assert_eq!(v.len(), 9);
    [[v[0], v[1], v[2]], [v[3], v[4], v[5]], [v[6], v[7], v[8]]]
}

/// Tangents V_xi, V_eta of the face at natural point `xi`, computed here
/// independently of the kernel.
fn tangents(shape: CellShape, face: &[V3], xi: [f64; 2]) -> (V3, V3) {
    let m = m_of(shape);
    let mut n = [0.0; 9];
    let mut dn = [[0.0; 2]; 9];
    surface_shape(face_of(shape), xi, &mut n[..m], &mut dn[..m]);
    let mut vx = [0.0; 3];
    let mut ve = [0.0; 3];
    for a in 0..m {
        vx = add(vx, scale(dn[a][0], face[a]));
        ve = add(ve, scale(dn[a][1], face[a]));
    }
    (vx, ve)
}

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |m, x| m.max(x.abs()))
}

fn label(shape: CellShape, rule: InterfaceRule) -> String {
    format!("{}/{:?}", shape.name(), rule)
}

/// Node `a`'s 3-vector in a node-major array.
fn node(v: &[f64], a: usize) -> V3 {
    [v[3 * a], v[3 * a + 1], v[3 * a + 2]]
}

/// Sum of the nodal vectors of nodes `range`.
fn resultant(f: &[f64], range: std::ops::Range<usize>) -> V3 {
    range.fold([0.0; 3], |s, a| add(s, node(f, a)))
}

// ------------------------------------------------------ a nonlinear law

/// Test law, nonlinear and with a non-symmetric, full tangent:
///
/// ```text
/// t_1 = d1 delta_1 + c delta_1^3 + b delta_2 delta_3
/// t_2 = d2 delta_2 + c delta_2^3
/// t_3 = d3 delta_3 + c delta_3^3 + a delta_1^2
/// ```
///
/// One state value per point: the trial opening delta_3 (to check the
/// element's state slicing).
#[derive(Debug)]
struct CubicLaw {
    d: V3,
    c: f64,
    a: f64,
    b: f64,
}

impl InterfaceLaw for CubicLaw {
    fn key(&self) -> &'static str {
        "test_cubic"
    }
    /// Nonsymmetric tangent: the element must assemble it in full (laws
    /// that do not declare `General` get the symmetric part).
    fn tangent_kind(&self) -> junta_core::MatrixKind {
        junta_core::MatrixKind::General
    }
    fn state_len(&self) -> usize {
        1
    }
    fn init_state(&self, state: &mut [f64]) {
        state[0] = -7.0;
    }
    fn evaluate(&self, ctx: &LawContext<'_>, state: &mut [f64]) -> Result<LawResponse, LawError> {
        assert_eq!(ctx.state_committed, &[-7.0], "committed state slice");
        let [x, y, z] = ctx.jump;
        let (d, c) = (self.d, self.c);
        let r = LawResponse {
            traction: [
                d[0] * x + c * x * x * x + self.b * y * z,
                d[1] * y + c * y * y * y,
                d[2] * z + c * z * z * z + self.a * x * x,
            ],
            tangent: [
                [d[0] + 3.0 * c * x * x, self.b * z, self.b * y],
                [0.0, d[1] + 3.0 * c * y * y, 0.0],
                [2.0 * self.a * x, 0.0, d[2] + 3.0 * c * z * z],
            ],
        };
        state[0] = z;
        Ok(r)
    }
    fn initial_stiffness(&self) -> V3 {
        self.d
    }
}

// ------------------------------------------------------------------ tests

/// 1. K symmetric, PSD, exactly 3m zero eigenvalues; rigid-body modes give
///    zero internal force and K r = 0.
#[test]
fn stiffness_symmetric_psd_rank_and_rigid_modes() {
    let d = [2.0e3, 3.5e3, 7.0e3];
    for shape in SHAPES {
        for rule in RULES {
            if !exists(shape, rule) {
                continue;
            }
            for curved in [false, true] {
                let name = format!("{} curved={curved}", label(shape, rule));
                let face = if curved {
                    curved_face(shape)
                } else {
                    face_nodes(shape, bilinear(skewed_corners().0))
                };
                let coords = doubled(&face);
                let m = m_of(shape);
                let nd = 6 * m;
                let el = element(shape, rule, d);
                let (f0, k) = compute(&el, &coords, &vec![0.0; nd]);
                assert!(f0.iter().all(|v| *v == 0.0), "{name}: f(0) != 0");
                let kmax = max_abs(&k);
                assert!(kmax > 0.0 && kmax.is_finite(), "{name}");
                for i in 0..nd {
                    for j in 0..nd {
                        let (a, b) = (k[i * nd + j], k[j * nd + i]);
                        assert!(
                            (a - b).abs() <= 1e-12 * kmax,
                            "{name}: K[{i}][{j}] = {a} vs K[{j}][{i}] = {b}"
                        );
                    }
                }
                let km = DMatrix::from_row_slice(nd, nd, &k);
                let ev = km.symmetric_eigen().eigenvalues;
                let lmax = ev.iter().fold(0.0f64, |m, v| m.max(*v));
                let lmin = ev.iter().fold(f64::INFINITY, |m, v| m.min(*v));
                assert!(lmin >= -1e-10 * lmax, "{name}: eigenvalue {lmin} < 0");
                let zeros = ev.iter().filter(|v| v.abs() <= 1e-10 * lmax).count();
                assert_eq!(zeros, 3 * m, "{name}: zero eigenvalues {ev:?}");
                // the non-zero ones are clearly non-zero (rank is 3m, not less)
                let smallest_nonzero = ev
                    .iter()
                    .filter(|v| v.abs() > 1e-10 * lmax)
                    .fold(f64::INFINITY, |m, v| m.min(*v));
                assert!(smallest_nonzero > 1e-6 * lmax, "{name}: {ev:?}");

                // rigid-body modes of the pair: translations and rotations
                // about an arbitrary point, both faces identically
                let p0 = [0.7, -1.3, 2.1];
                let mut modes: Vec<Vec<f64>> = Vec::new();
                for c in 0..3 {
                    let mut u = vec![0.0; nd];
                    for a in 0..2 * m {
                        u[3 * a + c] = 1e-3;
                    }
                    modes.push(u);
                }
                for c in 0..3 {
                    let mut w = [0.0; 3];
                    w[c] = 1e-3;
                    let u: Vec<f64> = coords.iter().flat_map(|x| cross(w, sub(*x, p0))).collect();
                    modes.push(u);
                }
                // a generic combination too
                let mut comb = vec![0.0; nd];
                for (i, u) in modes.iter().enumerate() {
                    for (cv, uv) in comb.iter_mut().zip(u) {
                        *cv += (i as f64 + 1.3) * uv;
                    }
                }
                modes.push(comb);
                // scale of a genuine (non-rigid) force for the tolerance
                let mut top_only = vec![0.0; nd];
                for a in m..2 * m {
                    top_only[3 * a] = 1e-3;
                }
                let fref = max_abs(&force(&el, &coords, &top_only));
                assert!(fref > 0.0, "{name}: a relative slip gives no force");
                for (i, u) in modes.iter().enumerate() {
                    let f = force(&el, &coords, u);
                    assert!(
                        max_abs(&f) <= 1e-13 * fref,
                        "{name}: rigid mode {i} gives force {f:?}"
                    );
                    let ku: Vec<f64> = (0..nd)
                        .map(|r| (0..nd).map(|c| k[r * nd + c] * u[c]).sum())
                        .collect();
                    assert!(
                        max_abs(&ku) <= 1e-13 * fref,
                        "{name}: K r != 0 for mode {i}"
                    );
                }
            }
        }
    }
}

/// 2. Constant-jump patch test on a skewed, trapezoidal, flat face in an
///    arbitrary 3D orientation (triangles: the triangle c0, c1, c3 of its
///    corners, straight-edged). A uniform jump gives the uniform traction
///    D theta^T jump at every point, the resultants are traction x area,
///    and on triangles each top node carries its consistent share
///    `t int N_a dA` (closed forms: Tri3 A/3 per corner; Tri6 0 per corner
///    and A/3 per mid-edge node), the bottom nodes the opposite.
#[test]
fn constant_jump_patch_test() {
    let (corners, rot) = skewed_corners();
    // normal and area computed independently from the corners
    let nvec = cross(sub(corners[1], corners[0]), sub(corners[2], corners[0]));
    let nvec2 = cross(sub(corners[2], corners[0]), sub(corners[3], corners[0]));
    let quad_area = 0.5 * norm(nvec) + 0.5 * norm(nvec2);
    let tri_area = 0.5
        * norm(cross(
            sub(corners[1], corners[0]),
            sub(corners[3], corners[0]),
        ));
    let n = scale(1.0 / norm(nvec), nvec);
    // the face is flat and its normal is the rotated z axis
    assert!(norm(sub(n, [rot[0][2], rot[1][2], rot[2][2]])) < 1e-14);
    assert!(norm(sub(scale(1.0 / norm(nvec2), nvec2), n)) < 1e-14);

    let jump_g = [3.0e-4, -1.7e-4, 2.2e-4];
    let mut rng = Rng(0x1234_5678_9abc_def1);
    for shape in SHAPES {
        for rule in RULES {
            if !exists(shape, rule) {
                continue;
            }
            let name = label(shape, rule);
            let (face, area) = if is_tri(shape) {
                (face_nodes(shape, affine(corners)), tri_area)
            } else {
                (face_nodes(shape, bilinear(corners)), quad_area)
            };
            let coords = doubled(&face);
            let m = m_of(shape);
            // common (arbitrary) motion of both faces plus the jump on top
            let common = rng.vec(3 * m);
            let mut disp = vec![0.0; 6 * m];
            for a in 0..m {
                for c in 0..3 {
                    disp[3 * a + c] = 1e-3 * common[3 * a + c];
                    disp[3 * (m + a) + c] = 1e-3 * common[3 * a + c] + jump_g[c];
                }
            }

            // (a) anisotropic D: local traction = D theta^T jump at every point
            let d = [1.0e4, 2.5e4, 6.0e4];
            let el = element(shape, rule, d);
            let outs = outputs(&el, &coords, &disp);
            assert_eq!(outs.len(), el.num_points(), "{name}");
            for (q, p) in outs.iter().enumerate() {
                let e = frame(p);
                let local = [dot(e[0], jump_g), dot(e[1], jump_g), dot(e[2], jump_g)];
                let jump = get3(p, "jump");
                let t = get3(p, "traction");
                for i in 0..3 {
                    assert!(
                        (jump[i] - local[i]).abs() <= 1e-12 * norm(jump_g),
                        "{name} point {q}: jump {jump:?} vs {local:?}"
                    );
                    assert!(
                        (t[i] - d[i] * local[i]).abs() <= 1e-12 * 6.0e4 * norm(jump_g),
                        "{name} point {q}: traction {t:?}"
                    );
                }
                // normal of the frame is the face normal (bottom -> top)
                assert!(
                    norm(sub(e[2], n)) < 1e-13,
                    "{name} point {q}: e3 {:?}",
                    e[2]
                );
            }
            let area_sum: f64 = outs.iter().map(|p| p.get("area").unwrap()[0]).sum();
            assert!(
                (area_sum - area).abs() <= 1e-13 * area,
                "{name}: area {area_sum} vs {area}"
            );

            // (b) in-plane isotropic D: global traction is constant, total
            //     force on the top face = traction * area
            let d = [1.0e4, 1.0e4, 6.0e4];
            let el = element(shape, rule, d);
            let jn = dot(jump_g, n);
            let tg = add(scale(d[0], sub(jump_g, scale(jn, n))), scale(d[2] * jn, n));
            let f = force(&el, &coords, &disp);
            let top = resultant(&f, m..2 * m);
            let bot = resultant(&f, 0..m);
            let expect = scale(area, tg);
            for c in 0..3 {
                assert!(
                    (top[c] - expect[c]).abs() <= 1e-12 * norm(expect),
                    "{name}: top resultant {top:?} vs {expect:?}"
                );
                assert!(
                    (bot[c] + expect[c]).abs() <= 1e-12 * norm(expect),
                    "{name}: bottom resultant {bot:?} vs {:?}",
                    scale(-1.0, expect)
                );
            }
            if is_tri(shape) {
                for a in 0..m {
                    let share = match (shape, a < 3) {
                        (CellShape::Inter6, _) => 1.0 / 3.0,
                        (_, true) => 0.0,
                        (_, false) => 1.0 / 3.0,
                    };
                    let want = scale(share * area, tg);
                    let (top, bot) = (node(&f, m + a), node(&f, a));
                    assert!(
                        norm(sub(top, want)) <= 1e-12 * norm(expect),
                        "{name}: top node {a} force {top:?} vs {want:?}"
                    );
                    assert!(
                        norm(add(bot, want)) <= 1e-12 * norm(expect),
                        "{name}: bottom node {a} force {bot:?}"
                    );
                }
            }
        }
    }
}

/// The paper's prism interface (0.2 x 0.2 face at z = 0.01, INTER18).
fn prism_face(shape: CellShape) -> Vec<V3> {
    face_nodes(shape, |x, y| [0.1 * (1.0 + x), 0.1 * (1.0 + y), 0.01])
}

/// 3. Frame invariance: rotating the element and its displacements leaves
///    the local jumps and tractions unchanged and rotates the nodal forces.
#[test]
fn frame_invariance_under_rotation() {
    let r = rotation([1.0, 2.0, 3.0], 0.7);
    let offset = [0.3, -0.5, 1.7];
    let d = [1.0e25, 2.0e25, 3.0e25];
    let mut rng = Rng(0x0f0f_1234_5555_9999);
    let cases: Vec<(CellShape, InterfaceRule, Vec<V3>, &str)> = vec![
        (
            CellShape::Inter18,
            InterfaceRule::Gauss,
            prism_face(CellShape::Inter18),
            "prism",
        ),
        (
            CellShape::Inter18,
            InterfaceRule::Lobatto,
            prism_face(CellShape::Inter18),
            "prism",
        ),
    ]
    .into_iter()
    .chain(SHAPES.iter().flat_map(|&s| {
        RULES
            .iter()
            .filter(move |&&rule| exists(s, rule))
            .map(move |&rule| (s, rule, curved_face(s), "curved"))
    }))
    .collect();
    for (shape, rule, face, what) in cases {
        let name = format!("{} {what}", label(shape, rule));
        let m = m_of(shape);
        let el = element(shape, rule, d);
        let coords = doubled(&face);
        // prism: a uniform jump given in the local frame (= global axes
        // there), plus arbitrary nodal noise on both faces
        let local_jump = [1.0e-6, -2.0e-6, 1.25e-5];
        let noise = rng.vec(6 * m);
        let disp: Vec<f64> = (0..6 * m)
            .map(|i| {
                let top = if i >= 3 * m { local_jump[i % 3] } else { 0.0 };
                top + 3.0e-6 * noise[i]
            })
            .collect();
        let coords_r: Vec<V3> = coords
            .iter()
            .map(|x| add(offset, mat_vec(&r, *x)))
            .collect();
        let disp_r: Vec<f64> = (0..2 * m)
            .flat_map(|a| mat_vec(&r, node(&disp, a)))
            .collect();

        let o = outputs(&el, &coords, &disp);
        let o_r = outputs(&el, &coords_r, &disp_r);
        if what == "prism" {
            // on the axis-aligned prism the local frame is the global one
            for p in &o {
                let e = frame(p);
                for (i, ei) in e.iter().enumerate() {
                    let mut ax = [0.0; 3];
                    ax[i] = 1.0;
                    assert!(norm(sub(*ei, ax)) < 1e-14, "{name}: frame {e:?}");
                }
            }
        }
        for (q, (p, pr)) in o.iter().zip(&o_r).enumerate() {
            for key in ["jump", "traction"] {
                let (a, b) = (get3(p, key), get3(pr, key));
                assert!(
                    norm(sub(a, b)) <= 1e-10 * norm(a),
                    "{name} point {q}: {key} {a:?} vs rotated {b:?}"
                );
            }
            let (e, er) = (frame(p), frame(pr));
            for i in 0..3 {
                assert!(
                    norm(sub(mat_vec(&r, e[i]), er[i])) < 1e-13,
                    "{name} point {q}: frame vector e{} does not rotate",
                    i + 1
                );
            }
            let x = add(offset, mat_vec(&r, p.position));
            assert!(norm(sub(x, pr.position)) < 1e-13, "{name}: position");
        }
        let (f, k) = compute(&el, &coords, &disp);
        let (f_r, k_r) = compute(&el, &coords_r, &disp_r);
        let fmax = max_abs(&f);
        for a in 0..2 * m {
            let expect = mat_vec(&r, node(&f, a));
            assert!(
                norm(sub(expect, node(&f_r, a))) <= 1e-10 * fmax,
                "{name} node {a}: R f = {expect:?}, rotated element gives {:?}",
                node(&f_r, a)
            );
        }
        // and the tangent: K_r = Q K Q^T, Q = blockdiag(R)
        let nd = 6 * m;
        let q = DMatrix::from_fn(
            nd,
            nd,
            |i, j| {
                if i / 3 == j / 3 {
                    r[i % 3][j % 3]
                } else {
                    0.0
                }
            },
        );
        let km = DMatrix::from_row_slice(nd, nd, &k);
        let kr = DMatrix::from_row_slice(nd, nd, &k_r);
        let diff = &q * km * q.transpose() - &kr;
        assert!(
            diff.amax() <= 1e-10 * kr.amax(),
            "{name}: tangent does not rotate"
        );
    }
}

/// 4. On a skewed parallelogram (non-orthogonal tangents) and on curved
///    faces, the frame is orthonormal and right-handed, e3 is normal to both
///    tangents, e1 along V_xi. The paper's eq. 26 normalisation would not
///    give a unit normal there.
#[test]
fn frame_orthonormal_on_skewed_and_curved_faces() {
    let r = rotation([-0.4, 0.9, 0.2], 2.3);
    let o = [1.0, 2.0, -0.5];
    let para: [V3; 4] = [
        [0.0, 0.0, 0.0],
        [2.0, 0.0, 0.0],
        [3.5, 1.0, 0.0],
        [1.5, 1.0, 0.0],
    ]
    .map(|p| add(o, mat_vec(&r, p)));
    let plane_n = [r[0][2], r[1][2], r[2][2]];
    for shape in SHAPES {
        for rule in RULES {
            if !exists(shape, rule) {
                continue;
            }
            let mut faces = vec![("parallelogram", face_nodes(shape, bilinear(para)))];
            faces.push(("curved", curved_face(shape)));
            if shape == CellShape::Inter18 {
                // a Q9 face with mid-side nodes and centre lifted out of plane
                // over the skewed parallelogram
                let base = bilinear(para);
                let mut f = face_nodes(shape, base);
                for (a, lift) in [(4, 0.2), (5, -0.15), (6, 0.1), (7, 0.25), (8, 0.3)] {
                    f[a] = add(f[a], scale(lift, plane_n));
                }
                faces.push(("lifted Q9", f));
            }
            for (what, face) in faces {
                let name = format!("{} {what}", label(shape, rule));
                let coords = doubled(&face);
                let el = element(shape, rule, [1.0, 1.0, 1.0]);
                let outs = outputs(&el, &coords, &vec![0.0; coords.len() * 3]);
                let mut worst_wrong: f64 = 0.0;
                for (q, p) in outs.iter().enumerate() {
                    let [e1, e2, e3] = frame(p);
                    let (vx, ve) = tangents(shape, &face, el.points()[q]);
                    for (i, ei) in [e1, e2, e3].iter().enumerate() {
                        assert!(
                            (norm(*ei) - 1.0).abs() <= 1e-14,
                            "{name} point {q}: |e{}| = {}",
                            i + 1,
                            norm(*ei)
                        );
                    }
                    assert!(dot(e1, e2).abs() <= 1e-14, "{name} point {q}: e1.e2");
                    assert!(dot(e1, e3).abs() <= 1e-14, "{name} point {q}: e1.e3");
                    assert!(dot(e2, e3).abs() <= 1e-14, "{name} point {q}: e2.e3");
                    assert!(
                        (dot(cross(e1, e2), e3) - 1.0).abs() <= 1e-14,
                        "{name} point {q}: not right-handed"
                    );
                    assert!(
                        dot(e3, vx).abs() <= 1e-14 * norm(vx),
                        "{name} point {q}: e3 not normal to V_xi"
                    );
                    assert!(
                        dot(e3, ve).abs() <= 1e-14 * norm(ve),
                        "{name} point {q}: e3 not normal to V_eta"
                    );
                    assert!(
                        norm(sub(e1, scale(1.0 / norm(vx), vx))) <= 1e-14,
                        "{name} point {q}: e1 not along V_xi"
                    );
                    // normal from bottom to top = V_xi x V_eta side
                    assert!(dot(e3, cross(vx, ve)) > 0.0, "{name} point {q}");
                    // area factor |V_xi x V_eta| w
                    let w = p.get("area").unwrap()[0];
                    assert!(w > 0.0, "{name} point {q}: area weight {w}");
                    // the erratum: eq. 26 as printed
                    let wrong = scale(1.0 / (norm(vx) * norm(ve)), cross(vx, ve));
                    worst_wrong = worst_wrong.max((norm(wrong) - 1.0).abs());
                }
                if what == "parallelogram" {
                    // angle between the tangents is constant on a parallelogram:
                    // sin = |V_xi x V_eta| / (|V_xi||V_eta|) < 1
                    let (vx, ve) = tangents(shape, &face, [0.0, 0.0]);
                    let sin = norm(cross(vx, ve)) / (norm(vx) * norm(ve));
                    assert!(sin < 0.9, "{name}: tangents are nearly orthogonal");
                    assert!(
                        (worst_wrong - (1.0 - sin)).abs() < 1e-12,
                        "{name}: eq. 26 gives |n| = {}",
                        1.0 - worst_wrong
                    );
                }
                assert!(
                    worst_wrong > 1e-3,
                    "{name}: eq. 26 would give a unit normal here, the test is void"
                );
            }
        }
    }
}

/// The frame is built on the mid-surface of the two faces (matters only when
/// the reference faces do not coincide, e.g. an initial gap in a mesh).
#[test]
fn frame_is_built_on_the_mid_surface() {
    for shape in SHAPES {
        for rule in RULES {
            if !exists(shape, rule) {
                continue;
            }
            let name = label(shape, rule);
            let bottom = face_nodes(shape, bilinear(skewed_corners().0));
            let top = curved_face(shape);
            let coords: Vec<V3> = bottom.iter().chain(top.iter()).copied().collect();
            let mid: Vec<V3> = bottom
                .iter()
                .zip(&top)
                .map(|(a, b)| scale(0.5, add(*a, *b)))
                .collect();
            let el = element(shape, rule, [1.0, 1.0, 1.0]);
            let outs = outputs(&el, &coords, &vec![0.0; 3 * coords.len()]);
            let mut differs: f64 = 0.0;
            for (q, p) in outs.iter().enumerate() {
                let (vx, ve) = tangents(shape, &mid, el.points()[q]);
                let n = cross(vx, ve);
                let e = frame(p);
                assert!(
                    norm(sub(e[2], scale(1.0 / norm(n), n))) < 1e-13,
                    "{name} point {q}: e3 is not the mid-surface normal"
                );
                let w = p.get("area").unwrap()[0];
                assert!(
                    (w - norm(n) * area_weight(&el, q)).abs() < 1e-13 * w,
                    "{name}"
                );
                let (bx, be) = tangents(shape, &bottom, el.points()[q]);
                let nb = cross(bx, be);
                differs = differs.max(norm(sub(e[2], scale(1.0 / norm(nb), nb))));
            }
            assert!(
                differs > 1e-3,
                "{name}: the faces are too alike for this test"
            );
        }
    }
}

/// Weight of point `q` of the rule (the "area" output is |V_xi x V_eta| w;
/// weights are those of the 1D rules' tensor product).
fn area_weight(el: &InterfaceElement, q: usize) -> f64 {
    // triangles: the rules of junta_elements::quadrature (their exactness
    // is tested there)
    match (el.shape(), el.rule()) {
        (CellShape::Inter6, InterfaceRule::Gauss) => return triangle_rule(3).unwrap().weights[q],
        (CellShape::Inter6, InterfaceRule::Lobatto) => return triangle_vertex_rule().weights[q],
        (CellShape::Inter12, _) => return triangle_rule(6).unwrap().weights[q],
        _ => {}
    }
    let p = el.points()[q];
    let w1 = |x: f64| -> f64 {
        let n = match el.shape() {
            CellShape::Inter8 => 2,
            _ => 3,
        };
        match (el.rule(), n) {
            (InterfaceRule::Gauss, 2) => 1.0,
            (InterfaceRule::Gauss, _) => {
                if x.abs() < 1e-12 {
                    8.0 / 9.0
                } else {
                    5.0 / 9.0
                }
            }
            (InterfaceRule::Lobatto, 2) => 1.0,
            (InterfaceRule::Lobatto, _) => {
                if x.abs() < 1e-12 {
                    4.0 / 3.0
                } else {
                    1.0 / 3.0
                }
            }
        }
    };
    w1(p[0]) * w1(p[1])
}

/// K v against central differences of the internal force.
fn check_tangent_fd(el: &InterfaceElement, coords: &[V3], u: &[f64], v: &[f64], h: f64, tol: f64) {
    let nd = u.len();
    let (_, k) = compute(el, coords, u);
    let kv: Vec<f64> = (0..nd)
        .map(|r| (0..nd).map(|c| k[r * nd + c] * v[c]).sum())
        .collect();
    let up: Vec<f64> = u.iter().zip(v).map(|(a, b)| a + h * b).collect();
    let um: Vec<f64> = u.iter().zip(v).map(|(a, b)| a - h * b).collect();
    let (fp, fm) = (force(el, coords, &up), force(el, coords, &um));
    let fd: Vec<f64> = fp
        .iter()
        .zip(&fm)
        .map(|(a, b)| (a - b) / (2.0 * h))
        .collect();
    let err: Vec<f64> = kv.iter().zip(&fd).map(|(a, b)| a - b).collect();
    let name = label(el.shape(), el.rule());
    assert!(max_abs(&kv) > 0.0, "{name}: K v = 0");
    assert!(
        max_abs(&err) <= tol * max_abs(&kv),
        "{name}: |K v - FD| / |K v| = {:e}",
        max_abs(&err) / max_abs(&kv)
    );
}

/// 5. Element tangent vs finite differences: linear law and a nonlinear,
///    non-symmetric test law.
#[test]
fn tangent_matches_finite_differences() {
    let mut rng = Rng(0xdead_beef_cafe_f00d);
    for shape in SHAPES {
        for rule in RULES {
            if !exists(shape, rule) {
                continue;
            }
            let face = curved_face(shape);
            let coords = doubled(&face);
            let nd = 3 * coords.len();
            // linear law
            let el = element(shape, rule, [1.0e4, 3.0e4, 9.0e4]);
            let u: Vec<f64> = rng.vec(nd).iter().map(|x| 1e-3 * x).collect();
            let v = rng.vec(nd);
            check_tangent_fd(&el, &coords, &u, &v, 1e-6, 1e-8);

            // nonlinear law: cubic terms and couplings of the same order as
            // the linear ones for jumps O(1)
            let law = Arc::new(CubicLaw {
                d: [1.0, 2.0, 3.0],
                c: 0.8,
                a: 1.5,
                b: -0.9,
            });
            let el = element_with(shape, rule, law);
            let u = rng.vec(nd);
            let v = rng.vec(nd);
            check_tangent_fd(&el, &coords, &u, &v, 1e-5, 1e-6);

            // the tangent of this law is not symmetric and the law says so
            // (`MatrixKind::General`): the element must use the full law
            // tangent (a symmetrised or diagonal one fails FD)
            let (_, k) = compute(&el, &coords, &u);
            let asym = (0..nd)
                .flat_map(|i| (0..nd).map(move |j| (i, j)))
                .map(|(i, j)| (k[i * nd + j] - k[j * nd + i]).abs())
                .fold(0.0, f64::max);
            assert!(asym > 1e-3 * max_abs(&k), "{}", label(shape, rule));

            // trial state: the law's per-point value lands in its slot
            let committed = committed_state(&el);
            assert_eq!(committed, vec![-7.0; el.num_points()]);
            let mut trial = vec![f64::NAN; el.state_len()];
            let mut f = vec![0.0; nd];
            el.compute(&ctx(&coords, &u, &committed), &mut trial, &mut f, None)
                .unwrap();
            let outs = outputs(&el, &coords, &u);
            for (q, p) in outs.iter().enumerate() {
                assert_eq!(trial[q], get3(p, "jump")[2], "state slot {q}");
            }
        }
    }
}

/// 6. Gauss vs Lobatto: equal resultants for a constant jump; nodal
///    (Lobatto) integration of INTER8/INTER18 (and the vertex rule of
///    INTER6) couples only homologous node pairs, Gauss couples every pair
///    (Schellekens & de Borst 1993). INTER12 has no nodal rule.
#[test]
fn gauss_vs_lobatto() {
    let (corners, _) = skewed_corners();
    let d = [2.0e4, 2.0e4, 5.0e4];
    let jump = [1.0e-4, 2.0e-4, -3.0e-4];
    for shape in SHAPES {
        if !exists(shape, InterfaceRule::Lobatto) {
            continue;
        }
        let m = m_of(shape);
        let nd = 6 * m;
        for (what, face) in [
            ("flat", face_nodes(shape, bilinear(corners))),
            ("curved", curved_face(shape)),
        ] {
            let coords = doubled(&face);
            let disp: Vec<f64> = (0..nd)
                .map(|i| if i >= 3 * m { jump[i % 3] } else { 0.0 })
                .collect();
            let eg = element(shape, InterfaceRule::Gauss, d);
            let el = element(shape, InterfaceRule::Lobatto, d);
            let (fg, kg) = compute(&eg, &coords, &disp);
            let (fl, kl) = compute(&el, &coords, &disp);
            let (rg, rl) = (resultant(&fg, m..2 * m), resultant(&fl, m..2 * m));
            let name = format!("{} {what}", shape.name());
            if what == "flat" {
                // constant integrand: both rules exact
                assert!(
                    norm(sub(rg, rl)) <= 1e-12 * norm(rg),
                    "{name}: Gauss {rg:?} vs Lobatto {rl:?}"
                );
            }
            let kmax = max_abs(&kg);
            // block (bottom a, top b)
            let block = |k: &[f64], a: usize, b: usize| {
                let mut mx: f64 = 0.0;
                for c in 0..3 {
                    for e in 0..3 {
                        mx = mx.max(k[(3 * a + c) * nd + 3 * (m + b) + e].abs());
                    }
                }
                mx
            };
            let mut gauss_min_offdiag = f64::INFINITY;
            let mut lobatto_max_offdiag: f64 = 0.0;
            for a in 0..m {
                for b in 0..m {
                    if a == b {
                        assert!(block(&kl, a, a) > 1e-3 * kmax, "{name}: pair {a}");
                        continue;
                    }
                    gauss_min_offdiag = gauss_min_offdiag.min(block(&kg, a, b));
                    lobatto_max_offdiag = lobatto_max_offdiag.max(block(&kl, a, b));
                }
            }
            // Gauss couples every bottom node with every other top node
            // (INTER16 is checked separately below)
            match shape {
                CellShape::Inter16 => {
                    // serendipity face: the Lobatto 3x3 centre point is not
                    // a node, so Lobatto couples too
                    assert!(lobatto_max_offdiag > 1e-3 * kmax, "{name}");
                }
                _ => {
                    assert!(
                        gauss_min_offdiag > 1e-6 * kmax,
                        "{name}: Gauss leaves a pair uncoupled"
                    );
                    assert!(
                        lobatto_max_offdiag <= 1e-14 * kmax,
                        "{name}: Lobatto couples bottom a with top b != a ({lobatto_max_offdiag:e})"
                    );
                }
            }
        }
    }
    // the Gauss coupling on INTER16 (stated separately: some Q8 pairs may
    // have small coupling, but the element as a whole is coupled)
    let face = face_nodes(CellShape::Inter16, bilinear(corners));
    let coords = doubled(&face);
    let (_, kg) = compute(
        &element(CellShape::Inter16, InterfaceRule::Gauss, d),
        &coords,
        &vec![0.0; 48],
    );
    let off = (0..8)
        .flat_map(|a| (0..8).filter(move |b| *b != a).map(move |b| (a, b)))
        .map(|(a, b)| kg[(3 * a) * 48 + 3 * (8 + b)].abs())
        .fold(0.0, f64::max);
    assert!(off > 1e-3 * max_abs(&kg));
}

/// 7. Degenerate surfaces: collinear nodes, all nodes at one point.
#[test]
fn degenerate_surface_is_rejected() {
    for shape in SHAPES {
        for rule in RULES {
            if !exists(shape, rule) {
                continue;
            }
            let name = label(shape, rule);
            let el = element(shape, rule, [1.0, 1.0, 1.0]);
            let line = face_nodes(shape, |x, y| {
                let s = 0.3 * x + 0.2 * y;
                [1.0 + s, 2.0 - 2.0 * s, 0.5 + 3.0 * s]
            });
            let point = face_nodes(shape, |_, _| [0.3, 0.3, 0.3]);
            for (what, face) in [("collinear", line), ("point", point)] {
                let coords = doubled(&face);
                match el.check_geometry(&coords) {
                    Err(ElementError::DegenerateSurface { area, .. }) => {
                        assert!(area.abs() < 1e-12, "{name} {what}: area {area}")
                    }
                    other => panic!("{name} {what}: {other:?}"),
                }
                let nd = 3 * coords.len();
                let mut f = vec![0.0; nd];
                let mut k = vec![0.0; nd * nd];
                let r = el.compute(
                    &ctx(&coords, &vec![0.0; nd], &[]),
                    &mut [],
                    &mut f,
                    Some(&mut k),
                );
                assert!(
                    matches!(r, Err(ElementError::DegenerateSurface { .. })),
                    "{name} {what}: compute gave {r:?}"
                );
                let msg = el.check_geometry(&coords).unwrap_err().to_string();
                assert!(msg.contains("degenerate"), "{msg}");
            }
            // a sound face passes
            el.check_geometry(&doubled(&curved_face(shape))).unwrap();
        }
    }
}

/// 8. Registry: element and law entries and their parameter checks.
#[test]
fn registry_entries() {
    let law = find::<LawEntry>("linear_penalty").unwrap();
    let mut t = toml::Table::new();
    t.insert("d".into(), toml::Value::Float(1e25));
    let l = (law.build)(&t).unwrap();
    assert_eq!(l.initial_stiffness(), [1e25; 3]);
    assert_eq!(l.key(), "linear_penalty");
    for bad in [0.0, -1.0e10] {
        let mut t = toml::Table::new();
        t.insert("d".into(), toml::Value::Float(bad));
        let e = (law.build)(&t).unwrap_err().to_string();
        assert!(e.contains("positive"), "d = {bad}: {e}");
    }
    let mut t = toml::Table::new();
    t.insert("d3".into(), toml::Value::Float(0.0));
    t.insert("d".into(), toml::Value::Float(1.0));
    assert!((law.build)(&t).is_err(), "d3 = 0 accepted");

    for (key, shape, nodes) in [
        ("inter8", CellShape::Inter8, 8),
        ("inter16", CellShape::Inter16, 16),
        ("inter18", CellShape::Inter18, 18),
        ("inter6", CellShape::Inter6, 6),
        ("inter12", CellShape::Inter12, 12),
    ] {
        let entry = find::<ElementEntry>(key).unwrap();
        assert_eq!(entry.shape, shape);
        let empty = toml::Table::new();
        let e = (entry.build)(&ElementBuild {
            material: None,
            law: None,
            options: &empty,
            kinematics: Default::default(),
        })
        .unwrap_err()
        .to_string();
        assert!(e.contains("law"), "{key} without a law: {e}");

        let el = (entry.build)(&ElementBuild {
            material: None,
            law: Some(l.clone()),
            options: &empty,
            kinematics: Default::default(),
        })
        .unwrap();
        assert_eq!(el.key(), key);
        assert_eq!(el.num_nodes(), nodes);
        let face = prism_face(shape);
        let coords = doubled(&face);
        let zero = vec![0.0; 3 * nodes];
        // default: Gauss, no point at a corner
        let outs = el.point_outputs(&ctx(&coords, &zero, &[])).unwrap();
        assert!(outs.iter().all(|p| norm(sub(p.position, face[0])) > 1e-6));

        let mut opts = toml::Table::new();
        opts.insert("integration".into(), toml::Value::String("lobatto".into()));
        let built = (entry.build)(&ElementBuild {
            material: None,
            law: Some(l.clone()),
            options: &opts,
            kinematics: Default::default(),
        });
        if shape == CellShape::Inter12 {
            // no nodal rule for the quadratic triangle: a clear refusal
            let e = match built {
                Ok(_) => panic!("inter12 lobatto accepted"),
                Err(e) => e.to_string(),
            };
            assert!(
                e.contains("inter12") && e.contains("lobatto") && e.contains("gauss"),
                "{e}"
            );
        } else {
            // Lobatto: points at the corners
            let el = built.unwrap();
            let outs = el.point_outputs(&ctx(&coords, &zero, &[])).unwrap();
            assert!(outs.iter().any(|p| norm(sub(p.position, face[0])) < 1e-14));
            if shape == CellShape::Inter6 {
                // the vertex rule: exactly the three corners
                assert_eq!(outs.len(), 3);
                for (p, x) in outs.iter().zip(&face) {
                    assert!(norm(sub(p.position, *x)) < 1e-14);
                }
            }
        }

        opts.insert("integration".into(), toml::Value::String("simpson".into()));
        let e = (entry.build)(&ElementBuild {
            material: None,
            law: Some(l.clone()),
            options: &opts,
            kinematics: Default::default(),
        })
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("simpson") && e.contains("lobatto"),
            "{key} simpson: {e}"
        );

        let mut opts = toml::Table::new();
        opts.insert("integraton".into(), toml::Value::String("gauss".into()));
        let e = (entry.build)(&ElementBuild {
            material: None,
            law: Some(l.clone()),
            options: &opts,
            kinematics: Default::default(),
        })
        .unwrap_err()
        .to_string();
        assert!(e.contains("integraton"), "{key} misspelt option: {e}");
    }
    let e = match find::<ElementEntry>("inter27") {
        Ok(_) => panic!("inter27 found"),
        Err(e) => e.to_string(),
    };
    assert!(e.contains("inter18"), "{e}");
    // a non-interface shape is refused by the constructor
    assert!(InterfaceElement::new(CellShape::Hex8, InterfaceRule::Gauss, l).is_err());
}
