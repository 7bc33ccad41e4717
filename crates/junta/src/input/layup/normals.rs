//! The stacking direction of a Gmsh base: its cells oriented consistently
//! across the surface, the side the plies go chosen, and a unit normal at
//! every node.
//!
//! * **Orientation.** Two cells sharing an edge are consistently oriented
//!   when they run along it in opposite directions. A breadth-first walk
//!   over the edge neighbours of each connected part of the surface
//!   reverses the cells that disagree with the first; a cell found to
//!   disagree with two neighbours that are already fixed means the part is
//!   not orientable (a Möbius strip) and is refused, as is an edge shared
//!   by more than two cells.
//! * **The side.** Each part's area vector `S = sum_c A_c n_c` (the cells'
//!   right-hand normals weighted by area) decides by default: the plies go
//!   where `S . e_z > 0` (on a plane `z = const` base, along `+z`; a part
//!   whose `S` has no clear `z` component, a cylinder about `z`, needs a
//!   key). `normal_away_from = p` picks the side with `sum_c A_c n_c .
//!   (x_c - p) > 0` (`x_c` the cell's centre: outward from an axis point of
//!   a cylinder), `normal_towards = p` the opposite; `flip = true` turns the
//!   choice over.
//! * **Nodal normals.** `n(X) = sum_c n_c(X) / |sum_c n_c(X)|` over the
//!   cells `c` at node `X`, `n_c(X) = (dx/dxi x dx/deta) / |.|` the cell's
//!   own normal at the node (from its shape functions; on a plane all equal
//!   `e_z`; at an inner node of a cylinder of uniform cells the two sides
//!   cancel out and `n` is the radius). A cell normal more than 60 degrees
//!   from the nodal normal (a fold, or so sharp a corner that the plies
//!   would overlap) is refused.

use super::extrude::OrientedBase;
use crate::input::gmsh::SurfaceMesh;
use junta_core::topology::CellShape;
use nalgebra::Vector3;
use std::collections::{HashMap, VecDeque};

/// Which side of the base the plies go (`[laminate.base]` keys).
#[derive(Debug, Clone, Copy, Default)]
pub struct StackSide {
    /// `normal_towards`: the normal points towards this point.
    pub towards: Option<[f64; 3]>,
    /// `normal_away_from`: the normal points away from this point.
    pub away_from: Option<[f64; 3]>,
    /// `flip`: the other side.
    pub flip: bool,
}

/// One cell: its shape and its nodes.
struct Cell<'a> {
    shape: CellShape,
    nodes: &'a [usize],
}

fn cells(s: &SurfaceMesh) -> Vec<Cell<'_>> {
    let (q, t) = (s.quad_shape(), s.tri_shape());
    let quads = s
        .quads
        .chunks(q.num_nodes())
        .map(|n| Cell { shape: q, nodes: n });
    let tris = s
        .tris
        .chunks(t.num_nodes())
        .map(|n| Cell { shape: t, nodes: n });
    quads.chain(tris).collect()
}

/// The cell's nodes in the other direction (corners reversed about the
/// first, mid-side nodes following their edges).
fn reversed(shape: CellShape, q: &[usize]) -> Vec<usize> {
    match shape {
        CellShape::Quad4 => vec![q[0], q[3], q[2], q[1]],
        CellShape::Quad8 => vec![q[0], q[3], q[2], q[1], q[7], q[6], q[5], q[4]],
        CellShape::Tri3 => vec![q[0], q[2], q[1]],
        _ => vec![q[0], q[2], q[1], q[5], q[4], q[3]],
    }
}

/// The right-hand normal `dx/dxi x dx/deta` of a cell at its node `a`
/// (not normalised).
fn cell_normal(s: &SurfaceMesh, c: &Cell, a: usize) -> Vector3<f64> {
    let (mut n, mut dn) = ([0.0; 9], [[0.0; 2]; 9]);
    let xi = junta_elements::shape::natural_node(c.shape, a);
    junta_elements::shape::surface_shape(c.shape, [xi[0], xi[1]], &mut n, &mut dn);
    tangent_cross(s, c, &dn)
}

fn tangent_cross(s: &SurfaceMesh, c: &Cell, dn: &[[f64; 2]; 9]) -> Vector3<f64> {
    let (mut a, mut b) = (Vector3::zeros(), Vector3::zeros());
    for (k, &i) in c.nodes.iter().enumerate() {
        let x = Vector3::from(s.nodes[i]);
        a += dn[k][0] * x;
        b += dn[k][1] * x;
    }
    a.cross(&b)
}

/// The area vector `A_c n_c` and the centre of a cell.
fn area_vector(s: &SurfaceMesh, c: &Cell) -> (Vector3<f64>, Vector3<f64>) {
    let tri = matches!(c.shape, CellShape::Tri3 | CellShape::Tri6);
    let (xi, weight) = if tri {
        ([1.0 / 3.0, 1.0 / 3.0], 0.5)
    } else {
        ([0.0, 0.0], 4.0)
    };
    let (mut n, mut dn) = ([0.0; 9], [[0.0; 2]; 9]);
    junta_elements::shape::surface_shape(c.shape, xi, &mut n, &mut dn);
    let centre = c
        .nodes
        .iter()
        .enumerate()
        .fold(Vector3::zeros(), |acc, (k, &i)| {
            acc + n[k] * Vector3::from(s.nodes[i])
        });
    (weight * tangent_cross(s, c, &dn), centre)
}

/// The oriented cells and nodal normals of `s` (module docs); errors say
/// what is wrong with the surface.
pub fn orient(s: &SurfaceMesh, side: StackSide) -> Result<OrientedBase, String> {
    let cells = cells(s);
    if cells.is_empty() {
        return Err("the base has no cell".into());
    }
    let corners = |c: &Cell| if c.nodes.len() % 4 == 0 { 4 } else { 3 };
    // edge (sorted corners) -> (cell, runs from the smaller corner)
    let mut edges: HashMap<[usize; 2], Vec<(usize, bool)>> = HashMap::new();
    for (e, c) in cells.iter().enumerate() {
        let nc = corners(c);
        for k in 0..nc {
            let (a, b) = (c.nodes[k], c.nodes[(k + 1) % nc]);
            edges
                .entry([a.min(b), a.max(b)])
                .or_default()
                .push((e, a < b));
        }
    }
    if let Some((edge, _)) = edges.iter().find(|(_, v)| v.len() > 2) {
        return Err(format!(
            "the edge between nodes {} and {} is shared by more than two cells: the surface is not a manifold",
            edge[0] + 1,
            edge[1] + 1
        ));
    }
    // reverse[e]: cell e is taken in the other direction; part[e]: its connected part
    let mut reverse: Vec<Option<bool>> = vec![None; cells.len()];
    let mut part = vec![0usize; cells.len()];
    let mut parts = 0;
    for seed in 0..cells.len() {
        if reverse[seed].is_some() {
            continue;
        }
        reverse[seed] = Some(false);
        part[seed] = parts;
        let mut queue = VecDeque::from([seed]);
        while let Some(e) = queue.pop_front() {
            let c = &cells[e];
            let nc = corners(c);
            let re = reverse[e] == Some(true);
            for k in 0..nc {
                let (a, b) = (c.nodes[k], c.nodes[(k + 1) % nc]);
                let forward = (a < b) != re;
                for &(f, f_forward) in &edges[&[a.min(b), a.max(b)]] {
                    if f == e {
                        continue;
                    }
                    // consistent: f runs the edge the other way than e
                    let want = f_forward == forward;
                    match reverse[f] {
                        None => {
                            reverse[f] = Some(want);
                            part[f] = parts;
                            queue.push_back(f);
                        }
                        Some(r) if r != want => {
                            return Err(format!(
                                "the surface is not orientable (no consistent side around the cells at the edge between nodes {} and {})",
                                a + 1,
                                b + 1
                            ))
                        }
                        Some(_) => {}
                    }
                }
            }
        }
        parts += 1;
    }
    let sign = part_signs(s, &cells, &reverse, &part, parts, side)?;
    let mut out = OrientedBase {
        quads: Vec::with_capacity(s.quads.len()),
        tris: Vec::with_capacity(s.tris.len()),
        normals: vec![[0.0; 3]; s.nodes.len()],
    };
    let mut sum = vec![Vector3::zeros(); s.nodes.len()];
    let mut oriented: Vec<Vec<usize>> = Vec::with_capacity(cells.len());
    for (e, c) in cells.iter().enumerate() {
        let flip = (reverse[e] == Some(true)) != (sign[part[e]] < 0.0);
        let nodes = if flip {
            reversed(c.shape, c.nodes)
        } else {
            c.nodes.to_vec()
        };
        let oc = Cell {
            shape: c.shape,
            nodes: &nodes,
        };
        for (a, &i) in nodes.iter().enumerate() {
            let n = cell_normal(s, &oc, a);
            let len = n.norm();
            if !(len > 0.0 && len.is_finite()) {
                return Err(format!(
                    "a cell at node {} is degenerate (no normal there)",
                    i + 1
                ));
            }
            sum[i] += n / len;
        }
        let into = if corners(c) == 4 {
            &mut out.quads
        } else {
            &mut out.tris
        };
        into.extend_from_slice(&nodes);
        oriented.push(nodes);
    }
    for (i, v) in sum.iter().enumerate() {
        if let Some(n) = v.try_normalize(1e-12) {
            out.normals[i] = n.into();
        }
    }
    for (e, nodes) in oriented.iter().enumerate() {
        let oc = Cell {
            shape: cells[e].shape,
            nodes,
        };
        for (a, &i) in nodes.iter().enumerate() {
            let n = cell_normal(s, &oc, a).normalize();
            if n.dot(&Vector3::from(out.normals[i])) < 0.5 {
                return Err(format!(
                    "the surface folds at node {} (a cell's normal is more than 60 degrees from the node's averaged normal): the plies would overlap there",
                    i + 1
                ));
            }
        }
    }
    Ok(out)
}

/// `+1` or `-1` for each connected part: the side its plies go (module docs).
fn part_signs(
    s: &SurfaceMesh,
    cells: &[Cell],
    reverse: &[Option<bool>],
    part: &[usize],
    parts: usize,
    side: StackSide,
) -> Result<Vec<f64>, String> {
    let (mut measure, mut scale) = (vec![0.0; parts], vec![0.0; parts]);
    for (e, c) in cells.iter().enumerate() {
        let (mut av, centre) = area_vector(s, c);
        if reverse[e] == Some(true) {
            av = -av;
        }
        let (m, w) = match (side.towards, side.away_from) {
            (Some(p), _) => {
                let d = centre - Vector3::from(p);
                (-av.dot(&d), av.norm() * d.norm())
            }
            (_, Some(p)) => {
                let d = centre - Vector3::from(p);
                (av.dot(&d), av.norm() * d.norm())
            }
            _ => (av.z, av.norm()),
        };
        measure[part[e]] += m;
        scale[part[e]] += w;
    }
    measure
        .iter()
        .zip(&scale)
        .map(|(&m, &w)| {
            if m.abs() <= 1e-6 * w {
                let what = if side.towards.is_some() || side.away_from.is_some() {
                    "the point given does not tell the side (it is as much on one side of the surface as on the other); give a point clearly on one side"
                } else {
                    "the surface does not face +z or -z as a whole, so the side the plies go must be given: `normal_away_from = [x, y, z]` (e.g. a point of a cylinder's axis for plies outside it) or `normal_towards = [x, y, z]`"
                };
                return Err(what.to_string());
            }
            Ok(if (m > 0.0) != side.flip { 1.0 } else { -1.0 })
        })
        .collect()
}
