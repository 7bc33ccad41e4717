//! A ply extruded from a plane 2D mesh of quadrilaterals (a Gmsh base,
//! holes and all): every quadrilateral becomes a column of hexahedra
//! through the ply, Quad4 -> Hex8, Quad8 -> Hex20.
//!
//! The base lies in a plane `z = z_b`; the plies stack along `+z`. A
//! quadrilateral whose right-hand normal points down is taken in reverse
//! order, so that every hexahedron has its bottom face first with a
//! positive Jacobian. Node order of the hexahedra (ours, Abaqus' C3D8 /
//! C3D20, `junta_core::topology::HEX_FACES`): the quad's corners at the
//! bottom then at the top; for Hex20 the quad's mid-side nodes at the
//! bottom, at the top, then its corners at mid-height.
//!
//! Sets of the ply (renamed `ply_K.*` when the plies are merged): node and
//! face sets `z0` (bottom), `z1` (top) and one per physical curve of the
//! base (the side faces over its line elements, e.g. a hole's edge).

use crate::input::gmsh::SurfaceMesh;
use junta_core::mesh::{ElementBlock, ElementRef, FaceRef, Mesh};
use junta_core::topology::CellShape;
use std::collections::HashMap;

/// The quadrilaterals of `s`, each counter-clockwise seen from `+z`, and
/// the plane's `z`; an error when the base is not plane and horizontal.
pub fn oriented_cells(s: &SurfaceMesh) -> Result<(Vec<usize>, f64), String> {
    let n = s.shape.num_nodes();
    let used: Vec<usize> = s.cells.clone();
    let z_b = used
        .first()
        .map(|&i| s.nodes[i][2])
        .ok_or("the base has no quadrilateral")?;
    let extent = used
        .iter()
        .map(|&i| s.nodes[i][0].abs().max(s.nodes[i][1].abs()))
        .fold(0.0f64, f64::max)
        .max(z_b.abs())
        .max(f64::MIN_POSITIVE);
    if let Some(&i) = used
        .iter()
        .find(|&&i| (s.nodes[i][2] - z_b).abs() > 1e-9 * extent)
    {
        return Err(format!(
            "the base must lie in a plane z = const (the plies stack along +z): node {} is at z = {} against {z_b}",
            i + 1,
            s.nodes[i][2]
        ));
    }
    let mut cells = Vec::with_capacity(s.cells.len());
    for q in s.cells.chunks(n) {
        let p = |k: usize| s.nodes[q[k]];
        let (a, b) = (sub(p(1), p(0)), sub(p(2), p(0)));
        let up = a[0] * b[1] - a[1] * b[0];
        if up >= 0.0 {
            cells.extend_from_slice(q);
        } else if n == 4 {
            cells.extend_from_slice(&[q[0], q[3], q[2], q[1]]);
        } else {
            cells.extend_from_slice(&[q[0], q[3], q[2], q[1], q[7], q[6], q[5], q[4]]);
        }
    }
    Ok((cells, z_b))
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// One ply over `cells` (from [`oriented_cells`]) between `z0` and `z0 +
/// thickness`, `layers` elements through it.
pub fn extrude_ply(
    s: &SurfaceMesh,
    cells: &[usize],
    z0: f64,
    thickness: f64,
    layers: usize,
    element_type: &str,
    material: &str,
) -> Mesh {
    let n = s.shape.num_nodes();
    let quadratic = n == 8;
    // the base nodes the cells use, numbered 0..m; corners among them 0..c
    let mut local: HashMap<usize, usize> = HashMap::new();
    let mut corner_local: HashMap<usize, usize> = HashMap::new();
    let mut base: Vec<usize> = Vec::new();
    let mut corners: Vec<usize> = Vec::new();
    for q in cells.chunks(n) {
        for (k, &i) in q.iter().enumerate() {
            local.entry(i).or_insert_with(|| {
                base.push(i);
                base.len() - 1
            });
            if k < 4 {
                corner_local.entry(i).or_insert_with(|| {
                    corners.push(i);
                    corners.len() - 1
                });
            }
        }
    }
    let (m, c) = (base.len(), corners.len());
    let dz = thickness / layers as f64;
    let mut nodes = Vec::with_capacity(m * (layers + 1) + if quadratic { c * layers } else { 0 });
    for j in 0..=layers {
        let z = z0 + dz * j as f64;
        nodes.extend(base.iter().map(|&i| [s.nodes[i][0], s.nodes[i][1], z]));
    }
    let mid = nodes.len();
    if quadratic {
        for j in 0..layers {
            let z = z0 + dz * (j as f64 + 0.5);
            nodes.extend(corners.iter().map(|&i| [s.nodes[i][0], s.nodes[i][1], z]));
        }
    }
    let at = |level: usize, i: usize| level * m + local[&i];
    let at_mid = |layer: usize, i: usize| mid + layer * c + corner_local[&i];
    let shape = if quadratic {
        CellShape::Hex20
    } else {
        CellShape::Hex8
    };
    let mut conn = Vec::with_capacity(cells.len() / n * layers * shape.num_nodes());
    for j in 0..layers {
        for q in cells.chunks(n) {
            conn.extend(q[..4].iter().map(|&i| at(j, i)));
            conn.extend(q[..4].iter().map(|&i| at(j + 1, i)));
            if quadratic {
                conn.extend(q[4..].iter().map(|&i| at(j, i)));
                conn.extend(q[4..].iter().map(|&i| at(j + 1, i)));
                conn.extend(q[..4].iter().map(|&i| at_mid(j, i)));
            }
        }
    }
    let mut mesh = Mesh {
        nodes,
        blocks: vec![ElementBlock {
            name: "solid".into(),
            shape,
            connectivity: conn,
            element_type: element_type.into(),
            material: material.into(),
        }],
        ..Mesh::default()
    };
    add_ply_sets(&mut mesh, s, cells, layers);
    mesh
}

/// `z0`, `z1`, one set per physical curve, and `all`.
fn add_ply_sets(mesh: &mut Mesh, s: &SurfaceMesh, cells: &[usize], layers: usize) {
    let n = s.shape.num_nodes();
    let per_layer = cells.len() / n;
    let face = |layer: usize, cell: usize, face: usize| FaceRef {
        block: 0,
        element: layer * per_layer + cell,
        face,
    };
    let mut sets: Vec<(String, Vec<FaceRef>)> = vec![
        ("z0".into(), (0..per_layer).map(|e| face(0, e, 0)).collect()),
        (
            "z1".into(),
            (0..per_layer).map(|e| face(layers - 1, e, 1)).collect(),
        ),
    ];
    // quad edge k (corners k, k+1) -> hexahedron side face k + 2 (HEX_FACES S3..S6)
    let mut edges: HashMap<[usize; 2], Vec<(usize, usize)>> = HashMap::new();
    for (e, q) in cells.chunks(n).enumerate() {
        for k in 0..4 {
            let (a, b) = (q[k], q[(k + 1) % 4]);
            edges.entry([a.min(b), a.max(b)]).or_default().push((e, k));
        }
    }
    for (name, pairs) in &s.curves {
        let mut faces = Vec::new();
        for &[a, b] in pairs {
            for &(e, k) in edges.get(&[a.min(b), a.max(b)]).map_or(&[][..], |v| v) {
                faces.extend((0..layers).map(|j| face(j, e, k + 2)));
            }
        }
        sets.push((name.clone(), faces));
    }
    for (name, faces) in sets {
        let nodes = mesh.nodes_of_faces(&faces);
        mesh.node_sets.insert(name.clone(), nodes);
        mesh.face_sets.insert(name, faces);
    }
    mesh.element_sets.insert(
        "all".into(),
        (0..mesh.blocks[0].len())
            .map(|element| ElementRef { block: 0, element })
            .collect(),
    );
}
