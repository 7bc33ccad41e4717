//! Supernodal Cholesky numeric kernels in panel storage, generic over the
//! working precision (`f64`, or `f32` for the mixed-precision mode of
//! [`crate::CholeskySolver`]).
//!
//! The structure ([`PanelFactor`]) comes from the supernodal symbolic
//! analysis ([`crate::symbolic`]) and does not depend on the precision; the values live in a
//! separate buffer (`Vec<T>`) so that one structure serves a single- and a
//! double-precision factor. The maths:
//!
//! * factorisation `P A P^T = L L^T`, left-looking over panels: panel `s`
//!   (columns `J`) receives `A[J', J] - sum_d L[J', K_d] L[J, K_d]^T` from
//!   every descendant panel `d` whose rows meet `J` (`J'` = `J` plus the
//!   rows below), then the dense Cholesky of its diagonal block
//!   `L[J, J] L[J, J]^T` and the triangular solve `L[R, J] = A'[R, J]
//!   L[J, J]^-T` for the rows `R` below it;
//! * solve `L y = b` (forward, panels in order) and `L^T x = y` (backward,
//!   panels in reverse order).

use crate::ordering::{self, OrderingKind};
use crate::symbolic::Supernodes;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::{LltError as DenseLltError, LltRegularization};
use faer::reborrow::{Reborrow, ReborrowMut};
use faer::{Accum, MatMut, MatRef, Par};
use junta_core::{PrecomputedDissection, SolverError, SymmetricCsc};
use rayon::prelude::*;

/// Working precision of a factor: `f64` or `f32`.
pub(crate) trait FactorScalar:
    faer::traits::RealField + Copy + Send + Sync + Default + 'static
{
    /// Rounded from `f64`.
    fn of_f64(x: f64) -> Self;
    /// Widened to `f64`.
    fn to_f64(self) -> f64;
}

impl FactorScalar for f64 {
    #[inline(always)]
    fn of_f64(x: f64) -> Self {
        x
    }
    #[inline(always)]
    fn to_f64(self) -> f64 {
        self
    }
}

impl FactorScalar for f32 {
    #[inline(always)]
    fn of_f64(x: f64) -> Self {
        x as f32
    }
    #[inline(always)]
    fn to_f64(self) -> f64 {
        self as f64
    }
}

/// Widest block of columns stored as one dense panel. faer's supernodal
/// layout stores the whole square diagonal block of every supernode (the
/// root separator of a 100k-equation cube is a 5459-column supernode: 120 MB
/// of zeros above its diagonal); splitting wide supernodes into panels of at
/// most this width bounds that waste by `PANEL / 2` entries per column.
pub(crate) const PANEL: usize = 256;

/// Branching depth of the elimination tree down to which subtrees become
/// separate rayon tasks (2^depth subtrees is plenty for a few threads).
const MAX_TASK_DEPTH: usize = 12;

/// Supernodal Cholesky factor `P A P^T = L L^T` in panel storage, factorised
/// left-looking with subtree parallelism (independent subtrees of the
/// supernodal elimination tree run as rayon tasks; the dense kernels of
/// large panels run in parallel too). The supernode partition and row
/// structure come from [`crate::symbolic`]; wide supernodes are split
/// into panels (a panel of a supernode is itself a valid supernode whose
/// structure is the rest of its supernode plus the supernode's rows).
///
/// Panel `s` covers the permuted columns `begin[s]..begin[s + 1]` (width
/// `w`), with below-diagonal rows `pat[pat_ptr[s]..pat_ptr[s + 1]]` (`r`
/// rows); its values are the column-major `(w + r) x w` block at
/// `values[val_ptr[s]..]` (the upper triangle of the `w x w` diagonal block
/// is unused).
#[derive(Debug, Default)]
pub(crate) struct PanelFactor {
    pub(crate) n: usize,
    pub(crate) begin: Vec<usize>,
    pub(crate) pat_ptr: Vec<usize>,
    pub(crate) pat: Vec<u32>,
    pub(crate) val_ptr: Vec<usize>,
    /// Panel of each permuted column.
    pub(crate) panel_of: Vec<u32>,
    /// Parent of each panel in the panel elimination tree (`u32::MAX`
    /// for a root); a parent is numbered after its children.
    pub(crate) parent: Vec<u32>,
    /// Multiply-adds of each panel's numeric factorisation: the
    /// left-looking updates it receives plus its dense block (the work a
    /// partial refactorisation of the panel redoes).
    pub(crate) work: Vec<f64>,
    /// Children in the panel elimination tree (CSR) and the roots.
    pub(crate) child_ptr: Vec<usize>,
    pub(crate) child: Vec<u32>,
    pub(crate) roots: Vec<u32>,
    /// Descendants updating each panel (CSR).
    pub(crate) desc_ptr: Vec<usize>,
    pub(crate) desc: Vec<u32>,
}

/// Where the entries of a matrix go in the panel values, both ways
/// ([`PanelFactor::scatter_index`]).
#[derive(Debug, Default)]
pub(crate) struct ScatterIndex {
    /// Position in the panel values of each stored entry of `A`.
    pub(crate) pos: Vec<usize>,
    /// Panel of each stored entry.
    pub(crate) panel: Vec<u32>,
    /// Entries of each panel: `entries[entry_ptr[s]..entry_ptr[s + 1]]`.
    entry_ptr: Vec<usize>,
    entries: Vec<usize>,
}

/// Stored factor entries from which the triangular solves run a
/// [`SolvePlan`]'s subtrees in parallel by default (`ldlt` and `cholesky`
/// `parallel_solve_entries`): a solve is memory-bound, and below this the
/// threads' hand-over costs more than it saves.
pub(crate) const PARALLEL_SOLVE_ENTRIES: usize = 1 << 20;

/// The independent parts of a triangular solve with a [`PanelFactor`].
/// Below the first branching of each root's chain, the subtrees (`tasks`,
/// each a contiguous range of panels and so of columns) touch only their
/// own columns and those of their root's chain (`tops`: the panels from
/// the branching panel up to the root, also contiguous); so the forward
/// solve runs the tasks in parallel, each adding its updates of the chain's
/// rows into its own buffer, then the chains; the backward solve runs the
/// chains, then the tasks in parallel (they read the chain's rows only).
#[derive(Debug, Default, Clone)]
pub(crate) struct SolvePlan {
    pub(crate) tasks: Vec<SolveTask>,
    /// `(first, last)` panel of each chain.
    pub(crate) tops: Vec<(usize, usize)>,
    /// The tasks grouped for the threads ([`SolvePlan::balance`]): each
    /// group runs its tasks in order, the groups in parallel.
    pub(crate) groups: Vec<Vec<usize>>,
}

impl SolvePlan {
    /// Group the tasks for `threads` threads, largest first into the
    /// lightest group (a solve reads each stored entry once, so a task
    /// weighs its entries).
    pub(crate) fn balance(&mut self, threads: usize) {
        let mut order: Vec<usize> = (0..self.tasks.len()).collect();
        order.sort_by_key(|&t| std::cmp::Reverse(self.tasks[t].entries));
        let mut groups = vec![(0usize, Vec::new()); threads.clamp(1, self.tasks.len().max(1))];
        for t in order {
            let g = groups
                .iter_mut()
                .min_by_key(|(w, _)| *w)
                .expect("at least one group");
            g.0 += self.tasks[t].entries;
            g.1.push(t);
        }
        self.groups = groups
            .into_iter()
            .map(|(_, mut g)| {
                g.sort_unstable();
                g
            })
            .filter(|g| !g.is_empty())
            .collect();
    }
}

impl SolvePlan {
    /// Columns `first..end` of chain `t`, for a factor whose panel `s`
    /// starts at column `begin[s]`.
    pub(crate) fn top_columns(&self, begin: &[usize], t: usize) -> (usize, usize) {
        let (lo, hi) = self.tops[t];
        (begin[lo], begin[hi + 1])
    }

    /// The forward steps of the tasks, the groups in parallel: for each
    /// task, `step(s, own_end, acc, acc_begin, scratch)` on its panels in
    /// order, where `own_end` is the end of the task's columns and `acc`
    /// (`width` times the chain's columns, zeroed, from column
    /// `acc_begin`) takes its updates of the chain's rows. Returns each
    /// task's `(task, acc)`, for the caller to subtract.
    pub(crate) fn forward_tasks<T, S, F>(
        &self,
        begin: &[usize],
        width: usize,
        step: F,
    ) -> Vec<(usize, Vec<T>)>
    where
        T: Clone + Default + Send,
        S: Default,
        F: Fn(usize, usize, &mut [T], usize, &mut S) + Sync,
    {
        self.groups
            .par_iter()
            .flat_map_iter(|group| {
                let mut scratch = S::default();
                group
                    .iter()
                    .map(|&ti| {
                        let t = &self.tasks[ti];
                        let (t0, t1) = self.top_columns(begin, t.top);
                        let mut acc = vec![T::default(); width * (t1 - t0)];
                        let own_end = begin[t.hi + 1];
                        for s in t.lo..=t.hi {
                            step(s, own_end, &mut acc, t0, &mut scratch);
                        }
                        (ti, acc)
                    })
                    .collect::<Vec<_>>()
            })
            .collect()
    }

    /// The backward steps of the tasks, the groups in parallel:
    /// `step(s, scratch)` on each task's panels in reverse order.
    pub(crate) fn backward_tasks<S, F>(&self, step: F)
    where
        S: Default,
        F: Fn(usize, &mut S) + Sync,
    {
        self.groups.par_iter().for_each(|group| {
            let mut scratch = S::default();
            for &ti in group {
                let t = &self.tasks[ti];
                for s in (t.lo..=t.hi).rev() {
                    step(s, &mut scratch);
                }
            }
        });
    }
}

/// One subtree of a [`SolvePlan`]: panels `lo..=hi`, below chain `top`.
#[derive(Debug, Default, Clone, Copy)]
pub(crate) struct SolveTask {
    pub(crate) lo: usize,
    pub(crate) hi: usize,
    pub(crate) top: usize,
    /// Stored factor entries of the panels.
    pub(crate) entries: usize,
}

/// `dst (+)= alpha lhs rhs^T` where the top `mid x mid` block of the
/// product (`mid` = rows of `rhs`) is symmetric: only its lower triangle is
/// computed (the rest of `dst`'s top block is left alone), then the
/// rectangle below it with a plain product.
pub(crate) fn sym_update<T: FactorScalar>(
    dst: MatMut<'_, T>,
    lhs: MatRef<'_, T>,
    rhs: MatRef<'_, T>,
    beta: Accum,
    alpha: T,
    par: Par,
) {
    use faer::linalg::matmul::triangular::{self, BlockStructure};
    let mid = rhs.nrows();
    let (dst_top, dst_bot) = dst.split_at_row_mut(mid);
    let (lhs_top, lhs_bot) = lhs.split_at_row(mid);
    triangular::matmul(
        dst_top,
        BlockStructure::TriangularLower,
        beta,
        lhs_top,
        BlockStructure::Rectangular,
        rhs.transpose(),
        BlockStructure::Rectangular,
        alpha,
        par,
    );
    if dst_bot.nrows() > 0 {
        faer::linalg::matmul::matmul(dst_bot, beta, lhs_bot, rhs.transpose(), alpha, par);
    }
}

/// Pointer wrapper for writes to disjoint parts of the factor from rayon tasks.
pub(crate) struct SharedPtr<T>(pub(crate) *mut T);
impl<T> Clone for SharedPtr<T> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<T> Copy for SharedPtr<T> {}
unsafe impl<T> Send for SharedPtr<T> {}
unsafe impl<T> Sync for SharedPtr<T> {}
impl<T> SharedPtr<T> {
    /// The pointer (a method, so closures capture the `Sync` wrapper).
    #[inline]
    pub(crate) fn get(self) -> *mut T {
        self.0
    }
}

/// Threads of a `Par`.
pub(crate) fn threads_of(par: Par) -> usize {
    match par {
        Par::Seq => 1,
        Par::Rayon(t) => t.get(),
    }
}

/// The symbolic analysis shared by the direct back ends (Cholesky and
/// LDL^T): the fill-reducing ordering, the supernodal symbolic Cholesky
/// on it, and the panel structure.
pub(crate) struct Analysis {
    /// `perm[new] = old`, and its inverse.
    pub(crate) perm: Vec<usize>,
    pub(crate) perm_inv: Vec<usize>,
    pub(crate) factor: PanelFactor,
    /// Seconds of the ordering computation.
    pub(crate) ordering_seconds: f64,
    /// The ordering kept (for `auto`, the candidate with fewer predicted
    /// flops), the predicted factor non-zeros of every candidate, and a
    /// note saying so.
    pub(crate) kind: OrderingKind,
    pub(crate) candidates: Vec<(OrderingKind, ordering::FillEstimate)>,
    pub(crate) ordering_note: String,
    /// The nested dissection came from the caller
    /// ([`junta_core::LinearSolver::offer_dissection`]).
    pub(crate) dissection_reused: bool,
}

/// Ordering `kind` of `matrix` ([`ordering::choose_reusing`], with `coords`
/// for the geometric orderings and `known` a nested dissection computed
/// earlier), then the supernodal symbolic Cholesky with that ordering
/// (elimination tree, column counts, supernodes, row structure of `L`) and
/// the panels. The symbolic step runs on the quotient graph of equation
/// groups ([`crate::symbolic`]), reusing the graph the ordering's fill
/// prediction built (the groups are split into runs where the ordering
/// parts them). The structure of an `L D L^T` factor without delayed
/// pivots is the same.
pub(crate) fn analyze(
    kind: OrderingKind,
    matrix: &SymmetricCsc,
    coords: Option<&[[f64; 3]]>,
    nd_weight: f64,
    known: Option<&PrecomputedDissection>,
) -> Result<Analysis, SolverError> {
    let t0 = std::time::Instant::now();
    let n = matrix.n;
    let (choice, counter) =
        ordering::choose_keeping_counter(kind, matrix, coords, nd_weight, known);
    let dissection_reused = choice.dissection_reused;
    let ordering_note = choice.note();
    let ordering::OrderingChoice {
        perm,
        kind,
        candidates,
        ..
    } = choice;
    debug_assert!(ordering::is_permutation(&perm, n));
    let ordering_seconds = t0.elapsed().as_secs_f64();
    let perm_inv = ordering::inverse(&perm);
    let counter = counter.unwrap_or_else(|| ordering::FillCounter::new(matrix));
    let supernodes = counter.supernodes(&perm, true);
    let factor = PanelFactor::new(&supernodes);
    Ok(Analysis {
        perm,
        perm_inv,
        factor,
        ordering_seconds,
        kind,
        candidates,
        ordering_note,
        dissection_reused,
    })
}

impl PanelFactor {
    pub(crate) fn n_panels(&self) -> usize {
        self.begin.len() - 1
    }

    /// Columns of the widest panel.
    #[cfg(test)]
    pub(crate) fn widest_panel(&self) -> usize {
        self.begin
            .windows(2)
            .map(|p| p[1] - p[0])
            .max()
            .unwrap_or(0)
    }

    pub(crate) fn pattern(&self, s: usize) -> &[u32] {
        &self.pat[self.pat_ptr[s]..self.pat_ptr[s + 1]]
    }

    /// Stored entries (lower trapezoids only).
    pub(crate) fn nonzeros(&self) -> usize {
        (0..self.n_panels())
            .map(|s| {
                let w = self.begin[s + 1] - self.begin[s];
                w * (w + 1) / 2 + w * (self.pat_ptr[s + 1] - self.pat_ptr[s])
            })
            .sum()
    }

    /// Panels of a supernodal symbolic structure.
    pub(crate) fn new(sym: &Supernodes) -> Self {
        let n = sym.n;
        let ns = sym.count();
        let mut begin = vec![0usize];
        let mut pat_ptr = vec![0usize];
        let mut pat: Vec<u32> = Vec::new();
        let mut val_ptr = vec![0usize];
        let pw = PANEL;
        for k in 0..ns {
            let (b, e) = (sym.bounds[k], sym.bounds[k + 1]);
            let below = sym.rows_of(k);
            let mut c0 = b;
            while c0 < e {
                let c1 = (c0 + pw).min(e);
                pat.extend((c1..e).map(|i| i as u32));
                pat.extend_from_slice(below);
                let r = (e - c1) + below.len();
                let w = c1 - c0;
                begin.push(c1);
                pat_ptr.push(pat.len());
                val_ptr.push(val_ptr.last().unwrap() + (w + r) * w);
                c0 = c1;
            }
        }
        let np = begin.len() - 1;
        let mut panel_of = vec![0u32; n];
        for s in 0..np {
            panel_of[begin[s]..begin[s + 1]].fill(s as u32);
        }
        // elimination tree of panels: parent = panel of the first row below
        let mut parent = vec![u32::MAX; np];
        let mut nchild = vec![0usize; np + 1];
        let mut roots = Vec::new();
        for s in 0..np {
            match pat[pat_ptr[s]..pat_ptr[s + 1]].first() {
                Some(&r) => {
                    let p = panel_of[r as usize];
                    parent[s] = p;
                    nchild[p as usize + 1] += 1;
                }
                None => roots.push(s as u32),
            }
        }
        for s in 0..np {
            nchild[s + 1] += nchild[s];
        }
        let child_ptr = nchild.clone();
        let mut next = nchild;
        let mut child = vec![0u32; np.saturating_sub(roots.len())];
        for (s, &ps) in parent.iter().enumerate() {
            if ps != u32::MAX {
                let p = ps as usize;
                child[next[p]] = s as u32;
                next[p] += 1;
            }
        }
        // descendants updating each panel: panels hit by d's rows
        let mut count = vec![0usize; np + 1];
        for d in 0..np {
            let mut last = u32::MAX;
            for &r in &pat[pat_ptr[d]..pat_ptr[d + 1]] {
                let s = panel_of[r as usize];
                if s != last {
                    count[s as usize + 1] += 1;
                    last = s;
                }
            }
        }
        for s in 0..np {
            count[s + 1] += count[s];
        }
        let desc_ptr = count.clone();
        let mut next = count;
        let mut desc = vec![0u32; desc_ptr[np]];
        for d in 0..np {
            let mut last = u32::MAX;
            for &r in &pat[pat_ptr[d]..pat_ptr[d + 1]] {
                let s = panel_of[r as usize];
                if s != last {
                    desc[next[s as usize]] = d as u32;
                    next[s as usize] += 1;
                    last = s;
                }
            }
        }
        // work of each panel: updates received (rows of d from s on, times
        // its rows within s, times its width) and the dense block
        let mut work = vec![0.0f64; np];
        for (s, ws) in work.iter_mut().enumerate() {
            let (b, e) = (begin[s], begin[s + 1]);
            let w = (e - b) as f64;
            let m = w + (pat_ptr[s + 1] - pat_ptr[s]) as f64;
            let mut acc = w * w * m;
            for &d in &desc[desc_ptr[s]..desc_ptr[s + 1]] {
                let d = d as usize;
                let pd = &pat[pat_ptr[d]..pat_ptr[d + 1]];
                let k0 = pd.partition_point(|&x| (x as usize) < b);
                let k1 = k0 + pd[k0..].partition_point(|&x| (x as usize) < e);
                acc += ((pd.len() - k0) * (k1 - k0) * (begin[d + 1] - begin[d])) as f64;
            }
            *ws = acc;
        }
        PanelFactor {
            n,
            begin,
            pat_ptr,
            pat,
            val_ptr,
            panel_of,
            parent,
            work,
            child_ptr,
            child,
            roots,
            desc_ptr,
            desc,
        }
    }

    pub(crate) fn len_val(&self) -> usize {
        *self.val_ptr.last().unwrap()
    }

    /// Numeric factorisation of `P A P^T` (`A` upper CSC, `perm_inv[old] =
    /// new`) into `values` (resized to [`Self::len_val`]; the allocation is
    /// reused when it already has that length). `Err(k)`: non-positive
    /// pivot at permuted column `k`.
    pub(crate) fn factorize<T: FactorScalar>(
        &self,
        values: &mut Vec<T>,
        a: &SymmetricCsc,
        perm_inv: &[usize],
        par: Par,
    ) -> Result<(), usize> {
        self.scatter(values, a, perm_inv);
        let ptr = SharedPtr(values.as_mut_ptr());
        let threads = threads_of(par);
        self.traverse(threads, |s, tmp: &mut Vec<T>| {
            self.factor_panel(s, ptr, threads, tmp)
        })
    }

    /// Resize `values` to [`Self::len_val`] (reusing the allocation when it
    /// already has that length), zero it and scatter `P A P^T` into it:
    /// entry `(i, j)` with `i >= j` goes to the panel of column `j`.
    pub(crate) fn scatter<T: FactorScalar>(
        &self,
        values: &mut Vec<T>,
        a: &SymmetricCsc,
        perm_inv: &[usize],
    ) {
        self.zeroed(values);
        let ptr = SharedPtr(values.as_mut_ptr());
        let this = self;
        (0..a.n).into_par_iter().with_min_len(256).for_each(|c| {
            let jc = perm_inv[c];
            for p in a.col_ptr[c]..a.col_ptr[c + 1] {
                let (_, q) = this.entry_position(perm_inv[a.row_idx[p]], jc);
                // SAFETY: every entry of A maps to its own position.
                unsafe { *ptr.get().add(q) = T::of_f64(a.values[p]) };
            }
        });
    }

    /// `values` resized to [`Self::len_val`] (the allocation reused when it
    /// already has that length) and zeroed.
    fn zeroed<T: FactorScalar>(&self, values: &mut Vec<T>) {
        if values.len() != self.len_val() {
            *values = Vec::new();
            *values = vec![T::default(); self.len_val()];
        } else {
            values.par_iter_mut().for_each(|v| *v = T::default());
        }
    }

    /// Panel and position in the panel values of the entry `(r, c)` of `P
    /// A P^T` (permuted numbering, either triangle): it is stored in the
    /// panel of column `min(r, c)`.
    fn entry_position(&self, r: usize, c: usize) -> (usize, usize) {
        let (i, j) = if r >= c { (r, c) } else { (c, r) };
        let s = self.panel_of[j] as usize;
        let (b, e) = (self.begin[s], self.begin[s + 1]);
        let w = e - b;
        let pat = self.pattern(s);
        let lr = if i < e {
            i - b
        } else {
            w + pat.binary_search(&(i as u32)).expect("structure covers A")
        };
        (s, self.val_ptr[s] + (j - b) * (w + pat.len()) + lr)
    }

    /// Where every stored entry of `a` (upper CSC, `perm_inv[old] = new`)
    /// goes in the panel values, and the entries of each panel: a scatter
    /// is then one indexed copy per panel (see [`Self::scatter_with`]).
    pub(crate) fn scatter_index(&self, a: &SymmetricCsc, perm_inv: &[usize]) -> ScatterIndex {
        let nnz = a.row_idx.len();
        let mut pos = vec![0usize; nnz];
        let mut panel = vec![0u32; nnz];
        let this = self;
        let (pp, pl) = (SharedPtr(pos.as_mut_ptr()), SharedPtr(panel.as_mut_ptr()));
        (0..a.n).into_par_iter().with_min_len(256).for_each(|c| {
            let jc = perm_inv[c];
            for p in a.col_ptr[c]..a.col_ptr[c + 1] {
                let (s, q) = this.entry_position(perm_inv[a.row_idx[p]], jc);
                // SAFETY: entry p is written by its column's task only.
                unsafe {
                    *pp.get().add(p) = q;
                    *pl.get().add(p) = s as u32;
                }
            }
        });
        // entries by panel (counting sort)
        let np = self.n_panels();
        let mut entry_ptr = vec![0usize; np + 1];
        for &s in &panel {
            entry_ptr[s as usize + 1] += 1;
        }
        for s in 0..np {
            entry_ptr[s + 1] += entry_ptr[s];
        }
        let mut next = entry_ptr.clone();
        let mut entries = vec![0usize; nnz];
        for (p, &s) in panel.iter().enumerate() {
            entries[next[s as usize]] = p;
            next[s as usize] += 1;
        }
        ScatterIndex {
            pos,
            panel,
            entry_ptr,
            entries,
        }
    }

    /// Scatter `a` into `values` through a [`ScatterIndex`]: every panel,
    /// or only the panels listed in `only`, is zeroed and receives its
    /// entries of `a` (panels in parallel).
    pub(crate) fn scatter_with<T: FactorScalar>(
        &self,
        values: &mut Vec<T>,
        a: &SymmetricCsc,
        index: &ScatterIndex,
        only: Option<&[u32]>,
    ) {
        if values.len() != self.len_val() {
            *values = Vec::new();
            *values = vec![T::default(); self.len_val()];
        }
        let ptr = SharedPtr(values.as_mut_ptr());
        let one = |s: usize| {
            let (v0, v1) = (self.val_ptr[s], self.val_ptr[s + 1]);
            // SAFETY: panel s owns values[v0..v1], and its entries' positions
            // lie there.
            unsafe {
                std::slice::from_raw_parts_mut(ptr.get().add(v0), v1 - v0).fill(T::default());
                for &p in &index.entries[index.entry_ptr[s]..index.entry_ptr[s + 1]] {
                    *ptr.get().add(index.pos[p]) = T::of_f64(a.values[p]);
                }
            }
        };
        match only {
            None => (0..self.n_panels())
                .into_par_iter()
                .with_min_len(64)
                .for_each(one),
            Some(list) => list
                .par_iter()
                .with_min_len(16)
                .for_each(|&s| one(s as usize)),
        }
    }

    /// The independent parts of a triangular solve ([`SolvePlan`]), or
    /// `None` when the panel numbering is not a postorder of the panel
    /// elimination tree (then the solve runs in panel order).
    pub(crate) fn solve_plan(&self) -> Option<SolvePlan> {
        let children = |x: usize| &self.child[self.child_ptr[x]..self.child_ptr[x + 1]];
        let mut plan = SolvePlan::default();
        let mut stack = Vec::new();
        for &root in &self.roots {
            let root = root as usize;
            // chain of single-child ancestors, numbered consecutively
            let mut cur = root;
            while let [only] = children(cur) {
                if *only as usize + 1 != cur {
                    return None;
                }
                cur = *only as usize;
            }
            let top = plan.tops.len();
            plan.tops.push((cur, root));
            for &c in children(cur) {
                // the subtree of c must be the panels lo..=c
                let (mut count, mut lo) = (0usize, c as usize);
                stack.clear();
                stack.push(c);
                while let Some(x) = stack.pop() {
                    count += 1;
                    lo = lo.min(x as usize);
                    stack.extend_from_slice(children(x as usize));
                }
                if count != c as usize - lo + 1 {
                    return None;
                }
                plan.tasks.push(SolveTask {
                    lo,
                    hi: c as usize,
                    top,
                    entries: self.val_ptr[c as usize + 1] - self.val_ptr[lo],
                });
            }
        }
        Some(plan)
    }

    /// Run `panel(s, scratch)` on every panel, descendants before their
    /// ancestors: in panel order on one thread, otherwise independent
    /// subtrees of the panel elimination tree as rayon tasks. `panel` may
    /// write panel `s` only and read its (complete) descendants.
    pub(crate) fn traverse<S, E, F>(&self, threads: usize, panel: F) -> Result<(), E>
    where
        S: Default,
        E: Send,
        F: Fn(usize, &mut S) -> Result<(), E> + Sync,
    {
        if threads > 1 {
            self.roots
                .par_iter()
                .try_for_each(|&s| self.run_subtree(s as usize, &panel, 0))
        } else {
            // panels are numbered in elimination order: descendants first
            let mut tmp = S::default();
            for s in 0..self.n_panels() {
                panel(s, &mut tmp)?;
            }
            Ok(())
        }
    }

    /// Factor the subtree rooted at `s`: children subtrees in parallel, then
    /// the chain of single-child ancestors up to `s` in order. Below
    /// [`MAX_TASK_DEPTH`] branchings (where there are far more subtrees than
    /// threads) a subtree is factorised sequentially, without recursion.
    fn run_subtree<S, E, F>(&self, s: usize, panel: &F, depth: usize) -> Result<(), E>
    where
        S: Default,
        E: Send,
        F: Fn(usize, &mut S) -> Result<(), E> + Sync,
    {
        let children = |x: usize| &self.child[self.child_ptr[x]..self.child_ptr[x + 1]];
        let mut tmp = S::default();
        if depth >= MAX_TASK_DEPTH {
            let mut nodes = Vec::new();
            let mut stack = vec![s as u32];
            while let Some(x) = stack.pop() {
                nodes.push(x);
                stack.extend_from_slice(children(x as usize));
            }
            // descendants have smaller numbers than their ancestors
            nodes.sort_unstable();
            for &x in &nodes {
                panel(x as usize, &mut tmp)?;
            }
            return Ok(());
        }
        let mut chain = vec![s];
        let mut cur = s;
        while let [only] = children(cur) {
            cur = *only as usize;
            chain.push(cur);
        }
        children(cur)
            .par_iter()
            .try_for_each(|&c| self.run_subtree(c as usize, panel, depth + 1))?;
        for &x in chain.iter().rev() {
            panel(x, &mut tmp)?;
        }
        Ok(())
    }

    /// The rows of descendant panel `d` that panel `s` receives: `k0` and
    /// `k1`, where `d`'s pattern enters and leaves the columns of `s`
    /// (`pattern(d)[k0..k1]` are columns of `s`, `pattern(d)[k1..]` rows
    /// below them), and in `loc` the local row in panel `s` of each of
    /// `pattern(d)[k0..]` (diagonal block first, then `s`'s own pattern).
    pub(crate) fn descendant_rows(&self, s: usize, d: usize, loc: &mut Vec<u32>) -> (usize, usize) {
        let (b, e) = (self.begin[s], self.begin[s + 1]);
        let w = e - b;
        let (pd, pat_s) = (self.pattern(d), self.pattern(s));
        let k0 = pd.partition_point(|&x| (x as usize) < b);
        let k1 = k0 + pd[k0..].partition_point(|&x| (x as usize) < e);
        loc.clear();
        let mut q = 0usize;
        for &g in &pd[k0..] {
            let g = g as usize;
            if g < e {
                loc.push((g - b) as u32);
            } else {
                while pat_s[q] as usize != g {
                    q += 1;
                }
                loc.push((w + q) as u32);
            }
        }
        (k0, k1)
    }

    /// Left-looking update of panel `s`: `A'[J', J] = A[J', J] - sum_d
    /// L[J', K_d] R_d^T` over the descendants `d` whose rows meet `J`, with
    /// `R_d = L[J, K_d]` (Cholesky), or `R_d = L[J, K_d] D_d` written by
    /// `scale(d, L[J, K_d], R_d)` (`L D L^T`, `D_d` the block-diagonal pivots
    /// of panel `d`; `wbuf` holds `R_d`). Only the lower trapezoid of the
    /// panel is updated.
    #[allow(clippy::type_complexity)]
    pub(crate) fn update_panel<T: FactorScalar>(
        &self,
        s: usize,
        ptr: SharedPtr<T>,
        threads: usize,
        tmp: &mut Vec<T>,
        wbuf: &mut Vec<T>,
        scale: Option<&(dyn Fn(usize, MatRef<'_, T>, MatMut<'_, T>) + Sync)>,
    ) {
        let (b, e) = (self.begin[s], self.begin[s + 1]);
        let w = e - b;
        let pat_s = self.pattern(s);
        let m = w + pat_s.len();
        // SAFETY: panel s is written only here; its descendants are complete
        // and only read.
        let ls_slice =
            unsafe { std::slice::from_raw_parts_mut(ptr.get().add(self.val_ptr[s]), m * w) };
        let mut ls = MatMut::from_column_major_slice_mut(ls_slice, m, w);
        let mut loc: Vec<u32> = Vec::new();
        for &d in &self.desc[self.desc_ptr[s]..self.desc_ptr[s + 1]] {
            let d = d as usize;
            let wd = self.begin[d + 1] - self.begin[d];
            let pd = self.pattern(d);
            let md = wd + pd.len();
            let (k0, k1) = self.descendant_rows(s, d, &mut loc);
            let (len, mid) = (pd.len() - k0, k1 - k0);
            let ld = unsafe {
                std::slice::from_raw_parts(ptr.get().add(self.val_ptr[d]) as *const T, md * wd)
            };
            let ld = MatRef::from_column_major_slice(ld, md, wd);
            let lhs = ld.subrows(wd + k0, len);
            let mut rhs = ld.subrows(wd + k0, mid);
            if let Some(scale) = scale {
                // rhs <- L[J, K_d] D_d (LDL^T factors)
                wbuf.clear();
                wbuf.resize(mid * wd, T::default());
                let mut wm = MatMut::from_column_major_slice_mut(&mut wbuf[..], mid, wd);
                scale(d, rhs, wm.rb_mut());
                rhs = MatRef::from_column_major_slice(&wbuf[..], mid, wd);
            }
            let p = if threads > 1 && len * mid * wd >= 1 << 21 {
                Par::rayon(threads)
            } else {
                Par::Seq
            };
            let (l0, ln) = (loc[0] as usize, loc[len - 1] as usize);
            if ln - l0 == len - 1 {
                // contiguous rows (e.g. an earlier panel of the same
                // supernode): update in place, no scatter
                let dst = ls.rb_mut().submatrix_mut(l0, l0, len, mid);
                sym_update(dst, lhs, rhs, Accum::Add, T::of_f64(-1.0), p);
                continue;
            }
            tmp.clear();
            tmp.resize(len * mid, T::default());
            let t = MatMut::from_column_major_slice_mut(&mut tmp[..], len, mid);
            sym_update(t, lhs, rhs, Accum::Replace, T::of_f64(1.0), p);
            for jj in 0..mid {
                let lc = loc[jj] as usize;
                let col = ls
                    .rb_mut()
                    .col_mut(lc)
                    .try_as_col_major_mut()
                    .unwrap()
                    .as_slice_mut();
                let tc = &tmp[jj * len..(jj + 1) * len];
                for ii in jj..len {
                    col[loc[ii] as usize] -= tc[ii];
                }
            }
        }
    }

    /// Left-looking update and dense factorisation of panel `s`.
    fn factor_panel<T: FactorScalar>(
        &self,
        s: usize,
        ptr: SharedPtr<T>,
        threads: usize,
        tmp: &mut Vec<T>,
    ) -> Result<(), usize> {
        let (b, e) = (self.begin[s], self.begin[s + 1]);
        let w = e - b;
        let m = w + self.pattern(s).len();
        self.update_panel(s, ptr, threads, tmp, &mut Vec::new(), None);
        // SAFETY: panel s is written only here; its descendants are complete
        // and only read.
        let ls_slice =
            unsafe { std::slice::from_raw_parts_mut(ptr.get().add(self.val_ptr[s]), m * w) };
        let mut ls = MatMut::from_column_major_slice_mut(ls_slice, m, w);
        let big = threads > 1 && m * w >= 128 * 128;
        let par = if big { Par::rayon(threads) } else { Par::Seq };
        let (mut top, bot) = ls.rb_mut().split_at_row_mut(w);
        let mut mem = MemBuffer::new(
            faer::linalg::cholesky::llt::factor::cholesky_in_place_scratch::<T>(
                w,
                par,
                Default::default(),
            ),
        );
        match faer::linalg::cholesky::llt::factor::cholesky_in_place(
            top.rb_mut(),
            LltRegularization::default(),
            par,
            MemStack::new(&mut mem),
            Default::default(),
        ) {
            Ok(_) => {}
            Err(DenseLltError::NonPositivePivot { index }) => return Err(b + index),
        }
        if bot.nrows() > 0 {
            faer::linalg::triangular_solve::solve_lower_triangular_in_place(
                top.rb().conjugate(),
                bot.transpose_mut(),
                par,
            );
        }
        Ok(())
    }

    /// Diagonal of `L` (permuted numbering), widened to `f64`.
    pub(crate) fn diagonal<T: FactorScalar>(&self, values: &[T]) -> Vec<f64> {
        let mut d = vec![0.0; self.n];
        for s in 0..self.n_panels() {
            let (b, e) = (self.begin[s], self.begin[s + 1]);
            let m = (e - b) + self.pat_ptr[s + 1] - self.pat_ptr[s];
            for c in 0..e - b {
                d[b + c] = values[self.val_ptr[s] + c * m + c].to_f64();
            }
        }
        d
    }

    /// `x <- (L L^T)^-1 x` in the permuted numbering: one dense triangular
    /// solve and one dense product per panel, in panel order; with a
    /// `plan` ([`SolvePlan`], balanced for the threads) the independent
    /// subtrees run in parallel, each forward step adding its updates of
    /// its chain's rows into a buffer of its own (summed before the
    /// chains), each backward step reading the chain's rows only. Same
    /// arithmetic per entry either way except for the order in which a
    /// chain row's updates are summed.
    pub(crate) fn solve_permuted<T: FactorScalar>(
        &self,
        values: &[T],
        x: &mut [T],
        plan: Option<&SolvePlan>,
    ) {
        let n = x.len();
        let xp = SharedPtr(x.as_mut_ptr());
        let mut tmp: Vec<T> = Vec::new();
        // SAFETY (all blocks below): a step writes only its panel's
        // columns and the rows its plan gives it, or its own buffer.
        match plan {
            Some(plan) => {
                let accs = plan.forward_tasks(&self.begin, 1, |s, own_end, acc, t0, tmp| unsafe {
                    self.forward_step(s, values, xp, own_end, acc, t0, tmp)
                });
                for (ti, acc) in &accs {
                    let (t0, _) = plan.top_columns(&self.begin, plan.tasks[*ti].top);
                    for (xi, &a) in x[t0..t0 + acc.len()].iter_mut().zip(acc) {
                        *xi -= a;
                    }
                }
                for &(lo, hi) in &plan.tops {
                    for s in lo..=hi {
                        unsafe { self.forward_step(s, values, xp, n, &mut [], 0, &mut tmp) };
                    }
                }
                for &(lo, hi) in plan.tops.iter().rev() {
                    for s in (lo..=hi).rev() {
                        unsafe { self.backward_step(s, values, xp, &mut tmp) };
                    }
                }
                plan.backward_tasks(|s, tmp| unsafe { self.backward_step(s, values, xp, tmp) });
            }
            None => {
                for s in 0..self.n_panels() {
                    unsafe { self.forward_step(s, values, xp, n, &mut [], 0, &mut tmp) };
                }
                for s in (0..self.n_panels()).rev() {
                    unsafe { self.backward_step(s, values, xp, &mut tmp) };
                }
            }
        }
    }

    /// Panel `s`: its first column, its pattern (the rows below its
    /// diagonal block), its diagonal block `L_JJ` and the rows below it,
    /// `L_RJ`.
    fn panel_blocks<'a, T: FactorScalar>(
        &'a self,
        s: usize,
        values: &'a [T],
    ) -> (usize, &'a [u32], MatRef<'a, T>, MatRef<'a, T>) {
        let (b, e) = (self.begin[s], self.begin[s + 1]);
        let w = e - b;
        let pat = self.pattern(s);
        let m = w + pat.len();
        let v = &values[self.val_ptr[s]..self.val_ptr[s] + m * w];
        let (top, bot) = MatRef::from_column_major_slice(v, m, w).split_at_row(w);
        (b, pat, top, bot)
    }

    /// Forward step of panel `s` on `x`: `x_J <- L_JJ^-1 x_J`, then `x_R -=
    /// L_RJ x_J`, where a row at or past `own_end` is not subtracted: its
    /// update is added to `acc` (from row `acc_begin` on) instead.
    ///
    /// # Safety
    /// No other task may touch the columns of `s` or the rows below
    /// `own_end` that it updates.
    #[allow(clippy::too_many_arguments)]
    unsafe fn forward_step<T: FactorScalar>(
        &self,
        s: usize,
        values: &[T],
        x: SharedPtr<T>,
        own_end: usize,
        acc: &mut [T],
        acc_begin: usize,
        tmp: &mut Vec<T>,
    ) {
        use faer::linalg::triangular_solve as tri;
        let (b, pat, top, bot) = self.panel_blocks(s, values);
        let w = top.nrows();
        let xj = std::slice::from_raw_parts_mut(x.get().add(b), w);
        tri::solve_lower_triangular_in_place(
            top,
            MatMut::from_column_major_slice_mut(&mut *xj, w, 1),
            Par::Seq,
        );
        if pat.is_empty() {
            return;
        }
        tmp.clear();
        tmp.resize(pat.len(), T::default());
        let t = MatMut::from_column_major_slice_mut(&mut tmp[..], pat.len(), 1);
        let xr = MatRef::from_column_major_slice(&*xj, w, 1);
        faer::linalg::matmul::matmul(t, Accum::Replace, bot, xr, T::of_f64(1.0), Par::Seq);
        for (&g, &t) in pat.iter().zip(tmp.iter()) {
            let g = g as usize;
            if g < own_end {
                *x.get().add(g) -= t;
            } else {
                debug_assert!(g >= acc_begin && g - acc_begin < acc.len());
                acc[g - acc_begin] += t;
            }
        }
    }

    /// Backward step of panel `s` on `x`: `x_J <- L_JJ^-T (x_J - L_RJ^T
    /// x_R)`.
    ///
    /// # Safety
    /// No other task may touch the columns of `s`, or write the rows of its
    /// pattern, meanwhile.
    unsafe fn backward_step<T: FactorScalar>(
        &self,
        s: usize,
        values: &[T],
        x: SharedPtr<T>,
        tmp: &mut Vec<T>,
    ) {
        use faer::linalg::triangular_solve as tri;
        let (b, pat, top, bot) = self.panel_blocks(s, values);
        let w = top.nrows();
        let xj = std::slice::from_raw_parts_mut(x.get().add(b), w);
        if !pat.is_empty() {
            tmp.clear();
            tmp.extend(pat.iter().map(|&g| *x.get().add(g as usize)));
            let t = MatRef::from_column_major_slice(&tmp[..], pat.len(), 1);
            faer::linalg::matmul::matmul(
                MatMut::from_column_major_slice_mut(&mut *xj, w, 1),
                Accum::Add,
                bot.transpose(),
                t,
                T::of_f64(-1.0),
                Par::Seq,
            );
        }
        tri::solve_upper_triangular_in_place(
            top.transpose(),
            MatMut::from_column_major_slice_mut(xj, w, 1),
            Par::Seq,
        );
    }
}
