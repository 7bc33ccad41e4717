//! Supernodal symbolic Cholesky on the quotient graph of equation groups.
//!
//! The equations of a node of a solid mesh (its 2 or 3 displacement
//! components) have the same closed neighbourhood in the matrix graph: they
//! form a group ([`crate::ordering::equation_groups`]), and an ordering
//! that keeps every group contiguous (nested dissection does) gives all of
//! a group's columns of `L` the same structure below the group. The
//! symbolic factorisation can then run on the quotient graph (a third of
//! the vertices and a ninth of the entries of the equation graph for 3
//! components) and be expanded to equations at the end:
//!
//! 1. elimination tree and weighted column counts `C_g` of the quotient
//!    graph in the group order (`C_g` = the equations of the groups in
//!    column `g` of the quotient factor, `g` included; Gilbert, Ng and
//!    Peyton 1994, see [`crate::ordering::FillCounter`]);
//! 2. fundamental supernodes: group `g` joins the supernode of `g - 1`
//!    when `g - 1` is its only child and `C_{g-1} = w_{g-1} + C_g` (the
//!    column of `g - 1` is that of `g` plus its own rows);
//! 3. relaxed amalgamation: a supernode absorbs the supernode numbered
//!    just before it when that one is its child and the explicit zeros this
//!    adds, `(size_p + degree_p - degree_c) size_c` for parent `p` and
//!    child `c` (sizes and degrees in equations), stay within the fraction
//!    of the merged trapezoid given by [`RELAX`] for the merged size (the
//!    cut-offs of faer's default supernodal parameters; faer may also merge
//!    children that are not adjacent, after renumbering, which this does
//!    not need);
//! 4. row structure of every supernode below its columns: the rows of `A`
//!    in its columns and the structures of its children, beyond its last
//!    column (a child's structure lies in its parent's columns and
//!    structure, the property of the elimination tree the merge relies on);
//! 5. each group expanded to its consecutive equations.
//!
//! The result equals faer's supernodal symbolic factorisation of the
//! equation matrix up to the amalgamation step (same fundamental
//! supernodes and structures, checked in the tests), for a fraction of its
//! time: about 0.06 s against 0.39 s on the H20 unit cube n=20 (102,039
//! equations, 125M factor entries).

use crate::ordering::Graph;

/// Amalgamation cut-offs `(largest merged size, largest fraction of
/// explicit zeros)`, the first whose size covers the merged supernode
/// applies (faer 0.24's `DEFAULT_RELAX`).
const RELAX: [(usize, f64); 4] = [(4, 1.0), (16, 0.8), (48, 0.1), (usize::MAX, 0.05)];

/// A supernodal partition of the permuted equations and the row structure
/// below each supernode.
#[derive(Debug, Clone, Default, PartialEq)]
pub(crate) struct Supernodes {
    /// Equations.
    pub(crate) n: usize,
    /// Supernode `s` covers the permuted columns `bounds[s]..bounds[s +
    /// 1]`.
    pub(crate) bounds: Vec<usize>,
    /// Rows of `L` below supernode `s` (permuted numbering, increasing):
    /// `rows[row_ptr[s]..row_ptr[s + 1]]`.
    pub(crate) row_ptr: Vec<usize>,
    pub(crate) rows: Vec<u32>,
}

impl Supernodes {
    pub(crate) fn count(&self) -> usize {
        self.bounds.len() - 1
    }

    pub(crate) fn rows_of(&self, s: usize) -> &[u32] {
        &self.rows[self.row_ptr[s]..self.row_ptr[s + 1]]
    }

    /// The supernodes of the quotient graph `graph` whose vertex `v` stands
    /// for `w[v]` consecutive equations, eliminated in the order `order`
    /// (`order[k]` = the vertex eliminated `k`-th); see the module
    /// documentation. `relax`: amalgamate (step 3) or keep the
    /// fundamental supernodes.
    pub(crate) fn of_groups(graph: &Graph, w: &[usize], order: &[u32], relax: bool) -> Self {
        let (parent, counts) = crate::ordering::weighted_column_counts(graph, w, order);
        let wk: Vec<usize> = order.iter().map(|&v| w[v as usize]).collect();
        let first = fundamental(&parent, &counts, &wk);
        let first = if relax {
            amalgamated(&first, &parent, &counts, &wk)
        } else {
            first
        };
        let group_rows = group_structures(graph, order, &parent, &first);
        expand(&first, &group_rows, &wk)
    }
}

const NONE: usize = usize::MAX;

/// First group of every fundamental supernode, then `ng` (step 2).
fn fundamental(parent: &[usize], counts: &[usize], w: &[usize]) -> Vec<usize> {
    let ng = parent.len();
    let mut children = vec![0u32; ng];
    for &p in parent {
        if p != NONE {
            children[p] += 1;
        }
    }
    let mut first = Vec::new();
    for g in 0..ng {
        let joins = g > 0
            && parent[g - 1] == g
            && children[g] == 1
            && counts[g - 1] == w[g - 1] + counts[g];
        if !joins {
            first.push(g);
        }
    }
    first.push(ng);
    first
}

/// The fundamental supernodes `first` merged with the child numbered just
/// before them where [`RELAX`] allows (step 3).
fn amalgamated(first: &[usize], parent: &[usize], counts: &[usize], w: &[usize]) -> Vec<usize> {
    let mut merged: Vec<usize> = Vec::with_capacity(first.len());
    // of the last merged supernode: equations, rows below, explicit zeros
    let (mut size, mut degree, mut zeros) = (0usize, 0usize, 0usize);
    for s in 0..first.len() - 1 {
        let (a, b) = (first[s], first[s + 1]);
        let s_size: usize = w[a..b].iter().sum();
        let s_degree = counts[a] - s_size;
        // the last merged supernode ends at group a - 1: is it a child of s?
        let child_adjacent = !merged.is_empty() && (a..b).contains(&parent[a - 1]);
        if child_adjacent {
            let new_zeros = (s_size + s_degree - degree) * size;
            let all = new_zeros + zeros;
            let combined = size + s_size;
            let entries = combined * (combined + 1) / 2 + s_degree * combined;
            let allowed = RELAX
                .iter()
                .find(|&&(cap, _)| cap >= combined)
                .is_some_and(|&(_, frac)| all as f64 <= frac * entries as f64);
            if allowed {
                // the child's columns join s: keep its first group
                size = combined;
                degree = s_degree;
                zeros = all;
                continue;
            }
        }
        merged.push(a);
        size = s_size;
        degree = s_degree;
        zeros = 0;
    }
    merged.push(*first.last().unwrap());
    merged
}

/// Row structure (groups beyond the last column) of every supernode of
/// `first` (step 4).
fn group_structures(
    graph: &Graph,
    order: &[u32],
    parent: &[usize],
    first: &[usize],
) -> (Vec<usize>, Vec<u32>) {
    let ng = order.len();
    let ns = first.len() - 1;
    let mut inv = vec![0u32; ng];
    for (k, &v) in order.iter().enumerate() {
        inv[v as usize] = k as u32;
    }
    let mut super_of = vec![0u32; ng];
    for s in 0..ns {
        super_of[first[s]..first[s + 1]].fill(s as u32);
    }
    // children of each supernode (CSR), by the parent of its last group
    let mut child_ptr = vec![0usize; ns + 1];
    let parent_super = |s: usize| {
        let p = parent[first[s + 1] - 1];
        (p != NONE).then(|| super_of[p] as usize)
    };
    for s in 0..ns {
        if let Some(p) = parent_super(s) {
            child_ptr[p + 1] += 1;
        }
    }
    for s in 0..ns {
        child_ptr[s + 1] += child_ptr[s];
    }
    let mut next = child_ptr.clone();
    let mut child = vec![0u32; child_ptr[ns]];
    for s in 0..ns {
        if let Some(p) = parent_super(s) {
            child[next[p]] = s as u32;
            next[p] += 1;
        }
    }
    let mut row_ptr = vec![0usize];
    let mut rows: Vec<u32> = Vec::new();
    let mut mark = vec![u32::MAX; ng];
    for s in 0..ns {
        let last = first[s + 1] - 1;
        let start = rows.len();
        let mut add = |r: u32, rows: &mut Vec<u32>| {
            if r as usize > last && mark[r as usize] != s as u32 {
                mark[r as usize] = s as u32;
                rows.push(r);
            }
        };
        for g in first[s]..=last {
            for &u in graph.neighbours(order[g] as usize) {
                add(inv[u as usize], &mut rows);
            }
        }
        for &c in &child[child_ptr[s]..child_ptr[s + 1]] {
            let c = c as usize;
            for i in row_ptr[c]..row_ptr[c + 1] {
                let r = rows[i];
                add(r, &mut rows);
            }
        }
        rows[start..].sort_unstable();
        row_ptr.push(rows.len());
    }
    (row_ptr, rows)
}

/// Supernodes of groups expanded to equations (step 5).
fn expand(first: &[usize], group_rows: &(Vec<usize>, Vec<u32>), w: &[usize]) -> Supernodes {
    let (row_ptr_g, rows_g) = group_rows;
    let mut eq_begin = Vec::with_capacity(w.len() + 1);
    eq_begin.push(0usize);
    for &wg in w {
        eq_begin.push(eq_begin.last().unwrap() + wg);
    }
    let n = *eq_begin.last().unwrap();
    let ns = first.len() - 1;
    let bounds: Vec<usize> = first.iter().map(|&g| eq_begin[g]).collect();
    let mut row_ptr = Vec::with_capacity(ns + 1);
    row_ptr.push(0usize);
    let total: usize = rows_g.iter().map(|&g| w[g as usize]).sum();
    let mut rows = Vec::with_capacity(total);
    for s in 0..ns {
        for &g in &rows_g[row_ptr_g[s]..row_ptr_g[s + 1]] {
            let g = g as usize;
            rows.extend((eq_begin[g]..eq_begin[g + 1]).map(|e| e as u32));
        }
        row_ptr.push(rows.len());
    }
    Supernodes {
        n,
        bounds,
        row_ptr,
        rows,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gallery::{grid_3d, Stencil};
    use crate::ordering::{self, FillCounter};
    use faer::sparse::linalg::cholesky::{
        factorize_symbolic_cholesky, CholeskySymbolicParams, SymbolicCholeskyRaw, SymmetricOrdering,
    };
    use faer::sparse::linalg::{SupernodalThreshold, SymbolicSupernodalParams};
    use faer::sparse::SymbolicSparseColMatRef;
    use junta_core::SymmetricCsc;

    /// faer's supernodal symbolic factorisation of `a` ordered by `perm`,
    /// amalgamated by its defaults or fundamental.
    fn faer_supernodes(a: &SymmetricCsc, perm: &[usize], relax: bool) -> Supernodes {
        let n = a.n;
        let inv = ordering::inverse(perm);
        let pat = SymbolicSparseColMatRef::new_checked(n, n, &a.col_ptr, None, &a.row_idx);
        let p = faer::perm::PermRef::new_checked(perm, &inv, n);
        let mut params = CholeskySymbolicParams {
            supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
            ..Default::default()
        };
        if !relax {
            params.supernodal_params = SymbolicSupernodalParams { relax: None };
        }
        let sym = factorize_symbolic_cholesky(
            pat,
            faer::Side::Upper,
            SymmetricOrdering::Custom(p),
            params,
        )
        .unwrap();
        let SymbolicCholeskyRaw::Supernodal(sn) = sym.raw() else {
            panic!("supernodal expected")
        };
        let (cpr, nps, idx) = (sn.col_ptr_for_row_idx(), sn.nnz_per_super(), sn.row_idx());
        let mut out = Supernodes {
            n,
            bounds: sn.supernode_begin().to_vec(),
            row_ptr: vec![0],
            rows: Vec::new(),
        };
        out.bounds.push(n);
        for k in 0..sn.n_supernodes() {
            out.rows
                .extend(idx[cpr[k]..cpr[k] + nps[k]].iter().map(|&i| i as u32));
            out.row_ptr.push(out.rows.len());
        }
        out
    }

    /// Stored entries of the factor (lower trapezoids).
    fn stored(s: &Supernodes) -> usize {
        (0..s.count())
            .map(|k| {
                let w = s.bounds[k + 1] - s.bounds[k];
                w * (w + 1) / 2 + w * s.rows_of(k).len()
            })
            .sum()
    }

    /// The orderings tried: nested dissection by coordinates (groups kept),
    /// AMD, nodes in a shuffled order (groups kept, a poor ordering) and
    /// equations shuffled (every group split into runs).
    fn orderings(a: &SymmetricCsc, coords: &[[f64; 3]]) -> Vec<(&'static str, Vec<usize>)> {
        let nodes = a.n / 3;
        let mut x = 12345u64;
        let mut shuffle = |v: &mut Vec<usize>| {
            for i in (1..v.len()).rev() {
                x = x
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                v.swap(i, (x >> 33) as usize % (i + 1));
            }
        };
        let mut node_order: Vec<usize> = (0..nodes).collect();
        shuffle(&mut node_order);
        let by_nodes = node_order.iter().flat_map(|&v| 3 * v..3 * v + 3).collect();
        let mut equations: Vec<usize> = (0..a.n).collect();
        shuffle(&mut equations);
        vec![
            (
                "nested dissection",
                ordering::nested_dissection(a, Some(coords)),
            ),
            ("amd", ordering::amd_ordering(a)),
            ("shuffled nodes", by_nodes),
            ("shuffled equations", equations),
        ]
    }

    #[test]
    fn fundamental_supernodes_equal_faers_on_the_equation_graph() {
        let (a, coords) = grid_3d(7, 6, 5, 3, Stencil::Point27);
        let counter = FillCounter::new(&a);
        for (name, perm) in orderings(&a, &coords) {
            let ours = counter.supernodes(&perm, false);
            let faer = faer_supernodes(&a, &perm, false);
            assert_eq!(ours.bounds, faer.bounds, "{name}: supernode bounds");
            assert_eq!(ours.row_ptr, faer.row_ptr, "{name}: rows per supernode");
            assert_eq!(ours.rows, faer.rows, "{name}: row structure");
            // and the fill counted by walking the rows of L
            let exact = ordering::factor_nonzeros(&a, Some(&perm));
            assert_eq!(stored(&ours), exact, "{name}");
        }
    }

    #[test]
    fn amalgamation_adds_few_zeros_and_keeps_every_entry() {
        let (a, coords) = grid_3d(8, 7, 6, 3, Stencil::Point27);
        let counter = FillCounter::new(&a);
        for (name, perm) in orderings(&a, &coords) {
            let relaxed = counter.supernodes(&perm, true);
            let fundamental = counter.supernodes(&perm, false);
            assert!(
                relaxed.count() < fundamental.count(),
                "{name}: nothing merged"
            );
            // every fundamental supernode lies inside one relaxed supernode,
            // whose structure covers the fundamental one's rows
            for k in 0..fundamental.count() {
                let (b, e) = (fundamental.bounds[k], fundamental.bounds[k + 1]);
                let s = relaxed.bounds.partition_point(|&x| x <= b) - 1;
                let (rb, re) = (relaxed.bounds[s], relaxed.bounds[s + 1]);
                assert!(e <= re, "{name}: fundamental supernode {k} straddles two");
                let covered: std::collections::HashSet<u32> = (e as u32..re as u32)
                    .chain(relaxed.rows_of(s).iter().copied())
                    .collect();
                assert!(
                    fundamental.rows_of(k).iter().all(|r| covered.contains(r)),
                    "{name}: supernode {k} ({rb}..{re}) misses rows"
                );
            }
            // faer's defaults amalgamate as much or more (it may merge
            // children that are not adjacent)
            let (ours, theirs, exact) = (
                stored(&relaxed),
                stored(&faer_supernodes(&a, &perm, true)),
                stored(&fundamental),
            );
            assert!(
                ours >= exact && ours as f64 <= 1.1 * exact as f64,
                "{name}: {ours} for {exact}"
            );
            assert!(
                ours <= theirs + theirs / 20,
                "{name}: {ours} against faer's {theirs}"
            );
        }
    }
}
