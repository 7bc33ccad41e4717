//! Consistent nodal forces of distributed loads on solid faces.
//!
//! For a face with shape functions N_a(xi, eta) and position
//! x(xi, eta) = sum N_a x_a, the tangents V_xi = dx/dxi, V_eta = dx/deta give
//! the outward area vector n dA = (V_xi x V_eta) dxi deta (faces are ordered
//! with outward right-hand normals, see `junta_core::topology`). Then
//!
//! ```text
//! pressure p (positive into the solid):  f_a = - int N_a p n dA
//! traction t (force per area):            f_a =   int N_a t dA
//! ```
//!
//! integrated with 3x3 Gauss points (exact for flat faces of every order).

use crate::shape::quad_shape;
use junta_core::mesh::{FaceRef, Mesh};
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
pub fn add_face_load(
    mesh: &Mesh,
    faces: &[FaceRef],
    load: FaceLoad,
    f: &mut [f64],
) -> Result<(), CoreError> {
    let mut n = [0.0; 9];
    let mut dn = [[0.0; 2]; 9];
    for &face in faces {
        let block = &mesh.blocks[face.block];
        let fshape = block
            .shape
            .face_shape()
            .filter(|_| block.shape.is_solid())
            .ok_or_else(|| {
                CoreError::Invalid(format!(
                    "face loads need solid elements; block `{}` is {}",
                    block.name,
                    block.shape.name()
                ))
            })?;
        let nodes = mesh.face_nodes(face);
        let nn = nodes.len();
        for &(xi, wx) in &G3 {
            for &(eta, wy) in &G3 {
                quad_shape(fshape, [xi, eta], &mut n[..nn], &mut dn[..nn]);
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
                let w = wx * wy;
                for a in 0..nn {
                    for c in 0..3 {
                        f[3 * nodes[a] + c] += w * n[a] * t[c];
                    }
                }
            }
        }
    }
    Ok(())
}
