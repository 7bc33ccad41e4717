//! Fill-reducing orderings for sparse Cholesky: nested dissection
//! (geometric when coordinates are known, graph-based otherwise), faer's
//! approximate minimum degree (AMD), and `auto`, which predicts the fill of
//! both and keeps the better.
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
//!    * *geometric* (coordinates known): for every axis `a` along which the
//!      points of `V` are not all equal, the median `m` of `x_a` over `V`
//!      gives `P1 = {x_a < m}`, `P2 = {x_a >= m}` (ties fall wholly on one
//!      side, so on a structured grid the cut is a grid plane). Of these
//!      (at most three) cuts, the one whose separator (step 3) is smallest
//!      relative to the smaller part is kept. Cutting across the longest
//!      extent of the bounding box, the usual rule, fails on meshes that
//!      are finer along a shorter side: a cantilever 1 x 0.1 x 0.1 with 10
//!      x 1 x 1000 H20 elements was cut into `x` planes of ~5000 nodes
//!      (predicted factor 4.67G non-zeros instead of 40M; 1000 x 1 x 10:
//!      515M instead of 44M; 100 x 1 x 100: 684M instead of 76M);
//! 3. **Separator.** The edge cut between `P1` and `P2` is turned into a
//!    vertex separator by taking its endpoints on one side: the vertices of
//!    `P2` with a neighbour in `P1`, or those of `P1` with a neighbour in
//!    `P2`, whichever set is smaller (both are vertex covers of the cut).
//! 4. **Recursion.** Order `P1 \ S`, then `P2 \ S`, then `S`. Below
//!    [`ND_LEAF_NODES`] vertices the subgraph is ordered by faer's AMD.
//!
//! Each level of the recursion costs `O(|V| + |E|)` (median by
//! quick-select, one pass over the edges per axis tried), and there are
//! `O(log N)` levels, so the ordering costs `O((N + E) log N)`: a few
//! tenths of a second at 200k dofs.
//!
//! # Automatic choice
//!
//! [`OrderingKind::Auto`] (the default of the direct solvers, through
//! [`choose`]) computes nested dissection and AMD, predicts the non-zeros
//! and flops of the factor of each with [`FillCounter`] (exact column
//! counts in `O(nnz(A))`, no factorisation), and keeps the one with fewer
//! flops. Nested dissection wins on 3D solids (unit cube H20 n=20: 125.1M
//! non-zeros against AMD's 238.9M), AMD on long or flat meshes (the
//! cantilever above, 10 x 1 x 1000: 33.2M against 40.4M).

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::amd;
use faer::sparse::SymbolicSparseColMatRef;
use junta_core::{PrecomputedDissection, SymmetricCsc};
use rayon::prelude::*;

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
    /// Compute nested dissection and AMD, predict the fill of each with the
    /// symbolic column counts ([`predict_fill`]) and keep the one with the
    /// fewest predicted factor flops (see [`choose`]).
    #[default]
    Auto,
    /// Nested dissection (geometric with coordinates, graph-based without).
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
            OrderingKind::Auto => "auto",
            OrderingKind::NestedDissection => "nested_dissection",
            OrderingKind::Amd => "amd",
            OrderingKind::Natural => "natural",
        }
    }
}

/// Predicted size and cost of the Cholesky factor `L` of `P A P^T`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FillEstimate {
    /// Non-zeros of `L`, diagonal included (exact for the pattern).
    pub nonzeros: usize,
    /// Floating-point operations of the factorisation, `sum_j c_j^2` over
    /// the column counts `c_j` of `L` (the left-looking update of column
    /// `j` costs about `c_j^2` multiply-adds summed over its descendants).
    pub flops: f64,
}

/// An ordering, the kind it came from and the predicted fill of every
/// candidate that was computed (one for a fixed kind, several for
/// [`OrderingKind::Auto`]).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct OrderingChoice {
    /// `perm[new] = old`.
    pub perm: Vec<usize>,
    /// The kind kept (never `Auto`).
    pub kind: OrderingKind,
    /// Every candidate and its predicted fill, the kept one included.
    pub candidates: Vec<(OrderingKind, FillEstimate)>,
    /// Seconds spent ordering and predicting.
    pub seconds: f64,
    /// Weight of nested dissection's flops in the comparison (1 unless
    /// the caller refactorises partially, see [`choose_weighted`]).
    pub nd_weight: f64,
    /// The nested-dissection candidate was the caller's
    /// ([`choose_reusing`]), not computed here.
    pub dissection_reused: bool,
}

impl OrderingChoice {
    /// The predicted fill of the kept ordering.
    pub fn estimate(&self) -> FillEstimate {
        self.candidates
            .iter()
            .find(|(k, _)| *k == self.kind)
            .map(|c| c.1)
            .unwrap_or_default()
    }

    /// One line for reports, e.g. `ordering auto: nested_dissection 124.0M
    /// (flops 2.1e12), amd 250.3M (flops 8.0e12) non-zeros predicted, kept
    /// nested_dissection`; for a fixed kind `ordering amd: 36.0M non-zeros
    /// predicted`.
    pub fn note(&self) -> String {
        let list: Vec<String> = self
            .candidates
            .iter()
            .map(|(k, e)| {
                format!(
                    "{} {:.1}M (flops {:.1e})",
                    k.name(),
                    e.nonzeros as f64 / 1e6,
                    e.flops
                )
            })
            .collect();
        let reused = if self.dissection_reused {
            " (nested dissection reused from the solver choice)"
        } else {
            ""
        };
        if self.candidates.len() > 1 {
            let weight = if self.nd_weight != 1.0 {
                format!(
                    " (nested dissection's flops weighted by {} for partial refactorisation)",
                    self.nd_weight
                )
            } else {
                String::new()
            };
            format!(
                "ordering auto: {} non-zeros predicted, kept {}{weight}{reused}",
                list.join(", "),
                self.kind.name()
            )
        } else {
            format!(
                "ordering {}: {} non-zeros predicted{reused}",
                self.kind.name(),
                list.join(", ")
            )
        }
    }
}

/// Compute the ordering `kind` of `matrix` (`perm[new] = old`); `Auto`
/// as in [`choose`].
pub fn compute(
    kind: OrderingKind,
    matrix: &SymmetricCsc,
    coords: Option<&[[f64; 3]]>,
) -> Vec<usize> {
    match kind {
        OrderingKind::Auto => choose(kind, matrix, coords).perm,
        OrderingKind::NestedDissection => nested_dissection(matrix, coords),
        OrderingKind::Amd => amd_ordering(matrix),
        OrderingKind::Natural => (0..matrix.n).collect(),
    }
}

/// The ordering `kind` with its predicted fill. For
/// [`OrderingKind::Auto`]: nested dissection and AMD are both computed,
/// the fill of each is predicted by [`predict_fill`] (elimination tree and
/// column counts, `O(nnz(A))`: a few percent of the cheapest
/// factorisation), and the candidate with the fewest predicted flops is
/// kept (flops measure the factorisation time; the non-zeros, its memory,
/// follow them closely). A poor ordering on one kind of mesh (nested
/// dissection on very irregular graphs, minimum degree on 3D solids, whose
/// last fronts are much larger) is then never the one used.
pub fn choose(
    kind: OrderingKind,
    matrix: &SymmetricCsc,
    coords: Option<&[[f64; 3]]>,
) -> OrderingChoice {
    choose_weighted(kind, matrix, coords, 1.0)
}

/// [`choose`] with nested dissection's predicted flops multiplied by
/// `nd_weight` in the comparison. A solver that refactorises only the
/// panels a change reaches (`ldlt`'s partial refactorisation) redoes one
/// path of a dissection tree, whose separators are balanced, but most of
/// a minimum-degree tree, which is close to a chain on slender meshes
/// (measured on the DCB: 6-13 % of the work against 83-93 %); a weight
/// below 1 lets it prefer dissection unless minimum degree is much cheaper.
pub fn choose_weighted(
    kind: OrderingKind,
    matrix: &SymmetricCsc,
    coords: Option<&[[f64; 3]]>,
    nd_weight: f64,
) -> OrderingChoice {
    choose_reusing(kind, matrix, coords, nd_weight, None)
}

/// [`choose_weighted`], with the nested-dissection candidate taken from
/// `known` (computed by the caller on the same pattern and coordinates,
/// with its prediction) instead of computed again. `known` is ignored when
/// `kind` asks for no nested dissection or when it is not a permutation of
/// the matrix's equations.
pub fn choose_reusing(
    kind: OrderingKind,
    matrix: &SymmetricCsc,
    coords: Option<&[[f64; 3]]>,
    nd_weight: f64,
    known: Option<&PrecomputedDissection>,
) -> OrderingChoice {
    choose_keeping_counter(kind, matrix, coords, nd_weight, known).0
}

/// [`choose_reusing`], and the [`FillCounter`] that predicted the
/// candidates' fill (`None` when there was nothing to predict), for the
/// symbolic analysis to reuse its quotient graph.
pub(crate) fn choose_keeping_counter(
    kind: OrderingKind,
    matrix: &SymmetricCsc,
    coords: Option<&[[f64; 3]]>,
    nd_weight: f64,
    known: Option<&PrecomputedDissection>,
) -> (OrderingChoice, Option<FillCounter>) {
    let t0 = std::time::Instant::now();
    let kinds: &[OrderingKind] = match kind {
        OrderingKind::Auto => &[OrderingKind::NestedDissection, OrderingKind::Amd],
        OrderingKind::NestedDissection => &[OrderingKind::NestedDissection],
        OrderingKind::Amd => &[OrderingKind::Amd],
        OrderingKind::Natural => &[OrderingKind::Natural],
    };
    let known = known.filter(|k| {
        kinds.contains(&OrderingKind::NestedDissection) && is_permutation(&k.perm, matrix.n)
    });
    let to_compute: Vec<OrderingKind> = kinds
        .iter()
        .copied()
        .filter(|&k| known.is_none() || k != OrderingKind::NestedDissection)
        .collect();
    // the candidates and the counter are independent: compute them in
    // parallel, then predict each candidate's fill
    let (counter, computed) = rayon::join(
        || (!to_compute.is_empty()).then(|| FillCounter::new(matrix)),
        || {
            to_compute
                .par_iter()
                .map(|&k| (k, compute(k, matrix, coords)))
                .collect::<Vec<_>>()
        },
    );
    let mut candidates: Vec<(OrderingKind, Vec<usize>, FillEstimate)> = Vec::new();
    if let Some(k) = known {
        let est = FillEstimate {
            nonzeros: k.nonzeros,
            flops: k.flops,
        };
        candidates.push((OrderingKind::NestedDissection, k.perm.clone(), est));
    }
    for (k, perm) in computed {
        let est = counter
            .as_ref()
            .map(|c| c.predict(&perm))
            .unwrap_or_default();
        candidates.push((k, perm, est));
    }
    let weighted = |k: OrderingKind, e: &FillEstimate| {
        if k == OrderingKind::NestedDissection {
            e.flops * nd_weight
        } else {
            e.flops
        }
    };
    let best = (0..candidates.len()).min_by(|&a, &b| {
        let (ka, _, ea) = &candidates[a];
        let (kb, _, eb) = &candidates[b];
        weighted(*ka, ea).total_cmp(&weighted(*kb, eb))
    });
    let (perm, kept) = match best {
        Some(b) => (std::mem::take(&mut candidates[b].1), candidates[b].0),
        None => (Vec::new(), OrderingKind::Natural),
    };
    let choice = OrderingChoice {
        perm,
        kind: kept,
        candidates: candidates.into_iter().map(|(k, _, e)| (k, e)).collect(),
        seconds: t0.elapsed().as_secs_f64(),
        nd_weight: if kinds.len() > 1 { nd_weight } else { 1.0 },
        dissection_reused: known.is_some(),
    };
    (choice, counter)
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

/// faer's AMD ordering (`perm[new] = old`), computed on the quotient
/// graph of the equation groups (the dofs of a node, see
/// [`equation_groups`]) and expanded group by group: the groups are
/// indistinguishable vertices, which minimum degree would eliminate
/// together anyway, and the quotient graph of a 3-dof mesh has about 9
/// times fewer edges (AMD takes ~0.15 s instead of ~1.2 s at 210k
/// equations). Matrices without groups are ordered as they are.
pub fn amd_ordering(matrix: &SymmetricCsc) -> Vec<usize> {
    let group_ptr = equation_groups(matrix, None);
    let ng = group_ptr.len() - 1;
    if ng == matrix.n {
        return amd_scalar(matrix);
    }
    let graph = group_graph(matrix, &group_ptr);
    let mut col_ptr = Vec::with_capacity(ng + 1);
    col_ptr.extend(graph.xadj.iter().copied());
    let mut row_idx: Vec<usize> = graph.adj.iter().map(|&u| u as usize).collect();
    for g in 0..ng {
        row_idx[col_ptr[g]..col_ptr[g + 1]].sort_unstable();
    }
    let mut order = vec![0usize; ng];
    let mut order_inv = vec![0usize; ng];
    let a = SymbolicSparseColMatRef::new_checked(ng, ng, &col_ptr, None, &row_idx);
    let mut mem = MemBuffer::new(amd::order_scratch::<usize>(ng, row_idx.len()));
    match amd::order(
        &mut order,
        &mut order_inv,
        a,
        amd::Control::default(),
        MemStack::new(&mut mem),
    ) {
        Ok(_) => {
            let mut perm = Vec::with_capacity(matrix.n);
            for &g in &order {
                perm.extend(group_ptr[g]..group_ptr[g + 1]);
            }
            perm
        }
        Err(e) => {
            tracing::warn!("AMD ordering of the node graph failed ({e:?}); ordering the equations");
            amd_scalar(matrix)
        }
    }
}

/// faer's AMD ordering of the matrix's own graph.
fn amd_scalar(matrix: &SymmetricCsc) -> Vec<usize> {
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

/// Elimination tree of a symmetric pattern by Liu's algorithm with path
/// compression: `parent[i]` (or `usize::MAX` for a root), from the
/// neighbours of each vertex `k` in elimination order (those `< k` are
/// used). `O(nnz log n)` at worst, near-linear in practice.
fn elimination_tree<I: Iterator<Item = usize>>(
    n: usize,
    neighbours: impl Fn(usize) -> I,
) -> Vec<usize> {
    const NONE: usize = usize::MAX;
    let mut parent = vec![NONE; n];
    let mut ancestor = vec![NONE; n];
    for k in 0..n {
        for i0 in neighbours(k) {
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
    parent
}

/// Exact number of non-zeros of the Cholesky factor `L` (diagonal
/// included) of `P A P^T` for the ordering `perm` (`None`: natural order).
///
/// Elimination tree by Liu's algorithm with path compression, then row
/// counts by walking, for every entry `a_ik` (`i < k`) of the permuted
/// upper triangle, the tree path from `i` towards `k` until a vertex already
/// marked for row `k`: the walk visits exactly the pattern of row `k` of
/// `L`, so the cost is `O(nnz(L))`. For statistics and tests; the solver
/// itself reads its factor size from its symbolic structure
/// ([`crate::symbolic`]).
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
    let parent = elimination_tree(n, |k| {
        a.row_idx[a.col_ptr[k]..a.col_ptr[k + 1]].iter().copied()
    });
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

/// Predicts the factor fill of orderings of one matrix ([`predict_fill`]).
///
/// The equations are first merged into groups of consecutive equations
/// with identical closed neighbourhoods ([`equation_groups`] without
/// coordinates: the dofs of a node). Equations of a group are
/// indistinguishable: when an ordering keeps every group contiguous, the
/// columns of a group `g` of `w_g` equations share the row structure of
/// the group's column in the quotient graph, so with the weighted column
/// count `C_g` (the sum of `w_h` over the groups `h` in column `g` of the
/// quotient factor, `g` included) the group adds `sum_{t < w_g} (C_g - t)
/// = w_g C_g - w_g (w_g - 1) / 2` non-zeros and `sum_{t < w_g} (C_g -
/// t)^2` flops. Orderings that split groups are counted on the graph of
/// their runs (stretches of one group, [`FillCounter`]'s `run_graph`).
///
/// Column counts by the algorithm of Gilbert, Ng and Peyton (1994), as in
/// Davis' CSparse `cs_counts`, with weights: elimination tree (Liu, path
/// compression), its postorder, then for every row `r` the leaves of its
/// row subtree `T_r` (the columns `j < r` of row `r` of `A` whose first
/// descendant comes after the previous leaf's) add `w_r` at the leaf and
/// subtract it at the least common ancestor of consecutive leaves (found
/// by union-find); every non-root `j` subtracts `w_j` at its parent, every
/// leaf of the tree adds its own weight; `C_j` is the sum of these
/// differences over the subtree of `j`. Cost `O(nnz(A) alpha(n))`, with no
/// dependence on the size of `L`.
pub struct FillCounter {
    n: usize,
    group_ptr: Vec<usize>,
    group_of: Vec<u32>,
    graph: Graph,
}

impl FillCounter {
    /// Groups and quotient graph of `matrix`.
    pub fn new(matrix: &SymmetricCsc) -> Self {
        let group_ptr = equation_groups(matrix, None);
        let ng = group_ptr.len() - 1;
        let mut group_of = vec![0u32; matrix.n];
        for g in 0..ng {
            group_of[group_ptr[g]..group_ptr[g + 1]].fill(g as u32);
        }
        let graph = group_graph(matrix, &group_ptr);
        FillCounter {
            n: matrix.n,
            group_ptr,
            group_of,
            graph,
        }
    }

    /// Predicted fill of `perm` (`perm[new] = old`, a permutation of the
    /// matrix's equations).
    pub fn predict(&self, perm: &[usize]) -> FillEstimate {
        debug_assert_eq!(perm.len(), self.n);
        self.with_quotient(perm, weighted_counts)
    }

    /// The supernodal structure of the factor of `perm` computed on the
    /// quotient graph ([`crate::symbolic`]), amalgamated (`relax`) or
    /// fundamental.
    pub(crate) fn supernodes(&self, perm: &[usize], relax: bool) -> crate::symbolic::Supernodes {
        debug_assert_eq!(perm.len(), self.n);
        self.with_quotient(perm, |graph, w, order| {
            crate::symbolic::Supernodes::of_groups(graph, w, order, relax)
        })
    }

    /// `f(graph, w, order)` on the quotient graph of `perm`: the groups'
    /// graph when `perm` keeps every group contiguous, else the graph of
    /// its runs ([`Self::run_graph`]).
    fn with_quotient<R>(&self, perm: &[usize], f: impl Fn(&Graph, &[usize], &[u32]) -> R) -> R {
        if let Some(order) = self.group_order(perm) {
            let w: Vec<usize> = (0..self.group_ptr.len() - 1)
                .map(|g| self.group_ptr[g + 1] - self.group_ptr[g])
                .collect();
            f(&self.graph, &w, &order)
        } else {
            let (graph, w) = self.run_graph(perm);
            let order: Vec<u32> = (0..w.len() as u32).collect();
            f(&graph, &w, &order)
        }
    }

    /// The quotient graph of the runs of `perm` (maximal stretches of
    /// consecutive positions whose equations lie in one group) and the
    /// size of each run; runs are numbered in the order of `perm`. The
    /// equations of a group have one closed neighbourhood, so they are
    /// adjacent to each other and to the same other groups: run `r` of
    /// group `g` neighbours the other runs of `g` and every run of the
    /// groups next to `g`. An ordering that splits groups (nested
    /// dissection by coordinates parts two corner nodes of one element
    /// that hashing joins; AMD on equations) is then still counted on a
    /// graph smaller than the equations'.
    fn run_graph(&self, perm: &[usize]) -> (Graph, Vec<usize>) {
        let n = perm.len();
        let group = |p: usize| self.group_of[perm[p]] as usize;
        let mut run_ptr = vec![0usize];
        for p in 1..n {
            if group(p) != group(p - 1) {
                run_ptr.push(p);
            }
        }
        run_ptr.push(n);
        let nr = run_ptr.len() - 1;
        let ng = self.group_ptr.len() - 1;
        let mut runs_ptr = vec![0usize; ng + 1];
        for r in 0..nr {
            runs_ptr[group(run_ptr[r]) + 1] += 1;
        }
        for g in 0..ng {
            runs_ptr[g + 1] += runs_ptr[g];
        }
        let mut next = runs_ptr.clone();
        let mut runs = vec![0u32; nr];
        for r in 0..nr {
            let g = group(run_ptr[r]);
            runs[next[g]] = r as u32;
            next[g] += 1;
        }
        let runs_of = |g: usize| &runs[runs_ptr[g]..runs_ptr[g + 1]];
        let mut xadj = Vec::with_capacity(nr + 1);
        xadj.push(0usize);
        let mut adj = Vec::new();
        for r in 0..nr {
            let g = group(run_ptr[r]);
            adj.extend(runs_of(g).iter().filter(|&&q| q as usize != r));
            for &h in self.graph.neighbours(g) {
                adj.extend_from_slice(runs_of(h as usize));
            }
            xadj.push(adj.len());
        }
        let w = run_ptr.windows(2).map(|p| p[1] - p[0]).collect();
        (Graph { xadj, adj }, w)
    }

    /// The sequence of groups of `perm` when it keeps every group
    /// contiguous, else `None`.
    fn group_order(&self, perm: &[usize]) -> Option<Vec<u32>> {
        let ng = self.group_ptr.len() - 1;
        let mut order = Vec::with_capacity(ng);
        let mut k = 0;
        while k < perm.len() {
            let g = self.group_of[perm[k]] as usize;
            let w = self.group_ptr[g + 1] - self.group_ptr[g];
            if k + w > perm.len()
                || perm[k..k + w]
                    .iter()
                    .any(|&e| self.group_of[e] as usize != g)
            {
                return None;
            }
            order.push(g as u32);
            k += w;
        }
        // each group once (true when the groups are contiguous and perm is
        // a permutation)
        (order.len() == ng).then_some(order)
    }
}

/// Predicted fill of the ordering `perm` of `matrix` (see [`FillCounter`];
/// build one counter to compare several orderings of one matrix).
pub fn predict_fill(matrix: &SymmetricCsc, perm: &[usize]) -> FillEstimate {
    FillCounter::new(matrix).predict(perm)
}

/// Weighted column counts of the Cholesky factor of the graph `graph`
/// (vertex weights `w`) eliminated in the order `order` (`order[new] =
/// vertex`); see [`FillCounter`].
fn weighted_counts(graph: &Graph, w: &[usize], order: &[u32]) -> FillEstimate {
    let (_, counts) = weighted_column_counts(graph, w, order);
    let mut est = FillEstimate::default();
    for (j, &c) in counts.iter().enumerate() {
        let wg = w[order[j] as usize];
        est.nonzeros += wg * c - wg * (wg - 1) / 2;
        for t in 0..wg {
            let ct = (c - t) as f64;
            est.flops += ct * ct;
        }
    }
    est
}

/// The elimination tree (`parent[k]`, `usize::MAX` for a root) and the
/// weighted column counts `C_k` of the Cholesky factor of the graph
/// `graph` (vertex weights `w`) eliminated in the order `order`, both in
/// the elimination numbering (`order[k]` is the `k`-th vertex); see
/// [`FillCounter`].
pub(crate) fn weighted_column_counts(
    graph: &Graph,
    w: &[usize],
    order: &[u32],
) -> (Vec<usize>, Vec<usize>) {
    const NONE: usize = usize::MAX;
    let n = order.len();
    let mut inv = vec![0usize; n];
    for (k, &v) in order.iter().enumerate() {
        inv[v as usize] = k;
    }
    let neighbours = |k: usize| {
        graph
            .neighbours(order[k] as usize)
            .iter()
            .map(|&u| inv[u as usize])
    };
    // elimination tree (new numbering)
    let parent = elimination_tree(n, neighbours);
    // postorder: children lists, then an explicit-stack depth-first search
    let mut head = vec![NONE; n];
    let mut next = vec![NONE; n];
    for j in (0..n).rev() {
        if parent[j] != NONE {
            next[j] = head[parent[j]];
            head[parent[j]] = j;
        }
    }
    let mut post = Vec::with_capacity(n);
    let mut stack = Vec::new();
    for (root, _) in parent.iter().enumerate().filter(|(_, &p)| p == NONE) {
        stack.push(root);
        while let Some(&top) = stack.last() {
            let child = head[top];
            if child == NONE {
                stack.pop();
                post.push(top);
            } else {
                head[top] = next[child];
                stack.push(child);
            }
        }
    }
    debug_assert_eq!(post.len(), n);
    // first descendant (postorder index) and leaf deltas
    let mut first = vec![NONE; n];
    let mut delta = vec![0i64; n];
    for (k, &j0) in post.iter().enumerate() {
        if first[j0] == NONE {
            delta[j0] = w[order[j0] as usize] as i64; // a leaf of the tree
        }
        let mut j = j0;
        while j != NONE && first[j] == NONE {
            first[j] = k;
            j = parent[j];
        }
    }
    let mut maxfirst = vec![NONE; n];
    let mut prevleaf = vec![NONE; n];
    let mut uf: Vec<usize> = (0..n).collect();
    for &j in &post {
        let wj = w[order[j] as usize] as i64;
        if parent[j] != NONE {
            delta[parent[j]] -= wj;
        }
        for i in neighbours(j) {
            if i <= j || (maxfirst[i] != NONE && first[j] <= maxfirst[i]) {
                continue; // j is not a new leaf of row subtree i
            }
            let wi = w[order[i] as usize] as i64;
            maxfirst[i] = first[j];
            let jprev = prevleaf[i];
            prevleaf[i] = j;
            delta[j] += wi;
            if jprev != NONE {
                // least common ancestor of jprev and j, with path compression
                let mut q = jprev;
                while q != uf[q] {
                    q = uf[q];
                }
                let mut s = jprev;
                while s != q {
                    let sp = uf[s];
                    uf[s] = q;
                    s = sp;
                }
                delta[q] -= wi;
            }
        }
        if parent[j] != NONE {
            uf[j] = parent[j];
        }
    }
    for j in 0..n {
        if parent[j] != NONE {
            delta[parent[j]] += delta[j];
        }
    }
    let counts = delta.into_iter().map(|d| d as usize).collect();
    (parent, counts)
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
        lower: Vec::new(),
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
pub(crate) struct Graph {
    xadj: Vec<usize>,
    adj: Vec<u32>,
}

impl Graph {
    #[inline]
    pub(crate) fn neighbours(&self, v: usize) -> &[u32] {
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
    nested_dissection_with(matrix, coords, false)
}

/// [`nested_dissection`]; with `longest_extent_only`, the geometric cut is
/// always across the longest extent of the bounding box (the rule before
/// the cut with the smallest separator was chosen; kept for the test that
/// shows why).
fn nested_dissection_with(
    matrix: &SymmetricCsc,
    coords: Option<&[[f64; 3]]>,
    longest_extent_only: bool,
) -> Vec<usize> {
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
        longest_extent_only,
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
    /// Only cut across the longest extent (see [`nested_dissection_with`]).
    longest_extent_only: bool,
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
        // Candidate splits into part 1 and part 2 (one per axis with a
        // positive extent, or the graph split); keep the one whose vertex
        // separator is smallest relative to the smaller part.
        let mut splits = self.geometric_splits(&set);
        if splits.is_empty() {
            splits.extend(self.graph_split(&set));
        }
        let mut best: Option<(f64, Vec<bool>, Vec<u32>)> = None;
        for in_part2 in splits {
            let sep = self.separator(&set, &in_part2);
            let n2 = in_part2.iter().filter(|&&b| b).count();
            let smaller = n2.min(set.len() - n2).saturating_sub(sep.len());
            let score = sep.len() as f64 / (smaller as f64 + 1.0);
            if best.as_ref().is_none_or(|b| score < b.0) {
                best = Some((score, in_part2, sep));
            }
        }
        let Some((_, in_part2, sep)) = best else {
            // Could not split (should not happen with |set| > 1): order by AMD.
            self.leaf(&set);
            return;
        };
        for (k, &v) in set.iter().enumerate() {
            self.label[v as usize] = if in_part2[k] { 2 } else { 1 };
        }
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

    /// Vertex separator of the split `in_part2` of `set`: the vertices of
    /// part 2 with a neighbour in part 1, or those of part 1 with a
    /// neighbour in part 2, whichever set is smaller. Labels are left at 0.
    fn separator(&mut self, set: &[u32], in_part2: &[bool]) -> Vec<u32> {
        for (k, &v) in set.iter().enumerate() {
            self.label[v as usize] = if in_part2[k] { 2 } else { 1 };
        }
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
        for &v in set {
            self.label[v as usize] = 0;
        }
        if b1.len() < b2.len() {
            b1
        } else {
            b2
        }
    }

    /// Median cuts across every axis along which the points of `set` are
    /// not all equal (none without coordinates or when all points
    /// coincide). The caller keeps the cut with the smallest separator:
    /// the longest extent of the bounding box alone is not enough, because
    /// a mesh may be much finer along a shorter side (a beam 1 x 0.1 x 0.1
    /// with 10 x 1 x 1000 elements: cuts across the long side `x` are
    /// planes of ~5000 nodes, cuts across `z` planes of ~60).
    fn geometric_splits(&mut self, set: &[u32]) -> Vec<Vec<bool>> {
        let Some(pts) = self.points else {
            return Vec::new();
        };
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for &v in set {
            let p = pts[v as usize];
            for a in 0..3 {
                lo[a] = lo[a].min(p[a]);
                hi[a] = hi[a].max(p[a]);
            }
        }
        let mut splits = Vec::with_capacity(3);
        let mut keys: Vec<f64> = Vec::with_capacity(set.len());
        let longest = (0..3)
            .max_by(|&a, &b| (hi[a] - lo[a]).total_cmp(&(hi[b] - lo[b])))
            .unwrap_or(0);
        for axis in 0..3 {
            if hi[axis] <= lo[axis] || (self.longest_extent_only && axis != longest) {
                continue;
            }
            keys.clear();
            keys.extend(set.iter().map(|&v| pts[v as usize][axis]));
            let mid = keys.len() / 2;
            let m = *keys.select_nth_unstable_by(mid, f64::total_cmp).1;
            let below = set.iter().any(|&v| pts[v as usize][axis] < m);
            // Part 2 is x >= m (ties fall wholly on one side, so on a
            // structured grid the cut is a grid plane), or x > m when the
            // whole lower half sits on m (then some point lies above m
            // because hi > lo = m).
            splits.push(if below {
                set.iter().map(|&v| pts[v as usize][axis] >= m).collect()
            } else {
                set.iter().map(|&v| pts[v as usize][axis] > m).collect()
            });
        }
        splits
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

    /// Fisher-Yates shuffle with a fixed linear congruential generator.
    fn shuffled(n: usize, seed: u64) -> Vec<usize> {
        let mut p: Vec<usize> = (0..n).collect();
        let mut x = seed;
        for i in (1..n).rev() {
            x = x
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            p.swap(i, (x >> 33) as usize % (i + 1));
        }
        p
    }

    #[test]
    fn predicted_fill_matches_the_row_count_walk() {
        // The column-count prediction (Gilbert-Ng-Peyton, on node groups
        // or on equations) against the independent row-subtree walk of
        // `factor_nonzeros`, for orderings that keep the nodes' dofs
        // together and for ones that do not.
        let (a, coords) = gallery::grid_3d(7, 5, 6, 3, gallery::Stencil::Point27);
        let counter = FillCounter::new(&a);
        let nodes = a.n / 3;
        let node_shuffle: Vec<usize> = shuffled(nodes, 7)
            .into_iter()
            .flat_map(|v| [3 * v, 3 * v + 1, 3 * v + 2])
            .collect();
        let perms = [
            (0..a.n).collect::<Vec<_>>(),
            nested_dissection(&a, Some(&coords)),
            nested_dissection(&a, None),
            amd_ordering(&a),
            node_shuffle,
            shuffled(a.n, 11), // splits the groups: counted per equation
        ];
        for (k, p) in perms.iter().enumerate() {
            let exact = factor_nonzeros(&a, Some(p));
            let est = counter.predict(p);
            assert_eq!(est.nonzeros, exact, "ordering {k}");
            // flops >= nnz^2 / n (Cauchy-Schwarz) and <= n_max * nnz
            assert!(est.flops >= (exact as f64).powi(2) / a.n as f64);
            assert!(est.flops <= (a.n * exact) as f64);
        }
        // a 1x1 and an empty matrix
        let mut one = SymmetricCsc::from_columns(vec![vec![0]]);
        one.values = vec![1.0];
        assert_eq!(predict_fill(&one, &[0]).nonzeros, 1);
    }

    /// A slender grid whose mesh is finest along a shorter side: 10 x 2 x
    /// 400 nodes (27-point stencil, 3 dofs per node, 24,000 equations)
    /// spaced 1 along x and 0.01 along z, so the bounding box is 9 x 1 x
    /// 3.99 (the shape of the cantilever 1 x 0.1 x 0.1 meshed 10 x 1 x 1000).
    fn slender_grid() -> (SymmetricCsc, Vec<[f64; 3]>) {
        let (a, mut coords) = gallery::grid_3d(10, 2, 400, 3, gallery::Stencil::Point27);
        for p in &mut coords {
            p[2] *= 0.01;
        }
        (a, coords)
    }

    #[test]
    fn nested_dissection_cuts_slender_meshes_across_their_fine_axis() {
        let (a, coords) = slender_grid();
        let counter = FillCounter::new(&a);
        let old = counter.predict(&nested_dissection_with(&a, Some(&coords), true));
        let nd = counter.predict(&nested_dissection(&a, Some(&coords)));
        let amd = counter.predict(&amd_ordering(&a));
        let ratio = |e: FillEstimate| e.nonzeros as f64 / amd.nonzeros as f64;
        println!(
            "slender grid 10x2x400: nnz(L) longest-extent ND {} ({:.1} x AMD), ND {} ({:.2} x AMD), AMD {}",
            old.nonzeros,
            ratio(old),
            nd.nonzeros,
            ratio(nd),
            amd.nonzeros
        );
        // the longest-extent rule cuts planes of 2 x 400 nodes: many times
        // AMD's fill; the smallest-separator cut planes of 10 x 2 nodes
        assert!(ratio(old) > 5.0, "{}", ratio(old));
        assert!(ratio(nd) < 1.5, "{}", ratio(nd));
        // auto keeps the candidate with the fewest flops, whose fill is
        // within a few percent of the smallest
        let auto = choose(OrderingKind::Auto, &a, Some(&coords));
        assert!(is_permutation(&auto.perm, a.n));
        assert_eq!(auto.candidates.len(), 2);
        let best_nnz = auto.candidates.iter().map(|c| c.1.nonzeros).min().unwrap();
        let best_flops = auto
            .candidates
            .iter()
            .map(|c| c.1.flops)
            .fold(f64::INFINITY, f64::min);
        assert_eq!(auto.estimate().flops, best_flops);
        assert!(
            auto.estimate().nonzeros as f64 <= 1.05 * best_nnz as f64,
            "{}",
            auto.note()
        );
        assert_eq!(counter.predict(&auto.perm), auto.estimate());
        assert!(
            auto.note().starts_with("ordering auto: nested_dissection"),
            "{}",
            auto.note()
        );
        assert!(auto.note().ends_with(&format!("kept {}", auto.kind.name())));
    }

    #[test]
    fn auto_keeps_nested_dissection_on_a_cube() {
        // 24^3 nodes, 27-point stencil, 3 dofs per node (41,472 equations):
        // minimum degree's last fronts on a 3D mesh are much larger than the
        // separators of nested dissection
        let (a, coords) = gallery::grid_3d(24, 24, 24, 3, gallery::Stencil::Point27);
        let auto = choose(OrderingKind::Auto, &a, Some(&coords));
        let nd = auto.candidates[0].1;
        let amd = auto.candidates[1].1;
        println!("cube 24^3: {}", auto.note());
        assert_eq!(auto.kind, OrderingKind::NestedDissection);
        assert!(nd.nonzeros < amd.nonzeros, "{}", auto.note());
        assert!(nd.flops < amd.flops, "{}", auto.note());
        // a fixed kind computes only itself
        let fixed = choose(OrderingKind::Amd, &a, Some(&coords));
        assert_eq!(fixed.kind, OrderingKind::Amd);
        assert_eq!(fixed.candidates, vec![(OrderingKind::Amd, amd)]);
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
