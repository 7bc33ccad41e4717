//! Structured box meshes: the built-in generator, so that the paper's scenes
//! need no external mesher.
//!
//! A box `[x0, x0+lx] x [y0, y0+ly] x [z0, z0+lz]` is split into
//! `nx x ny x nz` hexahedra (H8, H20 or H27), or into `2 nx ny nz` wedges
//! (Wedge6 or Wedge15): each hexahedral cell cut along the diagonal from its
//! corner 0 to its corner 2 (the (x-, y-) to (x+, y+) diagonal of its z
//! faces) into the wedges on the triangles 0-1-2 and 0-2-3 (hexahedron
//! corners, [`crate::topology::HEX27_NODES`]), extruded along z: wedge
//! layers stack in z and share triangles, neighbours in x and y share
//! quadrilateral sides. Optional grading per axis is the ratio of the last
//! element's size to the first's (geometric progression). Named sets: node
//! and face sets `x0, x1, y0, y1, z0, z1` on the six sides (for wedges the
//! z sides are triangles S1 / S2, the others quadrilaterals S3..S5),
//! element set `all`.

use super::{ElementBlock, ElementRef, FaceRef, Mesh};
use crate::error::CoreError;
use crate::topology::{CellShape, HEX27_NODES, HEX_FACE_NAMES};

/// The two wedges of a hexahedral cell: their nodes as H27 local ids (in
/// Wedge15 order; the first 6 serve Wedge6; the diagonal mid-nodes are the
/// z-face centres 24, 25), and which wedge face (S1..S5, 0-based) lies on
/// each side of the cell in [`HEX_FACE_NAMES`] order (`None`: the side is
/// the other wedge's or the cut).
const WEDGES_OF_HEX: [([usize; 15], [Option<usize>; 6]); 2] = [
    // triangle 0-1-2: sides z0 (S1), z1 (S2), y0 (S3: edge 0-1), x1 (S4: 1-2)
    (
        [0, 1, 2, 4, 5, 6, 8, 9, 24, 12, 13, 25, 16, 17, 18],
        [Some(0), Some(1), Some(2), Some(3), None, None],
    ),
    // triangle 0-2-3: z0, z1, y1 (S4: edge 2-3), x0 (S5: edge 3-0)
    (
        [0, 2, 3, 4, 6, 7, 24, 10, 11, 25, 14, 15, 16, 18, 19],
        [Some(0), Some(1), None, None, Some(3), Some(4)],
    ),
];

/// Specification of a box mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct BoxSpec {
    /// Lower corner.
    pub origin: [f64; 3],
    /// Edge lengths.
    pub size: [f64; 3],
    /// Elements along each axis.
    pub divisions: [usize; 3],
    /// Hexahedron or wedge shape.
    pub shape: CellShape,
    /// Ratio of last to first element size along each axis (1 = uniform).
    pub grading: [f64; 3],
}

impl BoxSpec {
    /// A uniform box at the origin.
    pub fn new(size: [f64; 3], divisions: [usize; 3], shape: CellShape) -> Self {
        BoxSpec {
            origin: [0.0; 3],
            size,
            divisions,
            shape,
            grading: [1.0; 3],
        }
    }
}

/// Element boundaries along one axis with geometric grading.
fn axis_ticks(origin: f64, length: f64, n: usize, ratio: f64) -> Vec<f64> {
    let q = if n > 1 {
        ratio.powf(1.0 / (n as f64 - 1.0))
    } else {
        1.0
    };
    let weights: Vec<f64> = (0..n).map(|i| q.powi(i as i32)).collect();
    let total: f64 = weights.iter().sum();
    let mut x = vec![origin];
    let mut acc = 0.0;
    for w in &weights {
        acc += w;
        x.push(origin + length * acc / total);
    }
    x[n] = origin + length;
    x
}

/// The size, divisions and grading of a box: positive and finite.
fn check_box_spec(spec: &BoxSpec) -> Result<(), CoreError> {
    for a in 0..3 {
        if spec.divisions[a] == 0 {
            return Err(CoreError::Invalid("box divisions must be >= 1".into()));
        }
        if !spec.size[a].is_finite() || spec.size[a] <= 0.0 {
            return Err(CoreError::Invalid(format!(
                "box size must be positive and finite, got {:?}",
                spec.size
            )));
        }
        if !spec.grading[a].is_finite() || spec.grading[a] <= 0.0 {
            return Err(CoreError::Invalid(format!(
                "box grading must be positive, got {:?}",
                spec.grading
            )));
        }
    }
    Ok(())
}

/// The lattice coordinates of each axis: the element ends, with the
/// midpoints for quadratic cells (`p = 2`).
fn box_lattice(spec: &BoxSpec, p: usize) -> Vec<Vec<f64>> {
    // lattice coordinates per axis (element ends, plus midpoints if quadratic)
    (0..3)
        .map(|a| {
            let t = axis_ticks(
                spec.origin[a],
                spec.size[a],
                spec.divisions[a],
                spec.grading[a],
            );
            if p == 1 {
                t
            } else {
                let mut v = Vec::with_capacity(2 * t.len() - 1);
                for w in t.windows(2) {
                    v.push(w[0]);
                    v.push(0.5 * (w[0] + w[1]));
                }
                v.push(*t.last().unwrap());
                v
            }
        })
        .collect()
}

/// The connectivity of the box's cells on the lattice (`[lx, ly]` points
/// along x and y), the faces on each side of the box (in
/// `HEX_FACE_NAMES` order) and the number of elements.
fn box_cells(
    spec: &BoxSpec,
    p: usize,
    wedge: bool,
    [lx, ly]: [usize; 2],
) -> (Vec<usize>, Vec<Vec<FaceRef>>, usize) {
    let [nx, ny, nz] = spec.divisions;
    let lid = |i: usize, j: usize, k: usize| (k * ly + j) * lx + i;
    let npe = spec.shape.num_nodes();
    // lattice points of one cell, in H8 (p = 1) or H27 (p = 2) order
    let cell_nodes = if p == 1 { 8 } else { 27 };
    let cells_per_hex = if wedge { 2 } else { 1 };
    let mut conn = Vec::with_capacity(nx * ny * nz * npe * cells_per_hex);
    let mut faces: Vec<Vec<FaceRef>> = vec![Vec::new(); 6];
    let mut e = 0;
    let mut cell = [0usize; 27];
    for ez in 0..nz {
        for ey in 0..ny {
            for ex in 0..nx {
                for (c, xi) in cell.iter_mut().zip(HEX27_NODES.iter().take(cell_nodes)) {
                    let i = p * ex + ((xi[0] + 1.0) * 0.5 * p as f64) as usize;
                    let j = p * ey + ((xi[1] + 1.0) * 0.5 * p as f64) as usize;
                    let k = p * ez + ((xi[2] + 1.0) * 0.5 * p as f64) as usize;
                    *c = lid(i, j, k);
                }
                // sides of the box this cell touches, in HEX_FACE_NAMES order
                let on = [
                    ez == 0,
                    ez == nz - 1,
                    ey == 0,
                    ex == nx - 1,
                    ey == ny - 1,
                    ex == 0,
                ];
                if !wedge {
                    conn.extend(cell[..npe].iter());
                    for (f, &b) in on.iter().enumerate() {
                        if b {
                            faces[f].push(FaceRef {
                                block: 0,
                                element: e,
                                face: f,
                            });
                        }
                    }
                    e += 1;
                    continue;
                }
                for (w, (local, sides)) in WEDGES_OF_HEX.iter().enumerate() {
                    conn.extend(local[..npe].iter().map(|&a| cell[a]));
                    for (side, &b) in on.iter().enumerate() {
                        if let (true, Some(face)) = (b, sides[side]) {
                            faces[side].push(FaceRef {
                                block: 0,
                                element: e + w,
                                face,
                            });
                        }
                    }
                }
                e += 2;
            }
        }
    }
    (conn, faces, e)
}

/// Drop the lattice points no element uses (H20 has no face or body
/// centres); renumber `conn` and return the nodes' coordinates.
fn compact_lattice(lattice: &[Vec<f64>], conn: &mut [usize]) -> Vec<[f64; 3]> {
    let (lx, ly, lz) = (lattice[0].len(), lattice[1].len(), lattice[2].len());
    let lid = |i: usize, j: usize, k: usize| (k * ly + j) * lx + i;
    let mut new_id = vec![usize::MAX; lx * ly * lz];
    let mut nodes = Vec::new();
    let mut used = vec![false; lx * ly * lz];
    for &c in conn.iter() {
        used[c] = true;
    }
    for k in 0..lz {
        for j in 0..ly {
            for i in 0..lx {
                let l = lid(i, j, k);
                if used[l] {
                    new_id[l] = nodes.len();
                    nodes.push([lattice[0][i], lattice[1][j], lattice[2][k]]);
                }
            }
        }
    }
    for c in conn.iter_mut() {
        *c = new_id[*c];
    }
    nodes
}

/// Generate a box mesh with one block named `block_name`, element type key
/// `element_type` and material `material`.
pub fn box_mesh(
    spec: &BoxSpec,
    block_name: &str,
    element_type: &str,
    material: &str,
) -> Result<Mesh, CoreError> {
    if spec.shape.is_plane() {
        return plane_box_mesh(spec, block_name, element_type, material);
    }
    let p = match spec.shape {
        CellShape::Hex8 | CellShape::Wedge6 => 1,
        CellShape::Hex20 | CellShape::Hex27 | CellShape::Wedge15 => 2,
        s => {
            return Err(CoreError::Invalid(format!(
                "box generator makes hexahedra (hex8, hex20, hex27) or wedges (wedge6, wedge15), not {}",
                s.name()
            )))
        }
    };
    let wedge = matches!(spec.shape, CellShape::Wedge6 | CellShape::Wedge15);
    check_box_spec(spec)?;
    let lattice = box_lattice(spec, p);
    let (lx, ly) = (lattice[0].len(), lattice[1].len());
    let (mut conn, faces, e) = box_cells(spec, p, wedge, [lx, ly]);
    let nodes = compact_lattice(&lattice, &mut conn);
    let block = ElementBlock {
        name: block_name.to_string(),
        shape: spec.shape,
        connectivity: conn,
        element_type: element_type.to_string(),
        material: material.to_string(),
    };
    Ok(box_with_sets(nodes, block, faces, &HEX_FACE_NAMES, e))
}

/// The mesh of one box block: its side sets (node and face sets named
/// `names[f]` for the faces `faces[f]`) and the element set `all` of its
/// `e` elements.
fn box_with_sets(
    nodes: Vec<[f64; 3]>,
    block: ElementBlock,
    faces: Vec<Vec<FaceRef>>,
    names: &[&str],
    e: usize,
) -> Mesh {
    let mut mesh = Mesh {
        nodes,
        blocks: vec![block],
        ..Default::default()
    };
    for (list, name) in faces.into_iter().zip(names) {
        mesh.node_sets
            .insert(name.to_string(), mesh.nodes_of_faces(&list));
        mesh.face_sets.insert(name.to_string(), list);
    }
    mesh.element_sets.insert(
        "all".into(),
        (0..e)
            .map(|element| ElementRef { block: 0, element })
            .collect(),
    );
    mesh
}

/// Names of the sides of a plane box in the edge order of its
/// quadrilaterals (Abaqus S1..S4: y-, x+, y+, x-).
const PLANE_SIDE_NAMES: [&str; 4] = ["y0", "x1", "y1", "x0"];

/// A plane box (the x-y rectangle at `z = origin[2]`; the z size and
/// divisions are not used) of quadrilaterals, or of triangles, two per
/// rectangle split along its diagonal from the lower-left corner: node
/// sets and face (edge) sets `x0`, `x1`, `y0`, `y1` and the element set
/// `all`, as [`box_mesh`].
fn plane_box_mesh(
    spec: &BoxSpec,
    block_name: &str,
    element_type: &str,
    material: &str,
) -> Result<Mesh, CoreError> {
    let p = if spec.shape.num_nodes() > 4 { 2 } else { 1 };
    let flat = BoxSpec {
        size: [spec.size[0], spec.size[1], 1.0],
        divisions: [spec.divisions[0], spec.divisions[1], 1],
        grading: [spec.grading[0], spec.grading[1], 1.0],
        ..*spec
    };
    check_box_spec(&flat)?;
    let lattice = box_lattice(&flat, p);
    let lx = lattice[0].len();
    let [nx, ny, _] = flat.divisions;
    // one quadrilateral's lattice points in Quad9 order
    let quad = |ex: usize, ey: usize| -> [usize; 9] {
        std::array::from_fn(|a| {
            let xi = crate::topology::QUAD9_NODES[a];
            let i = p * ex + ((xi[0] + 1.0) * 0.5 * p as f64) as usize;
            let j = p * ey + ((xi[1] + 1.0) * 0.5 * p as f64) as usize;
            j * lx + i
        })
    };
    // triangles of a rectangle: local Quad9 ids, and which side (in
    // PLANE_SIDE_NAMES order) each triangle edge lies on
    const TRIS: [([usize; 6], [Option<usize>; 3]); 2] = [
        ([0, 1, 2, 4, 5, 8], [Some(0), Some(1), None]),
        ([0, 2, 3, 8, 6, 7], [None, Some(2), Some(3)]),
    ];
    let tri = matches!(spec.shape, CellShape::PlaneTri3 | CellShape::PlaneTri6);
    let npe = spec.shape.num_nodes();
    let (mut conn, mut faces, mut e) = (Vec::new(), vec![Vec::new(); 4], 0);
    for ey in 0..ny {
        for ex in 0..nx {
            let q = quad(ex, ey);
            let on = [ey == 0, ex == nx - 1, ey == ny - 1, ex == 0];
            let cells: Vec<(Vec<usize>, [Option<usize>; 4])> = if tri {
                TRIS.iter()
                    .map(|(local, sides)| {
                        let mut edge_of_side = [None; 4];
                        for (k, s) in sides.iter().enumerate() {
                            if let Some(s) = s {
                                edge_of_side[*s] = Some(k);
                            }
                        }
                        (local[..npe].iter().map(|&a| q[a]).collect(), edge_of_side)
                    })
                    .collect()
            } else {
                vec![(q[..npe].to_vec(), [Some(0), Some(1), Some(2), Some(3)])]
            };
            for (nodes, edge_of_side) in cells {
                conn.extend(nodes);
                for side in 0..4 {
                    if let (true, Some(face)) = (on[side], edge_of_side[side]) {
                        faces[side].push(FaceRef {
                            block: 0,
                            element: e,
                            face,
                        });
                    }
                }
                e += 1;
            }
        }
    }
    let plane = [lattice[0].clone(), lattice[1].clone(), vec![spec.origin[2]]];
    let nodes = compact_lattice(&plane, &mut conn);
    let block = ElementBlock {
        name: block_name.to_string(),
        shape: spec.shape,
        connectivity: conn,
        element_type: element_type.to_string(),
        material: material.to_string(),
    };
    Ok(box_with_sets(nodes, block, faces, &PLANE_SIDE_NAMES, e))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Plane boxes: node counts, counter-clockwise cells of the box's area,
    /// and side sets made of edges on the sides.
    #[test]
    fn plane_boxes_cover_the_rectangle_with_their_sides_named() {
        for (shape, nodes) in [
            (CellShape::PlaneQuad4, 4 * 3),
            (CellShape::PlaneQuad8, 7 * 5 - 6),
            (CellShape::PlaneQuad9, 7 * 5),
            (CellShape::PlaneTri3, 4 * 3),
            (CellShape::PlaneTri6, 7 * 5),
        ] {
            let mut spec = BoxSpec::new([3.0, 2.0, 9.0], [3, 2, 5], shape);
            spec.origin = [1.0, -1.0, 0.5];
            let m = box_mesh(&spec, "b", "k", "m").unwrap();
            assert_eq!(m.nodes.len(), nodes, "{shape:?}");
            let b = &m.blocks[0];
            let mut area = 0.0;
            for e in 0..b.len() {
                let c = b.element(e);
                let k = if b.shape.num_faces() == 3 { 3 } else { 4 };
                let a: f64 = (0..k)
                    .map(|i| {
                        let (p, q) = (m.nodes[c[i]], m.nodes[c[(i + 1) % k]]);
                        0.5 * (p[0] * q[1] - q[0] * p[1])
                    })
                    .sum();
                assert!(a > 0.0, "{shape:?}: clockwise cell {e}");
                area += a;
            }
            assert!((area - 6.0).abs() < 1e-12, "{shape:?}: {area}");
            assert!(m.nodes.iter().all(|x| x[2] == 0.5));
            for (side, axis, at) in [
                ("x0", 0, 1.0),
                ("x1", 0, 4.0),
                ("y0", 1, -1.0),
                ("y1", 1, 1.0),
            ] {
                let faces = &m.face_sets[side];
                assert_eq!(
                    faces.len(),
                    if axis == 0 { 2 } else { 3 },
                    "{shape:?} {side}"
                );
                for &f in faces {
                    assert!(
                        m.face_nodes(f).iter().all(|&n| m.nodes[n][axis] == at),
                        "{shape:?} {side}"
                    );
                }
            }
        }
    }

    #[test]
    fn node_counts_match_closed_forms() {
        // H8: (n+1)^3; H27: (2n+1)^3; H20: (2n+1)^3 minus face and body centres
        let n = 3;
        let h8 = box_mesh(
            &BoxSpec::new([1.0; 3], [n; 3], CellShape::Hex8),
            "b",
            "h8",
            "m",
        )
        .unwrap();
        assert_eq!(h8.nodes.len(), (n + 1).pow(3));
        let h27 = box_mesh(
            &BoxSpec::new([1.0; 3], [n; 3], CellShape::Hex27),
            "b",
            "h27",
            "m",
        )
        .unwrap();
        assert_eq!(h27.nodes.len(), (2 * n + 1).pow(3));
        let h20 = box_mesh(
            &BoxSpec::new([1.0; 3], [n; 3], CellShape::Hex20),
            "b",
            "h20",
            "m",
        )
        .unwrap();
        // corners (n+1)^3 + edges 3 n (n+1)^2
        assert_eq!(h20.nodes.len(), (n + 1).pow(3) + 3 * n * (n + 1).pow(2));
        assert_eq!(h20.face_sets["z1"].len(), n * n);
        // top face nodes of H20: (n+1)^2 corners + 2 n (n+1) mid-edges
        assert_eq!(h20.node_sets["z1"].len(), (n + 1).pow(2) + 2 * n * (n + 1));
        assert!(h20.node_sets["z1"].iter().all(|&i| h20.nodes[i][2] == 1.0));
    }

    /// Wedge boxes: two wedges per cell, the node counts of the H8 / H27
    /// lattice without the face centres off the cut and the body centres,
    /// every side set covering the side's area with faces whose outward
    /// normal (right-hand rule on the face, hence the element's
    /// orientation) is the side's.
    #[test]
    fn wedge_boxes() {
        let (n, size) = ([2, 3, 2], [2.0, 1.5, 1.0]);
        for shape in [CellShape::Wedge6, CellShape::Wedge15] {
            let m = box_mesh(&BoxSpec::new(size, n, shape), "b", shape.name(), "m").unwrap();
            let cells = n[0] * n[1] * n[2];
            assert_eq!(m.blocks[0].len(), 2 * cells);
            assert_eq!(m.element_sets["all"].len(), 2 * cells);
            let lattice = |p: usize| (0..3).map(|a| p * n[a] + 1).product::<usize>();
            let want = if shape == CellShape::Wedge6 {
                lattice(1)
            } else {
                // H27 lattice minus the body centres and the x- and y-face
                // centres (the z-face centres are the cut's mid-nodes)
                lattice(2) - cells - n[1] * n[2] * (n[0] + 1) - n[0] * n[2] * (n[1] + 1)
            };
            assert_eq!(m.nodes.len(), want, "{shape:?}");
            assert!(m.used_nodes().iter().all(|u| *u));
            let normals = [
                [0.0, 0.0, -1.0],
                [0.0, 0.0, 1.0],
                [0.0, -1.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [-1.0, 0.0, 0.0],
            ];
            for (side, name) in HEX_FACE_NAMES.iter().enumerate() {
                let faces = &m.face_sets[*name];
                let mut area = 0.0;
                for &f in faces {
                    let x = m.face_nodes(f);
                    let k = m.blocks[0]
                        .shape
                        .face_shape_of(f.face)
                        .unwrap()
                        .num_corners();
                    let p = |i: usize| m.nodes[x[i]];
                    // polygon area vector from the corners
                    let mut a = [0.0; 3];
                    for i in 1..k - 1 {
                        let (u, v) = (sub(p(i), p(0)), sub(p(i + 1), p(0)));
                        let c = [
                            u[1] * v[2] - u[2] * v[1],
                            u[2] * v[0] - u[0] * v[2],
                            u[0] * v[1] - u[1] * v[0],
                        ];
                        for d in 0..3 {
                            a[d] += 0.5 * c[d];
                        }
                    }
                    let along: f64 = (0..3).map(|d| a[d] * normals[side][d]).sum();
                    let len = (0..3).map(|d| a[d] * a[d]).sum::<f64>().sqrt();
                    assert!((along - len).abs() < 1e-12, "{shape:?} {name}: {a:?}");
                    area += along;
                }
                let axis = (0..3).position(|d| normals[side][d] != 0.0).unwrap();
                let want = size[(axis + 1) % 3] * size[(axis + 2) % 3];
                assert!((area - want).abs() < 1e-12, "{shape:?} {name}: {area}");
                assert!(m.node_sets[*name].iter().all(|&i| {
                    let c = m.nodes[i][axis];
                    c == if normals[side][axis] < 0.0 {
                        0.0
                    } else {
                        size[axis]
                    }
                }));
            }
        }
    }

    fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
        [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
    }

    #[test]
    fn grading_keeps_length_and_ratio() {
        let t = axis_ticks(0.0, 2.0, 4, 8.0);
        assert!((t[4] - 2.0).abs() < 1e-15);
        let first = t[1] - t[0];
        let last = t[4] - t[3];
        assert!((last / first - 8.0).abs() < 1e-12);
    }
}
