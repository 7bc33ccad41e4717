//! Structured box meshes: the built-in generator, so that the paper's scenes
//! need no external mesher.
//!
//! A box `[x0, x0+lx] x [y0, y0+ly] x [z0, z0+lz]` is split into
//! `nx x ny x nz` hexahedra (H8, H20 or H27). Optional grading per axis is
//! the ratio of the last element's size to the first's (geometric
//! progression). Named sets: node and face sets `x0, x1, y0, y1, z0, z1` on
//! the six sides, element set `all`.

use super::{ElementBlock, ElementRef, FaceRef, Mesh};
use crate::error::CoreError;
use crate::topology::{CellShape, HEX27_NODES, HEX_FACE_NAMES};

/// Specification of a box mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct BoxSpec {
    /// Lower corner.
    pub origin: [f64; 3],
    /// Edge lengths.
    pub size: [f64; 3],
    /// Elements along each axis.
    pub divisions: [usize; 3],
    /// Hexahedron shape.
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

/// Generate a box mesh with one block named `block_name`, element type key
/// `element_type` and material `material`.
pub fn box_mesh(
    spec: &BoxSpec,
    block_name: &str,
    element_type: &str,
    material: &str,
) -> Result<Mesh, CoreError> {
    let p = match spec.shape {
        CellShape::Hex8 => 1,
        CellShape::Hex20 | CellShape::Hex27 => 2,
        s => {
            return Err(CoreError::Invalid(format!(
                "box generator makes hexahedra (hex8, hex20, hex27), not {}",
                s.name()
            )))
        }
    };
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
    let [nx, ny, nz] = spec.divisions;
    // lattice coordinates per axis (element ends, plus midpoints if quadratic)
    let lattice: Vec<Vec<f64>> = (0..3)
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
        .collect();
    let (lx, ly, lz) = (lattice[0].len(), lattice[1].len(), lattice[2].len());
    let lid = |i: usize, j: usize, k: usize| (k * ly + j) * lx + i;
    let npe = spec.shape.num_nodes();
    let mut conn = Vec::with_capacity(nx * ny * nz * npe);
    let mut faces: Vec<Vec<FaceRef>> = vec![Vec::new(); 6];
    let mut e = 0;
    for ez in 0..nz {
        for ey in 0..ny {
            for ex in 0..nx {
                for xi in HEX27_NODES.iter().take(npe) {
                    let i = p * ex + ((xi[0] + 1.0) * 0.5 * p as f64) as usize;
                    let j = p * ey + ((xi[1] + 1.0) * 0.5 * p as f64) as usize;
                    let k = p * ez + ((xi[2] + 1.0) * 0.5 * p as f64) as usize;
                    conn.push(lid(i, j, k));
                }
                let on = [
                    ez == 0,
                    ez == nz - 1,
                    ey == 0,
                    ex == nx - 1,
                    ey == ny - 1,
                    ex == 0,
                ];
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
            }
        }
    }
    // compact: drop lattice points no element uses (H20 has no face/body centres)
    let mut new_id = vec![usize::MAX; lx * ly * lz];
    let mut nodes = Vec::new();
    let mut used = vec![false; lx * ly * lz];
    for &c in &conn {
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
    let mut mesh = Mesh {
        nodes,
        blocks: vec![ElementBlock {
            name: block_name.to_string(),
            shape: spec.shape,
            connectivity: conn,
            element_type: element_type.to_string(),
            material: material.to_string(),
        }],
        ..Default::default()
    };
    for (f, list) in faces.into_iter().enumerate() {
        let name = HEX_FACE_NAMES[f].to_string();
        mesh.node_sets
            .insert(name.clone(), mesh.nodes_of_faces(&list));
        mesh.face_sets.insert(name, list);
    }
    mesh.element_sets.insert(
        "all".into(),
        (0..e)
            .map(|element| ElementRef { block: 0, element })
            .collect(),
    );
    Ok(mesh)
}

#[cfg(test)]
mod tests {
    use super::*;

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

    #[test]
    fn grading_keeps_length_and_ratio() {
        let t = axis_ticks(0.0, 2.0, 4, 8.0);
        assert!((t[4] - 2.0).abs() < 1e-15);
        let first = t[1] - t[0];
        let last = t[4] - t[3];
        assert!((last / first - 8.0).abs() < 1e-12);
    }
}
