//! Helpers shared by the back ends: pattern validation and bookkeeping,
//! vector norms, and a parallel full-CSR symmetric product.

use junta_core::{SolverError, SymmetricCsc};
use rayon::prelude::*;

/// Check the invariants of [`SymmetricCsc`] that the back ends rely on:
/// `col_ptr` of length `n + 1`, non-decreasing, ending at `nnz`; rows
/// strictly increasing within a column and `<= column`; values aligned.
pub(crate) fn validate(m: &SymmetricCsc) -> Result<(), SolverError> {
    let bad = |msg: String| Err(SolverError::Usage(format!("invalid SymmetricCsc: {msg}")));
    if m.col_ptr.len() != m.n + 1 {
        return bad(format!(
            "col_ptr has {} entries for n = {}",
            m.col_ptr.len(),
            m.n
        ));
    }
    if m.col_ptr[0] != 0 || m.col_ptr[m.n] != m.row_idx.len() {
        return bad("col_ptr must start at 0 and end at nnz".into());
    }
    if !m.lower.is_empty() && m.lower.len() != m.row_idx.len() {
        return bad(format!(
            "{} lower values for {} row indices",
            m.lower.len(),
            m.row_idx.len()
        ));
    }
    if m.values.len() != m.row_idx.len() {
        return bad(format!(
            "{} values for {} row indices",
            m.values.len(),
            m.row_idx.len()
        ));
    }
    for j in 0..m.n {
        let (s, e) = (m.col_ptr[j], m.col_ptr[j + 1]);
        if s > e {
            return bad(format!("col_ptr decreases at column {j}"));
        }
        let rows = &m.row_idx[s..e];
        if rows.windows(2).any(|w| w[0] >= w[1]) {
            return bad(format!("rows of column {j} are not strictly increasing"));
        }
        if rows.last().is_some_and(|&r| r > j) {
            return bad(format!(
                "column {j} holds a row below the diagonal (upper triangle expected)"
            ));
        }
    }
    Ok(())
}

/// `Usage` error naming `lu` when a symmetric back end (`key`) is given a
/// nonsymmetric matrix ([`SymmetricCsc::is_general`]).
pub(crate) fn symmetric_only(m: &SymmetricCsc, key: &str) -> Result<(), SolverError> {
    if m.is_general() {
        return Err(SolverError::Usage(format!(
            "{key} solves symmetric matrices only, but this matrix is nonsymmetric (a law with a general tangent: friction or non-associated plasticity); use the `lu` back end ([solver] type = \"lu\" or \"auto\")"
        )));
    }
    Ok(())
}

/// The sparsity pattern a solver was analysed for, kept as a fingerprint
/// (dimension, number of entries and a 64-bit hash of `col_ptr` and
/// `row_idx`) rather than a copy: a copy of the indices of a 100k-equation
/// 3D matrix is 66 MB, the fingerprint 24 bytes. The hash reads every
/// column length but only a sample of the row indices, so that checking
/// the pattern at every factorisation of a Newton run costs a small part of
/// a pass over the matrix (it read half the indices before: 3 % of the
/// 50k-dof DCB's run time, `bench/dcb_performance.py`).
/// One row index in this many enters [`pattern_hash`] (one per 4 kB page).
const HASH_STRIDE: usize = 512;
/// The first and last row of one column in this many enter [`pattern_hash`].
const HASH_COLUMN_STRIDE: usize = 64;

#[derive(Debug, Clone, Default)]
pub(crate) struct Pattern {
    n: usize,
    nnz: usize,
    hash: u64,
}

/// Order-dependent 64-bit hash of the pattern of `m`: every column length,
/// the first and last row of every [`HASH_COLUMN_STRIDE`]-th column and
/// every [`HASH_STRIDE`]-th row index (a factorisation or solve checks the
/// pattern each call, so the hash reads a fraction of it; a pattern that
/// differs only in unsampled row indices while keeping every column length
/// is not a mistake a caller makes). Columns are hashed in
/// parallel, then combined in order.
fn pattern_hash(m: &SymmetricCsc) -> u64 {
    #[inline]
    fn mix(h: u64, v: u64) -> u64 {
        let z = (h ^ v).wrapping_mul(0x9E37_79B9_7F4A_7C15);
        z ^ (z >> 29)
    }
    const CHUNK: usize = 4096;
    let n = m.n;
    let chunks: Vec<u64> = (0..n.div_ceil(CHUNK))
        .into_par_iter()
        .map(|c| {
            let (j0, j1) = (c * CHUNK, ((c + 1) * CHUNK).min(n));
            let mut h = 0x243F_6A88_85A3_08D3u64 ^ c as u64;
            for j in j0..j1 {
                let (s, e) = (m.col_ptr[j], m.col_ptr[j + 1]);
                h = mix(h, (e - s) as u64 ^ ((j as u64) << 32));
                // first and last row of some columns, and a sample between
                if e > s && j % HASH_COLUMN_STRIDE == 0 {
                    h = mix(h, m.row_idx[s] as u64 ^ ((m.row_idx[e - 1] as u64) << 32));
                }
                let first = s.next_multiple_of(HASH_STRIDE);
                for &i in m.row_idx[first.min(e)..e].iter().step_by(HASH_STRIDE) {
                    h = mix(h, i as u64);
                }
            }
            h
        })
        .collect();
    chunks
        .iter()
        .fold(mix(n as u64, m.row_idx.len() as u64), |h, &c| mix(h, c))
}

impl Pattern {
    pub(crate) fn of(m: &SymmetricCsc) -> Self {
        Pattern {
            n: m.n,
            nnz: m.row_idx.len(),
            hash: pattern_hash(m),
        }
    }

    /// `Usage` error unless `m` has this pattern.
    pub(crate) fn check(&self, m: &SymmetricCsc, what: &str) -> Result<(), SolverError> {
        if m.n != self.n
            || m.row_idx.len() != self.nnz
            || m.col_ptr.len() != m.n + 1
            || m.col_ptr[m.n] != self.nnz
            || pattern_hash(m) != self.hash
        {
            return Err(SolverError::Usage(format!(
                "{what}: the matrix (n = {}, nnz = {}) does not have the analysed pattern (n = {}, nnz = {}); call analyze again",
                m.n,
                m.nnz(),
                self.n,
                self.nnz
            )));
        }
        if m.values.len() != m.row_idx.len() {
            return Err(SolverError::Usage(format!(
                "{what}: {} values for {} entries",
                m.values.len(),
                m.row_idx.len()
            )));
        }
        Ok(())
    }
}

/// `max_i |x_i|`.
pub(crate) fn inf_norm(x: &[f64]) -> f64 {
    x.iter().fold(0.0f64, |m, v| m.max(v.abs()))
}

/// Euclidean norm.
pub(crate) fn norm2(x: &[f64]) -> f64 {
    if x.len() > 50_000 {
        x.par_iter().map(|v| v * v).sum::<f64>().sqrt()
    } else {
        x.iter().map(|v| v * v).sum::<f64>().sqrt()
    }
}

/// Vectors shorter than this are updated on the calling thread: below it,
/// handing the work to the thread pool and waking it costs more than the
/// arithmetic (a Krylov iteration on a 4000-equation model does dozens of
/// such updates).
pub(crate) const PAR_MIN_LEN: usize = 50_000;

/// `y[i] = f(i, y[i])` for every `i`, in parallel for long vectors.
pub(crate) fn update(y: &mut [f64], f: impl Fn(usize, f64) -> f64 + Sync + Send) {
    if y.len() >= PAR_MIN_LEN {
        y.par_iter_mut()
            .enumerate()
            .for_each(|(i, v)| *v = f(i, *v));
    } else {
        for (i, v) in y.iter_mut().enumerate() {
            *v = f(i, *v);
        }
    }
}

/// `y[i] = f(i, y[i]).0` for every `i`, returning the sum of the `.1`.
pub(crate) fn update_sum(y: &mut [f64], f: impl Fn(usize, f64) -> (f64, f64) + Sync + Send) -> f64 {
    if y.len() >= PAR_MIN_LEN {
        y.par_iter_mut()
            .enumerate()
            .map(|(i, v)| {
                let (new, c) = f(i, *v);
                *v = new;
                c
            })
            .sum()
    } else {
        let mut sum = 0.0;
        for (i, v) in y.iter_mut().enumerate() {
            let (new, c) = f(i, *v);
            *v = new;
            sum += c;
        }
        sum
    }
}

/// Dot product.
pub(crate) fn dot(x: &[f64], y: &[f64]) -> f64 {
    if x.len() > 50_000 {
        x.par_iter().zip(y.par_iter()).map(|(a, b)| a * b).sum()
    } else {
        x.iter().zip(y).map(|(a, b)| a * b).sum()
    }
}

/// `||b - A x||` with [`SymmetricCsc::mul_vec`]; `r` receives `b - A x`.
pub(crate) fn residual(a: &SymmetricCsc, x: &[f64], b: &[f64], r: &mut [f64]) -> f64 {
    a.mul_vec(x, r);
    for (ri, bi) in r.iter_mut().zip(b) {
        *ri = bi - *ri;
    }
    norm2(r)
}

/// Both triangles of the symmetric matrix `m` (upper triangle stored) in
/// CSR: row starts, columns (increasing within a row) and, for each
/// entry, its index in `m.values`. Row `i` is column `i` of the upper
/// triangle (the entries `(r, i)`, `r <= i`, as columns `r`) followed by
/// row `i` of the upper triangle without its diagonal (the entries
/// `(i, j)`, `j > i`, from the columns `j`: a transpose,
/// [`transpose_pattern`]). Rows are filled in parallel.
pub(crate) fn symmetric_to_full_pattern(m: &SymmetricCsc) -> (Vec<usize>, Vec<u32>, Vec<usize>) {
    let n = m.n;
    let (up_ptr, up_col, up_src) = transpose_pattern(&m.col_ptr, n, |q| m.row_idx[q]);
    let strict_upper = |i: usize| {
        let (s, e) = (up_ptr[i], up_ptr[i + 1]);
        if s < e && up_col[s] as usize == i {
            s + 1..e
        } else {
            s..e
        }
    };
    let mut row_ptr = vec![0usize; n + 1];
    for i in 0..n {
        row_ptr[i + 1] = row_ptr[i] + (m.col_ptr[i + 1] - m.col_ptr[i]) + strict_upper(i).len();
    }
    let total = row_ptr[n];
    let mut col_idx = vec![0u32; total];
    let mut src = vec![0usize; total];
    let (col_out, src_out) = (SharedSlice::new(&mut col_idx), SharedSlice::new(&mut src));
    (0..n).into_par_iter().with_min_len(1024).for_each(|i| {
        let lower = (m.col_ptr[i]..m.col_ptr[i + 1]).map(|p| (m.row_idx[p] as u32, p));
        let upper = strict_upper(i).map(|t| (up_col[t], up_src[t]));
        for (at, (c, p)) in (row_ptr[i]..).zip(lower.chain(upper)) {
            // SAFETY: row i's positions row_ptr[i]..row_ptr[i + 1] are its
            // own, and below `total`
            unsafe {
                col_out.write(at, c);
                src_out.write(at, p);
            }
        }
    });
    (row_ptr, col_idx, src)
}

/// The transpose of the pattern with row starts `row_ptr` and `n_cols`
/// columns, `column(q)` being the column of entry `q`: its row starts, its
/// columns (the original rows, increasing within each row) and, for each
/// of its entries, the original entry `q`. The rows are split into one
/// contiguous block per thread; each block counts its entries per column,
/// prefix sums give every block its positions in every transposed row
/// (blocks in row order), and the blocks scatter their entries in
/// parallel. The result is the same for any number of threads.
pub(crate) fn transpose_pattern(
    row_ptr: &[usize],
    n_cols: usize,
    column: impl Fn(usize) -> usize + Sync,
) -> (Vec<usize>, Vec<u32>, Vec<usize>) {
    let n = row_ptr.len() - 1;
    let nnz = row_ptr[n];
    let blocks = if nnz < PAR_MIN_LEN {
        1
    } else {
        rayon::current_num_threads().max(1)
    };
    let rows_per = n.div_ceil(blocks).max(1);
    let range = |b: usize| (b * rows_per).min(n)..((b + 1) * rows_per).min(n);
    // counts[b][j]: entries of block b in column j
    let counts: Vec<Vec<usize>> = (0..blocks)
        .into_par_iter()
        .map(|b| {
            let mut c = vec![0usize; n_cols];
            let r = range(b);
            for q in row_ptr[r.start]..row_ptr[r.end] {
                c[column(q)] += 1;
            }
            c
        })
        .collect();
    let mut t_ptr = vec![0usize; n_cols + 1];
    let mut starts = vec![vec![0usize; n_cols]; blocks];
    for j in 0..n_cols {
        let mut at = t_ptr[j];
        for b in 0..blocks {
            starts[b][j] = at;
            at += counts[b][j];
        }
        t_ptr[j + 1] = at;
    }
    let mut t_col = vec![0u32; nnz];
    let mut src = vec![0usize; nnz];
    let (col_out, src_out) = (SharedSlice::new(&mut t_col), SharedSlice::new(&mut src));
    starts
        .into_par_iter()
        .enumerate()
        .for_each(|(b, mut next)| {
            for i in range(b) {
                for q in row_ptr[i]..row_ptr[i + 1] {
                    let j = column(q);
                    // SAFETY: the positions next[j] of block b are its own
                    // (disjoint from every other block's by the prefix sums
                    // above) and below nnz
                    unsafe {
                        col_out.write(next[j], i as u32);
                        src_out.write(next[j], q);
                    }
                    next[j] += 1;
                }
            }
        });
    (t_ptr, t_col, src)
}

/// A slice that several threads write at disjoint positions
/// ([`transpose_pattern`], [`symmetric_to_full_pattern`]).
#[derive(Clone, Copy)]
pub(crate) struct SharedSlice<T>(*mut T);
// SAFETY: the writers keep to disjoint positions (see each use)
unsafe impl<T: Send> Send for SharedSlice<T> {}
unsafe impl<T: Send> Sync for SharedSlice<T> {}

impl<T> SharedSlice<T> {
    pub(crate) fn new(slice: &mut [T]) -> Self {
        SharedSlice(slice.as_mut_ptr())
    }

    /// # Safety
    /// `k` is in bounds and no other thread touches position `k`.
    pub(crate) unsafe fn write(&self, k: usize, value: T) {
        self.0.add(k).write(value)
    }
}

/// Both triangles of a [`SymmetricCsc`] in compressed sparse row form, for
/// a symmetric product `y = A x` computed row by row in parallel (no
/// scatter, no write conflicts). Built once per pattern; [`FullCsr::fill`]
/// copies new values through a precomputed source map.
#[derive(Debug, Clone, Default)]
pub(crate) struct FullCsr {
    row_ptr: Vec<usize>,
    col_idx: Vec<u32>,
    /// Index into the upper-triangle `values` of each full entry.
    src: Vec<usize>,
    values: Vec<f64>,
}

impl FullCsr {
    /// Pattern of `A` (values left zero until [`FullCsr::fill`]).
    pub(crate) fn new(m: &SymmetricCsc) -> Self {
        let (row_ptr, col_idx, src) = symmetric_to_full_pattern(m);
        let total = col_idx.len();
        FullCsr {
            row_ptr,
            col_idx,
            src,
            values: vec![0.0; total],
        }
    }

    /// Copy the values of `m` (same pattern as at construction).
    pub(crate) fn fill(&mut self, m: &SymmetricCsc) {
        let upper = &m.values;
        self.values
            .par_iter_mut()
            .zip(self.src.par_iter())
            .for_each(|(v, &p)| *v = upper[p]);
    }

    /// `y = A x`, rows in parallel.
    pub(crate) fn mul(&self, x: &[f64], y: &mut [f64]) {
        y.par_chunks_mut(1024).enumerate().for_each(|(c, chunk)| {
            let base = c * 1024;
            for (k, yi) in chunk.iter_mut().enumerate() {
                let i = base + k;
                let (s, e) = (self.row_ptr[i], self.row_ptr[i + 1]);
                let mut acc = 0.0;
                for p in s..e {
                    acc += self.values[p] * x[self.col_idx[p] as usize];
                }
                *yi = acc;
            }
        });
    }

    /// `eps || |A| |x| ||_2` (see [`residual_floor`]).
    pub(crate) fn residual_floor(&self, x: &[f64]) -> f64 {
        residual_floor(&self.row_ptr, &self.col_idx, &self.values, x)
    }
}

/// `eps || |A| |x| ||_2` for a matrix in full CSR: the size below which
/// the residual `b - A x` cannot be resolved in double precision (each
/// entry of `A x` carries a rounding error of order `eps (|A| |x|)_i`).
pub(crate) fn residual_floor(row_ptr: &[usize], col: &[u32], val: &[f64], x: &[f64]) -> f64 {
    let sq: f64 = (0..row_ptr.len().saturating_sub(1))
        .into_par_iter()
        .map(|i| {
            let acc: f64 = (row_ptr[i]..row_ptr[i + 1])
                .map(|p| (val[p] * x[col[p] as usize]).abs())
                .sum();
            acc * acc
        })
        .sum();
    f64::EPSILON * sq.sqrt()
}

/// `||A||_inf` (largest absolute row sum) of a symmetric matrix stored as
/// its upper triangle.
pub(crate) fn symmetric_norm_inf(a: &SymmetricCsc) -> f64 {
    inf_norm(&symmetric_row_sums(a))
}

/// Absolute row sums `sum_j |a_ij|` of a matrix stored as its upper
/// triangle (symmetric) or, when general ([`SymmetricCsc::is_general`]),
/// with its lower triangle transposed in `lower`.
pub(crate) fn symmetric_row_sums(a: &SymmetricCsc) -> Vec<f64> {
    let low = if a.is_general() { &a.lower } else { &a.values };
    // row sums over column chunks in parallel (one vector per chunk)
    let chunks = if a.row_idx.len() > 200_000 {
        rayon::current_num_threads().clamp(1, 8)
    } else {
        1
    };
    let per = a.n.div_ceil(chunks.max(1)).max(1);
    let sums: Vec<Vec<f64>> = (0..chunks)
        .into_par_iter()
        .map(|c| {
            let mut rows = vec![0.0f64; a.n];
            for j in (c * per).min(a.n)..((c + 1) * per).min(a.n) {
                for p in a.col_ptr[j]..a.col_ptr[j + 1] {
                    let i = a.row_idx[p];
                    rows[i] += a.values[p].abs();
                    if i != j {
                        rows[j] += low[p].abs();
                    }
                }
            }
            rows
        })
        .collect();
    let mut it = sums.into_iter();
    let Some(mut rows) = it.next() else {
        return Vec::new();
    };
    for other in it {
        rows.iter_mut().zip(&other).for_each(|(r, o)| *r += o);
    }
    rows
}

/// `max(a, b)` that keeps a NaN (a scan for the largest entry that must
/// also notice a non-finite one).
pub(crate) fn nan_max(a: f64, b: f64) -> f64 {
    if a.is_nan() || b.is_nan() {
        f64::NAN
    } else {
        a.max(b)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gallery::{grid_3d, Stencil};

    /// The fingerprint tells apart what a caller could pass by mistake:
    /// another matrix of the same size and number of entries (column
    /// lengths moved) or a sampled row index changed, and accepts the same
    /// pattern with other values.
    #[test]
    fn pattern_fingerprint_catches_a_changed_pattern() {
        let (a, _) = grid_3d(6, 5, 4, 3, Stencil::Point27);
        let p = Pattern::of(&a);
        let mut values = a.clone();
        values.values.iter_mut().for_each(|v| *v *= 2.0);
        assert!(p.check(&values, "t").is_ok());
        // one entry moved from the last column to the first: same n, nnz
        let mut moved = a.clone();
        moved.col_ptr[1..a.n].iter_mut().for_each(|c| *c += 1);
        assert!(matches!(p.check(&moved, "t"), Err(SolverError::Usage(_))));
        // the first row of column 0 (a sampled column) changed
        let mut row = a.clone();
        row.row_idx[0] += 1;
        assert!(matches!(p.check(&row, "t"), Err(SolverError::Usage(_))));
        // a sampled index deep inside the matrix changed
        let mut deep = a.clone();
        deep.row_idx[10 * HASH_STRIDE] ^= 1;
        assert!(matches!(p.check(&deep, "t"), Err(SolverError::Usage(_))));
    }

    #[test]
    fn full_csr_product_matches_mul_vec() {
        let (a, _) = grid_3d(4, 3, 5, 3, Stencil::Point27);
        let mut f = FullCsr::new(&a);
        f.fill(&a);
        let x: Vec<f64> = (0..a.n).map(|i| ((i * 7919) % 13) as f64 - 6.0).collect();
        let mut y1 = vec![0.0; a.n];
        let mut y2 = vec![0.0; a.n];
        a.mul_vec(&x, &mut y1);
        f.mul(&x, &mut y2);
        for (p, q) in y1.iter().zip(&y2) {
            assert!((p - q).abs() <= 1e-12 * p.abs().max(1.0));
        }
        assert!(y1.iter().any(|v| v.abs() > 1.0));
    }

    /// Above the parallel threshold (a 27-point grid of 20 x 20 x 12 nodes
    /// with 3 dofs per node: 1.2M stored entries), on three threads, both
    /// triangles come out entry for entry: every stored `(i, j)` appears in
    /// row `i` at column `j` and, off the diagonal, in row `j` at column
    /// `i`, both pointing at its value, each row's columns increasing.
    #[test]
    fn parallel_full_pattern_holds_both_triangles() {
        let (a, _) = grid_3d(20, 20, 12, 3, Stencil::Point27);
        assert!(a.nnz() > PAR_MIN_LEN);
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(3)
            .build()
            .unwrap();
        let (row_ptr, col, src) = pool.install(|| symmetric_to_full_pattern(&a));
        let diagonal = (0..a.n)
            .filter(|&j| a.row_idx[a.col_ptr[j]..a.col_ptr[j + 1]].contains(&j))
            .count();
        assert_eq!(row_ptr[a.n], 2 * a.nnz() - diagonal);
        let find = |i: usize, j: usize| {
            let row = &col[row_ptr[i]..row_ptr[i + 1]];
            assert!(row.windows(2).all(|w| w[0] < w[1]), "row {i} unsorted");
            row.binary_search(&(j as u32)).map(|k| src[row_ptr[i] + k])
        };
        for j in 0..a.n {
            for p in a.col_ptr[j]..a.col_ptr[j + 1] {
                let i = a.row_idx[p];
                assert_eq!(find(i, j), Ok(p), "({i}, {j})");
                assert_eq!(find(j, i), Ok(p), "({j}, {i})");
            }
        }
    }

    #[test]
    fn validation_rejects_lower_entries() {
        let mut a = SymmetricCsc::from_columns(vec![vec![0, 1], vec![1]]);
        a.values = vec![1.0, 2.0, 3.0];
        assert!(matches!(validate(&a), Err(SolverError::Usage(_))));
        let (ok, _) = grid_3d(2, 2, 2, 1, Stencil::Point7);
        assert!(validate(&ok).is_ok());
    }
}

/// Bytes of memory the system can still give (`MemAvailable` of
/// `/proc/meminfo`, Linux); `None` where unknown.
pub(crate) fn available_memory() -> Option<u64> {
    let info = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = info.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// Extend the empty `values` (reserved for at least `len` entries) to `len`
/// default values, written by rayon's threads in chunks. The first write
/// to a fresh page maps it; spread over the threads, mapping and zeroing
/// the half-gigabyte factor of a 100k-equation cube takes a fraction of
/// the single-thread `resize` (0.25 s on the H20 cube n=20).
pub(crate) fn fill_default_in_parallel<T: Default + Copy + Send + Sync>(
    values: &mut Vec<T>,
    len: usize,
) {
    assert!(values.is_empty() && values.capacity() >= len);
    values.spare_capacity_mut()[..len]
        .par_chunks_mut(1 << 16)
        .for_each(|chunk| {
            for v in chunk {
                v.write(T::default());
            }
        });
    // SAFETY: the first `len` entries were written just above.
    unsafe { values.set_len(len) };
}
