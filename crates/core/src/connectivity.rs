//! Parts of a model that no support holds: connected components of the
//! element graph and the rigid-body modes their prescribed dofs leave free.
//!
//! A part with a free rigid-body mode makes the tangent singular; a direct
//! back end then either stops at a zero pivot or (worse) works on a matrix
//! of round-off. This module finds such parts before any factorisation and
//! names them.
//!
//! # Algorithm
//!
//! 1. **Components.** Union-find over the nodes. Every solid (or any
//!    element that is not an interface) joins all its nodes. An interface
//!    element joins its nodes when its law carries stiffness in the initial
//!    state in some direction `[s1, s2, n]`
//!    ([`Element::interface_stiffness`]): a bonded cohesive law does, and so
//!    does a contact law (`[0, 0, k]`, stiff in compression). The check is
//!    for parts with no connection at all, and never refuses a model that
//!    might run: a part held only by contact is counted as held (its
//!    in-plane modes are free until friction or a load closes it, which
//!    the solver reports if it matters). Only an interface whose law has
//!    no stiffness at all (a precrack with no law, `[0, 0, 0]`) does not
//!    join its faces. Each linear
//!    equation (MPC) joins the nodes of its dependent dof and of its terms.
//!    Nodes that belong to no element are skipped.
//! 2. **Constrained dofs of a component.** A dof is constrained when it is
//!    prescribed (Dirichlet, [`CONSTRAINED`] in [`DofMap::eq`], orphans
//!    aside) or is the dependent dof of an equation. Counting every
//!    dependent dof as constrained never reports a part that is held; it
//!    can miss a part whose equations tie it only to itself.
//! 3. **Free modes.** With `x̄` the centroid of the component's nodes and
//!    `L` its size, the six rigid-body modes evaluated at node `i` are
//!    `t_a = e_a` and `r_a = e_a × (x_i - x̄) / L` (`a = x, y, z`). Let `R`
//!    be the matrix whose rows are the modes' components at the constrained
//!    dofs (one row per constrained dof, six columns). The modes left free
//!    are the null space of `R`, i.e. the eigenvectors of `G = RᵀR` (6×6)
//!    whose eigenvalue is below `1e-10 · max(1, λ_max)`. A mode of the
//!    canonical six is named free when its projection onto that null space
//!    is at least 0.99 of its length; null directions that are no canonical
//!    mode are counted as "combined" modes. Plane models (two dofs per
//!    node, or plane elements only) use the modes `t_x, t_y, r_z` only,
//!    axisymmetric ones `t_y` (along the axis) only.
//!
//! The cost is one pass over the connectivity (near-linear union-find) and
//! one pass over the constrained dofs.

use crate::dof::CONSTRAINED;
use crate::model::Model;
use nalgebra::{SMatrix, SymmetricEigen};

/// Names of the six rigid-body modes in the order of the columns of `R`.
const MODE_NAMES: [&str; 6] = [
    "translation x",
    "translation y",
    "translation z",
    "rotation about x",
    "rotation about y",
    "rotation about z",
];

/// Elements of one block that belong to a floating part.
#[derive(Debug, Clone, PartialEq)]
pub struct BlockShare {
    /// Block name.
    pub block: String,
    /// Number of the block's elements in the part.
    pub elements: usize,
    /// Number of elements of the block.
    pub block_elements: usize,
    /// First and last element of the part in the model's 1-based element
    /// numbering (blocks in order, as in the outputs).
    pub first: usize,
    /// See `first`.
    pub last: usize,
}

/// A connected part of the model with free rigid-body modes.
#[derive(Debug, Clone, PartialEq)]
pub struct FloatingPart {
    /// The blocks (or parts of blocks) it consists of.
    pub blocks: Vec<BlockShare>,
    /// Number of nodes.
    pub nodes: usize,
    /// The canonical modes left free (`"translation x"`, ...).
    pub free_modes: Vec<&'static str>,
    /// Free directions that are no canonical mode (combinations).
    pub combined_modes: usize,
}

impl FloatingPart {
    /// "block `a` (elements 1-200)" or "elements 5-9 (3 of 10) of block `a`".
    pub fn what(&self) -> String {
        let parts: Vec<String> = self
            .blocks
            .iter()
            .map(|b| {
                if b.elements == b.block_elements {
                    format!("block `{}` (elements {}-{})", b.block, b.first, b.last)
                } else {
                    format!(
                        "elements {}-{} ({} of {}) of block `{}`",
                        b.first, b.last, b.elements, b.block_elements, b.block
                    )
                }
            })
            .collect();
        parts.join(" with ")
    }

    /// The free modes, as words.
    pub fn modes(&self) -> String {
        let mut m = self.free_modes.join(", ");
        if self.combined_modes > 0 {
            if !m.is_empty() {
                m.push_str(" and ");
            }
            m.push_str(&format!(
                "{} combined rigid-body mode(s)",
                self.combined_modes
            ));
        }
        m
    }
}

impl std::fmt::Display for FloatingPart {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} is connected to no support: free {} (fix enough displacements on it, or connect it to a supported part)",
            self.what(),
            self.modes()
        )
    }
}

fn find(p: &mut [usize], mut i: usize) -> usize {
    while p[i] != i {
        p[i] = p[p[i]];
        i = p[i];
    }
    i
}

fn union(p: &mut [usize], a: usize, b: usize) {
    let (ra, rb) = (find(p, a), find(p, b));
    if ra != rb {
        p[rb] = ra;
    }
}

/// Union-find roots of the nodes (step 1 of the module doc) and whether
/// each node belongs to an element.
fn components(model: &Model) -> (Vec<usize>, Vec<bool>) {
    let n = model.mesh.nodes.len();
    let mut parent: Vec<usize> = (0..n).collect();
    let mut used = vec![false; n];
    for (b, el) in model.mesh.blocks.iter().zip(&model.elements) {
        let joins = match el.interface_stiffness() {
            None => true,
            Some(k) => k.iter().any(|v| *v > 0.0),
        };
        let k = b.nodes_per_element().max(1);
        for cell in b.connectivity.chunks(k) {
            for &v in cell {
                used[v] = true;
            }
            if joins {
                for &v in &cell[1..] {
                    union(&mut parent, cell[0], v);
                }
            }
        }
    }
    let dpn = dofs_per_node(model);
    for (d, terms) in model.dofs.dependents.iter() {
        for &(t, _) in terms {
            union(&mut parent, d / dpn, t / dpn);
        }
    }
    let roots = (0..n).map(|i| find(&mut parent, i)).collect();
    (roots, used)
}

fn dofs_per_node(model: &Model) -> usize {
    (model.dofs.num_dofs() / model.dofs.num_nodes.max(1)).max(1)
}

/// Rows of `R` for dof component `c` at relative position `r` (module doc).
fn mode_row(c: usize, r: [f64; 3]) -> [f64; 6] {
    let mut row = [0.0; 6];
    row[c] = 1.0;
    // (e_a × r)_c for a = x, y, z
    let [x, y, z] = r;
    let rot = [[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]];
    for a in 0..3 {
        row[3 + a] = rot[a][c];
    }
    row
}

/// Free rigid-body modes of a component from its Gram matrix `G = RᵀR`.
fn free_modes(g: &SMatrix<f64, 6, 6>, active: &[usize]) -> (Vec<&'static str>, usize) {
    let eig = SymmetricEigen::new(*g);
    let lmax = eig.eigenvalues.iter().fold(1.0f64, |m, v| m.max(*v));
    let null: Vec<usize> = (0..6)
        .filter(|&i| eig.eigenvalues[i] <= 1e-10 * lmax)
        .collect();
    let mut named = Vec::new();
    for &m in active {
        let proj: f64 = null.iter().map(|&j| eig.eigenvectors[(m, j)].powi(2)).sum();
        if proj >= 0.98 {
            named.push(MODE_NAMES[m]);
        }
    }
    // inactive modes (2D) are pinned by the caller: not in the null space
    (named.clone(), null.len().saturating_sub(named.len()))
}

/// The rigid-body modes of the model's kinematics: all six in 3D; `t_x,
/// t_y, r_z` for a plane model (two dofs per node, or only plane
/// elements); `t_y` alone for an axisymmetric one (a radial motion strains
/// the ring).
fn active_modes(model: &Model, dpn: usize) -> &'static [usize] {
    let plane = dpn == 2 || model.mesh.blocks.iter().all(|b| b.shape.dimension() == 2);
    let axisymmetric = model
        .elements
        .iter()
        .any(|e| e.plane_width() == Some(crate::element::PlaneWidth::Axisymmetric));
    match (plane, axisymmetric) {
        (true, true) => &[1],
        (true, false) => &[0, 1, 5],
        _ => &[0, 1, 2, 3, 4, 5],
    }
}

/// The connected parts of `model` that its prescribed dofs do not hold
/// (empty when every part is supported). See the module doc.
pub fn floating_parts(model: &Model) -> Vec<FloatingPart> {
    let (roots, used) = components(model);
    let n = roots.len();
    let dpn = dofs_per_node(model);
    // component index per root
    let mut comp = vec![usize::MAX; n];
    let mut count = 0;
    for i in 0..n {
        if used[i] && comp[roots[i]] == usize::MAX {
            comp[roots[i]] = count;
            count += 1;
        }
    }
    if count == 0 {
        return Vec::new();
    }
    let cid = |i: usize| comp[roots[i]];
    let mut centre = vec![[0.0f64; 3]; count];
    let mut nodes = vec![0usize; count];
    let (mut lo, mut hi) = (vec![[f64::MAX; 3]; count], vec![[f64::MIN; 3]; count]);
    for i in (0..n).filter(|&i| used[i]) {
        let (c, x) = (cid(i), model.mesh.nodes[i]);
        nodes[c] += 1;
        for a in 0..3 {
            centre[c][a] += x[a];
            lo[c][a] = lo[c][a].min(x[a]);
            hi[c][a] = hi[c][a].max(x[a]);
        }
    }
    let mut size = vec![1.0f64; count];
    for c in 0..count {
        let l = (0..3).map(|a| hi[c][a] - lo[c][a]).fold(0.0, f64::max);
        size[c] = if l > 0.0 { l } else { 1.0 };
        for a in 0..3 {
            centre[c][a] /= nodes[c] as f64;
        }
    }
    let mut gram = vec![SMatrix::<f64, 6, 6>::zeros(); count];
    let dofs = &model.dofs;
    for d in 0..dofs.num_dofs() {
        let (i, c) = (d / dpn, d % dpn);
        let prescribed = dofs.eq[d] == CONSTRAINED && !dofs.orphan.get(d).copied().unwrap_or(false);
        if !used[i] || !(prescribed || dofs.dependents.contains(d)) {
            continue;
        }
        let k = cid(i);
        let r: [f64; 3] =
            std::array::from_fn(|a| (model.mesh.nodes[i][a] - centre[k][a]) / size[k]);
        let row = SMatrix::<f64, 1, 6>::from_row_slice(&mode_row(c, r));
        gram[k] += row.transpose() * row;
    }
    let active = active_modes(model, dpn);
    if active.len() < 6 {
        // modes a 2D model does not have: pin them so that they are not free
        for g in &mut gram {
            for m in (0..6).filter(|m| !active.contains(m)) {
                g[(m, m)] += 1.0;
            }
        }
    }
    let mut parts: Vec<Option<FloatingPart>> = vec![None; count];
    for c in 0..count {
        let (named, combined) = free_modes(&gram[c], active);
        if !named.is_empty() || combined > 0 {
            parts[c] = Some(FloatingPart {
                blocks: Vec::new(),
                nodes: nodes[c],
                free_modes: named,
                combined_modes: combined,
            });
        }
    }
    name_blocks(model, &roots, &comp, &mut parts);
    parts.into_iter().flatten().collect()
}

/// Fill in the blocks and element ranges of each floating part.
fn name_blocks(model: &Model, roots: &[usize], comp: &[usize], parts: &mut [Option<FloatingPart>]) {
    let mut offset = 0;
    for b in &model.mesh.blocks {
        let k = b.nodes_per_element().max(1);
        for (e, cell) in b.connectivity.chunks(k).enumerate() {
            let c = comp[roots[cell[0]]];
            let Some(part) = parts[c].as_mut() else {
                continue;
            };
            let number = offset + e + 1;
            match part.blocks.last_mut() {
                Some(s) if s.block == b.name => {
                    s.elements += 1;
                    s.last = number;
                }
                _ => part.blocks.push(BlockShare {
                    block: b.name.clone(),
                    elements: 1,
                    block_elements: b.len(),
                    first: number,
                    last: number,
                }),
            }
        }
        offset += b.len();
    }
}

/// `Err` naming every floating part (one per line) when there is one.
pub fn check_supported(model: &Model) -> Result<(), crate::CoreError> {
    let parts = floating_parts(model);
    if parts.is_empty() {
        return Ok(());
    }
    let lines: Vec<String> = parts.iter().map(|p| p.to_string()).collect();
    Err(crate::CoreError::Unsupported(lines.join("; ")))
}
