//! Consistent nodal forces of body loads (force per unit volume) on solids.
//!
//! For an element with shape functions `N_a(xi)`, position
//! `x(xi) = sum N_a x_a` and Jacobian determinant `det J`, a body force
//! density `b(x)` (force per volume) gives the nodal forces
//!
//! ```text
//! f_a = int_V N_a b(x) dV = sum_g N_a(xi_g) b(x(xi_g)) det J(xi_g) w_g
//! ```
//!
//! - gravity (CalculiX / Abaqus `GRAV`): `b = rho g`, `g` the acceleration
//!   vector (magnitude times a direction);
//! - centrifugal load (`CENTRIF`): `b = rho omega^2 r`, with `r` the
//!   position's distance vector from the rotation axis (point `p`, unit
//!   direction `a`): `r = (x - p) - ((x - p) . a) a`. On the undeformed
//!   geometry: no spin softening (a linear analysis, as CalculiX without
//!   NLGEOM).
//!
//! Quadrature: 3x3x3 Gauss points on hexahedra (exact for a constant or
//! linear density on parallelepipeds of every order), a 3-point triangle
//! times 3-point line rule on wedges. Plane cells: 3x3 Gauss points on
//! quadrilaterals, the 6-point rule on triangles, with `dV = s(x) det J
//! dxi deta` for the width `s` the cell stands for (a thickness, or `2 pi
//! r` for an axisymmetric ring: [`add_body_load_with`]).

use crate::quadrature::{gauss_legendre_2d, gauss_legendre_3d, triangle_rule, wedge_rule, Rule};
use crate::shape::{solid_shape, surface_shape};
use junta_core::element::PlaneWidth;
use junta_core::mesh::{ElementRef, Mesh};
use junta_core::topology::CellShape;
use junta_core::CoreError;

/// A body load, per unit mass (multiplied by the density).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum BodyLoad {
    /// Acceleration of gravity (vector).
    Gravity([f64; 3]),
    /// Rotation about an axis: `omega^2`, a point of the axis and its
    /// direction (need not be unit).
    Centrifugal {
        /// Square of the angular velocity, `omega^2` (1 / time^2).
        omega2: f64,
        /// A point of the rotation axis.
        point: [f64; 3],
        /// Direction of the rotation axis (normalised here; not zero).
        axis: [f64; 3],
    },
}

impl BodyLoad {
    /// Acceleration (force per unit mass) at `x`.
    fn at(&self, x: [f64; 3], unit_axis: [f64; 3]) -> [f64; 3] {
        match *self {
            BodyLoad::Gravity(g) => g,
            BodyLoad::Centrifugal { omega2, point, .. } => {
                let d = [x[0] - point[0], x[1] - point[1], x[2] - point[2]];
                let s = d[0] * unit_axis[0] + d[1] * unit_axis[1] + d[2] * unit_axis[2];
                [
                    omega2 * (d[0] - s * unit_axis[0]),
                    omega2 * (d[1] - s * unit_axis[1]),
                    omega2 * (d[2] - s * unit_axis[2]),
                ]
            }
        }
    }
}

/// Add the consistent nodal forces of `load` times `density` on the
/// elements `elements` (solids) to `f` (length 3 x nodes); plane cells
/// stand for a unit thickness (see [`add_body_load_with`]).
pub fn add_body_load(
    mesh: &Mesh,
    elements: &[ElementRef],
    density: f64,
    load: BodyLoad,
    f: &mut [f64],
) -> Result<(), CoreError> {
    add_body_load_with(mesh, elements, density, load, &|_| None, f)
}

/// Position, shape functions and volume factor `det J` (times the width
/// for plane cells) at the points of a rule, for one element.
fn plane_points(
    mesh: &Mesh,
    conn: &[usize],
    shape: CellShape,
    width: PlaneWidth,
    rule: &Rule<2>,
    mut each: impl FnMut([f64; 3], &[f64], f64) -> Result<(), CoreError>,
) -> Result<(), CoreError> {
    let nn = conn.len();
    let (mut n, mut dn) = ([0.0; 9], [[0.0; 2]; 9]);
    for (xi, w) in rule.iter() {
        surface_shape(shape, *xi, &mut n[..nn], &mut dn[..nn]);
        let (mut jac, mut x) = ([[0.0; 2]; 2], [0.0; 3]);
        for a in 0..nn {
            let p = mesh.nodes[conn[a]];
            for i in 0..3 {
                x[i] += n[a] * p[i];
            }
            for i in 0..2 {
                for j in 0..2 {
                    jac[i][j] += p[i] * dn[a][j];
                }
            }
        }
        let det = jac[0][0] * jac[1][1] - jac[0][1] * jac[1][0];
        each(x, &n[..nn], w * det * width.at(x))?;
    }
    Ok(())
}

/// As [`add_body_load`], with the width `width(block)` of the plane cells
/// of each block (`None`: a unit thickness).
pub fn add_body_load_with(
    mesh: &Mesh,
    elements: &[ElementRef],
    density: f64,
    load: BodyLoad,
    width: &dyn Fn(usize) -> Option<PlaneWidth>,
    f: &mut [f64],
) -> Result<(), CoreError> {
    let unit_axis = match load {
        BodyLoad::Centrifugal { axis, .. } => {
            let l = (axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]).sqrt();
            if !(l > 0.0 && l.is_finite()) {
                return Err(CoreError::Invalid(format!(
                    "centrifugal load: the axis direction {axis:?} has no length"
                )));
            }
            [axis[0] / l, axis[1] / l, axis[2] / l]
        }
        BodyLoad::Gravity(_) => [0.0; 3],
    };
    let hex = gauss_legendre_3d(3).map_err(|e| CoreError::Invalid(e.to_string()))?;
    let wedge = wedge_rule(3, 3).map_err(|e| CoreError::Invalid(e.to_string()))?;
    let quad = gauss_legendre_2d(3).map_err(|e| CoreError::Invalid(e.to_string()))?;
    let tri = triangle_rule(6).map_err(|e| CoreError::Invalid(e.to_string()))?;
    let mut n = [0.0; 27];
    let mut dn = [[0.0; 3]; 27];
    for er in elements {
        let block = &mesh.blocks[er.block];
        let shape = block.shape;
        if !shape.is_solid() {
            return Err(CoreError::Invalid(format!(
                "body loads act on solid elements; block `{}` is {}",
                block.name,
                shape.name()
            )));
        }
        let conn = block.element(er.element);
        let bad_jacobian = |det: f64| {
            CoreError::Invalid(format!(
                "body load: element {} of block `{}` has a non-positive Jacobian ({det:e})",
                mesh.element_label(er.block, er.element),
                block.name
            ))
        };
        if shape.is_plane() {
            let rule = match shape {
                CellShape::PlaneTri3 | CellShape::PlaneTri6 => &tri,
                _ => &quad,
            };
            let pw = width(er.block).unwrap_or(PlaneWidth::Thickness(1.0));
            plane_points(mesh, conn, shape, pw, rule, |x, n, dv| {
                if !(dv > 0.0) {
                    return Err(bad_jacobian(dv));
                }
                let b = load.at(x, unit_axis);
                for (a, na) in n.iter().enumerate() {
                    for c in 0..3 {
                        f[3 * conn[a] + c] += density * dv * na * b[c];
                    }
                }
                Ok(())
            })?;
            continue;
        }
        let rule: &Rule<3> = match shape {
            CellShape::Wedge6 | CellShape::Wedge15 => &wedge,
            _ => &hex,
        };
        let nn = conn.len();
        for (xi, w) in rule.iter() {
            solid_shape(shape, *xi, &mut n[..nn], &mut dn[..nn]);
            let mut jac = [[0.0; 3]; 3];
            let mut x = [0.0; 3];
            for a in 0..nn {
                let p = mesh.nodes[conn[a]];
                for i in 0..3 {
                    x[i] += n[a] * p[i];
                    for j in 0..3 {
                        jac[i][j] += p[i] * dn[a][j];
                    }
                }
            }
            let det = jac[0][0] * (jac[1][1] * jac[2][2] - jac[1][2] * jac[2][1])
                - jac[0][1] * (jac[1][0] * jac[2][2] - jac[1][2] * jac[2][0])
                + jac[0][2] * (jac[1][0] * jac[2][1] - jac[1][1] * jac[2][0]);
            if !(det > 0.0) {
                return Err(bad_jacobian(det));
            }
            let b = load.at(x, unit_axis);
            let s = density * det * w;
            for a in 0..nn {
                for c in 0..3 {
                    f[3 * conn[a] + c] += s * n[a] * b[c];
                }
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use junta_core::mesh::generate::{box_mesh, BoxSpec};

    /// Total force of gravity is rho g V; the centrifugal total is
    /// rho omega^2 V times the centroid's distance from the axis (closed
    /// forms), on a box of every solid order.
    #[test]
    fn totals_equal_closed_forms() {
        for shape in [CellShape::Hex8, CellShape::Hex20, CellShape::Hex27] {
            let mut spec = BoxSpec::new([2.0, 1.0, 0.5], [2, 1, 1], shape);
            spec.origin = [1.0, 0.0, 0.0];
            let mesh = box_mesh(&spec, "b", "solid", "m").unwrap();
            let els: Vec<ElementRef> = (0..mesh.blocks[0].len())
                .map(|e| ElementRef {
                    block: 0,
                    element: e,
                })
                .collect();
            let total = |load| {
                let mut f = vec![0.0; 3 * mesh.nodes.len()];
                add_body_load(&mesh, &els, 7.0, load, &mut f).unwrap();
                let mut t = [0.0; 3];
                for (i, v) in f.iter().enumerate() {
                    t[i % 3] += v;
                }
                t
            };
            let v = 2.0 * 1.0 * 0.5;
            let g = total(BodyLoad::Gravity([0.0, 0.0, -9.81]));
            assert!((g[2] + 7.0 * 9.81 * v).abs() < 1e-12, "{shape:?} {g:?}");
            // axis along z through the origin: centroid at (2, 0.5) from it
            let c = total(BodyLoad::Centrifugal {
                omega2: 4.0,
                point: [0.0; 3],
                axis: [0.0, 0.0, 3.0],
            });
            assert!(
                (c[0] - 7.0 * 4.0 * v * 2.0).abs() < 1e-11,
                "{shape:?} {c:?}"
            );
            assert!(
                (c[1] - 7.0 * 4.0 * v * 0.5).abs() < 1e-11,
                "{shape:?} {c:?}"
            );
            assert!(c[2].abs() < 1e-12);
        }
    }
}
