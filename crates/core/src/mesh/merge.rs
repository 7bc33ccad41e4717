//! Merging named meshes (parts) into one mesh with shared nodes where they
//! touch.
//!
//! [`merge`] concatenates parts (for example boxes from
//! [`super::generate::box_mesh`], or meshes read from files), renames their
//! blocks and sets after the part, and then fuses coincident nodes of
//! *different* parts so that the parts are glued together. Interfaces can then
//! be inserted between two parts with
//! [`super::interface::insert_interface`].
//!
//! # Conventions
//!
//! * The parts must be *conforming* where they touch: every node of one part's
//!   contact surface must lie (within the tolerance) on a node of the other
//!   part. A merge never moves a node: the fused node keeps the coordinates
//!   of the node of the earliest part (lowest id), and nothing is projected
//!   or snapped.
//! * Only nodes of different parts are fused. Coincident nodes inside one part
//!   (an existing crack or interface) stay distinct.

use super::{ElementBlock, ElementRef, FaceRef, Mesh};
use crate::error::CoreError;
use std::collections::{BTreeMap, HashMap, HashSet};

/// Concatenate named meshes into one and fuse their coincident nodes.
///
/// `parts` is a list of `(name, mesh)`; names must be unique and non-empty.
///
/// Naming (part `name`):
/// * its blocks: `name` when the part has exactly one block, else
///   `name.<block name>`;
/// * a new element set `name` holding every element of the part; the part's
///   own element set `all` (from the box generator) is that same set and is
///   not copied again (an `all` set that does not hold every element becomes
///   `name.all`);
/// * every other node, element and face set `s` becomes `name.s` (box "lower"
///   with node set `z0` gives `lower.z0`).
///
/// Fusing: node `j` of a part is fused with the nearest node `i` of an
/// *earlier* part whose distance is at most `tol` times the diagonal of the
/// bounding box of all nodes (`tol = 0` fuses exactly equal positions only).
/// Candidates are found on a hashed grid of cell size `tol * diagonal`, so
/// the cost is O(n) expected. Nodes of one part are never fused with each
/// other; if two nodes of one part would both fuse with the same node of an
/// earlier part, the merge is refused (it would collapse that part).
///
/// Afterwards connectivity and node sets refer to the fused nodes; node sets
/// are sorted and deduplicated; nodes that no element uses are removed (and
/// dropped from node sets), and the remaining nodes keep their relative
/// order. Node labels are reset (`node_labels` empty: label = id + 1),
/// because the parts' labels would clash.
///
/// Errors ([`CoreError::Invalid`]): negative or non-finite `tol`, duplicate or
/// empty part names, non-finite coordinates, an invalid part, renamed sets
/// or blocks that collide, or a fusion that would collapse nodes of one part.
pub fn merge(parts: Vec<(String, Mesh)>, tol: f64) -> Result<Mesh, CoreError> {
    if !tol.is_finite() || tol < 0.0 {
        return Err(CoreError::Invalid(format!(
            "merge tolerance must be finite and >= 0 (a fraction of the bounding-box diagonal, e.g. 1e-8), got {tol}"
        )));
    }
    let mut seen = HashSet::new();
    for (name, mesh) in &parts {
        if name.is_empty() {
            return Err(CoreError::Invalid(
                "merge: every part needs a non-empty name".into(),
            ));
        }
        if !seen.insert(name.as_str()) {
            return Err(CoreError::Invalid(format!(
                "merge: part name `{name}` is used twice; part names must be unique"
            )));
        }
        mesh.validate()
            .map_err(|e| CoreError::Invalid(format!("merge: part `{name}`: {e}")))?;
        if let Some(i) = mesh
            .nodes
            .iter()
            .position(|p| p.iter().any(|c| !c.is_finite()))
        {
            return Err(CoreError::Invalid(format!(
                "merge: part `{name}`: node {} has non-finite coordinates {:?}",
                mesh.node_label(i),
                mesh.nodes[i]
            )));
        }
    }

    // 1. concatenate
    let mut out = Mesh::default();
    let mut node_ranges = Vec::with_capacity(parts.len());
    let mut part_names = Vec::with_capacity(parts.len());
    let mut block_names = HashSet::new();
    for (name, mesh) in parts {
        let node_off = out.nodes.len();
        let block_off = out.blocks.len();
        node_ranges.push(node_off..node_off + mesh.nodes.len());
        part_names.push(name.clone());
        out.nodes.extend_from_slice(&mesh.nodes);
        let single = mesh.blocks.len() == 1;
        let mut all = Vec::with_capacity(mesh.num_elements());
        for (b, block) in mesh.blocks.into_iter().enumerate() {
            let bname = if single {
                name.clone()
            } else {
                format!("{name}.{}", block.name)
            };
            if !block_names.insert(bname.clone()) {
                return Err(CoreError::Invalid(format!(
                    "merge: block name `{bname}` (from part `{name}`) is already used by another part; rename a part"
                )));
            }
            all.extend((0..block.len()).map(|element| ElementRef {
                block: block_off + b,
                element,
            }));
            out.blocks.push(ElementBlock {
                name: bname,
                connectivity: block.connectivity.iter().map(|&i| i + node_off).collect(),
                ..block
            });
        }
        insert_unique(&mut out.element_sets, "element", name.clone(), all.clone())?;
        for (s, set) in mesh.node_sets {
            let v = set.iter().map(|&i| i + node_off).collect();
            insert_unique(&mut out.node_sets, "node", format!("{name}.{s}"), v)?;
        }
        for (s, set) in mesh.element_sets {
            let v: Vec<ElementRef> = set
                .iter()
                .map(|r| ElementRef {
                    block: r.block + block_off,
                    element: r.element,
                })
                .collect();
            if s == "all" && same_elements(&v, &all) {
                continue;
            }
            insert_unique(&mut out.element_sets, "element", format!("{name}.{s}"), v)?;
        }
        for (s, set) in mesh.face_sets {
            let v = set
                .iter()
                .map(|f| FaceRef {
                    block: f.block + block_off,
                    ..*f
                })
                .collect();
            insert_unique(&mut out.face_sets, "face", format!("{name}.{s}"), v)?;
        }
    }

    // 2. fuse coincident nodes of different parts
    let fused = fuse_map(&out.nodes, &node_ranges, &part_names, tol)?;
    for b in &mut out.blocks {
        for i in &mut b.connectivity {
            *i = fused[*i];
        }
    }

    // 3. compact: keep used nodes in their order
    let used = out.used_nodes();
    let mut new_id = vec![usize::MAX; out.nodes.len()];
    let mut nodes = Vec::with_capacity(out.nodes.len());
    for (i, p) in out.nodes.iter().enumerate() {
        if used[i] {
            new_id[i] = nodes.len();
            nodes.push(*p);
        }
    }
    out.nodes = nodes;
    for b in &mut out.blocks {
        for i in &mut b.connectivity {
            *i = new_id[*i];
        }
    }
    for set in out.node_sets.values_mut() {
        let mut v: Vec<usize> = set
            .iter()
            .map(|&i| new_id[fused[i]])
            .filter(|&i| i != usize::MAX)
            .collect();
        v.sort_unstable();
        v.dedup();
        *set = v;
    }
    out.validate()?;
    Ok(out)
}

fn insert_unique<T>(
    map: &mut BTreeMap<String, T>,
    kind: &str,
    name: String,
    value: T,
) -> Result<(), CoreError> {
    if map.contains_key(&name) {
        return Err(CoreError::Invalid(format!(
            "merge: two parts both produce the {kind} set `{name}` (set names become `part.set`); rename a part or a set"
        )));
    }
    map.insert(name, value);
    Ok(())
}

fn same_elements(a: &[ElementRef], b: &[ElementRef]) -> bool {
    let mut a = a.to_vec();
    a.sort_unstable();
    a.dedup();
    a == b
}

/// Grid key of a point: cell of size `h`, or the exact bit pattern if `h == 0`.
fn grid_key(p: &[f64; 3], h: f64) -> [i64; 3] {
    if h > 0.0 {
        // `as` saturates for huge values; no panic
        p.map(|c| (c / h).floor() as i64)
    } else {
        // +0.0 turns -0.0 into 0.0 so that both hash alike
        p.map(|c| (c + 0.0).to_bits() as i64)
    }
}

/// For every node, the id of the node it is fused with (itself if none).
fn fuse_map(
    nodes: &[[f64; 3]],
    ranges: &[std::ops::Range<usize>],
    part_names: &[String],
    tol: f64,
) -> Result<Vec<usize>, CoreError> {
    let mut map: Vec<usize> = (0..nodes.len()).collect();
    if nodes.is_empty() {
        return Ok(map);
    }
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in nodes {
        for d in 0..3 {
            lo[d] = lo[d].min(p[d]);
            hi[d] = hi[d].max(p[d]);
        }
    }
    let diag = (0..3).map(|d| (hi[d] - lo[d]).powi(2)).sum::<f64>().sqrt();
    let eps = tol * diag;
    let eps2 = eps * eps;
    let reach: i64 = if eps > 0.0 { 1 } else { 0 };
    let mut grid: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
    // part index + 1 of the last part that fused a node into this one
    let mut claimed = vec![0usize; nodes.len()];
    for (p, range) in ranges.iter().enumerate() {
        for j in range.clone() {
            let q = &nodes[j];
            let k = grid_key(q, eps);
            let mut best: Option<(f64, usize)> = None;
            for dx in -reach..=reach {
                for dy in -reach..=reach {
                    for dz in -reach..=reach {
                        let key = [
                            k[0].saturating_add(dx),
                            k[1].saturating_add(dy),
                            k[2].saturating_add(dz),
                        ];
                        let Some(cands) = grid.get(&key) else {
                            continue;
                        };
                        for &i in cands {
                            let d2: f64 = (0..3).map(|d| (nodes[i][d] - q[d]).powi(2)).sum();
                            let better = match best {
                                None => true,
                                Some(b) => (d2, i) < b,
                            };
                            if d2 <= eps2 && better {
                                best = Some((d2, i));
                            }
                        }
                    }
                }
            }
            if let Some((_, i)) = best {
                if claimed[i] == p + 1 {
                    let other = (range.start..j).find(|&m| map[m] == i).unwrap_or(j);
                    let owner = ranges.iter().position(|r| r.contains(&i)).unwrap_or(0);
                    return Err(CoreError::Invalid(format!(
                        "merge: nodes {} and {} of part `{}` (at {:?} and {:?}) both coincide with node {} of part `{}` within the tolerance {tol} x diagonal {diag}; fusing them would collapse part `{}` (lower the tolerance)",
                        other - range.start + 1,
                        j - range.start + 1,
                        part_names[p],
                        nodes[other],
                        q,
                        i - ranges[owner].start + 1,
                        part_names[owner],
                        part_names[p],
                    )));
                }
                claimed[i] = p + 1;
                map[j] = i;
            }
        }
        // this part's unfused nodes become candidates for the later parts
        for j in range.clone() {
            if map[j] == j {
                grid.entry(grid_key(&nodes[j], eps)).or_default().push(j);
            }
        }
    }
    Ok(map)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::generate::{box_mesh, BoxSpec};
    use crate::topology::CellShape;

    fn cube(origin: [f64; 3], shape: CellShape) -> Mesh {
        let mut s = BoxSpec::new([1.0; 3], [1; 3], shape);
        s.origin = origin;
        box_mesh(&s, "b", "h", "m").unwrap()
    }

    #[test]
    fn renames_sets_and_blocks() {
        let m = merge(
            vec![
                ("a".into(), cube([0.0; 3], CellShape::Hex8)),
                ("b".into(), cube([0.0, 0.0, 1.0], CellShape::Hex8)),
            ],
            1e-9,
        )
        .unwrap();
        assert_eq!(m.nodes.len(), 12);
        assert_eq!(m.blocks[0].name, "a");
        assert_eq!(m.blocks[1].name, "b");
        assert!(m.element_sets.contains_key("a") && !m.element_sets.contains_key("a.all"));
        assert_eq!(m.element_sets["b"][0].block, 1);
        assert_eq!(m.node_sets["a.z1"], m.node_sets["b.z0"]);
        assert_eq!(m.face_sets["b.z0"][0].block, 1);
    }

    #[test]
    fn rejects_bad_input() {
        let c = cube([0.0; 3], CellShape::Hex8);
        assert!(merge(vec![("a".into(), c.clone())], -1.0).is_err());
        assert!(merge(vec![("a".into(), c.clone()), ("a".into(), c.clone())], 0.0).is_err());
        // two nodes of one part on the same node of an earlier part
        let mut pinched = cube([0.0, 0.0, 1.0], CellShape::Hex8);
        pinched.nodes[1] = pinched.nodes[0];
        let err = merge(vec![("a".into(), c), ("p".into(), pinched)], 1e-9).unwrap_err();
        assert!(err.to_string().contains("collapse"), "{err}");
    }

    #[test]
    fn exact_merge_with_zero_tolerance() {
        let m = merge(
            vec![
                ("a".into(), cube([0.0; 3], CellShape::Hex27)),
                ("b".into(), cube([1.0, 0.0, 0.0], CellShape::Hex27)),
            ],
            0.0,
        )
        .unwrap();
        assert_eq!(m.nodes.len(), 27 + 18);
    }
}
