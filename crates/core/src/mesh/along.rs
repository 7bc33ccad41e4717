//! Inserting interface elements along a face set inside the mesh: a line
//! of a plane model (a Gmsh physical curve, a box side) or a surface of a
//! solid one, which need not separate two element sets and may end inside
//! a body.
//!
//! [`insert_interface_along`] takes every face of the set, the element it
//! names as the bottom side and the element across the face as the top
//! side, and puts one interface element on each face (the shape of
//! [`super::interface`], bottom face nodes then top ones, the normal out of
//! the bottom element). A Gmsh curve's face set names, of the two cells
//! along an internal curve, the one whose outward normal agrees with the
//! curve's right-hand normal, so a consistently oriented curve gives a
//! consistent bottom side.
//!
//! # Which nodes are split
//!
//! For each node `n` of the faces, the elements that use `n` are grouped
//! into the pieces they form when joined across their shared faces through
//! `n` that are not faces of the set. Where a top element and a bottom
//! element of the faces at `n` fall in different pieces, `n` is copied and
//! the top pieces move to the copy; where they fall in one piece (the end
//! of a cut inside a body: the elements join around its tip) `n` stays
//! whole, and the interface closes there. So a cut through a body splits
//! it, and a cut that ends inside it opens like a crack whose tip is the
//! last node. Node sets follow the rule of [`super::interface`].

use super::interface::{
    add_interface_blocks, check_new_names, corner_key, describe, face_nodes, face_shape,
    finish_insertion, update_node_sets, InterfaceInsertion,
};
use super::{ElementRef, FaceRef, Mesh};
use crate::error::CoreError;
use crate::topology::CellShape;
use std::collections::{HashMap, HashSet};

/// One face of the cut: (bottom element, its face), (top element, its face).
type FacePair = ((ElementRef, usize), (ElementRef, usize));

/// Insert interface elements on the faces of face set `faces` (module
/// docs), as block `name` with law `law`; node sets `name.bottom` (the
/// faces' nodes) and `name.top` (their copies, or the node itself where it
/// was not split). On error the mesh is unchanged.
pub fn insert_interface_along(
    mesh: &mut Mesh,
    faces: &str,
    name: &str,
    law: &str,
) -> Result<InterfaceInsertion, CoreError> {
    if name.is_empty() {
        return Err(CoreError::Invalid(format!(
            "the interface along `{faces}` needs a non-empty name"
        )));
    }
    check_new_names(mesh, name)?;
    let listed = mesh.face_sets.get(faces).ok_or_else(|| {
        CoreError::Invalid(format!(
            "unknown face set `{faces}`; face sets: {}",
            mesh.face_sets
                .keys()
                .cloned()
                .collect::<Vec<_>>()
                .join(", ")
        ))
    })?;
    let by_key = faces_by_key(mesh);
    let pairs = face_pairs(mesh, faces, listed, &by_key)?;
    let mut shapes: Vec<CellShape> = Vec::new();
    for &((r, f), _) in &pairs {
        let s = face_shape(mesh, r, f);
        if s.matching_interface().is_none() {
            return Err(CoreError::Invalid(format!(
                "face {f} of {} ({}) takes no interface element",
                describe(mesh, r),
                s.name()
            )));
        }
        if !shapes.contains(&s) {
            shapes.push(s);
        }
    }
    if shapes.len() > 1 {
        return Err(CoreError::Invalid(format!(
            "face set `{faces}` mixes face shapes ({}); an interface along it needs one",
            shapes
                .iter()
                .map(|s| s.name())
                .collect::<Vec<_>>()
                .join(", ")
        )));
    }
    // --- checked: modify the mesh ---
    let bottom_faces: Vec<Vec<usize>> = pairs
        .iter()
        .map(|&((r, f), _)| face_nodes(mesh, r, f))
        .collect();
    let mut surface: Vec<usize> = bottom_faces.iter().flatten().copied().collect();
    surface.sort_unstable();
    surface.dedup();
    let copy = split_nodes(mesh, &pairs, &surface, &by_key);
    update_node_sets(mesh, &copy);
    let top_of: HashMap<usize, usize> = surface
        .iter()
        .map(|&n| (n, copy.get(&n).copied().unwrap_or(n)))
        .collect();
    let shared: Vec<(ElementRef, usize)> = pairs.iter().map(|&(b, _)| b).collect();
    let elements = shared.len();
    let n0 = mesh.nodes.len() - copy.len();
    let blocks = add_interface_blocks(mesh, &shapes, &shared, &bottom_faces, &top_of, name, law);
    let top = surface.iter().map(|n| top_of[n]).collect();
    finish_insertion(mesh, name, surface, top, blocks, elements, n0)
}

/// Every face of every solid element by its corner key.
fn faces_by_key(mesh: &Mesh) -> HashMap<[usize; 4], Vec<(ElementRef, usize)>> {
    let mut map: HashMap<[usize; 4], Vec<(ElementRef, usize)>> = HashMap::new();
    for (block, b) in mesh.blocks.iter().enumerate() {
        if !b.shape.is_solid() {
            continue;
        }
        for element in 0..b.len() {
            let r = ElementRef { block, element };
            for f in 0..b.shape.num_faces() {
                map.entry(corner_key(mesh, r, f)).or_default().push((r, f));
            }
        }
    }
    map
}

/// The faces of the set, once each, with the element across each: the
/// listed element is the bottom. A face on the mesh's boundary, or shared
/// by more than two elements, or not conforming, is an error.
fn face_pairs(
    mesh: &Mesh,
    set: &str,
    listed: &[FaceRef],
    by_key: &HashMap<[usize; 4], Vec<(ElementRef, usize)>>,
) -> Result<Vec<FacePair>, CoreError> {
    let mut seen = HashSet::new();
    let mut pairs = Vec::with_capacity(listed.len());
    for fr in listed {
        let r = ElementRef {
            block: fr.block,
            element: fr.element,
        };
        let ok = mesh.blocks.get(r.block).is_some_and(|b| {
            b.shape.is_solid() && r.element < b.len() && fr.face < b.shape.num_faces()
        });
        if !ok {
            return Err(CoreError::Invalid(format!(
                "face set `{set}` holds a face of no solid element ({fr:?})"
            )));
        }
        let key = corner_key(mesh, r, fr.face);
        if !seen.insert(key) {
            continue;
        }
        let across: Vec<_> = by_key[&key]
            .iter()
            .filter(|(o, _)| *o != r)
            .copied()
            .collect();
        let top = match across[..] {
            [t] => t,
            [] => {
                return Err(CoreError::Invalid(format!(
                    "face {} of {} (set `{set}`) is on the boundary of the mesh: an interface along a face set needs the faces inside it, with an element on each side",
                    fr.face,
                    describe(mesh, r)
                )))
            }
            _ => {
                return Err(CoreError::Invalid(format!(
                    "face {} of {} (set `{set}`) is shared by {} elements (non-manifold)",
                    fr.face,
                    describe(mesh, r),
                    across.len() + 1
                )))
            }
        };
        let (mut bn, mut tn) = (face_nodes(mesh, r, fr.face), face_nodes(mesh, top.0, top.1));
        bn.sort_unstable();
        tn.sort_unstable();
        if bn != tn || face_shape(mesh, r, fr.face) != face_shape(mesh, top.0, top.1) {
            return Err(CoreError::Invalid(format!(
                "face {} of {} (set `{set}`) and the face of {} across it share their corners but not their other nodes: the mesh is not conforming there",
                fr.face,
                describe(mesh, r),
                describe(mesh, top.0)
            )));
        }
        pairs.push(((r, fr.face), top));
    }
    Ok(pairs)
}

/// Split the nodes of the cut (module docs): returns node -> copy for the
/// nodes split, the top pieces moved to the copies.
fn split_nodes(
    mesh: &mut Mesh,
    pairs: &[FacePair],
    surface: &[usize],
    by_key: &HashMap<[usize; 4], Vec<(ElementRef, usize)>>,
) -> HashMap<usize, usize> {
    let cut_keys: HashSet<[usize; 4]> = pairs
        .iter()
        .map(|&((r, f), _)| corner_key(mesh, r, f))
        .collect();
    let on_surface: HashSet<usize> = surface.iter().copied().collect();
    // the elements around each node of the cut
    let mut around: HashMap<usize, Vec<ElementRef>> = HashMap::new();
    for (block, b) in mesh.blocks.iter().enumerate() {
        if !b.shape.is_solid() {
            continue;
        }
        for element in 0..b.len() {
            for &n in b.element(element) {
                if on_surface.contains(&n) {
                    around
                        .entry(n)
                        .or_default()
                        .push(ElementRef { block, element });
                }
            }
        }
    }
    // the top and bottom elements of the cut's faces at each node
    let mut sides: HashMap<usize, (Vec<ElementRef>, Vec<ElementRef>)> = HashMap::new();
    for &((br, bf), (tr, _)) in pairs {
        for n in face_nodes(mesh, br, bf) {
            let s = sides.entry(n).or_default();
            s.0.push(br);
            s.1.push(tr);
        }
    }
    let mut copy = HashMap::new();
    let mut moves: Vec<(ElementRef, usize, usize)> = Vec::new();
    for &n in surface {
        let elems = &around[&n];
        let piece = pieces(mesh, n, elems, &cut_keys, by_key);
        let (bottom, top) = &sides[&n];
        let top_pieces: HashSet<usize> = top.iter().map(|r| piece[r]).collect();
        if bottom.iter().any(|r| top_pieces.contains(&piece[r])) {
            continue; // joined around the tip: the interface closes here
        }
        let c = mesh.nodes.len() + copy.len();
        copy.insert(n, c);
        for r in elems.iter().filter(|r| top_pieces.contains(&piece[r])) {
            moves.push((*r, n, c));
        }
    }
    let mut order: Vec<(usize, usize)> = copy.iter().map(|(&n, &c)| (c, n)).collect();
    order.sort_unstable();
    for (_, n) in order {
        let p = mesh.nodes[n];
        mesh.nodes.push(p);
    }
    if !mesh.node_labels.is_empty() {
        let next = mesh.node_labels.iter().copied().max().unwrap_or(0) + 1;
        let n0 = mesh.nodes.len() - copy.len();
        mesh.node_labels.resize(n0, 0);
        mesh.node_labels.extend(next..next + copy.len());
    }
    for (r, n, c) in moves {
        let b = &mut mesh.blocks[r.block];
        let npe = b.nodes_per_element();
        for i in &mut b.connectivity[r.element * npe..(r.element + 1) * npe] {
            if *i == n {
                *i = c;
            }
        }
    }
    copy
}

/// The piece (a representative index) of each element around node `n`:
/// elements joined across faces through `n` that are not cut faces.
fn pieces(
    mesh: &Mesh,
    n: usize,
    elems: &[ElementRef],
    cut_keys: &HashSet<[usize; 4]>,
    by_key: &HashMap<[usize; 4], Vec<(ElementRef, usize)>>,
) -> HashMap<ElementRef, usize> {
    let index: HashMap<ElementRef, usize> =
        elems.iter().enumerate().map(|(i, &r)| (r, i)).collect();
    let mut parent: Vec<usize> = (0..elems.len()).collect();
    fn find(p: &mut [usize], mut i: usize) -> usize {
        while p[i] != i {
            p[i] = p[p[i]];
            i = p[i];
        }
        i
    }
    for (i, &r) in elems.iter().enumerate() {
        let shape = mesh.blocks[r.block].shape;
        for f in 0..shape.num_faces() {
            if !face_nodes(mesh, r, f).contains(&n) {
                continue;
            }
            let key = corner_key(mesh, r, f);
            if cut_keys.contains(&key) {
                continue;
            }
            for (o, _) in &by_key[&key] {
                if let Some(&j) = index.get(o) {
                    let (a, b) = (find(&mut parent, i), find(&mut parent, j));
                    parent[a] = b;
                }
            }
        }
    }
    elems
        .iter()
        .enumerate()
        .map(|(i, &r)| (r, find(&mut parent, i)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::generate::{box_mesh, BoxSpec};

    /// A plane box of 4 x 2 quadrilaterals, unit cells, and the face set
    /// `cut` of the edges at y = 1 from x = 0 to `to`.
    fn plate(shape: CellShape, to: usize) -> Mesh {
        let spec = BoxSpec {
            origin: [0.0; 3],
            size: [4.0, 2.0, 1.0],
            divisions: [4, 2, 1],
            shape,
            grading: [1.0; 3],
        };
        let mut m = box_mesh(&spec, "plate", "cpe4", "steel").unwrap();
        // the lower row's top edges (local edge 2 of a quadrilateral: y1)
        let cut: Vec<FaceRef> = (0..to)
            .map(|e| FaceRef {
                block: 0,
                element: e,
                face: 2,
            })
            .collect();
        m.face_sets.insert("cut".into(), cut);
        m
    }

    #[test]
    fn a_cut_through_splits_and_a_cut_inside_closes_at_its_tip() {
        // through: all 5 corner nodes of y = 1 are split
        let mut m = plate(CellShape::PlaneQuad4, 4);
        let n0 = m.nodes.len();
        let ins = insert_interface_along(&mut m, "cut", "bond", "glue").unwrap();
        assert_eq!((ins.elements, ins.duplicated_nodes), (4, 5));
        assert_eq!(m.nodes.len(), n0 + 5);
        assert_eq!(m.blocks[ins.block].shape, CellShape::LineInter4);
        // half way: x = 0, 1 split (the left end is on the boundary), x = 2
        // is the tip: whole
        let mut m = plate(CellShape::PlaneQuad4, 2);
        let ins = insert_interface_along(&mut m, "cut", "bond", "glue").unwrap();
        assert_eq!((ins.elements, ins.duplicated_nodes), (2, 2));
        let b = &m.blocks[ins.block];
        // the second element: of its bottom / top pairs one is the tip's
        // single node (x = 2), the other split (x = 1)
        let second = b.element(1);
        let whole: Vec<usize> = (0..2).filter(|&i| second[i] == second[2 + i]).collect();
        assert_eq!(whole.len(), 1, "{second:?}");
        assert_eq!(m.nodes[second[whole[0]]][0], 2.0);
        // quadratic: the mid-side nodes of the two cut edges are split too
        let mut m = plate(CellShape::PlaneQuad8, 2);
        let ins = insert_interface_along(&mut m, "cut", "bond", "glue").unwrap();
        assert_eq!((ins.elements, ins.duplicated_nodes), (2, 4));
    }

    #[test]
    fn faces_on_the_boundary_or_unknown_sets_are_refused() {
        let mut m = plate(CellShape::PlaneQuad4, 1);
        m.face_sets.insert(
            "edge".into(),
            vec![FaceRef {
                block: 0,
                element: 0,
                face: 0,
            }],
        );
        let before = m.clone();
        let e = insert_interface_along(&mut m, "edge", "bond", "glue").unwrap_err();
        assert!(e.to_string().contains("boundary of the mesh"), "{e}");
        let e = insert_interface_along(&mut m, "nope", "bond", "glue").unwrap_err();
        assert!(e.to_string().contains("unknown face set `nope`"), "{e}");
        assert_eq!(m, before);
    }
}
