//! A ply extruded from a 2D mesh of quadrilaterals and triangles (a Gmsh
//! base, holes and all): every cell becomes a column of solids through the
//! ply, Quad4 -> Hex8, Quad8 -> Hex20, Tri3 -> Wedge6, Tri6 -> Wedge15.
//!
//! Every base node `X` moves along its unit normal `n(X)`
//! ([`super::normals`]): the point at height `t` above the base is `X + t
//! n(X)` (on a plane base `n = e_z`, so the plies stack along `+z`). The
//! cells come oriented ([`super::normals::orient`]): counter-clockwise seen
//! from the side the plies go, so that every solid has its bottom face
//! first with a positive Jacobian. Node order of the solids (ours, Abaqus'
//! C3D8 / C3D20 / C3D6 / C3D15, `junta_core::topology::HEX_FACES`,
//! `WEDGE_FACES`): the cell's corners at the bottom then at the top; for
//! Hex20 / Wedge15 the cell's mid-side nodes at the bottom, at the top,
//! then its corners at mid-height. A hexahedron's side face `k + 2` and a
//! wedge's side face `k + 2` (S3..) stand on the cell's edge `k` (corners
//! `k`, `k + 1`).
//!
//! Blocks of the ply: `hex` and `wedge` (only those with cells; a ply of
//! one kind has one block, which the merge names after the ply). Sets of
//! the ply (renamed `ply_K.*` when the plies are merged): node and face
//! sets `z0` (bottom), `z1` (top) and one per physical curve of the base
//! (the side faces over its line elements, e.g. a hole's edge).

use crate::input::gmsh::SurfaceMesh;
use junta_core::mesh::{ElementBlock, ElementRef, FaceRef, Mesh};
use junta_core::topology::CellShape;
use std::collections::HashMap;

/// A base ready to extrude: its cells oriented, and a unit normal at every
/// node the cells use (indexed by the mesh's node ids; unused nodes hold
/// zeros).
#[derive(Debug, Clone)]
pub struct OrientedBase {
    /// Quadrilaterals, flat (4 or 8 nodes each), oriented.
    pub quads: Vec<usize>,
    /// Triangles, flat (3 or 6 nodes each), oriented.
    pub tris: Vec<usize>,
    /// Unit normal at each node, the stacking direction.
    pub normals: Vec<[f64; 3]>,
}

/// The element keys of a ply's two kinds of solids.
#[derive(Debug, Clone, Copy)]
pub struct PlyElements<'a> {
    /// On the quadrilaterals (h8, h8i, h20, h20r).
    pub hex: &'a str,
    /// On the triangles (wedge6, wedge15).
    pub wedge: &'a str,
}

/// One kind of cell of the base: corners, nodes per cell, its solid.
struct Kind<'a> {
    corners: usize,
    nodes: usize,
    conn: &'a [usize],
    solid: CellShape,
    block: &'static str,
    element_type: &'a str,
}

fn kinds<'a>(s: &SurfaceMesh, b: &'a OrientedBase, e: PlyElements<'a>) -> Vec<Kind<'a>> {
    let q = s.quadratic;
    let all = [
        Kind {
            corners: 4,
            nodes: if q { 8 } else { 4 },
            conn: &b.quads,
            solid: if q { CellShape::Hex20 } else { CellShape::Hex8 },
            block: "hex",
            element_type: e.hex,
        },
        Kind {
            corners: 3,
            nodes: if q { 6 } else { 3 },
            conn: &b.tris,
            solid: if q {
                CellShape::Wedge15
            } else {
                CellShape::Wedge6
            },
            block: "wedge",
            element_type: e.wedge,
        },
    ];
    all.into_iter().filter(|k| !k.conn.is_empty()).collect()
}

/// One ply over the cells of `b` from height `t0` above the base to `t0 +
/// thickness`, `layers` elements through it.
pub fn extrude_ply(
    s: &SurfaceMesh,
    b: &OrientedBase,
    t0: f64,
    thickness: f64,
    layers: usize,
    elements: PlyElements,
    material: &str,
) -> Mesh {
    let kinds = kinds(s, b, elements);
    // the base nodes the cells use, numbered 0..m; corners among them 0..c
    let mut local: HashMap<usize, usize> = HashMap::new();
    let mut corner_local: HashMap<usize, usize> = HashMap::new();
    let mut base: Vec<usize> = Vec::new();
    let mut corners: Vec<usize> = Vec::new();
    for k in &kinds {
        for cell in k.conn.chunks(k.nodes) {
            for (j, &i) in cell.iter().enumerate() {
                local.entry(i).or_insert_with(|| {
                    base.push(i);
                    base.len() - 1
                });
                if j < k.corners {
                    corner_local.entry(i).or_insert_with(|| {
                        corners.push(i);
                        corners.len() - 1
                    });
                }
            }
        }
    }
    let (m, c) = (base.len(), corners.len());
    let dt = thickness / layers as f64;
    let lift = |i: usize, t: f64| {
        let (x, n) = (s.nodes[i], b.normals[i]);
        [x[0] + t * n[0], x[1] + t * n[1], x[2] + t * n[2]]
    };
    let mut nodes = Vec::with_capacity(m * (layers + 1) + if s.quadratic { c * layers } else { 0 });
    for j in 0..=layers {
        let t = t0 + dt * j as f64;
        nodes.extend(base.iter().map(|&i| lift(i, t)));
    }
    let mid = nodes.len();
    if s.quadratic {
        for j in 0..layers {
            let t = t0 + dt * (j as f64 + 0.5);
            nodes.extend(corners.iter().map(|&i| lift(i, t)));
        }
    }
    let at = |level: usize, i: usize| level * m + local[&i];
    let at_mid = |layer: usize, i: usize| mid + layer * c + corner_local[&i];
    let mut blocks = Vec::with_capacity(kinds.len());
    for k in &kinds {
        let nc = k.corners;
        let mut conn = Vec::with_capacity(k.conn.len() / k.nodes * layers * k.solid.num_nodes());
        for j in 0..layers {
            for q in k.conn.chunks(k.nodes) {
                conn.extend(q[..nc].iter().map(|&i| at(j, i)));
                conn.extend(q[..nc].iter().map(|&i| at(j + 1, i)));
                if s.quadratic {
                    conn.extend(q[nc..].iter().map(|&i| at(j, i)));
                    conn.extend(q[nc..].iter().map(|&i| at(j + 1, i)));
                    conn.extend(q[..nc].iter().map(|&i| at_mid(j, i)));
                }
            }
        }
        blocks.push(ElementBlock {
            name: k.block.into(),
            shape: k.solid,
            connectivity: conn,
            element_type: k.element_type.into(),
            material: material.into(),
        });
    }
    let mut mesh = Mesh {
        nodes,
        blocks,
        ..Mesh::default()
    };
    add_ply_sets(&mut mesh, s, &kinds, layers);
    mesh
}

/// `z0`, `z1`, one set per physical curve, and `all`.
fn add_ply_sets(mesh: &mut Mesh, s: &SurfaceMesh, kinds: &[Kind], layers: usize) {
    let (mut z0, mut z1) = (Vec::new(), Vec::new());
    // cell edge (sorted corner pair) -> (block, cell, edge k)
    let mut edges: HashMap<[usize; 2], Vec<(usize, usize, usize)>> = HashMap::new();
    for (block, k) in kinds.iter().enumerate() {
        let per_layer = k.conn.len() / k.nodes;
        let face = |layer: usize, cell: usize, face: usize| FaceRef {
            block,
            element: layer * per_layer + cell,
            face,
        };
        z0.extend((0..per_layer).map(|e| face(0, e, 0)));
        z1.extend((0..per_layer).map(|e| face(layers - 1, e, 1)));
        for (e, q) in k.conn.chunks(k.nodes).enumerate() {
            for j in 0..k.corners {
                let (a, b) = (q[j], q[(j + 1) % k.corners]);
                edges
                    .entry([a.min(b), a.max(b)])
                    .or_default()
                    .push((block, e, j));
            }
        }
    }
    let mut sets: Vec<(String, Vec<FaceRef>)> = vec![("z0".into(), z0), ("z1".into(), z1)];
    for (name, pairs) in &s.curves {
        let mut faces = Vec::new();
        for &[a, b] in pairs {
            for &(block, e, j) in edges.get(&[a.min(b), a.max(b)]).map_or(&[][..], |v| v) {
                let per_layer = kinds[block].conn.len() / kinds[block].nodes;
                faces.extend((0..layers).map(|l| FaceRef {
                    block,
                    element: l * per_layer + e,
                    face: j + 2,
                }));
            }
        }
        sets.push((name.clone(), faces));
    }
    for (name, faces) in sets {
        let nodes = mesh.nodes_of_faces(&faces);
        mesh.node_sets.insert(name.clone(), nodes);
        mesh.face_sets.insert(name, faces);
    }
    let all = mesh
        .blocks
        .iter()
        .enumerate()
        .flat_map(|(block, b)| (0..b.len()).map(move |element| ElementRef { block, element }))
        .collect();
    mesh.element_sets.insert("all".into(), all);
}
