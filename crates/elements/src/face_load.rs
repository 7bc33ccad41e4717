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

use crate::quadrature::triangle_rule;
use crate::shape::surface_shape;
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

/// Add the consistent nodal forces of `load` on `faces` to `f` (length 3 x nodes).
///
/// Errors: a face of a non-solid element, or a face index the element's
/// shape does not have (6 faces for hexahedra, 5 for wedges).
pub fn add_face_load(
    mesh: &Mesh,
    faces: &[FaceRef],
    load: FaceLoad,
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
            _ => &quad,
        };
        for &(xi, w) in points {
            surface_shape(fshape, xi, &mut n[..nn], &mut dn[..nn]);
            let mut vxi = [0.0; 3];
            let mut veta = [0.0; 3];
            for a in 0..nn {
                let x = mesh.nodes[nodes[a]];
                for c in 0..3 {
                    vxi[c] += dn[a][0] * x[c];
                    veta[c] += dn[a][1] * x[c];
                }
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
