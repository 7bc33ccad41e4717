//! Runs over several processes (MPI ranks), seen from the core: the
//! collective operations a run needs ([`Collective`]), installed once per
//! process ([`install`]), and the partition of the elements among the ranks
//! ([`partition_elements`]).
//!
//! The scheme is *replicated data, distributed work*. Every rank reads the
//! whole input and keeps the whole mesh, the displacement vector and the
//! integration-point state; the elements are split among the ranks, and an
//! assembly ([`crate::assembly::Assembler::assemble`]) computes only the
//! rank's own elements, then
//! - sums the internal forces over the ranks (every rank gets the same
//!   full vector, bit for bit: [`Collective::sum_in_place`] reduces in a
//!   fixed order), and
//! - copies each element's new trial state from its owner to every rank
//!   (the other ranks' slices are zeroed before the sum, so the "sum" is an
//!   exact copy).
//!
//! The tangent stays partial, each rank holding its elements' part: the
//! distributed linear solver (PETSc, crate `junta-mpi`) sends each rank the
//! entries of the rows it owns from the ranks that share them, and each
//! rank hands PETSc its own rows, summed. Because every rank then holds the same vectors and
//! states, every norm, dot product, constraint and decision of a driver is
//! computed identically on every rank, with no further communication; and
//! a checkpoint written by one rank restarts on any number of ranks.
//!
//! Without an installed [`Collective`] (the ordinary, single-process run)
//! nothing here is used.

use crate::mesh::Mesh;
use std::sync::OnceLock;

/// The collective operations of the ranks of one run. Every method must be
/// called by every rank, in the same order.
pub trait Collective: Send + Sync {
    /// This process's rank, `0..size`.
    fn rank(&self) -> usize;
    /// Number of ranks.
    fn size(&self) -> usize;
    /// Sum `v` over the ranks; every rank receives the same values, bit for
    /// bit (a reduction in a fixed order, then a broadcast).
    fn sum_in_place(&self, v: &mut [f64]);
    /// Element-wise maximum of `v` over the ranks.
    fn max_in_place(&self, v: &mut [f64]);
    /// Element-wise minimum of `v` over the ranks (integers).
    fn min_in_place_usize(&self, v: &mut [usize]);
    /// Whether any rank passed `true`.
    fn any(&self, flag: bool) -> bool;
    /// The bytes of rank `root`, on every rank.
    fn broadcast_bytes(&self, root: usize, bytes: &mut Vec<u8>);
}

static COLLECTIVE: OnceLock<Box<dyn Collective>> = OnceLock::new();

/// Install the process's collective operations (once, before the model is
/// built). Returns `false` when one was installed already.
pub fn install(collective: Box<dyn Collective>) -> bool {
    COLLECTIVE.set(collective).is_ok()
}

/// The installed collective operations; `None` in a single-process run.
pub fn collective() -> Option<&'static dyn Collective> {
    COLLECTIVE.get().map(|c| &**c)
}

/// The lowest rank among those that pass `Some(message)`, with its
/// message, on every rank; `None` when no rank did. Used to agree on an
/// error met by some ranks only.
pub fn first_message(c: &dyn Collective, message: Option<String>) -> Option<(usize, String)> {
    if !c.any(message.is_some()) {
        return None;
    }
    let mut lowest = [if message.is_some() {
        c.rank()
    } else {
        c.size()
    }];
    c.min_in_place_usize(&mut lowest);
    let root = lowest[0];
    let mut bytes = if c.rank() == root {
        message.unwrap_or_default().into_bytes()
    } else {
        Vec::new()
    };
    c.broadcast_bytes(root, &mut bytes);
    Some((root, String::from_utf8_lossy(&bytes).into_owned()))
}

/// The rank of every element (`parts[block][element]`) for `ranks` ranks,
/// by recursive coordinate bisection of the element centroids: the set is
/// cut across its longest extent into two sets whose weights are in the
/// ratio of the ranks they go to, and so on down to one rank per set.
///
/// The weight of an element is `(3 n)^2`, its matrix entries (`n` nodes):
/// an 18-node interface element counts for 2.25 8-node solids. Interface
/// elements are elements like the others: each goes to exactly one rank,
/// whatever ranks its two faces' nodes touch. Deterministic: every rank
/// computes the same partition from the same mesh.
pub fn partition_elements(mesh: &Mesh, ranks: usize) -> Vec<Vec<u32>> {
    let mut items: Vec<(usize, usize, [f64; 3], f64)> = Vec::with_capacity(mesh.num_elements());
    for (bi, b) in mesh.blocks.iter().enumerate() {
        let n = b.nodes_per_element();
        let weight = (3.0 * n as f64).powi(2);
        for e in 0..b.len() {
            let mut c = [0.0; 3];
            for &node in b.element(e) {
                for (ci, x) in c.iter_mut().zip(mesh.nodes[node]) {
                    *ci += x / n as f64;
                }
            }
            items.push((bi, e, c, weight));
        }
    }
    let mut parts: Vec<Vec<u32>> = mesh.blocks.iter().map(|b| vec![0; b.len()]).collect();
    bisect(&mut items, 0, ranks.max(1), &mut parts);
    parts
}

/// Give ranks `first..first + ranks` to `items` (recursive coordinate
/// bisection, [`partition_elements`]).
fn bisect(
    items: &mut [(usize, usize, [f64; 3], f64)],
    first: usize,
    ranks: usize,
    parts: &mut [Vec<u32>],
) {
    if ranks <= 1 || items.len() <= 1 {
        for &(b, e, _, _) in items.iter() {
            parts[b][e] = first as u32;
        }
        return;
    }
    let axis = longest_axis(items);
    items.sort_by(|a, b| {
        a.2[axis]
            .total_cmp(&b.2[axis])
            .then((a.0, a.1).cmp(&(b.0, b.1)))
    });
    let left_ranks = ranks / 2;
    let total: f64 = items.iter().map(|i| i.3).sum();
    let target = total * left_ranks as f64 / ranks as f64;
    let mut acc = 0.0;
    let mut cut = 0;
    while cut < items.len() && acc + 0.5 * items[cut].3 <= target {
        acc += items[cut].3;
        cut += 1;
    }
    let (left, right) = items.split_at_mut(cut);
    bisect(left, first, left_ranks, parts);
    bisect(right, first + left_ranks, ranks - left_ranks, parts);
}

/// The coordinate axis along which the centroids spread the most.
fn longest_axis(items: &[(usize, usize, [f64; 3], f64)]) -> usize {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for (_, _, c, _) in items {
        for a in 0..3 {
            lo[a] = lo[a].min(c[a]);
            hi[a] = hi[a].max(c[a]);
        }
    }
    (0..3)
        .max_by(|&a, &b| (hi[a] - lo[a]).total_cmp(&(hi[b] - lo[b])))
        .unwrap_or(0)
}

/// What a partition cuts: per rank, its elements, the nodes its elements
/// touch, and of those the nodes other ranks' elements touch too (the
/// interface nodes, whose matrix rows and force entries are exchanged).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PartitionCut {
    /// Elements of each rank.
    pub elements: Vec<usize>,
    /// Nodes touched by each rank's elements.
    pub nodes: Vec<usize>,
    /// Of those, nodes shared with another rank.
    pub shared_nodes: Vec<usize>,
}

/// The ranks whose elements touch each node of `mesh` under `parts`
/// ([`partition_elements`]): bit r for rank r (ranks past 63 read as 63).
pub fn node_ranks(mesh: &Mesh, parts: &[Vec<u32>]) -> Vec<u64> {
    let mut touched: Vec<u64> = vec![0; mesh.nodes.len()];
    for (block, part) in mesh.blocks.iter().zip(parts) {
        for (e, &r) in part.iter().enumerate() {
            for &n in block.element(e) {
                touched[n] |= 1 << r.min(63);
            }
        }
    }
    touched
}

/// Measure the cut of `parts` ([`partition_elements`]) over `ranks` ranks.
pub fn partition_cut(mesh: &Mesh, parts: &[Vec<u32>], ranks: usize) -> PartitionCut {
    let mut cut = PartitionCut {
        elements: vec![0; ranks],
        nodes: vec![0; ranks],
        shared_nodes: vec![0; ranks],
    };
    for part in parts {
        for &r in part {
            cut.elements[r as usize] += 1;
        }
    }
    for mask in node_ranks(mesh, parts) {
        for r in 0..ranks.min(64) {
            if mask & (1 << r) != 0 {
                cut.nodes[r] += 1;
                if mask.count_ones() > 1 {
                    cut.shared_nodes[r] += 1;
                }
            }
        }
    }
    cut
}

/// Per rank, the equations it owns and its ghosts under `parts`: a node's
/// equations belong to the lowest rank whose elements touch it (the rule of
/// the distributed solver's rows); the other ranks touching it hold them as
/// ghosts.
pub fn equations_by_rank(
    mesh: &Mesh,
    parts: &[Vec<u32>],
    ranks: usize,
    dofs: &crate::dof::DofMap,
) -> (Vec<usize>, Vec<usize>) {
    let (mut owned, mut ghost) = (vec![0; ranks], vec![0; ranks]);
    let per_node = dofs.eq.len() / dofs.num_nodes.max(1);
    for (n, mask) in node_ranks(mesh, parts).into_iter().enumerate() {
        let free = (n * per_node..(n + 1) * per_node)
            .filter(|&d| {
                dofs.eq
                    .get(d)
                    .is_some_and(|&e| e != crate::dof::CONSTRAINED)
            })
            .count();
        if mask == 0 || free == 0 {
            continue;
        }
        owned[mask.trailing_zeros() as usize] += free;
        for r in (mask.trailing_zeros() as usize + 1)..ranks.min(64) {
            if mask & (1 << r) != 0 {
                ghost[r] += free;
            }
        }
    }
    (owned, ghost)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::generate::{box_mesh, BoxSpec};
    use crate::topology::CellShape;

    #[test]
    fn bisection_balances_the_weight_and_cuts_across_the_long_side() {
        // a 12 x 2 x 2 bar of hexahedra on 4 ranks: quarters along x, each
        // of 12 elements; a quarter shares one layer of 9 nodes per cut
        let spec = BoxSpec::new([12.0, 2.0, 2.0], [12, 2, 2], CellShape::Hex8);
        let mesh = box_mesh(&spec, "bar", "h8", "steel").unwrap();
        let parts = partition_elements(&mesh, 4);
        let cut = partition_cut(&mesh, &parts, 4);
        assert_eq!(cut.elements, vec![12, 12, 12, 12]);
        assert_eq!(cut.shared_nodes, vec![9, 18, 18, 9]);
        // three ranks: the weights split 1 : 2, then 1 : 1
        let cut3 = partition_cut(&mesh, &partition_elements(&mesh, 3), 3);
        assert_eq!(cut3.elements, vec![16, 16, 16]);
    }
}
