//! [`SymmetricCsc`]: a symmetric sparse matrix stored as its upper triangle
//! in compressed sparse column form (column `j` holds rows `i <= j`, sorted).
//! This is the layout faer's sparse Cholesky reads with `Side::Upper`.

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
        }
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

    /// y = A x (full symmetric product from the upper triangle).
    pub fn mul_vec(&self, x: &[f64], y: &mut [f64]) {
        // Row i of A = column i of the upper triangle (entries k<=i) plus the
        // transposed entries (i, j) stored in later columns j > i. Computing
        // y_j = sum over column j (upper part) in parallel, then scattering
        // the strictly-upper transpose part serially would serialise half
        // the work; instead use the column view twice: y = U x + U^T x - D x.
        let n = self.n;
        // U^T x and the diagonal: per column j, dot(column j, x) -> y_j (parallel)
        y.par_iter_mut().enumerate().for_each(|(j, yj)| {
            let (s, e) = (self.col_ptr[j], self.col_ptr[j + 1]);
            let mut acc = 0.0;
            for p in s..e {
                acc += self.values[p] * x[self.row_idx[p]];
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
}
