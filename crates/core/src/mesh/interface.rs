//! Inserting zero-thickness interface elements between two element sets.
//!
//! [`insert_interface`] finds the faces shared by an element of a `bottom`
//! set and an element of a `top` set, duplicates the nodes of that surface
//! for the `top` side and adds one interface element (INTER8 / INTER16 /
//! INTER18 on quadrilateral faces, INTER6 / INTER12 on triangular ones) per
//! shared face. The sets typically come from
//! [`super::merge::merge`] (one element set per part), from Gmsh physical
//! volumes or from `.inp` ELSETs.
//!
//! # Conventions
//!
//! * Interface element = the shared face's nodes as seen from the `bottom`
//!   element (its [`crate::topology::HEX_FACES`] / [`crate::topology::WEDGE_FACES`]
//!   order, right-hand normal out of the bottom element), then the copies
//!   of the same nodes in the same order. Its normal therefore points from
//!   `bottom` to `top`.
//! * The interface shape is the one that matches the shared faces' shape
//!   ([`crate::topology::CellShape::matching_interface`]): `Quad4` ->
//!   INTER8, `Quad8` -> INTER16, `Quad9` -> INTER18, `Tri3` -> INTER6,
//!   `Tri6` -> INTER12. Faces are matched by shape, not by solid: the
//!   triangles between two wedge layers get INTER6 / INTER12, a wedge's
//!   quadrilateral side against a hexahedron's face (Wedge6 / Hex8: Quad4;
//!   Wedge15 / Hex20: Quad8) gets INTER8 / INTER16.
//! * One interface block has one shape, so a surface that mixes triangles
//!   and quadrilaterals of one order (hexahedra and wedges side by side on
//!   the same surface) gets two blocks, `NAME` (quadrilaterals) and
//!   `NAME.tri` (triangles), inserted together: the nodes on the seam
//!   between the two parts are duplicated once, for both (splitting the
//!   sets into two insertions would cut each side apart along the seam).
//!   Faces of different orders on one surface are refused.
//! * Only elements of `top` are moved to the copied nodes. Elements of
//!   `bottom` **and of every other set** keep the original nodes: a third
//!   body touching the surface stays attached to the bottom side.
//! * Node sets: only entries that are duplicated surface nodes `n` change
//!   (their copy is `n'`).
//!   - A set belongs to a body when its name is an element set `p` or starts
//!     with `p.` for an element set `p` (the longest such prefix wins): after
//!     [`super::merge::merge`], `upper.z0` belongs to part `upper`. Such a
//!     set holds `n` if the elements of `p` use `n`, and `n'` if they use
//!     `n'`. Hence the sets of the `top` part (`top.*`) have each `n`
//!     replaced by `n'`, those of the `bottom` part (`bottom.*`) and of a
//!     third body are unchanged.
//!   - Any other set (an `.inp` NSET, a Gmsh physical group, or one whose
//!     body uses neither `n` nor `n'`), for example a symmetry plane or a
//!     clamped end crossing the interface, holds both `n` and `n'`, so that
//!     a condition on it acts on both sides.
//! * Face sets and element sets need no change: they refer to
//!   (block, element, face), and the connectivity of the top elements was
//!   updated in place.

use super::{ElementBlock, ElementRef, FaceRef, Mesh};
use crate::error::CoreError;
use crate::topology::CellShape;
use std::collections::{HashMap, HashSet};

/// What [`insert_interface`] added.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct InterfaceInsertion {
    /// Index of the new interface block in [`Mesh::blocks`] (on a surface
    /// of triangles and quadrilaterals: the quadrilaterals' block).
    pub block: usize,
    /// Every new interface block: `[block]`, or on a mixed surface the
    /// quadrilaterals' block `name` and the triangles' block `name.tri`.
    pub blocks: Vec<usize>,
    /// Number of interface elements (one per shared face).
    pub elements: usize,
    /// Number of nodes duplicated (all nodes of the shared surface,
    /// mid-side and centre nodes included).
    pub duplicated_nodes: usize,
}

/// Elements of a set, checked (in range, solid), sorted and deduplicated.
fn solid_elements(mesh: &Mesh, set: &str) -> Result<Vec<ElementRef>, CoreError> {
    let mut v = mesh.element_set(set)?.to_vec();
    v.sort_unstable();
    v.dedup();
    for r in &v {
        let Some(b) = mesh.blocks.get(r.block) else {
            return Err(CoreError::Invalid(format!(
                "element set `{set}` refers to block {}, but the mesh has {} blocks",
                r.block,
                mesh.blocks.len()
            )));
        };
        if r.element >= b.len() {
            return Err(CoreError::Invalid(format!(
                "element set `{set}` refers to element {} of block `{}`, which has {} elements",
                r.element,
                b.name,
                b.len()
            )));
        }
        if !b.shape.is_solid() {
            return Err(CoreError::Invalid(format!(
                "element set `{set}` holds {} elements (block `{}`); interfaces join solid elements (hex8, hex20, hex27, wedge6, wedge15)",
                b.shape.name(),
                b.name
            )));
        }
    }
    Ok(v)
}

/// Sorted corner ids of face `f` of element `r`: the key that identifies a
/// face ([`Mesh::face_key`]; `f` is below the shape's face count).
pub(super) fn corner_key(mesh: &Mesh, r: ElementRef, f: usize) -> [usize; 4] {
    mesh.face_key(FaceRef {
        block: r.block,
        element: r.element,
        face: f,
    })
    .expect("face index below num_faces")
}

/// Shape of face `f` of element `r` (`f` below the shape's face count).
pub(super) fn face_shape(mesh: &Mesh, r: ElementRef, f: usize) -> CellShape {
    mesh.blocks[r.block]
        .shape
        .face_shape_of(f)
        .expect("face index below num_faces")
}

pub(super) fn face_nodes(mesh: &Mesh, r: ElementRef, f: usize) -> Vec<usize> {
    let b = &mesh.blocks[r.block];
    let conn = b.element(r.element);
    b.shape.face_nodes(f).iter().map(|&l| conn[l]).collect()
}

pub(super) fn describe(mesh: &Mesh, r: ElementRef) -> String {
    format!(
        "element {} of block `{}`",
        r.element, mesh.blocks[r.block].name
    )
}

/// Insert zero-thickness interface elements on every face shared by an
/// element of element set `bottom` and an element of element set `top`.
///
/// * Shared faces are found by their corner nodes (a hash map keyed by the
///   sorted corner ids: 4 for quadrilaterals, 3 for triangles), so the two
///   sides must already share nodes (e.g. after [`super::merge::merge`]).
///   Both faces must have the same shape and the same nodes (same order of
///   interpolation on both sides; the solids may differ, e.g. a wedge's
///   quadrilateral side against a hexahedron's face).
/// * Every node of the shared surface (corners, mid-sides, centres) gets a
///   copy at the same position (appended to [`Mesh::nodes`]; labels, if
///   any, continue after the largest label); elements of `top`, and only
///   those, are renumbered to the copies.
/// * One interface element per shared face, appended as a new block named
///   `name` with shape `face_shape.matching_interface()` (element type key
///   `"inter8"`, `"inter16"`, `"inter18"`, `"inter6"` or `"inter12"`) and
///   material `law`; node order and normal as in the [module docs](self)
///   (bottom face, then top copies; normal from bottom to top). A surface
///   of triangles and quadrilaterals of one order (wedges next to
///   hexahedra: Tri3 with Quad4, Tri6 with Quad8) gets two blocks, `name`
///   for the quadrilaterals and `name.tri` for the triangles; they share
///   the duplicated nodes along the seam, so the interface is one surface.
/// * New sets: element set `name` (every interface element), node sets
///   `name.bottom` (original surface nodes) and `name.top` (their copies).
///   Existing node sets follow the rule in the [module docs](self).
///
/// Errors ([`CoreError`]): unknown sets, sets that overlap or hold
/// non-solid elements, names already in use, sets that share no face,
/// mismatched element orders across the surface, non-conforming faces
/// (same corners, different mid-side nodes), non-manifold surfaces, or a
/// surface mixing element orders.
/// On error the mesh is unchanged.
pub fn insert_interface(
    mesh: &mut Mesh,
    bottom: &str,
    top: &str,
    name: &str,
    law: &str,
) -> Result<InterfaceInsertion, CoreError> {
    let sides = Sides { bottom, top, name };
    sides.check_names(mesh)?;
    let bot_el = solid_elements(mesh, bottom)?;
    let top_el = solid_elements(mesh, top)?;
    let top_lookup: HashSet<ElementRef> = top_el.iter().copied().collect();
    if let Some(&r) = bot_el.iter().find(|r| top_lookup.contains(r)) {
        return Err(CoreError::Invalid(format!(
            "element sets `{bottom}` and `{top}` overlap ({} is in both); an interface needs two disjoint sets",
            describe(mesh, r)
        )));
    }
    let shared = sides.shared_faces(mesh, &bot_el, &top_el)?;
    if shared.is_empty() {
        return Err(sides.no_shared_face(mesh, &bot_el, &top_el));
    }
    let shapes = sides.face_shapes(mesh, &shared)?;

    // --- all checks passed: modify the mesh ---
    let bottom_faces: Vec<Vec<usize>> = shared
        .iter()
        .map(|&(r, f)| face_nodes(mesh, r, f))
        .collect();
    let n0 = mesh.nodes.len();
    let (surface, copy) = duplicate_surface(mesh, &bottom_faces, &top_el);
    update_node_sets(mesh, &copy);
    let elements = bottom_faces.len();
    let blocks = add_interface_blocks(mesh, &shapes, &shared, &bottom_faces, &copy, name, law);
    let top = (n0..n0 + surface.len()).collect();
    finish_insertion(mesh, name, surface, top, blocks, elements, n0)
}

/// The node sets `name.bottom` (`surface`) and `name.top` (`top`), the
/// mesh checked, and the record of an insertion that added the nodes from
/// `n0` on.
pub(super) fn finish_insertion(
    mesh: &mut Mesh,
    name: &str,
    surface: Vec<usize>,
    top: Vec<usize>,
    blocks: Vec<usize>,
    elements: usize,
    n0: usize,
) -> Result<InterfaceInsertion, CoreError> {
    mesh.node_sets.insert(format!("{name}.top"), top);
    mesh.node_sets.insert(format!("{name}.bottom"), surface);
    mesh.validate()?;
    Ok(InterfaceInsertion {
        block: blocks[0],
        blocks,
        elements,
        duplicated_nodes: mesh.nodes.len() - n0,
    })
}

/// The element sets and the name of one insertion (for the checks and
/// their messages).
struct Sides<'s> {
    bottom: &'s str,
    top: &'s str,
    name: &'s str,
}

/// No element set, block or node set (`name.bottom`, `name.top`) of the
/// names an interface `name` creates exists yet.
pub(super) fn check_new_names(mesh: &Mesh, name: &str) -> Result<(), CoreError> {
    if mesh.element_sets.contains_key(name) || mesh.blocks.iter().any(|b| b.name == name) {
        return Err(CoreError::Invalid(format!(
            "interface name `{name}` is already used by an element set or block; choose another name"
        )));
    }
    for s in ["bottom", "top"] {
        let n = format!("{name}.{s}");
        if mesh.node_sets.contains_key(&n) {
            return Err(CoreError::Invalid(format!(
                "interface `{name}` would create node set `{n}`, which already exists; choose another name"
            )));
        }
    }
    Ok(())
}

impl Sides<'_> {
    /// Two different sets, a non-empty name, and no element set, block or
    /// node set (`name.bottom`, `name.top`) of the names to be created.
    fn check_names(&self, mesh: &Mesh) -> Result<(), CoreError> {
        let Sides { bottom, top, name } = *self;
        if bottom == top {
            return Err(CoreError::Invalid(format!(
                "interface `{name}`: bottom and top are the same element set `{bottom}`; give two different sets"
            )));
        }
        if name.is_empty() {
            return Err(CoreError::Invalid(format!(
                "interface between `{bottom}` and `{top}` needs a non-empty name"
            )));
        }
        check_new_names(mesh, name)
    }

    /// The faces `(bottom element, face)` shared by a bottom and a top
    /// element, in the order of the bottom elements and their faces,
    /// matched by corner key; each must be shared by exactly two elements,
    /// with the same face shape and the same nodes on both sides.
    fn shared_faces(
        &self,
        mesh: &Mesh,
        bot_el: &[ElementRef],
        top_el: &[ElementRef],
    ) -> Result<Vec<(ElementRef, usize)>, CoreError> {
        let Sides { bottom, top, name } = *self;
        // faces of the top elements by corner key (internal top faces appear twice)
        let mut top_faces: HashMap<[usize; 4], Vec<(ElementRef, usize)>> = HashMap::new();
        for &r in top_el {
            for f in 0..mesh.blocks[r.block].shape.num_faces() {
                top_faces
                    .entry(corner_key(mesh, r, f))
                    .or_default()
                    .push((r, f));
            }
        }
        let mut shared: Vec<(ElementRef, usize)> = Vec::new();
        let mut used_keys: HashSet<[usize; 4]> = HashSet::new();
        for &r in bot_el {
            for f in 0..mesh.blocks[r.block].shape.num_faces() {
                let key = corner_key(mesh, r, f);
                let Some(cands) = top_faces.get(&key) else {
                    continue;
                };
                let (tr, tf) = cands[0];
                if cands.len() > 1 || !used_keys.insert(key) {
                    return Err(CoreError::Invalid(format!(
                        "face {f} of {} (set `{bottom}`) is shared by more than two elements of `{bottom}`/`{top}` (non-manifold surface, or duplicated elements); cannot insert interface `{name}`",
                        describe(mesh, r)
                    )));
                }
                let (bf, tf_shape) = (face_shape(mesh, r, f), face_shape(mesh, tr, tf));
                if bf != tf_shape {
                    let (a, b) = (
                        mesh.blocks[r.block].shape.name(),
                        mesh.blocks[tr.block].shape.name(),
                    );
                    return Err(CoreError::Invalid(format!(
                        "mismatched element orders across `{bottom}`/`{top}`: {a} faces against {b} faces ({} against {}); interfaces need the same solid order on both sides ({} against {})",
                        bf.name(),
                        tf_shape.name(),
                        describe(mesh, r),
                        describe(mesh, tr)
                    )));
                }
                let mut bn = face_nodes(mesh, r, f);
                let mut tn = face_nodes(mesh, tr, tf);
                bn.sort_unstable();
                tn.sort_unstable();
                if bn != tn {
                    return Err(CoreError::Invalid(format!(
                        "face {f} of {} (set `{bottom}`) and face {tf} of {} (set `{top}`) share their corners but not their mid-side/centre nodes; the mesh is not conforming there (merge the parts with a tolerance?)",
                        describe(mesh, r),
                        describe(mesh, tr)
                    )));
                }
                shared.push((r, f));
            }
        }
        Ok(shared)
    }

    /// The error for two sets without a shared face: whether they touch at
    /// a few nodes or not at all (with a hint).
    fn no_shared_face(
        &self,
        mesh: &Mesh,
        bot_el: &[ElementRef],
        top_el: &[ElementRef],
    ) -> CoreError {
        let Sides { bottom, top, name } = *self;
        let bot_nodes: HashSet<usize> = bot_el
            .iter()
            .flat_map(|r| mesh.blocks[r.block].element(r.element).iter().copied())
            .collect();
        let common: HashSet<usize> = top_el
            .iter()
            .flat_map(|r| mesh.blocks[r.block].element(r.element).iter().copied())
            .filter(|i| bot_nodes.contains(i))
            .collect();
        let faces = |v: &[ElementRef]| -> usize {
            v.iter()
                .map(|r| mesh.blocks[r.block].shape.num_faces())
                .sum()
        };
        let touch = if common.is_empty() {
            let hint = if mesh.blocks.iter().any(|b| b.shape.is_interface()) {
                " (an interface may already separate them, or the parts were not merged)"
            } else {
                " (were the parts merged?)"
            };
            format!("they have no node in common{hint}")
        } else {
            format!(
                "they touch at {} node(s) only (an edge or a corner); an interface needs whole faces in common",
                common.len()
            )
        };
        CoreError::Invalid(format!(
            "element sets `{bottom}` ({} elements, {} faces) and `{top}` ({} elements, {} faces) share no face, so interface `{name}` would be empty: {touch}",
            bot_el.len(),
            faces(bot_el),
            top_el.len(),
            faces(top_el)
        ))
    }

    /// The face shapes of the shared faces, quadrilaterals first: one
    /// shape, or triangles and quadrilaterals of one order (wedges next to
    /// hexahedra), each with a matching interface element; the triangles'
    /// block name `name.tri` must be free.
    fn face_shapes(
        &self,
        mesh: &Mesh,
        shared: &[(ElementRef, usize)],
    ) -> Result<Vec<CellShape>, CoreError> {
        let Sides { bottom, top, name } = *self;
        let (r0, f0) = shared[0];
        let shape = face_shape(mesh, r0, f0);
        let conforming = |a: CellShape, b: CellShape| {
            a == b
                || matches!(
                    (a, b),
                    (CellShape::Tri3, CellShape::Quad4)
                        | (CellShape::Quad4, CellShape::Tri3)
                        | (CellShape::Tri6, CellShape::Quad8)
                        | (CellShape::Quad8, CellShape::Tri6)
                )
        };
        if let Some(&(r, f)) = shared
            .iter()
            .find(|&&(r, f)| !conforming(face_shape(mesh, r, f), shape))
        {
            let other = face_shape(mesh, r, f);
            return Err(CoreError::Invalid(format!(
                "the surface between `{bottom}` and `{top}` mixes {} faces ({} elements, e.g. {}) and {} faces ({} elements, e.g. {}); interface `{name}` cannot mix element orders: insert one interface per element order (split the sets)",
                shape.name(),
                mesh.blocks[r0.block].shape.name(),
                describe(mesh, r0),
                other.name(),
                mesh.blocks[r.block].shape.name(),
                describe(mesh, r)
            )));
        }
        let mut shapes: Vec<CellShape> = Vec::with_capacity(2);
        for &(r, f) in shared {
            let s = face_shape(mesh, r, f);
            if !shapes.contains(&s) {
                shapes.push(s);
            }
        }
        shapes.sort_by_key(|s| std::cmp::Reverse(s.num_corners()));
        let mixed_name = format!("{name}.tri");
        if shapes.len() > 1
            && (mesh.element_sets.contains_key(&mixed_name)
                || mesh.blocks.iter().any(|b| b.name == mixed_name))
        {
            return Err(CoreError::Invalid(format!(
                "interface `{name}` mixes triangles and quadrilaterals and would put the triangles in block `{mixed_name}`, a name already in use; choose another name"
            )));
        }
        for s in &shapes {
            if s.matching_interface().is_none() {
                return Err(CoreError::Invalid(format!(
                    "no interface element matches {} faces",
                    s.name()
                )));
            }
        }
        Ok(shapes)
    }
}

/// Copy every node of the surface (the nodes of `bottom_faces`) at the same
/// position (labels continue after the largest), and move the elements of
/// `top_el` to the copies. Returns the surface nodes (sorted) and the map
/// node -> copy.
fn duplicate_surface(
    mesh: &mut Mesh,
    bottom_faces: &[Vec<usize>],
    top_el: &[ElementRef],
) -> (Vec<usize>, HashMap<usize, usize>) {
    let mut surface: Vec<usize> = bottom_faces.iter().flatten().copied().collect();
    surface.sort_unstable();
    surface.dedup();
    let n0 = mesh.nodes.len();
    let copy: HashMap<usize, usize> = surface
        .iter()
        .enumerate()
        .map(|(k, &i)| (i, n0 + k))
        .collect();
    for &i in &surface {
        let p = mesh.nodes[i];
        mesh.nodes.push(p);
    }
    if !mesh.node_labels.is_empty() {
        let next = mesh.node_labels.iter().copied().max().unwrap_or(0) + 1;
        mesh.node_labels.resize(n0, 0);
        mesh.node_labels.extend(next..next + surface.len());
    }
    for r in top_el {
        let b = &mut mesh.blocks[r.block];
        let n = b.nodes_per_element();
        for i in &mut b.connectivity[r.element * n..(r.element + 1) * n] {
            if let Some(&c) = copy.get(i) {
                *i = c;
            }
        }
    }
    (surface, copy)
}

/// One interface block per face shape (`name`, then `name.tri`): each
/// shared face's bottom nodes followed by their copies; element set `name`
/// holds them all. Returns the new blocks.
pub(super) fn add_interface_blocks(
    mesh: &mut Mesh,
    shapes: &[CellShape],
    shared: &[(ElementRef, usize)],
    bottom_faces: &[Vec<usize>],
    copy: &HashMap<usize, usize>,
    name: &str,
    law: &str,
) -> Vec<usize> {
    let mut blocks = Vec::with_capacity(shapes.len());
    let mut set = Vec::with_capacity(bottom_faces.len());
    for (k, &fshape) in shapes.iter().enumerate() {
        let ishape = fshape.matching_interface().expect("checked above");
        let mut connectivity = Vec::new();
        for (face, &(r, f)) in bottom_faces.iter().zip(shared) {
            if face_shape(mesh, r, f) == fshape {
                connectivity.extend_from_slice(face);
                connectivity.extend(face.iter().map(|i| copy[i]));
            }
        }
        let block = mesh.blocks.len();
        let n = connectivity.len() / ishape.num_nodes();
        set.extend((0..n).map(|element| ElementRef { block, element }));
        mesh.blocks.push(ElementBlock {
            name: if k == 0 {
                name.to_string()
            } else {
                format!("{name}.tri")
            },
            shape: ishape,
            connectivity,
            element_type: ishape.name().to_string(),
            material: law.to_string(),
        });
        blocks.push(block);
    }
    mesh.element_sets.insert(name.to_string(), set);
    blocks
}

/// The element set a node set belongs to: the set's own name or its longest
/// prefix before a `.` that names an element set (`upper.z0` -> `upper`).
fn owner<'a>(mesh: &Mesh, set: &'a str) -> Option<&'a str> {
    if mesh.element_sets.contains_key(set) {
        return Some(set);
    }
    let mut end = set.len();
    while let Some(dot) = set[..end].rfind('.') {
        if mesh.element_sets.contains_key(&set[..dot]) {
            return Some(&set[..dot]);
        }
        end = dot;
    }
    None
}

/// Apply the node-set rule of the module docs after the top elements were
/// renumbered; `copy` maps each duplicated node to its copy.
pub(super) fn update_node_sets(mesh: &mut Mesh, copy: &HashMap<usize, usize>) {
    let names: Vec<String> = mesh.node_sets.keys().cloned().collect();
    // per owner element set: the duplicated nodes and copies its elements use
    let mut used_by: HashMap<String, HashSet<usize>> = HashMap::new();
    let copies: HashSet<usize> = copy.values().copied().collect();
    for s in names {
        if !mesh.node_sets[&s].iter().any(|i| copy.contains_key(i)) {
            continue;
        }
        let own = owner(mesh, &s).map(str::to_string);
        if let Some(o) = &own {
            if !used_by.contains_key(o) {
                let mut used = HashSet::new();
                for r in &mesh.element_sets[o] {
                    let Some(b) = mesh.blocks.get(r.block) else {
                        continue;
                    };
                    if r.element < b.len() {
                        used.extend(
                            b.element(r.element)
                                .iter()
                                .filter(|i| copy.contains_key(i) || copies.contains(i)),
                        );
                    }
                }
                used_by.insert(o.clone(), used);
            }
        }
        let set = mesh.node_sets.get_mut(&s).expect("listed above");
        let mut out = Vec::with_capacity(set.len());
        for &i in set.iter() {
            let Some(&c) = copy.get(&i) else {
                out.push(i);
                continue;
            };
            match own.as_ref().map(|o| &used_by[o]) {
                Some(used) if used.contains(&i) || used.contains(&c) => {
                    if used.contains(&i) {
                        out.push(i);
                    }
                    if used.contains(&c) {
                        out.push(c);
                    }
                }
                // the owner uses neither side (or there is no owner): both
                _ => {
                    out.push(i);
                    out.push(c);
                }
            }
        }
        out.sort_unstable();
        out.dedup();
        *set = out;
    }
}

/// The (bottom node, top node) pairs of interface block `block`, sorted and
/// unique: node `i` of each element's bottom side with node `i` of its top
/// side. Empty if `block` does not exist or is not an interface block.
pub fn interface_pairs(mesh: &Mesh, block: usize) -> Vec<(usize, usize)> {
    let Some(b) = mesh.blocks.get(block) else {
        return Vec::new();
    };
    if !b.shape.is_interface() {
        return Vec::new();
    }
    let half = b.nodes_per_element() / 2;
    let mut v: Vec<(usize, usize)> = (0..b.len())
        .flat_map(|e| {
            let c = b.element(e);
            (0..half).map(move |i| (c[i], c[half + i]))
        })
        .collect();
    v.sort_unstable();
    v.dedup();
    v
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::generate::{box_mesh, BoxSpec};
    use crate::mesh::merge::merge;

    fn two_cubes(shape: CellShape) -> Mesh {
        let lo = box_mesh(&BoxSpec::new([1.0; 3], [1; 3], shape), "b", "h", "m").unwrap();
        let mut s = BoxSpec::new([1.0; 3], [1; 3], shape);
        s.origin = [0.0, 0.0, 1.0];
        let up = box_mesh(&s, "b", "h", "m").unwrap();
        merge(vec![("lo".into(), lo), ("up".into(), up)], 1e-9).unwrap()
    }

    #[test]
    fn node_set_rule() {
        let mut m = two_cubes(CellShape::Hex8);
        m.node_sets
            .insert("stack".into(), (0..m.nodes.len()).collect());
        let before_lo = m.node_sets["lo.z1"].clone();
        let ins = insert_interface(&mut m, "lo", "up", "i", "penalty").unwrap();
        assert_eq!(ins.duplicated_nodes, 4);
        // bottom part's sets unchanged; top part's sets moved to the copies
        assert_eq!(m.node_sets["lo.z1"], before_lo);
        assert_eq!(m.node_sets["up.z0"], m.node_sets["i.top"]);
        // neutral sets hold both sides
        assert_eq!(m.node_sets["stack"].len(), m.nodes.len());
        assert_eq!(interface_pairs(&m, ins.block).len(), 4);
        assert!(interface_pairs(&m, 0).is_empty());
        // second insertion: nothing shared any more, mesh unchanged
        let copy = m.clone();
        let err = insert_interface(&mut m, "lo", "up", "j", "penalty").unwrap_err();
        assert!(err.to_string().contains("share no face"), "{err}");
        assert_eq!(m, copy);
    }

    #[test]
    fn rejects_bad_names() {
        let mut m = two_cubes(CellShape::Hex8);
        assert!(insert_interface(&mut m, "lo", "lo", "i", "l").is_err());
        assert!(insert_interface(&mut m, "lo", "nope", "i", "l").is_err());
        assert!(insert_interface(&mut m, "lo", "up", "lo", "l").is_err());
    }
}
