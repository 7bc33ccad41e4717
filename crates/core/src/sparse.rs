//! [`SymmetricCsc`]: a symmetric sparse matrix stored as its upper triangle
//! in compressed sparse column form (column `j` holds rows `i <= j`, sorted).
//! This is the layout faer's sparse Cholesky reads with `Side::Upper`.
//!
//! A nonsymmetric matrix with a symmetric pattern (the tangent of a model
//! whose laws declare [`crate::MatrixKind::General`]: friction,
//! non-associated plasticity) uses the same pattern plus a second value
//! array, [`SymmetricCsc::lower`]: for the stored entry `p = (i, j)`,
//! `i <= j`, `values[p] = A[i][j]` and `lower[p] = A[j][i]` (so on the
//! diagonal both hold `A[j][j]`). An empty `lower` means a symmetric
//! matrix; symmetric back ends refuse a matrix with a non-empty `lower`.

use rayon::prelude::*;

/// Symmetric matrix, upper triangle, CSC.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SymmetricCsc {
    /// Dimension.
    pub n: usize,
    /// Column pointers (len n + 1).
    pub col_ptr: Vec<usize>,
    /// Row indices, sorted within each column, all `<= column`.
    pub row_idx: Vec<usize>,
    /// Values aligned with `row_idx`.
    pub values: Vec<f64>,
    /// Transposed values of a nonsymmetric matrix: `lower[p] = A[j][i]`
    /// for the entry `p = (i, j)` of `row_idx`; empty for a symmetric one.
    pub lower: Vec<f64>,
}

impl SymmetricCsc {
    /// Number of stored (upper-triangle) entries.
    pub fn nnz(&self) -> usize {
        self.row_idx.len()
    }

    /// Build from the sorted upper-triangle rows of every column; values zero.
    pub fn from_columns(columns: Vec<Vec<usize>>) -> Self {
        let n = columns.len();
        let mut col_ptr = Vec::with_capacity(n + 1);
        col_ptr.push(0);
        let total: usize = columns.iter().map(Vec::len).sum();
        let mut row_idx = Vec::with_capacity(total);
        for c in columns {
            row_idx.extend_from_slice(&c);
            col_ptr.push(row_idx.len());
        }
        let values = vec![0.0; total];
        SymmetricCsc {
            n,
            col_ptr,
            row_idx,
            values,
            lower: Vec::new(),
        }
    }

    /// True for a nonsymmetric matrix (a non-empty [`SymmetricCsc::lower`]).
    pub fn is_general(&self) -> bool {
        !self.lower.is_empty()
    }

    /// Make this a nonsymmetric matrix with the same pattern (`lower`
    /// allocated, copied from `values`), or symmetric again (`false`).
    pub fn set_general(&mut self, general: bool) {
        if general {
            self.lower = self.values.clone();
        } else {
            self.lower = Vec::new();
        }
    }

    /// The full matrix in CSC form `(col_ptr, row_idx, values)`, both
    /// triangles (from `values` and, for a nonsymmetric matrix, `lower`;
    /// the mirror of `values` otherwise). Rows sorted within each column.
    #[allow(clippy::needless_range_loop)]
    pub fn to_full_csc(&self) -> (Vec<usize>, Vec<usize>, Vec<f64>) {
        let n = self.n;
        let mut count = vec![0usize; n + 1];
        for j in 0..n {
            for p in self.col_ptr[j]..self.col_ptr[j + 1] {
                let i = self.row_idx[p];
                count[j + 1] += 1;
                if i != j {
                    count[i + 1] += 1;
                }
            }
        }
        for j in 0..n {
            count[j + 1] += count[j];
        }
        let nnz = count[n];
        let mut next = count.clone();
        let mut rows = vec![0usize; nnz];
        let mut vals = vec![0.0; nnz];
        let low = if self.is_general() {
            &self.lower
        } else {
            &self.values
        };
        // two passes keep the rows sorted: first the upper part of every
        // column (rows <= j), then the mirrored rows (> i) in increasing order
        for j in 0..n {
            for p in self.col_ptr[j]..self.col_ptr[j + 1] {
                let i = self.row_idx[p];
                rows[next[j]] = i;
                vals[next[j]] = self.values[p];
                next[j] += 1;
            }
        }
        for j in 0..n {
            for p in self.col_ptr[j]..self.col_ptr[j + 1] {
                let i = self.row_idx[p];
                if i != j {
                    // A[j][i] is entry (row j, column i), row j > i
                    rows[next[i]] = j;
                    vals[next[i]] = low[p];
                    next[i] += 1;
                }
            }
        }
        (count, rows, vals)
    }

    /// Position of entry (i, j) with i <= j in `values`, if present.
    #[inline]
    pub fn position(&self, i: usize, j: usize) -> Option<usize> {
        let (i, j) = if i <= j { (i, j) } else { (j, i) };
        let start = self.col_ptr[j];
        let rows = &self.row_idx[start..self.col_ptr[j + 1]];
        rows.binary_search(&i).ok().map(|p| start + p)
    }

    /// Diagonal entries.
    pub fn diagonal(&self) -> Vec<f64> {
        (0..self.n)
            .map(|j| {
                // the diagonal is the last entry of each column
                let end = self.col_ptr[j + 1];
                if end > self.col_ptr[j] && self.row_idx[end - 1] == j {
                    self.values[end - 1]
                } else {
                    0.0
                }
            })
            .collect()
    }

    /// y = A x (full product from the upper triangle, and `lower` for a
    /// nonsymmetric matrix).
    pub fn mul_vec(&self, x: &[f64], y: &mut [f64]) {
        let low = if self.is_general() {
            &self.lower
        } else {
            &self.values
        };
        // Row i of A = column i of the upper triangle (entries k<=i) plus the
        // transposed entries (i, j) stored in later columns j > i. Computing
        // y_j = sum over column j (upper part) in parallel, then scattering
        // the strictly-upper transpose part serially would serialise half
        // the work; instead use the column view twice: y = U x + U^T x - D x.
        let n = self.n;
        // L x and the diagonal: per column j of the upper pattern, row j of
        // the lower triangle is dot(lower column j, x) -> y_j (parallel)
        y.par_iter_mut().enumerate().for_each(|(j, yj)| {
            let (s, e) = (self.col_ptr[j], self.col_ptr[j + 1]);
            let mut acc = 0.0;
            for p in s..e {
                acc += low[p] * x[self.row_idx[p]];
            }
            *yj = acc;
        });
        // U x without the diagonal: y_i += a_ij x_j for i < j (serial scatter)
        for (j, &xj) in x.iter().enumerate().take(n) {
            for p in self.col_ptr[j]..self.col_ptr[j + 1] {
                let i = self.row_idx[p];
                if i != j {
                    y[i] += self.values[p] * xj;
                }
            }
        }
    }
}

impl SymmetricCsc {
    /// `y_r = A x_r` for the `x.len() / n` vectors stored one after another
    /// in `x` (and `y`), in one pass over the matrix: each stored entry
    /// `(i, j)` adds `a_ji x_r[i]` to `y_r[j]` (from `lower` for a
    /// nonsymmetric matrix) and, off the diagonal, `a_ij x_r[j]` to
    /// `y_r[i]`. Column ranges of equal entry counts run in parallel, each
    /// into its own buffer, summed at the end.
    pub fn mul_many(&self, x: &[f64], y: &mut [f64]) {
        let n = self.n;
        y.iter_mut().for_each(|v| *v = 0.0);
        if n == 0 {
            return;
        }
        let k = x.len() / n;
        let low = if self.is_general() {
            &self.lower
        } else {
            &self.values
        };
        let nnz = self.row_idx.len();
        let chunks = if nnz > 100_000 {
            rayon::current_num_threads().clamp(1, 8)
        } else {
            1
        };
        // column boundaries splitting the entries evenly
        let bounds: Vec<usize> = (0..=chunks)
            .map(|c| {
                self.col_ptr
                    .partition_point(|&p| p < c * nnz / chunks)
                    .min(n)
            })
            .collect();
        let columns = |j0: usize, j1: usize, out: &mut [f64]| {
            for j in j0..j1 {
                let (s, mut e) = (self.col_ptr[j], self.col_ptr[j + 1]);
                // the diagonal, when stored, is the column's last entry
                let diag = if e > s && self.row_idx[e - 1] == j {
                    e -= 1;
                    Some(low[e])
                } else {
                    None
                };
                let (rows, lows, ups) = (&self.row_idx[s..e], &low[s..e], &self.values[s..e]);
                for r in 0..k {
                    let (xr, out_r) = (&x[r * n..(r + 1) * n], &mut out[r * n..(r + 1) * n]);
                    let xj = xr[j];
                    let mut acc = 0.0;
                    for ((&i, l), v) in rows.iter().zip(lows).zip(ups) {
                        acc += l * xr[i];
                        out_r[i] += v * xj;
                    }
                    if let Some(d) = diag {
                        acc += d * xj;
                    }
                    out_r[j] += acc;
                }
            }
        };
        if chunks == 1 {
            columns(0, n, y);
            return;
        }
        let parts: Vec<Vec<f64>> = (0..chunks)
            .into_par_iter()
            .map(|c| {
                let mut out = vec![0.0; k * n];
                columns(bounds[c], bounds[c + 1], &mut out);
                out
            })
            .collect();
        y.par_chunks_mut(4096).enumerate().for_each(|(b, ys)| {
            let off = b * 4096;
            let len = ys.len();
            for part in &parts {
                for (yi, pi) in ys.iter_mut().zip(&part[off..off + len]) {
                    *yi += pi;
                }
            }
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn symmetric_product_matches_dense() {
        // A = [[4,1,0],[1,3,2],[0,2,5]]
        let mut a = SymmetricCsc::from_columns(vec![vec![0], vec![0, 1], vec![1, 2]]);
        a.values = vec![4.0, 1.0, 3.0, 2.0, 5.0];
        let x = [1.0, -2.0, 3.0];
        let mut y = [0.0; 3];
        a.mul_vec(&x, &mut y);
        assert_eq!(y, [4.0 - 2.0, 1.0 - 6.0 + 6.0, -4.0 + 15.0]);
        assert_eq!(a.position(2, 1), Some(3));
        assert_eq!(a.position(0, 2), None);
        assert_eq!(a.diagonal(), vec![4.0, 3.0, 5.0]);
    }

    #[test]
    fn general_product_and_full_csc_match_dense() {
        // A = [[4,1,0],[7,3,2],[0,-1,5]]: upper from `values`, lower from `lower`
        let mut a = SymmetricCsc::from_columns(vec![vec![0], vec![0, 1], vec![1, 2]]);
        a.values = vec![4.0, 1.0, 3.0, 2.0, 5.0];
        a.lower = vec![4.0, 7.0, 3.0, -1.0, 5.0];
        let x = [1.0, -2.0, 3.0];
        let mut y = [0.0; 3];
        a.mul_vec(&x, &mut y);
        assert_eq!(y, [4.0 - 2.0, 7.0 - 6.0 + 6.0, 2.0 + 15.0]);
        let (cp, ri, v) = a.to_full_csc();
        assert_eq!(cp, vec![0, 2, 5, 7]);
        assert_eq!(ri, vec![0, 1, 0, 1, 2, 1, 2]);
        assert_eq!(v, vec![4.0, 7.0, 1.0, 3.0, -1.0, 2.0, 5.0]);
        // two vectors at once
        let mut yy = [0.0; 6];
        a.mul_many(&[1.0, -2.0, 3.0, 0.5, 1.0, -1.0], &mut yy);
        assert_eq!(yy[..3], y);
        let mut y2 = [0.0; 3];
        a.mul_vec(&[0.5, 1.0, -1.0], &mut y2);
        assert_eq!(yy[3..], y2);
    }

    #[test]
    fn many_product_matches_mul_vec_on_a_large_band() {
        // 20,000 columns of 9 entries: past the threshold of the parallel
        // column ranges
        let n = 20_000;
        let cols = (0..n)
            .map(|j: usize| (j.saturating_sub(8)..=j).collect())
            .collect();
        let mut a = SymmetricCsc::from_columns(cols);
        for (p, v) in a.values.iter_mut().enumerate() {
            *v = ((p * 7919) % 97) as f64 - 48.0;
        }
        let x: Vec<f64> = (0..2 * n).map(|i| ((i * 31) % 17) as f64 - 8.0).collect();
        let mut y = vec![0.0; 2 * n];
        a.mul_many(&x, &mut y);
        for r in 0..2 {
            let mut y1 = vec![0.0; n];
            a.mul_vec(&x[r * n..(r + 1) * n], &mut y1);
            for (p, q) in y1.iter().zip(&y[r * n..(r + 1) * n]) {
                assert!((p - q).abs() <= 1e-12 * p.abs().max(1.0), "{p} vs {q}");
            }
        }
        assert!(y.iter().any(|v| v.abs() > 100.0));
    }
}
