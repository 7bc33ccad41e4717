//! The stacking direction at any point of a laminate extruded from a
//! curved Gmsh base ([`super::extrude`]): the field its plies' material
//! axes turn with ([`junta_elements::material::Rotated::on_surface`]).
//!
//! The extrusion maps a base cell's natural coordinates `(r, s)` and the
//! height `t` above the base to
//!
//! ```text
//! x(r, s, t) = sum_a N_a(r, s) (X_a + t n_a)
//! ```
//!
//! (`X_a` the cell's nodes, `n_a` their unit normals). At a point `x` of
//! the laminate the field finds the cell and `(r, s, t)` by Newton's
//! method on `x(r, s, t) = x` (Jacobian columns `dx/dr`, `dx/ds` and
//! `sum_a N_a n_a`), and gives
//!
//! ```text
//! n(x) = sum_a N_a(r, s) n_a / |sum_a N_a(r, s) n_a|
//! ```
//!
//! the normal interpolated as the extrusion interpolates it: continuous
//! across cells, and radial to within the interpolation error on a
//! cylinder whose nodes lie on the circle. The cells are found through a
//! uniform grid of buckets holding each cell's box (its nodes at `t = 0`
//! and at the laminate's thickness); a point no cell's Newton solve holds
//! (outside the laminate) takes the normal of the nearest node of its
//! bucket's cells.

use super::extrude::OrientedBase;
use crate::input::gmsh::SurfaceMesh;
use junta_core::topology::CellShape;
use junta_elements::material::StackingNormal;
use nalgebra::{Matrix3, Vector3};
use std::collections::HashMap;

/// Nodes of a cell at most (Quad8).
const MAX_CELL: usize = 8;

/// One base cell: its shape and where its nodes are in `nodes`.
#[derive(Debug, Clone, Copy)]
struct Cell {
    shape: CellShape,
    start: usize,
}

/// The normal field of an extruded base (module docs).
#[derive(Debug)]
pub struct SurfaceNormals {
    /// Base node positions and unit normals, per cell node, cells one after
    /// the other.
    nodes: Vec<(Vector3<f64>, Vector3<f64>)>,
    cells: Vec<Cell>,
    /// Bucket edge length, and bucket -> cells whose box reaches it.
    bucket: f64,
    buckets: HashMap<[i64; 3], Vec<u32>>,
}

impl SurfaceNormals {
    /// The field of `base` (cells of `mesh`) for a laminate of total
    /// thickness `thickness`.
    pub fn new(mesh: &SurfaceMesh, base: &OrientedBase, thickness: f64) -> Self {
        let mut nodes = Vec::with_capacity(base.quads.len() + base.tris.len());
        let mut cells = Vec::new();
        for (conn, shape) in [
            (&base.quads, mesh.quad_shape()),
            (&base.tris, mesh.tri_shape()),
        ] {
            for c in conn.chunks(shape.num_nodes()) {
                cells.push(Cell {
                    shape,
                    start: nodes.len(),
                });
                nodes.extend(
                    c.iter()
                        .map(|&i| (Vector3::from(mesh.nodes[i]), Vector3::from(base.normals[i]))),
                );
            }
        }
        let mut field = SurfaceNormals {
            nodes,
            cells,
            bucket: 1.0,
            buckets: HashMap::new(),
        };
        field.fill_buckets(thickness);
        field
    }

    fn cell_nodes(&self, c: &Cell) -> &[(Vector3<f64>, Vector3<f64>)] {
        &self.nodes[c.start..c.start + c.shape.num_nodes()]
    }

    /// Each cell's box (its nodes at `t = 0` and `t = thickness`, with a
    /// margin) into the buckets it reaches; the bucket edge is the mean
    /// box size.
    fn fill_buckets(&mut self, thickness: f64) {
        let boxes: Vec<(Vector3<f64>, Vector3<f64>)> = self
            .cells
            .iter()
            .map(|c| {
                let (mut lo, mut hi) = (Vector3::repeat(f64::MAX), Vector3::repeat(f64::MIN));
                for (x, n) in self.cell_nodes(c) {
                    for p in [*x, x + thickness * n] {
                        lo = lo.inf(&p);
                        hi = hi.sup(&p);
                    }
                }
                let margin = 0.05 * (hi - lo).max() + 1e-9 * lo.abs().max().max(hi.abs().max());
                (lo.add_scalar(-margin), hi.add_scalar(margin))
            })
            .collect();
        let mean =
            boxes.iter().map(|(lo, hi)| (hi - lo).max()).sum::<f64>() / boxes.len().max(1) as f64;
        self.bucket = if mean > 0.0 { mean } else { 1.0 };
        for (e, (lo, hi)) in boxes.iter().enumerate() {
            let (a, b) = (self.key(lo), self.key(hi));
            for i in a[0]..=b[0] {
                for j in a[1]..=b[1] {
                    for k in a[2]..=b[2] {
                        self.buckets.entry([i, j, k]).or_default().push(e as u32);
                    }
                }
            }
        }
    }

    fn key(&self, x: &Vector3<f64>) -> [i64; 3] {
        [0, 1, 2].map(|k| (x[k] / self.bucket).floor() as i64)
    }

    /// `(r, s, t)` of `x` in cell `c` when Newton's method converges to a
    /// point inside the cell (module docs), with the interpolated normal.
    fn solve_in(&self, c: &Cell, x: &Vector3<f64>) -> Option<Vector3<f64>> {
        let tri = matches!(c.shape, CellShape::Tri3 | CellShape::Tri6);
        let nodes = self.cell_nodes(c);
        let (mut n, mut dn) = ([0.0; MAX_CELL], [[0.0; 2]; MAX_CELL]);
        let mut rs = if tri { [1.0 / 3.0; 2] } else { [0.0; 2] };
        let mut t = 0.0;
        for _ in 0..25 {
            junta_elements::shape::surface_shape(c.shape, rs, &mut n, &mut dn);
            let (mut p, mut dr, mut ds, mut nn) = (
                Vector3::zeros(),
                Vector3::zeros(),
                Vector3::zeros(),
                Vector3::zeros(),
            );
            for (a, (xa, na)) in nodes.iter().enumerate() {
                let y = xa + t * na;
                p += n[a] * y;
                dr += dn[a][0] * y;
                ds += dn[a][1] * y;
                nn += n[a] * na;
            }
            let step = Matrix3::from_columns(&[dr, ds, nn]).lu().solve(&(x - p))?;
            rs = [
                (rs[0] + step[0]).clamp(-3.0, 3.0),
                (rs[1] + step[1]).clamp(-3.0, 3.0),
            ];
            t += step[2];
            if step[0].abs().max(step[1].abs()) < 1e-12 {
                junta_elements::shape::surface_shape(c.shape, rs, &mut n, &mut dn);
                let tol = 1e-8;
                let inside = if tri {
                    rs[0] >= -tol && rs[1] >= -tol && rs[0] + rs[1] <= 1.0 + tol
                } else {
                    rs[0].abs() <= 1.0 + tol && rs[1].abs() <= 1.0 + tol
                };
                let normal: Vector3<f64> =
                    nodes.iter().enumerate().map(|(a, (_, na))| n[a] * na).sum();
                return inside.then(|| normal.try_normalize(1e-12)).flatten();
            }
        }
        None
    }

    /// The normal of the node nearest `x` among `cells`.
    fn nearest_node(
        &self,
        cells: &mut dyn Iterator<Item = &Cell>,
        x: &Vector3<f64>,
    ) -> Option<Vector3<f64>> {
        cells
            .flat_map(|c| self.cell_nodes(c).iter())
            .min_by(|a, b| {
                (a.0 - x)
                    .norm_squared()
                    .total_cmp(&(b.0 - x).norm_squared())
            })
            .map(|(_, n)| *n)
    }
}

impl StackingNormal for SurfaceNormals {
    fn normal_at(&self, x: [f64; 3]) -> [f64; 3] {
        let x = Vector3::from(x);
        let found = self.buckets.get(&self.key(&x));
        let candidates = || {
            found
                .into_iter()
                .flatten()
                .map(|&e| &self.cells[e as usize])
        };
        let normal = candidates()
            .find_map(|c| self.solve_in(c, &x))
            .or_else(|| self.nearest_node(&mut candidates(), &x))
            .or_else(|| self.nearest_node(&mut self.cells.iter(), &x))
            .unwrap_or_else(Vector3::z);
        normal.into()
    }
}
