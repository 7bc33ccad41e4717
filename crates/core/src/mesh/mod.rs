//! The mesh: nodes, element blocks and named node / element / face sets.
//!
//! Node and element numbers are 0-based internally; readers convert the
//! user's labels and keep them in [`Mesh::node_labels`] for messages.

pub mod along;
pub mod generate;
pub mod interface;
pub mod merge;

use crate::error::CoreError;
use crate::topology::CellShape;
use std::collections::BTreeMap;

/// A block of elements of one shape, element type and material (or law).
#[derive(Debug, Clone, PartialEq)]
pub struct ElementBlock {
    /// Block name (used in messages and output).
    pub name: String,
    /// Cell shape of every element of the block.
    pub shape: CellShape,
    /// Flat connectivity: element `e` uses `connectivity[e*n..(e+1)*n]`.
    pub connectivity: Vec<usize>,
    /// Registry key of the element type (`"h8"`, `"h20r"`, `"inter18"`).
    pub element_type: String,
    /// Name of the material (solids) or law (interfaces) of the block.
    pub material: String,
}

impl ElementBlock {
    /// Number of nodes per element.
    pub fn nodes_per_element(&self) -> usize {
        self.shape.num_nodes()
    }
    /// Number of elements.
    pub fn len(&self) -> usize {
        self.connectivity.len() / self.nodes_per_element()
    }
    /// True when the block has no element.
    pub fn is_empty(&self) -> bool {
        self.connectivity.is_empty()
    }
    /// Nodes of element `e`.
    pub fn element(&self, e: usize) -> &[usize] {
        let n = self.nodes_per_element();
        &self.connectivity[e * n..(e + 1) * n]
    }
}

/// Reference to one element: block index and index within the block.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct ElementRef {
    /// Index of the block in [`Mesh::blocks`].
    pub block: usize,
    /// Index of the element within that block (0-based).
    pub element: usize,
}

/// Reference to one face of a solid element (face ids as in
/// [`crate::topology::HEX_FACES`] / [`crate::topology::WEDGE_FACES`]: the
/// Abaqus S1..S6 / S1..S5 order, 0-based).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct FaceRef {
    /// Index of the solid block in [`Mesh::blocks`].
    pub block: usize,
    /// Index of the element within that block (0-based).
    pub element: usize,
    /// Face of the element, 0-based (0 = Abaqus S1).
    pub face: usize,
}

/// A finite-element mesh.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Mesh {
    /// Reference coordinates.
    pub nodes: Vec<[f64; 3]>,
    /// The user's node labels (e.g. `.inp` numbers); empty means `i + 1`.
    pub node_labels: Vec<usize>,
    /// Element blocks.
    pub blocks: Vec<ElementBlock>,
    /// Named node sets (sorted, unique node ids).
    pub node_sets: BTreeMap<String, Vec<usize>>,
    /// Named element sets.
    pub element_sets: BTreeMap<String, Vec<ElementRef>>,
    /// Named face sets (for pressures and interfaces).
    pub face_sets: BTreeMap<String, Vec<FaceRef>>,
    /// The user's element labels per block (`element_labels[block][e]`,
    /// e.g. `.inp` numbers); a missing block or element means the running
    /// number over all blocks, 1-based (see [`Mesh::element_label`]).
    pub element_labels: Vec<Vec<usize>>,
}

fn names<T>(m: &BTreeMap<String, T>) -> String {
    if m.is_empty() {
        "(none)".into()
    } else {
        m.keys().cloned().collect::<Vec<_>>().join(", ")
    }
}

impl Mesh {
    /// Total number of elements.
    pub fn num_elements(&self) -> usize {
        self.blocks.iter().map(ElementBlock::len).sum()
    }

    /// Label of node `i` for messages.
    pub fn node_label(&self, i: usize) -> usize {
        self.node_labels.get(i).copied().unwrap_or(i + 1)
    }

    /// Label of element `e` of block `block`: the user's
    /// ([`Mesh::element_labels`]) or the 1-based running number over the
    /// blocks in order.
    pub fn element_label(&self, block: usize, e: usize) -> usize {
        match self.element_labels.get(block).and_then(|l| l.get(e)) {
            Some(&l) => l,
            None => {
                let before: usize = self.blocks[..block.min(self.blocks.len())]
                    .iter()
                    .map(ElementBlock::len)
                    .sum();
                before + e + 1
            }
        }
    }

    /// Node set `name`, or an error listing the defined sets.
    pub fn node_set(&self, name: &str) -> Result<&[usize], CoreError> {
        self.node_sets
            .get(name)
            .map(Vec::as_slice)
            .ok_or_else(|| CoreError::UnknownSet {
                kind: "node",
                name: name.into(),
                valid: names(&self.node_sets),
            })
    }

    /// Element set `name`.
    pub fn element_set(&self, name: &str) -> Result<&[ElementRef], CoreError> {
        self.element_sets
            .get(name)
            .map(Vec::as_slice)
            .ok_or_else(|| CoreError::UnknownSet {
                kind: "element",
                name: name.into(),
                valid: names(&self.element_sets),
            })
    }

    /// Face set `name`.
    pub fn face_set(&self, name: &str) -> Result<&[FaceRef], CoreError> {
        self.face_sets
            .get(name)
            .map(Vec::as_slice)
            .ok_or_else(|| CoreError::UnknownSet {
                kind: "face",
                name: name.into(),
                valid: names(&self.face_sets),
            })
    }

    /// Global node ids of a face.
    pub fn face_nodes(&self, f: FaceRef) -> Vec<usize> {
        let b = &self.blocks[f.block];
        let conn = b.element(f.element);
        b.shape
            .face_nodes(f.face)
            .iter()
            .map(|&l| conn[l])
            .collect()
    }

    /// The key that identifies a face whatever element it is seen from: its
    /// corner node ids sorted, a triangle's padded with `usize::MAX` (so a
    /// triangle never matches a quadrilateral). `None` if `f.face` is not a
    /// face of the element's shape.
    pub fn face_key(&self, f: FaceRef) -> Option<[usize; 4]> {
        let b = &self.blocks[f.block];
        let corners = b.shape.face_shape_of(f.face)?.num_corners();
        let conn = b.element(f.element);
        let l = b.shape.face_nodes(f.face);
        let mut k = [usize::MAX; 4];
        for (x, &i) in k.iter_mut().zip(&l[..corners]) {
            *x = conn[i];
        }
        k.sort_unstable();
        Some(k)
    }

    /// Node set made of all the nodes of a face set.
    pub fn nodes_of_faces(&self, faces: &[FaceRef]) -> Vec<usize> {
        let mut v: Vec<usize> = faces.iter().flat_map(|&f| self.face_nodes(f)).collect();
        v.sort_unstable();
        v.dedup();
        v
    }

    /// Check connectivity indices and set contents.
    pub fn validate(&self) -> Result<(), CoreError> {
        let n = self.nodes.len();
        if let Some(i) = self
            .nodes
            .iter()
            .position(|p| !p.iter().all(|x| x.is_finite()))
        {
            return Err(CoreError::Invalid(format!(
                "node {} has coordinates {:?}; coordinates must be finite numbers",
                self.node_label(i),
                self.nodes[i]
            )));
        }
        for b in &self.blocks {
            for e in 0..b.len() {
                for &node in b.element(e) {
                    if node >= n {
                        return Err(CoreError::BadConnectivity {
                            block: b.name.clone(),
                            element: e,
                            node,
                            num_nodes: n,
                        });
                    }
                }
            }
        }
        for (name, set) in &self.node_sets {
            if let Some(&bad) = set.iter().find(|&&i| i >= n) {
                return Err(CoreError::Invalid(format!(
                    "node set `{name}` holds node {bad}, but the mesh has {n} nodes"
                )));
            }
        }
        Ok(())
    }

    /// Nodes used by at least one element.
    pub fn used_nodes(&self) -> Vec<bool> {
        let mut used = vec![false; self.nodes.len()];
        for b in &self.blocks {
            for &i in &b.connectivity {
                used[i] = true;
            }
        }
        used
    }
}
