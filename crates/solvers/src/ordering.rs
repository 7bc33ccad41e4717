//! Fill-reducing orderings for sparse Cholesky: nested dissection
//! (geometric when coordinates are known, graph-based otherwise) and faer's
//! approximate minimum degree (AMD).
//!
//! # Permutation convention
//!
//! Every function here returns `perm` with `perm[new] = old`: the equation
//! eliminated `new`-th is the original equation `perm[new]`. This is faer's
//! "forward" array of a [`faer::perm::PermRef`]; [`inverse`] gives the other.
//!
//! # Nested dissection
//!
//! Eliminating a vertex of the graph of `A` connects all its not yet
//! eliminated neighbours (the fill of `L`). Nested dissection (George, 1973)
//! finds a small vertex separator `S` that splits the graph into two parts
//! `P1`, `P2` with no edge between them, orders `P1`, then `P2`, then `S`
//! last, and recurses into `P1` and `P2`. Because `P1` and `P2` are
//! eliminated independently, fill never crosses the separator, and the
//! factor of a 3D mesh with `N` vertices has `O(N^{4/3})` non-zeros and costs
//! `O(N^2)` flops (against the much larger constants minimum-degree methods
//! reach on 3D meshes, whose late fronts are bigger).
//!
//! Steps, in [`nested_dissection`]:
//!
//! 1. **Compression to nodes.** Finite-element dofs come in groups (3 per
//!    node in 3D solids) with identical couplings. Consecutive equations
//!    with identical coordinates (or, without coordinates, identical
//!    adjacency, detected with an order-independent 64-bit hash of each
//!    equation's closed neighbourhood) form one graph vertex. The groups stay
//!    together in the final order, which also makes the factor's supernodes
//!    line up with the nodes. Zero-thickness interface elements make two
//!    nodes coincide; with coordinates they share one vertex, which is
//!    harmless for the ordering.
//! 2. **Bisection.** For a vertex set `V` (a subgraph):
//!    * *geometric* (coordinates known): take the bounding box of `V`, its
//!      longest extent `x_a`, the median `m` of `x_a` over `V`; `P1 = {x_a <
//!      m}`, `P2 = {x_a >= m}` (ties fall wholly on one side, so on a
//!      structured grid the cut is a grid plane);
//!    * *graph* (no coordinates, or all points of `V` coincide): a breadth
//!      first level structure `L_0, L_1, ...` rooted at a pseudo-peripheral
//!      vertex (George-Liu: repeat BFS from the farthest vertex of least
//!      degree while the eccentricity grows); `P1` = levels below the level
//!      `L_m` where the cumulative count passes `|V|/2`, `P2` = the rest. If
//!      the BFS does not reach all of `V`, `P1` is the component reached and
//!      `P2` the rest (no separator needed).
//! 3. **Separator.** The edge cut between `P1` and `P2` is turned into a
//!    vertex separator by taking its endpoints on one side: the vertices of
//!    `P2` with a neighbour in `P1`, or those of `P1` with a neighbour in
//!    `P2`, whichever set is smaller (both are vertex covers of the cut).
//! 4. **Recursion.** Order `P1 \ S`, then `P2 \ S`, then `S`. Below
//!    [`ND_LEAF_NODES`] vertices the subgraph is ordered by faer's AMD.
//!
//! Each level of the recursion costs `O(|V| + |E|)` (median by
//! quick-select, one pass over the edges), and there are `O(log N)` levels,
//! so the ordering costs `O((N + E) log N)`: tens of milliseconds at 200k
//! dofs.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::amd;
use faer::sparse::SymbolicSparseColMatRef;
use junta_core::SymmetricCsc;
use serde::Deserialize;

/// Subgraphs with at most this many vertices (nodes, not dofs) are ordered
/// by AMD instead of being dissected further. Dissecting down to small
/// leaves gives slightly less fill than larger AMD leaves on 3D meshes
/// (unit cube H20 n=20: 96 -> 127.8M non-zeros in `L`, 16 -> 124.0M;
/// H8 n=40: 236.2M -> 232.8M).
pub const ND_LEAF_NODES: usize = 16;

/// Which fill-reducing ordering a direct solver uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum OrderingKind {
    /// Nested dissection (geometric with coordinates, graph-based without).
    #[default]
    NestedDissection,
    /// faer's approximate minimum degree.
    Amd,
    /// No reordering (for comparisons only: much more fill).
    Natural,
}

impl OrderingKind {
    /// snake_case name, as in the TOML parameters.
    pub fn name(self) -> &'static str {
        match self {
            OrderingKind::NestedDissection => "nested_dissection",
            OrderingKind::Amd => "amd",
            OrderingKind::Natural => "natural",
        }
    }
}

/// Compute the ordering `kind` of `matrix` (`perm[new] = old`).
pub fn compute(
    kind: OrderingKind,
    matrix: &SymmetricCsc,
    coords: Option<&[[f64; 3]]>,
) -> Vec<usize> {
    match kind {
        OrderingKind::NestedDissection => nested_dissection(matrix, coords),
        OrderingKind::Amd => amd_ordering(matrix),
        OrderingKind::Natural => (0..matrix.n).collect(),
    }
}

/// The inverse permutation: `inv[perm[k]] = k`.
pub fn inverse(perm: &[usize]) -> Vec<usize> {
    let mut inv = vec![0; perm.len()];
    for (k, &p) in perm.iter().enumerate() {
        inv[p] = k;
    }
    inv
}

/// Whether `perm` is a bijection of `0..n`.
pub fn is_permutation(perm: &[usize], n: usize) -> bool {
    if perm.len() != n {
        return false;
    }
    let mut seen = vec![false; n];
    for &p in perm {
        if p >= n || seen[p] {
            return false;
        }
        seen[p] = true;
    }
    true
}

/// faer's AMD ordering of the whole matrix (`perm[new] = old`).
pub fn amd_ordering(matrix: &SymmetricCsc) -> Vec<usize> {
    let n = matrix.n;
    let mut perm = vec![0usize; n];
    let mut perm_inv = vec![0usize; n];
    if n == 0 {
        return perm;
    }
    let a = SymbolicSparseColMatRef::new_checked(n, n, &matrix.col_ptr, None, &matrix.row_idx);
    let mut mem = MemBuffer::new(amd::order_scratch::<usize>(n, matrix.nnz()));
    match amd::order(
        &mut perm,
        &mut perm_inv,
        a,
        amd::Control::default(),
        MemStack::new(&mut mem),
    ) {
        Ok(_) => perm,
        Err(e) => {
            tracing::warn!("AMD ordering failed ({e:?}); using the natural order");
            (0..n).collect()
        }
    }
}

/// Exact number of non-zeros of the Cholesky factor `L` (diagonal
/// included) of `P A P^T` for the ordering `perm` (`None`: natural order).
///
/// Elimination tree by Liu's algorithm with path compression, then row
/// counts by walking, for every entry `a_ik` (`i < k`) of the permuted
/// upper triangle, the tree path from `i` towards `k` until a vertex already
/// marked for row `k`: the walk visits exactly the pattern of row `k` of
/// `L`, so the cost is `O(nnz(L))`. For statistics and tests; the solver
/// itself reads its factor size from faer's symbolic structure.
pub fn factor_nonzeros(matrix: &SymmetricCsc, perm: Option<&[usize]>) -> usize {
    let n = matrix.n;
    let permuted;
    let a: &SymmetricCsc = match perm {
        None => matrix,
        Some(p) => {
            permuted = permute_upper_pattern(matrix, p);
            &permuted
        }
    };
    const NONE: usize = usize::MAX;
    let mut parent = vec![NONE; n];
    let mut ancestor = vec![NONE; n];
    for k in 0..n {
        for &i0 in &a.row_idx[a.col_ptr[k]..a.col_ptr[k + 1]] {
            let mut i = i0;
            while i != NONE && i < k {
                let next = ancestor[i];
                ancestor[i] = k;
                if next == NONE {
                    parent[i] = k;
                }
                i = next;
            }
        }
    }
    let mut mark = vec![NONE; n];
    let mut count = n; // diagonal
    for k in 0..n {
        mark[k] = k;
        for &i0 in &a.row_idx[a.col_ptr[k]..a.col_ptr[k + 1]] {
            let mut i = i0;
            while i < k && mark[i] != k {
                mark[i] = k;
                count += 1;
                i = parent[i];
                if i == NONE {
                    break;
                }
            }
        }
    }
    count
}

/// Pattern (values zero) of the upper triangle of `P A P^T`, `perm[new] = old`.
pub fn permute_upper_pattern(matrix: &SymmetricCsc, perm: &[usize]) -> SymmetricCsc {
    let n = matrix.n;
    let inv = inverse(perm);
    let mut counts = vec![0usize; n + 1];
    for j in 0..n {
        for &i in &matrix.row_idx[matrix.col_ptr[j]..matrix.col_ptr[j + 1]] {
            counts[inv[i].max(inv[j]) + 1] += 1;
        }
    }
    for k in 0..n {
        counts[k + 1] += counts[k];
    }
    let col_ptr = counts.clone();
    let mut next = counts;
    let mut row_idx = vec![0usize; matrix.nnz()];
    for j in 0..n {
        for &i in &matrix.row_idx[matrix.col_ptr[j]..matrix.col_ptr[j + 1]] {
            let (a, b) = (inv[i], inv[j]);
            let (r, c) = (a.min(b), a.max(b));
            row_idx[next[c]] = r;
            next[c] += 1;
        }
    }
    for k in 0..n {
        row_idx[col_ptr[k]..col_ptr[k + 1]].sort_unstable();
    }
    let nnz = row_idx.len();
    SymmetricCsc {
        n,
        col_ptr,
        row_idx,
        values: vec![0.0; nnz],
    }
}

/// Groups of consecutive equations forming one graph vertex:
/// `group_ptr[g]..group_ptr[g + 1]` are the equations of group `g`.
///
/// With `coords` (one point per equation), equal consecutive points form a
/// group; otherwise equal consecutive closed-neighbourhood hashes do.
pub fn equation_groups(matrix: &SymmetricCsc, coords: Option<&[[f64; 3]]>) -> Vec<usize> {
    let n = matrix.n;
    let mut group_ptr = Vec::with_capacity(n / 3 + 2);
    group_ptr.push(0);
    if n == 0 {
        return group_ptr;
    }
    match coords {
        Some(c) if c.len() == n => {
            for i in 1..n {
                if c[i] != c[i - 1] {
                    group_ptr.push(i);
                }
            }
        }
        _ => {
            // Closed neighbourhood hash: sum of h(k) over k in adj(i) + {i},
            // order independent; plus the degree for a second check.
            let h = |k: usize| -> u64 {
                let mut z = (k as u64).wrapping_add(0x9E37_79B9_7F4A_7C15);
                z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
                z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
                z ^ (z >> 31)
            };
            let mut hash: Vec<u64> = (0..n).map(h).collect();
            let mut degree = vec![0u32; n];
            for j in 0..n {
                for &i in &matrix.row_idx[matrix.col_ptr[j]..matrix.col_ptr[j + 1]] {
                    if i != j {
                        hash[j] = hash[j].wrapping_add(h(i));
                        hash[i] = hash[i].wrapping_add(h(j));
                        degree[i] += 1;
                        degree[j] += 1;
                    }
                }
            }
            for i in 1..n {
                if hash[i] != hash[i - 1] || degree[i] != degree[i - 1] {
                    group_ptr.push(i);
                }
            }
        }
    }
    group_ptr.push(n);
    group_ptr
}

/// Undirected graph in CSR form (no self loops, no duplicates).
struct Graph {
    xadj: Vec<usize>,
    adj: Vec<u32>,
}

impl Graph {
    #[inline]
    fn neighbours(&self, v: usize) -> &[u32] {
        &self.adj[self.xadj[v]..self.xadj[v + 1]]
    }
}

/// The quotient graph of the equation groups.
fn group_graph(matrix: &SymmetricCsc, group_ptr: &[usize]) -> Graph {
    let n = matrix.n;
    let ng = group_ptr.len() - 1;
    let mut group_of = vec![0u32; n];
    for g in 0..ng {
        group_of[group_ptr[g]..group_ptr[g + 1]].fill(g as u32);
    }
    // Upper adjacency (I < J) per group J, deduplicated with a marker.
    let mut mark = vec![u32::MAX; ng];
    let mut up_ptr = Vec::with_capacity(ng + 1);
    up_ptr.push(0usize);
    let mut up: Vec<u32> = Vec::new();
    for gj in 0..ng {
        for j in group_ptr[gj]..group_ptr[gj + 1] {
            for &i in &matrix.row_idx[matrix.col_ptr[j]..matrix.col_ptr[j + 1]] {
                let gi = group_of[i];
                if gi as usize != gj && mark[gi as usize] != gj as u32 {
                    mark[gi as usize] = gj as u32;
                    up.push(gi);
                }
            }
        }
        up_ptr.push(up.len());
    }
    // Symmetrise.
    let mut deg = vec![0usize; ng + 1];
    for gj in 0..ng {
        for &gi in &up[up_ptr[gj]..up_ptr[gj + 1]] {
            deg[gi as usize + 1] += 1;
            deg[gj + 1] += 1;
        }
    }
    for g in 0..ng {
        deg[g + 1] += deg[g];
    }
    let xadj = deg.clone();
    let mut next = deg;
    let mut adj = vec![0u32; xadj[ng]];
    for gj in 0..ng {
        for &gi in &up[up_ptr[gj]..up_ptr[gj + 1]] {
            adj[next[gi as usize]] = gj as u32;
            next[gi as usize] += 1;
            adj[next[gj]] = gi;
            next[gj] += 1;
        }
    }
    Graph { xadj, adj }
}

/// Nested dissection ordering of `matrix` (`perm[new] = old`); geometric
/// when `coords` holds one point per equation, graph-based otherwise. See
/// the module documentation for the algorithm.
pub fn nested_dissection(matrix: &SymmetricCsc, coords: Option<&[[f64; 3]]>) -> Vec<usize> {
    let n = matrix.n;
    if n == 0 {
        return Vec::new();
    }
    let coords = match coords {
        Some(c) if c.len() == n && c.iter().all(|p| p.iter().all(|x| x.is_finite())) => Some(c),
        Some(c) => {
            tracing::warn!(
                "nested dissection: {} coordinates for {} equations (or non-finite ones); using the graph-based variant",
                c.len(),
                n
            );
            None
        }
        None => None,
    };
    let group_ptr = equation_groups(matrix, coords);
    let ng = group_ptr.len() - 1;
    let graph = group_graph(matrix, &group_ptr);
    let points: Option<Vec<[f64; 3]>> = coords.map(|c| (0..ng).map(|g| c[group_ptr[g]]).collect());
    let mut nd = Dissector {
        graph: &graph,
        points: points.as_deref(),
        label: vec![0u8; ng],
        local: vec![u32::MAX; ng],
        level: vec![u32::MAX; ng],
        order: Vec::with_capacity(ng),
    };
    nd.dissect((0..ng as u32).collect());
    debug_assert_eq!(nd.order.len(), ng);
    let mut perm = Vec::with_capacity(n);
    for &g in &nd.order {
        perm.extend(group_ptr[g as usize]..group_ptr[g as usize + 1]);
    }
    perm
}

struct Dissector<'a> {
    graph: &'a Graph,
    points: Option<&'a [[f64; 3]]>,
    /// 0: outside the current subgraph, 1: part 1, 2: part 2, 3: separator.
    label: Vec<u8>,
    /// Local index in the current leaf (AMD) or BFS scratch.
    local: Vec<u32>,
    /// BFS level scratch.
    level: Vec<u32>,
    order: Vec<u32>,
}

impl Dissector<'_> {
    fn dissect(&mut self, set: Vec<u32>) {
        if set.is_empty() {
            return;
        }
        if set.len() <= ND_LEAF_NODES {
            self.leaf(&set);
            return;
        }
        // Split into part 1 (label 1) and part 2 (label 2).
        let split = match self.geometric_split(&set) {
            Some(s) => Some(s),
            None => self.graph_split(&set),
        };
        let Some(in_part2) = split else {
            // Could not split (should not happen with |set| > 1): order by AMD.
            self.leaf(&set);
            return;
        };
        for (k, &v) in set.iter().enumerate() {
            self.label[v as usize] = if in_part2[k] { 2 } else { 1 };
        }
        // Vertex separator: boundary of part 2 or of part 1, the smaller.
        let boundary = |this: &Self, side: u8| -> Vec<u32> {
            let other = 3 - side;
            set.iter()
                .copied()
                .filter(|&v| {
                    this.label[v as usize] == side
                        && this
                            .graph
                            .neighbours(v as usize)
                            .iter()
                            .any(|&u| this.label[u as usize] == other)
                })
                .collect()
        };
        let b2 = boundary(self, 2);
        let b1 = boundary(self, 1);
        let sep = if b1.len() < b2.len() { b1 } else { b2 };
        for &v in &sep {
            self.label[v as usize] = 3;
        }
        let mut p1 = Vec::new();
        let mut p2 = Vec::new();
        for &v in &set {
            match self.label[v as usize] {
                1 => p1.push(v),
                2 => p2.push(v),
                _ => {}
            }
            self.label[v as usize] = 0;
        }
        drop(set);
        self.dissect(p1);
        self.dissect(p2);
        self.order.extend_from_slice(&sep);
    }

    /// Median cut across the longest extent of the bounding box (falling
    /// back to the next-longest extents). `None` without coordinates or
    /// when all points coincide.
    fn geometric_split(&mut self, set: &[u32]) -> Option<Vec<bool>> {
        let pts = self.points?;
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for &v in set {
            let p = pts[v as usize];
            for a in 0..3 {
                lo[a] = lo[a].min(p[a]);
                hi[a] = hi[a].max(p[a]);
            }
        }
        let mut axes = [0usize, 1, 2];
        axes.sort_by(|&a, &b| (hi[b] - lo[b]).total_cmp(&(hi[a] - lo[a])));
        let axis = axes[0];
        if hi[axis] <= lo[axis] {
            return None;
        }
        let mut keys: Vec<f64> = set.iter().map(|&v| pts[v as usize][axis]).collect();
        let mid = keys.len() / 2;
        let m = *keys.select_nth_unstable_by(mid, f64::total_cmp).1;
        let below = set.iter().any(|&v| pts[v as usize][axis] < m);
        // Part 2 is x >= m, or x > m when the whole lower half sits on m
        // (then some point lies above m because hi > lo = m).
        Some(if below {
            set.iter().map(|&v| pts[v as usize][axis] >= m).collect()
        } else {
            set.iter().map(|&v| pts[v as usize][axis] > m).collect()
        })
    }

    /// Level-structure split from a pseudo-peripheral vertex.
    fn graph_split(&mut self, set: &[u32]) -> Option<Vec<bool>> {
        if set.len() < 2 {
            return None;
        }
        for &v in set {
            self.label[v as usize] = 1;
        }
        // Pseudo-peripheral root (George-Liu), a few sweeps at most.
        let mut root = set[0];
        let (mut order, mut ecc) = self.bfs(root);
        for _ in 0..8 {
            let last_level = self.level[*order.last().unwrap() as usize];
            // candidate: the last-level vertex of least degree
            let cand = order
                .iter()
                .rev()
                .take_while(|&&v| self.level[v as usize] == last_level)
                .copied()
                .min_by_key(|&v| self.graph.neighbours(v as usize).len())
                .unwrap();
            self.reset_levels(&order);
            let (o2, e2) = self.bfs(cand);
            if e2 > ecc {
                root = cand;
                order = o2;
                ecc = e2;
            } else {
                self.reset_levels(&o2);
                let (o3, e3) = self.bfs(root);
                order = o3;
                ecc = e3;
                break;
            }
        }
        let _ = ecc;
        let result = if order.len() < set.len() {
            // Disconnected: part 1 = the component reached.
            Some(
                set.iter()
                    .map(|&v| self.level[v as usize] == u32::MAX)
                    .collect(),
            )
        } else {
            // Median level: first level where the cumulative count passes half.
            let half = set.len() / 2;
            let m = self.level[order[half] as usize].max(1);
            let max_level = self.level[*order.last().unwrap() as usize];
            if max_level == 0 {
                None
            } else {
                Some(set.iter().map(|&v| self.level[v as usize] >= m).collect())
            }
        };
        self.reset_levels(&order);
        for &v in set {
            self.label[v as usize] = 0;
        }
        result
    }

    /// BFS inside the vertices labelled 1; returns the visit order and the
    /// eccentricity of `root`. Levels are left in `self.level`.
    fn bfs(&mut self, root: u32) -> (Vec<u32>, u32) {
        let mut order = vec![root];
        self.level[root as usize] = 0;
        let mut head = 0;
        while head < order.len() {
            let v = order[head] as usize;
            head += 1;
            let lv = self.level[v];
            for &u in self.graph.neighbours(v) {
                if self.label[u as usize] == 1 && self.level[u as usize] == u32::MAX {
                    self.level[u as usize] = lv + 1;
                    order.push(u);
                }
            }
        }
        let ecc = self.level[*order.last().unwrap() as usize];
        (order, ecc)
    }

    fn reset_levels(&mut self, order: &[u32]) {
        for &v in order {
            self.level[v as usize] = u32::MAX;
        }
    }

    /// Order a small subgraph by faer's AMD.
    fn leaf(&mut self, set: &[u32]) {
        let m = set.len();
        if m <= 2 {
            self.order.extend_from_slice(set);
            return;
        }
        for (k, &v) in set.iter().enumerate() {
            self.local[v as usize] = k as u32;
        }
        let mut col_ptr = Vec::with_capacity(m + 1);
        col_ptr.push(0usize);
        let mut row_idx: Vec<usize> = Vec::new();
        for &v in set {
            let start = row_idx.len();
            for &u in self.graph.neighbours(v as usize) {
                let l = self.local[u as usize];
                if l != u32::MAX {
                    row_idx.push(l as usize);
                }
            }
            row_idx[start..].sort_unstable();
            col_ptr.push(row_idx.len());
        }
        for &v in set {
            self.local[v as usize] = u32::MAX;
        }
        let mut perm = vec![0usize; m];
        let mut perm_inv = vec![0usize; m];
        let a = SymbolicSparseColMatRef::new_checked(m, m, &col_ptr, None, &row_idx);
        let mut mem = MemBuffer::new(amd::order_scratch::<usize>(m, row_idx.len()));
        match amd::order(
            &mut perm,
            &mut perm_inv,
            a,
            amd::Control::default(),
            MemStack::new(&mut mem),
        ) {
            Ok(_) => self.order.extend(perm.iter().map(|&k| set[k])),
            Err(_) => self.order.extend_from_slice(set),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gallery;

    #[test]
    fn nested_dissection_is_a_permutation_with_and_without_coordinates() {
        let (a, coords) = gallery::grid_3d(9, 7, 8, 3, gallery::Stencil::Point27);
        let geo = nested_dissection(&a, Some(&coords));
        let graph = nested_dissection(&a, None);
        assert!(is_permutation(&geo, a.n));
        assert!(is_permutation(&graph, a.n));
        // dofs of one node stay together and in order
        for p in [&geo, &graph] {
            for k in (0..a.n).step_by(3) {
                assert_eq!(p[k] % 3, 0);
                assert_eq!(p[k + 1], p[k] + 1);
                assert_eq!(p[k + 2], p[k] + 2);
            }
        }
        let natural = factor_nonzeros(&a, None);
        let nd_graph = factor_nonzeros(&a, Some(&graph));
        assert!(
            nd_graph < natural,
            "graph ND {nd_graph} vs natural {natural}"
        );
    }

    #[test]
    fn groups_from_hash_match_nodes() {
        let (a, coords) = gallery::grid_3d(4, 3, 2, 3, gallery::Stencil::Point7);
        let from_coords = equation_groups(&a, Some(&coords));
        let from_hash = equation_groups(&a, None);
        assert_eq!(from_coords.len() - 1, 24);
        assert_eq!(from_coords, from_hash);
    }

    #[test]
    fn factor_count_of_a_tridiagonal_matrix() {
        // tridiagonal: L is bidiagonal, 2n - 1 non-zeros in natural order;
        // eliminating the middle vertex first of a path of 3 creates fill.
        let mut a = SymmetricCsc::from_columns(vec![vec![0], vec![0, 1], vec![1, 2]]);
        a.values = vec![2.0, -1.0, 2.0, -1.0, 2.0];
        assert_eq!(factor_nonzeros(&a, None), 5);
        assert_eq!(factor_nonzeros(&a, Some(&[1, 0, 2])), 6);
        assert_eq!(inverse(&[2, 0, 1]), vec![1, 2, 0]);
        assert!(!is_permutation(&[0, 0, 1], 3));
    }
}
