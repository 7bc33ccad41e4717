//! Supernodal `LU` on the symmetric structure with row pivoting restricted
//! to each panel's diagonal block (the default method of the `lu` back end,
//! [`crate::LuSolver`]).
//!
//! # Why
//!
//! A finite-element tangent is structurally symmetric even when its values
//! are not (friction, non-associated plasticity, a mixed-mode cohesive law's
//! exact tangent). An `LU` with unrestricted partial pivoting must reserve
//! room for any row interchange: its static structure is the Cholesky
//! factor of `A^T A` (George and Ng), which on the 12,420-equation mixed-mode
//! bending model is 127M entries, against 0.8M for the `L D L^T` of the
//! same ordering (SuperLU's dynamic structure gets 2.0M). Keeping the
//! structure of the symmetric factor, as PARDISO does, and pivoting only
//! inside a panel (whose rows all share one structure) gives an `LU` with
//! the cost of two Cholesky factors.
//!
//! # Method
//!
//! `P A P^T` (`P` the fill-reducing ordering of the shared analysis,
//! [`crate::supernodal::analyze`]) is factorised as `L U` left-looking over
//! the panels of the symmetric structure ([`PanelFactor`]). Panel `s` holds
//! the columns `J`, the rows `R` below (those of the symmetric factor), and
//! two blocks: the `lower` block `(|J| + |R|) x |J|` (column-major, the
//! whole diagonal block on top, `A[R, J]` below) and the `upper` block
//! `|R| x |J|` holding `A[J, R]` transposed. With the descendants `d` of `s`
//! complete,
//!
//! ```text
//! A'[J + R, J] = A[J + R, J] - sum_d L[J + R, K_d] U[K_d, J]
//! A'[J, R]     = A[J, R]     - sum_d L[J, K_d]     U[K_d, R]
//! Q_s A'[J, J] = L_JJ U_JJ          (partial pivoting among the rows J)
//! L_RJ = A'[R, J] U_JJ^-1,   U_JR = L_JJ^-1 Q_s A'[J, R]
//! ```
//!
//! Rows of `J` share one structure, so the interchanges `Q_s` change no
//! structure and later panels never see them; the descendants' rows `J`
//! keep the original equation labels, and the forward solve applies `Q_s`
//! when it reaches panel `s`: `y_J = L_JJ^-1 Q_s b_J`, `b_R -= L_RJ y_J`;
//! backward `x_J = U_JJ^-1 (y_J - U_JR x_R)`.
//!
//! A pivot column whose entries in the rows `J` are all at most
//! `tiny ||A||_inf` (the largest entry of the column may lie below `J`,
//! where the restriction cannot reach it) is given the pivot
//! `perturb ||A||_inf` (static pivoting, as in PARDISO) and counted; the
//! solver then refines the solution, or falls back to unrestricted partial
//! pivoting ([`crate::LuSolver`], `pivoting = "auto"`).

use crate::common::nan_max;
use crate::supernodal::{PanelFactor, SharedPtr};
use faer::linalg::triangular_solve as tri;
use faer::reborrow::{Reborrow, ReborrowMut};
use faer::{Accum, MatMut, MatRef, Par};
use junta_core::SymmetricCsc;
use rayon::prelude::*;

/// Flag of a scatter position in the `upper` block array.
const UPPER: usize = 1 << (usize::BITS - 1);

/// Numbers describing a factorisation.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct PanelLuStats {
    /// Pivots replaced by the static perturbation.
    pub(crate) perturbed: usize,
    /// Of those, pivots whose whole column of the Schur complement (rows
    /// below the panel included) is at most `tiny ||A||_inf`: the matrix is
    /// numerically singular (module doc).
    pub(crate) singular: usize,
    /// The first such column (permuted numbering), `usize::MAX` if none.
    pub(crate) first_singular: usize,
    /// Smallest `|u_kk| / ||A||_inf` of an unperturbed pivot.
    pub(crate) min_pivot_ratio: f64,
    /// Largest `|l_ij|` (at most 1 in `L_JJ`, unbounded in `L_RJ`).
    pub(crate) max_multiplier: f64,
    /// Largest `|u_ij|`.
    pub(crate) max_upper: f64,
}

impl PanelLuStats {
    /// The numbers of a factorisation with no pivot yet.
    fn empty() -> Self {
        PanelLuStats {
            perturbed: 0,
            singular: 0,
            first_singular: usize::MAX,
            min_pivot_ratio: f64::INFINITY,
            max_multiplier: 0.0,
            max_upper: 0.0,
        }
    }

    /// Growth `max(1, max|L|) max|U| / ||A||_inf` (`norm`): the backward
    /// error of the factor is a modest multiple of `eps |L| |U|`.
    pub(crate) fn growth(&self, norm: f64) -> f64 {
        self.max_multiplier.max(1.0) * self.max_upper / norm
    }
}

/// Numeric `L U` factor on a [`PanelFactor`] structure.
#[derive(Debug, Default)]
pub(crate) struct PanelLu {
    /// Lower blocks, at `PanelFactor::val_ptr`.
    lower: Vec<f64>,
    /// Upper blocks (`|R| x |J|`, column-major), at `upper_ptr`.
    upper: Vec<f64>,
    upper_ptr: Vec<usize>,
    /// `rows[b + i]`: the panel-local row taken as pivot `i` (`Q_s`).
    rows: Vec<u32>,
    /// For each stored entry `p` of the matrix: where `A'[pr][pc]` and
    /// `A'[pc][pr]` go (`UPPER` flag: in `upper`), `pr`, `pc` its permuted
    /// row and column.
    pos_rc: Vec<usize>,
    pos_cr: Vec<usize>,
    /// Matrix norm `||A||_inf` of the last factorisation.
    norm: f64,
}

/// Panel `s`'s first column, width and row pattern.
fn panel(f: &PanelFactor, s: usize) -> (usize, usize, &[u32]) {
    let b = f.begin[s];
    (b, f.begin[s + 1] - b, f.pattern(s))
}

impl PanelLu {
    /// Scatter maps of `a` (`perm_inv[old] = new`) on the structure `f`.
    pub(crate) fn new(f: &PanelFactor, a: &SymmetricCsc, perm_inv: &[usize]) -> Self {
        let np = f.n_panels();
        let mut upper_ptr = vec![0usize; np + 1];
        for s in 0..np {
            let (_, w, pat) = panel(f, s);
            upper_ptr[s + 1] = upper_ptr[s] + w * pat.len();
        }
        // where A'[i][j] goes (permuted numbering)
        let position = |i: usize, j: usize| -> usize {
            let (lo, hi) = (i.min(j), i.max(j));
            let s = f.panel_of[lo] as usize;
            let (b, w, pat) = panel(f, s);
            let m = w + pat.len();
            let in_pat = |g: usize| pat.binary_search(&(g as u32)).expect("structure covers A");
            if i >= j {
                // lower block of column j: the diagonal block or the rows below
                let lr = if i < b + w { i - b } else { w + in_pat(i) };
                f.val_ptr[s] + (j - b) * m + lr
            } else if hi < b + w {
                // upper triangle of the diagonal block
                f.val_ptr[s] + (j - b) * m + (i - b)
            } else {
                // A[J, R] transposed: row j (in R), column i (in J)
                UPPER | (upper_ptr[s] + (i - b) * pat.len() + in_pat(j))
            }
        };
        let nnz = a.row_idx.len();
        let (mut pos_rc, mut pos_cr) = (vec![0usize; nnz], vec![0usize; nnz]);
        pos_rc
            .par_iter_mut()
            .zip(pos_cr.par_iter_mut())
            .enumerate()
            .with_min_len(4096)
            .for_each(|(p, (rc, cr))| {
                // column of entry p: the last column start at or before p
                let c = a.col_ptr.partition_point(|&x| x <= p) - 1;
                let (pr, pc) = (perm_inv[a.row_idx[p]], perm_inv[c]);
                *rc = position(pr, pc);
                *cr = position(pc, pr);
            });
        PanelLu {
            lower: vec![0.0; f.len_val()],
            upper: vec![0.0; upper_ptr[np]],
            upper_ptr,
            rows: vec![0; f.n],
            pos_rc,
            pos_cr,
            norm: 0.0,
        }
    }

    /// Stored entries of `L` and `U` together.
    pub(crate) fn nonzeros(&self, f: &PanelFactor) -> usize {
        (0..f.n_panels())
            .map(|s| {
                let (_, w, pat) = panel(f, s);
                w * w + 2 * w * pat.len()
            })
            .sum()
    }

    /// Numeric factorisation of `a` (same pattern as at [`Self::new`];
    /// `values` its upper triangle, `lower` its lower triangle transposed;
    /// `norm` = `||A||_inf`), pivots below `tiny * norm` replaced by
    /// `perturb * norm`.
    pub(crate) fn factorize(
        &mut self,
        f: &PanelFactor,
        a: &SymmetricCsc,
        norm: f64,
        tiny: f64,
        perturb: f64,
        threads: usize,
    ) -> PanelLuStats {
        self.norm = norm;
        self.lower.par_iter_mut().for_each(|v| *v = 0.0);
        self.upper.par_iter_mut().for_each(|v| *v = 0.0);
        let low = if a.is_general() { &a.lower } else { &a.values };
        {
            let (lp, up) = (
                SharedPtr(self.lower.as_mut_ptr()),
                SharedPtr(self.upper.as_mut_ptr()),
            );
            let put = |q: usize, v: f64| {
                // SAFETY: every (row, column) of A' has its own position.
                unsafe {
                    if q & UPPER != 0 {
                        *up.get().add(q & !UPPER) = v;
                    } else {
                        *lp.get().add(q) = v;
                    }
                }
            };
            (0..a.row_idx.len())
                .into_par_iter()
                .with_min_len(4096)
                .for_each(|p| {
                    put(self.pos_rc[p], a.values[p]);
                    if self.pos_cr[p] != self.pos_rc[p] {
                        put(self.pos_cr[p], low[p]);
                    }
                });
        }
        let ptrs = Ptrs {
            lower: SharedPtr(self.lower.as_mut_ptr()),
            upper: SharedPtr(self.upper.as_mut_ptr()),
            rows: SharedPtr(self.rows.as_mut_ptr()),
        };
        let upper_ptr = &self.upper_ptr;
        let (tiny, perturb) = (tiny * norm, perturb * norm);
        let stats = std::sync::Mutex::new(Vec::<PanelLuStats>::new());
        let done: Result<(), std::convert::Infallible> =
            f.traverse(threads, |s, scratch: &mut Scratch| {
                let st = factor_panel(f, upper_ptr, s, ptrs, (tiny, perturb), threads, scratch);
                stats.lock().expect("not poisoned").push(st);
                Ok(())
            });
        let Ok(()) = done;
        stats
            .into_inner()
            .expect("not poisoned")
            .iter()
            .fold(PanelLuStats::empty(), |acc, st| PanelLuStats {
                max_upper: nan_max(acc.max_upper, st.max_upper),
                perturbed: acc.perturbed + st.perturbed,
                singular: acc.singular + st.singular,
                first_singular: acc.first_singular.min(st.first_singular),
                min_pivot_ratio: acc.min_pivot_ratio.min(st.min_pivot_ratio / norm),
                max_multiplier: nan_max(acc.max_multiplier, st.max_multiplier),
            })
    }

    /// `x <- (L U)^-1 x` in the permuted numbering.
    pub(crate) fn solve_permuted(&self, f: &PanelFactor, x: &mut [f64], tmp: &mut Vec<f64>) {
        let np = f.n_panels();
        // forward: y_J = L_JJ^-1 Q_s x_J, x_R -= L_RJ y_J
        for s in 0..np {
            let (b, w, pat) = panel(f, s);
            let m = w + pat.len();
            let l = &self.lower[f.val_ptr[s]..f.val_ptr[s] + m * w];
            tmp.clear();
            tmp.extend((0..w).map(|i| x[b + self.rows[b + i] as usize]));
            x[b..b + w].copy_from_slice(tmp);
            for k in 0..w {
                let xk = x[b + k];
                if xk == 0.0 {
                    continue;
                }
                let col = &l[k * m..(k + 1) * m];
                for (xi, li) in x[b + k + 1..b + w].iter_mut().zip(&col[k + 1..w]) {
                    *xi -= li * xk;
                }
                for (&g, li) in pat.iter().zip(&col[w..]) {
                    x[g as usize] -= li * xk;
                }
            }
        }
        // backward: x_J = U_JJ^-1 (y_J - U_JR x_R)
        for s in (0..np).rev() {
            let (b, w, pat) = panel(f, s);
            let (m, r) = (w + pat.len(), pat.len());
            let l = &self.lower[f.val_ptr[s]..f.val_ptr[s] + m * w];
            let u = &self.upper[self.upper_ptr[s]..self.upper_ptr[s] + r * w];
            for i in 0..w {
                let col = &u[i * r..(i + 1) * r];
                let dot: f64 = pat.iter().zip(col).map(|(&g, ui)| ui * x[g as usize]).sum();
                x[b + i] -= dot;
            }
            for k in (0..w).rev() {
                let col = &l[k * m..(k + 1) * m];
                let xk = x[b + k] / col[k];
                x[b + k] = xk;
                if xk != 0.0 {
                    for (xi, ui) in x[b..b + k].iter_mut().zip(&col[..k]) {
                        *xi -= ui * xk;
                    }
                }
            }
        }
    }
}

/// Raw pointers of the factor, for the panel tasks.
#[derive(Clone, Copy)]
struct Ptrs {
    lower: SharedPtr<f64>,
    upper: SharedPtr<f64>,
    rows: SharedPtr<u32>,
}
// SAFETY: each task writes its own panel only, and reads complete ones.
unsafe impl Send for Ptrs {}
unsafe impl Sync for Ptrs {}

/// Scratch of one panel task.
#[derive(Default)]
struct Scratch {
    prod: Vec<f64>,
    loc: Vec<u32>,
    cols: Vec<f64>,
    /// Panel-local columns whose pivot was perturbed.
    perturbed: Vec<usize>,
}

/// Left-looking update and dense restricted-pivoting `LU` of panel `s`:
/// the updates of its descendants ([`update_from_descendants`]), the
/// dense `LU` of its diagonal block ([`factor_diagonal_block`]), the
/// triangular solves of its off-diagonal parts ([`solve_off_diagonal`])
/// and its statistics ([`panel_statistics`]).
fn factor_panel(
    f: &PanelFactor,
    upper_ptr: &[usize],
    s: usize,
    ptrs: Ptrs,
    (tiny, perturb): (f64, f64),
    threads: usize,
    scratch: &mut Scratch,
) -> PanelLuStats {
    let (b, w, pat_s) = panel(f, s);
    let (r, m) = (pat_s.len(), w + pat_s.len());
    // SAFETY: panel s is written only by this task; its descendants are
    // complete and only read.
    let (ls, us, rows) = unsafe {
        (
            std::slice::from_raw_parts_mut(ptrs.lower.get().add(f.val_ptr[s]), m * w),
            std::slice::from_raw_parts_mut(ptrs.upper.get().add(upper_ptr[s]), r * w),
            std::slice::from_raw_parts_mut(ptrs.rows.get().add(b), w),
        )
    };
    update_from_descendants(f, upper_ptr, s, ptrs, threads, scratch, ls, us);
    // dense LU of the diagonal block with row interchanges among its rows
    let mut st = PanelLuStats::empty();
    factor_diagonal_block(
        ls,
        rows,
        (m, w),
        (tiny, perturb),
        &mut st,
        &mut scratch.perturbed,
    );
    if r > 0 {
        solve_off_diagonal(ls, us, rows, (m, w, r), threads, &mut scratch.cols);
    }
    panel_statistics(
        ls,
        us,
        (m, w, b),
        (tiny, perturb),
        &scratch.perturbed,
        &mut st,
    );
    st
}

/// The updates of panel `s` (lower part `ls`: `m x w`, upper part `us`:
/// `r x w`, column-major) by each descendant `d` that touches it:
/// `A'[rows, J] -= L[rows, K_d] U[K_d, J]` on the lower side and
/// `A'[J, R] -= L[J, K_d] U[K_d, R]` on the upper side (stored
/// transposed), large products in parallel.
#[allow(clippy::too_many_arguments)]
fn update_from_descendants(
    f: &PanelFactor,
    upper_ptr: &[usize],
    s: usize,
    ptrs: Ptrs,
    threads: usize,
    scratch: &mut Scratch,
    ls: &mut [f64],
    us: &mut [f64],
) {
    let (_, w, pat_s) = panel(f, s);
    let (r, m) = (pat_s.len(), w + pat_s.len());
    for &d in &f.desc[f.desc_ptr[s]..f.desc_ptr[s + 1]] {
        let d = d as usize;
        let (_, wd, pd) = panel(f, d);
        let md = wd + pd.len();
        let (k0, k1) = f.descendant_rows(s, d, &mut scratch.loc);
        let loc = &scratch.loc;
        let (len, mid) = (pd.len() - k0, k1 - k0);
        if mid == 0 {
            continue;
        }
        // SAFETY: descendant d is complete and only read.
        let (ld, ud) = unsafe {
            (
                std::slice::from_raw_parts(
                    ptrs.lower.get().add(f.val_ptr[d]) as *const f64,
                    md * wd,
                ),
                std::slice::from_raw_parts(
                    ptrs.upper.get().add(upper_ptr[d]) as *const f64,
                    pd.len() * wd,
                ),
            )
        };
        let ld = MatRef::from_column_major_slice(ld, md, wd);
        let ud = MatRef::from_column_major_slice(ud, pd.len(), wd);
        // large updates (the top separators) in parallel, as in `ldlt`
        let par = if threads > 1 && len * mid * wd >= 1 << 21 {
            Par::rayon(threads)
        } else {
            Par::Seq
        };
        // lower side: L[rows, K_d] U[K_d, J]
        let prod = &mut scratch.prod;
        prod.clear();
        prod.resize(len * mid, 0.0);
        let t = MatMut::from_column_major_slice_mut(&mut prod[..], len, mid);
        faer::linalg::matmul::matmul(
            t,
            Accum::Replace,
            ld.subrows(wd + k0, len),
            ud.subrows(k0, mid).transpose(),
            1.0,
            par,
        );
        for jj in 0..mid {
            let col = &mut ls[loc[jj] as usize * m..(loc[jj] as usize + 1) * m];
            for (ii, v) in prod[jj * len..(jj + 1) * len].iter().enumerate() {
                col[loc[ii] as usize] -= v;
            }
        }
        // upper side: (L[J, K_d] U[K_d, R])^T = U[K_d, R]^T L[J, K_d]^T
        let rest = len - mid;
        if rest > 0 {
            prod.clear();
            prod.resize(rest * mid, 0.0);
            let t = MatMut::from_column_major_slice_mut(&mut prod[..], rest, mid);
            faer::linalg::matmul::matmul(
                t,
                Accum::Replace,
                ud.subrows(k1, rest),
                ld.subrows(wd + k0, mid).transpose(),
                1.0,
                Par::Seq,
            );
            for jj in 0..mid {
                let col = &mut us[loc[jj] as usize * r..(loc[jj] as usize + 1) * r];
                for (gg, v) in prod[jj * rest..(jj + 1) * rest].iter().enumerate() {
                    col[loc[mid + gg] as usize - w] -= v;
                }
            }
        }
    }
}

/// Dense `LU` with partial pivoting of the `w x w` diagonal block of a
/// panel (`ls`, column-major with leading dimension `m`): row interchanges
/// among the block's rows only, recorded in `rows`; a pivot not above
/// `tiny` is replaced by `+-perturb` (its column pushed to `perturbed`),
/// the others lower `min_pivot_ratio` of `st`.
fn factor_diagonal_block(
    ls: &mut [f64],
    rows: &mut [u32],
    (m, w): (usize, usize),
    (tiny, perturb): (f64, f64),
    st: &mut PanelLuStats,
    perturbed: &mut Vec<usize>,
) {
    perturbed.clear();
    for (i, p) in rows.iter_mut().enumerate() {
        *p = i as u32;
    }
    for k in 0..w {
        let col = &ls[k * m..k * m + w];
        let (mut p, mut big) = (k, col[k].abs());
        for (i, v) in col.iter().enumerate().skip(k + 1) {
            if v.abs() > big {
                (p, big) = (i, v.abs());
            }
        }
        if p != k {
            for j in 0..w {
                ls.swap(j * m + k, j * m + p);
            }
            rows.swap(k, p);
        }
        let mut piv = ls[k * m + k];
        if !(piv.abs() > tiny) {
            piv = if piv < 0.0 { -perturb } else { perturb };
            ls[k * m + k] = piv;
            st.perturbed += 1;
            perturbed.push(k);
        } else {
            st.min_pivot_ratio = st.min_pivot_ratio.min(piv.abs());
        }
        let inv = 1.0 / piv;
        for v in &mut ls[k * m + k + 1..k * m + w] {
            *v *= inv;
        }
        let (left, right) = ls.split_at_mut((k + 1) * m);
        let lk = &left[k * m + k + 1..k * m + w];
        for j in k + 1..w {
            let ukj = right[(j - k - 1) * m + k];
            if ukj != 0.0 {
                let cj = &mut right[(j - k - 1) * m + k + 1..(j - k - 1) * m + w];
                for (c, l) in cj.iter_mut().zip(lk) {
                    *c -= l * ukj;
                }
            }
        }
    }
}

/// The off-diagonal parts of a panel with `r > 0` rows below its `w x w`
/// diagonal block: `L_RJ` from `L_RJ U_JJ = A'[R, J]` and `U_JR` from
/// `L_JJ U_JR = Q_s A'[J, R]` (`Q_s` the block's row interchanges `rows`),
/// both in place; `cols` is scratch.
fn solve_off_diagonal(
    ls: &mut [f64],
    us: &mut [f64],
    rows: &[u32],
    (m, w, r): (usize, usize, usize),
    threads: usize,
    cols: &mut Vec<f64>,
) {
    let par = if threads > 1 && m * w >= 128 * 128 {
        Par::rayon(threads)
    } else {
        Par::Seq
    };
    let mut panel = MatMut::from_column_major_slice_mut(&mut ls[..], m, w);
    let (top, mut bot) = panel.rb_mut().split_at_row_mut(w);
    // L_RJ U_JJ = A'[R, J]  <=>  U_JJ^T L_RJ^T = A'[R, J]^T
    tri::solve_lower_triangular_in_place(top.rb().transpose(), bot.rb_mut().transpose_mut(), par);
    // U_JR^T = (Q_s A'[J, R])^T L_JJ^-T: columns of `us` in pivot order
    if rows.iter().enumerate().any(|(i, &p)| p as usize != i) {
        cols.clear();
        cols.extend_from_slice(us);
        for (i, &p) in rows.iter().enumerate() {
            let p = p as usize;
            us[i * r..(i + 1) * r].copy_from_slice(&cols[p * r..(p + 1) * r]);
        }
    }
    let mut u = MatMut::from_column_major_slice_mut(&mut us[..], r, w);
    tri::solve_unit_lower_triangular_in_place(top.rb(), u.rb_mut().transpose_mut(), par);
}

/// Statistics of a factored panel (`w` columns from column `b`, `m` rows):
/// perturbed pivots with nothing below the panel either are singular
/// (`singular`, `first_singular`); the largest entries of `U` and the
/// largest multiplier of `L`.
fn panel_statistics(
    ls: &[f64],
    us: &[f64],
    (m, w, b): (usize, usize, usize),
    (tiny, perturb): (f64, f64),
    perturbed: &[usize],
    st: &mut PanelLuStats,
) {
    // perturbed pivots with nothing below the panel either: singular
    for &k in perturbed {
        let below = ls[k * m + w..(k + 1) * m]
            .iter()
            .fold(0.0f64, |a, v| nan_max(a, v.abs()));
        if !(below * perturb > tiny) {
            st.singular += 1;
            st.first_singular = st.first_singular.min(b + k);
        }
    }
    for j in 0..w {
        let col = &ls[j * m..(j + 1) * m];
        st.max_upper = col[..=j]
            .iter()
            .fold(st.max_upper, |a, v| nan_max(a, v.abs()));
        st.max_multiplier = col[j + 1..]
            .iter()
            .fold(st.max_multiplier, |a, v| nan_max(a, v.abs()));
    }
    st.max_upper = us.iter().fold(st.max_upper, |a, v| nan_max(a, v.abs()));
}
