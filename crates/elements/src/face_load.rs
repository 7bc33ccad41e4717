//! Consistent nodal forces of distributed loads on solid faces.
//!
//! For a face with shape functions N_a(xi, eta) and position
//! x(xi, eta) = sum N_a x_a, the tangents V_xi = dx/dxi, V_eta = dx/deta give
//! the outward area vector n dA = (V_xi x V_eta) dxi deta (faces are ordered
//! with outward right-hand normals, see `junta_core::topology`: hexahedron
//! faces S1..S6, wedge faces S1..S5). Then
//!
//! ```text
//! pressure p (positive into the solid):  f_a = - int N_a p n dA
//! traction t (force per area):            f_a =   int N_a t dA
//! ```
//!
//! Quadrilateral faces (Q4 / Q8 / Q9, natural square) are integrated with
//! 3x3 Gauss points (exact for flat faces of every order). Triangular faces
//! (Tri3 / Tri6 of wedges, `(xi, eta) = (r, s)` on the unit triangle) with
//! the 6-point degree-4 rule of [`crate::quadrature::triangle_rule`]: for a
//! pressure the integrand `N_a (V_r x V_s)` is a polynomial of degree at
//! most 2 + 2 (Tri6, even curved: each tangent is linear), so the forces are
//! exact on every triangular face. On a flat Tri3 face each corner gets a
//! third of the load; on a flat Tri6 face the corners get none and each
//! mid-edge node a third (`int N_corner = 0`, `int N_mid = A / 3`).
//!
//! Line loads on element edges ([`add_edge_load`]): an edge of 2 nodes
//! (linear elements) or 3 (ends then middle, quadratic elements) with the
//! 1D shape functions `(1 -+ s) / 2`, or `s (s -+ 1) / 2` and `1 - s^2`
//! on `s in [-1, 1]`, gets `f_a = int N_a q dl` (q force per length,
//! 3 Gauss points: exact on straight edges). A straight quadratic edge
//! of length L gives its ends L/6 and its middle 2L/3 per unit load.
//!
//! Total forces on node sets ([`set_weights`]): the share of each node of
//! the set is the integral of its shape function over the element faces
//! the set spans (all their nodes in the set), divided by the area of
//! those faces; if the set holds no complete face, over the element edges
//! it spans; if neither, the nodes share equally. On a flat 8-node face
//! the corners get -1/12 and the mid-sides 1/3 of the face's part; on a
//! 4-node face each corner 1/4; on a quadratic edge 1/6, 2/3, 1/6; on a
//! linear edge 1/2, 1/2.

use crate::quadrature::{gauss_legendre, triangle_rule};
use crate::shape::surface_shape;
use junta_core::element::PlaneWidth;
use junta_core::mesh::{FaceRef, Mesh};
use junta_core::topology::CellShape;
use junta_core::CoreError;

/// A distributed load on faces.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FaceLoad {
    /// Pressure, positive pushing into the solid.
    Pressure(f64),
    /// Traction vector, force per unit area.
    Traction([f64; 3]),
}

const G3: [(f64, f64); 3] = [
    (-0.774_596_669_241_483_4, 5.0 / 9.0),
    (0.0, 8.0 / 9.0),
    (0.774_596_669_241_483_4, 5.0 / 9.0),
];

/// Add the consistent nodal forces of `load` on `faces` to `f` (length 3 x
/// nodes); the edges of plane cells stand for a unit width (see
/// [`add_face_load_with`]).
///
/// Errors: a face of a non-solid element, or a face index the element's
/// shape does not have (6 faces for hexahedra, 5 for wedges, the edges of
/// plane cells).
pub fn add_face_load(
    mesh: &Mesh,
    faces: &[FaceRef],
    load: FaceLoad,
    f: &mut [f64],
) -> Result<(), CoreError> {
    add_face_load_with(mesh, faces, load, &|_| None, f)
}

/// As [`add_face_load`], with the width `width(block)` of the plane cells
/// of each block (`None`: a unit thickness). An edge of a plane cell, the
/// line `x(xi)`, is the face of the width `s(x)` it stands for: `V_eta =
/// s e_z`, so that `n dA = V_xi x V_eta dxi` is the outward normal of a
/// counter-clockwise cell times `s |V_xi| dxi` (`s = t`, or `2 pi r` for an
/// axisymmetric ring), integrated with 3 Gauss points.
pub fn add_face_load_with(
    mesh: &Mesh,
    faces: &[FaceRef],
    load: FaceLoad,
    width: &dyn Fn(usize) -> Option<PlaneWidth>,
    f: &mut [f64],
) -> Result<(), CoreError> {
    let mut n = [0.0; 9];
    let mut dn = [[0.0; 2]; 9];
    // quadrilateral points (3x3 Gauss) and triangle points (6-point rule)
    let mut quad = [([0.0; 2], 0.0); 9];
    for (j, &(eta, wy)) in G3.iter().enumerate() {
        for (i, &(xi, wx)) in G3.iter().enumerate() {
            quad[3 * j + i] = ([xi, eta], wx * wy);
        }
    }
    let line = G3.map(|(xi, w)| ([xi, 0.0], w));
    let tri_rule = triangle_rule(6).map_err(|e| CoreError::Invalid(e.to_string()))?;
    let mut tri = [([0.0; 2], 0.0); 6];
    for (t, (p, w)) in tri.iter_mut().zip(tri_rule.iter()) {
        *t = (*p, w);
    }
    for &face in faces {
        let block = &mesh.blocks[face.block];
        if !block.shape.is_solid() {
            return Err(CoreError::Invalid(format!(
                "face loads need solid elements; block `{}` is {}",
                block.name,
                block.shape.name()
            )));
        }
        let fshape = block.shape.face_shape_of(face.face).ok_or_else(|| {
            let nf = block.shape.num_faces();
            CoreError::Invalid(format!(
                "element {} of block `{}` is a {} element, which has faces S1..S{nf}, not S{}",
                mesh.element_label(face.block, face.element),
                block.name,
                block.shape.name(),
                face.face + 1
            ))
        })?;
        let nodes = mesh.face_nodes(face);
        let nn = nodes.len();
        let points: &[([f64; 2], f64)] = match fshape {
            CellShape::Tri3 | CellShape::Tri6 => &tri,
            CellShape::Line2 | CellShape::Line3 => &line,
            _ => &quad,
        };
        let plane = block
            .shape
            .is_plane()
            .then(|| width(face.block).unwrap_or(PlaneWidth::Thickness(1.0)));
        for &(xi, w) in points {
            surface_shape(fshape, xi, &mut n[..nn], &mut dn[..nn]);
            let mut vxi = [0.0; 3];
            let mut veta = [0.0; 3];
            let mut pos = [0.0; 3];
            for a in 0..nn {
                let x = mesh.nodes[nodes[a]];
                for c in 0..3 {
                    vxi[c] += dn[a][0] * x[c];
                    veta[c] += dn[a][1] * x[c];
                    pos[c] += n[a] * x[c];
                }
            }
            if let Some(pw) = plane {
                veta = [0.0, 0.0, pw.at(pos)];
            }
            let area = [
                vxi[1] * veta[2] - vxi[2] * veta[1],
                vxi[2] * veta[0] - vxi[0] * veta[2],
                vxi[0] * veta[1] - vxi[1] * veta[0],
            ];
            let da = (area[0] * area[0] + area[1] * area[1] + area[2] * area[2]).sqrt();
            let t = match load {
                FaceLoad::Pressure(p) => [-p * area[0], -p * area[1], -p * area[2]],
                FaceLoad::Traction(t) => [t[0] * da, t[1] * da, t[2] * da],
            };
            for a in 0..nn {
                for c in 0..3 {
                    f[3 * nodes[a] + c] += w * n[a] * t[c];
                }
            }
        }
    }
    Ok(())
}

/// Add the consistent nodal forces of a line load `q` (force per length)
/// on `edges` to `f` (length 3 x nodes). Each edge is its global node ids
/// `[end, end]` or `[end, end, middle]`.
///
/// Errors: an edge that has neither 2 nor 3 nodes.
pub fn add_edge_load(
    mesh: &Mesh,
    edges: &[Vec<usize>],
    q: [f64; 3],
    f: &mut [f64],
) -> Result<(), CoreError> {
    let rule = gauss_legendre(3).map_err(|e| CoreError::Invalid(e.to_string()))?;
    for edge in edges {
        if !(edge.len() == 2 || edge.len() == 3) {
            return Err(CoreError::Invalid(format!(
                "an element edge has 2 or 3 nodes, not {}",
                edge.len()
            )));
        }
        for (&s, &w) in rule.points.iter().zip(rule.weights) {
            let (n, dn): ([f64; 3], [f64; 3]) = if edge.len() == 2 {
                ([0.5 * (1.0 - s), 0.5 * (1.0 + s), 0.0], [-0.5, 0.5, 0.0])
            } else {
                (
                    [0.5 * s * (s - 1.0), 0.5 * s * (s + 1.0), 1.0 - s * s],
                    [s - 0.5, s + 0.5, -2.0 * s],
                )
            };
            let mut t = [0.0; 3];
            for (a, &node) in edge.iter().enumerate() {
                let x = mesh.nodes[node];
                for c in 0..3 {
                    t[c] += dn[a] * x[c];
                }
            }
            let dl = (t[0] * t[0] + t[1] * t[1] + t[2] * t[2]).sqrt();
            for (a, &node) in edge.iter().enumerate() {
                for c in 0..3 {
                    f[3 * node + c] += w * n[a] * dl * q[c];
                }
            }
        }
    }
    Ok(())
}

/// What a node set spans, as found by [`set_weights`].
#[derive(Debug, Clone, PartialEq)]
pub enum SetSpan {
    /// Solid faces whose nodes all lie in the set (each counted once,
    /// whatever element it is seen from).
    Faces(Vec<FaceRef>),
    /// Solid element edges whose nodes all lie in the set (no complete
    /// face does), each as [`add_edge_load`] takes it.
    Edges(Vec<Vec<usize>>),
    /// Neither: isolated points.
    Points,
}

/// The consistent shares of a total force over a node set.
#[derive(Debug, Clone, PartialEq)]
pub struct SetWeights {
    /// One weight per node of the set, in the set's order, summing to 1.
    pub weights: Vec<f64>,
    /// The faces or edges the weights come from.
    pub span: SetSpan,
    /// The face area or edge length those weights integrate over (0 for
    /// [`SetSpan::Points`]).
    pub measure: f64,
    /// How many nodes of the set lie on none of the faces or edges (they
    /// get 0; 0 for [`SetSpan::Points`]).
    pub off_span: usize,
}

/// The edges of a solid face, each as `[end, end]` or `[end, end,
/// middle]` in local face node order.
fn face_edges(face: CellShape) -> &'static [&'static [usize]] {
    match face {
        CellShape::Quad4 => &[&[0, 1], &[1, 2], &[2, 3], &[3, 0]],
        CellShape::Quad8 | CellShape::Quad9 => &[&[0, 1, 4], &[1, 2, 5], &[2, 3, 6], &[3, 0, 7]],
        CellShape::Tri3 => &[&[0, 1], &[1, 2], &[2, 0]],
        CellShape::Tri6 => &[&[0, 1, 3], &[1, 2, 4], &[2, 0, 5]],
        _ => &[],
    }
}

/// The consistent shares of a total force over the node set `set`: see
/// the module docs. Faces and edges are those of the solid elements
/// (hexahedra, wedges); a face or edge shared by several elements counts
/// once; coincident faces with distinct nodes (the two sides of an
/// interface) count each. Nodes of the set on no such face or edge get 0
/// (except for [`SetSpan::Points`], where every node gets `1 / n`).
///
/// Errors: an empty set, or faces or edges of zero total measure.
pub fn set_weights(mesh: &Mesh, set: &[usize]) -> Result<SetWeights, CoreError> {
    if set.is_empty() {
        return Err(CoreError::Invalid("the node set is empty".into()));
    }
    let mut in_set = vec![false; mesh.nodes.len()];
    for &n in set {
        in_set[n] = true;
    }
    let mut seen = std::collections::HashSet::new();
    let mut faces = Vec::new();
    let mut seen_edges = std::collections::HashSet::new();
    let mut edges: Vec<Vec<usize>> = Vec::new();
    for (b, block) in mesh.blocks.iter().enumerate() {
        if !block.shape.is_solid() {
            continue;
        }
        for e in 0..block.len() {
            let conn = block.element(e);
            for fi in 0..block.shape.num_faces() {
                let local = block.shape.face_nodes(fi);
                let nodes: Vec<usize> = local.iter().map(|&l| conn[l]).collect();
                if nodes.iter().all(|&n| in_set[n]) {
                    let mut key = nodes.clone();
                    key.sort_unstable();
                    if seen.insert(key) {
                        faces.push(FaceRef {
                            block: b,
                            element: e,
                            face: fi,
                        });
                    }
                }
                if !faces.is_empty() {
                    continue;
                }
                let Some(fshape) = block.shape.face_shape_of(fi) else {
                    continue;
                };
                for edge in face_edges(fshape) {
                    let nodes: Vec<usize> = edge.iter().map(|&l| nodes[l]).collect();
                    if nodes.iter().all(|&n| in_set[n]) {
                        let mut key = nodes.clone();
                        key.sort_unstable();
                        if seen_edges.insert(key) {
                            edges.push(nodes);
                        }
                    }
                }
            }
        }
    }
    let mut f = vec![0.0; 3 * mesh.nodes.len()];
    let span = if !faces.is_empty() {
        add_face_load(mesh, &faces, FaceLoad::Traction([1.0, 0.0, 0.0]), &mut f)?;
        SetSpan::Faces(faces)
    } else if !edges.is_empty() {
        add_edge_load(mesh, &edges, [1.0, 0.0, 0.0], &mut f)?;
        SetSpan::Edges(edges)
    } else {
        return Ok(SetWeights {
            weights: vec![1.0 / set.len() as f64; set.len()],
            span: SetSpan::Points,
            measure: 0.0,
            off_span: 0,
        });
    };
    let mut on_span = vec![false; mesh.nodes.len()];
    match &span {
        SetSpan::Faces(faces) => faces
            .iter()
            .flat_map(|&r| mesh.face_nodes(r))
            .for_each(|n| on_span[n] = true),
        SetSpan::Edges(edges) => edges.iter().flatten().for_each(|&n| on_span[n] = true),
        SetSpan::Points => {}
    }
    let off_span = set.iter().filter(|&&n| !on_span[n]).count();
    let measure: f64 = f.iter().step_by(3).sum();
    if !(measure.is_finite() && measure > 0.0) {
        return Err(CoreError::Invalid(format!(
            "the {} the node set spans have zero total {}",
            if matches!(span, SetSpan::Faces(_)) {
                "faces"
            } else {
                "edges"
            },
            if matches!(span, SetSpan::Faces(_)) {
                "area"
            } else {
                "length"
            },
        )));
    }
    Ok(SetWeights {
        weights: set.iter().map(|&n| f[3 * n] / measure).collect(),
        span,
        measure,
        off_span,
    })
}
