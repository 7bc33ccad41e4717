//! Model sparse matrices for tests, benchmarks and examples (SPD grids; a
//! shifted, indefinite Laplacian and a saddle point for the indefinite and
//! general back ends).
//!
//! [`grid_3d`] builds `A = L ⊗ B` on an `nx × ny × nz` grid of nodes with
//! unit spacing, `d` dofs per node:
//!
//! * `L` is a graph Laplacian of the 7-point (faces) or 27-point (faces,
//!   edges and corners, the pattern of a hex8 mesh) stencil with a
//!   Dirichlet-like diagonal: `L_II` = the full stencil's neighbour count (6
//!   or 26) everywhere, `L_IJ = -1` for the neighbours present. Boundary rows
//!   are then strictly diagonally dominant, so `L` is SPD (irreducibly
//!   diagonally dominant), with a condition number growing like `h^-2`.
//! * `B` (`d × d`) couples the dofs of a node like an elasticity block:
//!   `B_aa = 2`, `B_ab = 1/2`; its eigenvalues `3/2` and `2 + (d-1)/2` are
//!   positive, so `A = L ⊗ B` is SPD with eigenvalues `λ_L λ_B`.
//!
//! [`grid_3d_neumann`] uses `L_II` = the actual neighbour count: constant
//! vectors lie in its null space, so `A` is singular (positive
//! semi-definite), like an unconstrained elastic body.
//!
//! Equations are numbered node by node (`x` fastest), the dofs of a node
//! consecutively; the coordinates returned hold one point per equation.

use junta_core::SymmetricCsc;

/// Neighbourhood of a grid node.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stencil {
    /// 6 face neighbours.
    Point7,
    /// 26 neighbours (hex8 mesh pattern).
    Point27,
}

/// SPD grid matrix `L ⊗ B` and one point per equation (see module docs).
pub fn grid_3d(
    nx: usize,
    ny: usize,
    nz: usize,
    dofs_per_node: usize,
    stencil: Stencil,
) -> (SymmetricCsc, Vec<[f64; 3]>) {
    build(nx, ny, nz, dofs_per_node, stencil, false)
}

/// Singular (Neumann) variant of [`grid_3d`]: constants are in the kernel.
pub fn grid_3d_neumann(
    nx: usize,
    ny: usize,
    nz: usize,
    dofs_per_node: usize,
    stencil: Stencil,
) -> (SymmetricCsc, Vec<[f64; 3]>) {
    build(nx, ny, nz, dofs_per_node, stencil, true)
}

fn build(
    nx: usize,
    ny: usize,
    nz: usize,
    d: usize,
    stencil: Stencil,
    neumann: bool,
) -> (SymmetricCsc, Vec<[f64; 3]>) {
    let nodes = nx * ny * nz;
    let n = nodes * d;
    let full_count = match stencil {
        Stencil::Point7 => 6.0,
        Stencil::Point27 => 26.0,
    };
    let b = |a: usize, c: usize| if a == c { 2.0 } else { 0.5 };
    let mut col_ptr = Vec::with_capacity(n + 1);
    col_ptr.push(0);
    let mut row_idx = Vec::new();
    let mut values = Vec::new();
    let mut coords = Vec::with_capacity(n);
    let mut neighbours: Vec<(usize, f64)> = Vec::with_capacity(27);
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                let node = i + nx * (j + ny * k);
                // neighbours with index <= node, in increasing index order
                neighbours.clear();
                let mut degree = 0.0;
                for dk in -1i64..=1 {
                    for dj in -1i64..=1 {
                        for di in -1i64..=1 {
                            let manhattan = di.abs() + dj.abs() + dk.abs();
                            if manhattan == 0 {
                                continue;
                            }
                            if stencil == Stencil::Point7 && manhattan > 1 {
                                continue;
                            }
                            let (ii, jj, kk) = (i as i64 + di, j as i64 + dj, k as i64 + dk);
                            if ii < 0
                                || jj < 0
                                || kk < 0
                                || ii >= nx as i64
                                || jj >= ny as i64
                                || kk >= nz as i64
                            {
                                continue;
                            }
                            degree += 1.0;
                            let other = ii as usize + nx * (jj as usize + ny * kk as usize);
                            if other < node {
                                neighbours.push((other, -1.0));
                            }
                        }
                    }
                }
                let diag = if neumann { degree } else { full_count };
                neighbours.push((node, diag));
                for c in 0..d {
                    for &(other, l) in &neighbours {
                        for a in 0..d {
                            if other == node && a > c {
                                break;
                            }
                            row_idx.push(other * d + a);
                            values.push(l * b(a, c));
                        }
                    }
                    col_ptr.push(row_idx.len());
                    coords.push([i as f64, j as f64, k as f64]);
                }
            }
        }
    }
    (
        SymmetricCsc {
            n,
            col_ptr,
            row_idx,
            values,
            lower: Vec::new(),
        },
        coords,
    )
}

/// 7-point Dirichlet Laplacian on an `n^3` grid of interior points (unit
/// spacing) shifted by `-sigma I`, upper CSC, with one point per equation.
pub fn shifted_laplacian(n: usize, sigma: f64) -> (SymmetricCsc, Vec<[f64; 3]>) {
    let mut cols = Vec::with_capacity(n * n * n);
    let mut vals = Vec::new();
    let mut coords = Vec::new();
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                let idx = i + n * (j + n * k);
                let mut rows = Vec::new();
                if k > 0 {
                    rows.push(idx - n * n);
                }
                if j > 0 {
                    rows.push(idx - n);
                }
                if i > 0 {
                    rows.push(idx - 1);
                }
                vals.extend(std::iter::repeat_n(-1.0, rows.len()));
                rows.push(idx);
                vals.push(6.0 - sigma);
                cols.push(rows);
                coords.push([i as f64, j as f64, k as f64]);
            }
        }
    }
    let mut a = SymmetricCsc::from_columns(cols);
    a.values = vals;
    (a, coords)
}

/// Sparse saddle point: a Laplacian `A` (SPD) tied by `m` constraints
/// `u_p - u_q = 0`, each multiplier with an explicit zero diagonal.
pub fn constrained_laplacian(n: usize, m: usize) -> (SymmetricCsc, Vec<[f64; 3]>) {
    let (lap, mut coords) = shifted_laplacian(n, 0.0);
    let na = lap.n;
    let mut cols: Vec<Vec<usize>> = (0..na)
        .map(|j| lap.row_idx[lap.col_ptr[j]..lap.col_ptr[j + 1]].to_vec())
        .collect();
    let mut vals = lap.values.clone();
    let stride = na / m;
    for c in 0..m {
        let p = c * stride + stride / 3;
        let q = p + n; // neighbour in y
        cols.push(vec![p, q, na + c]);
        vals.extend([1.0, -1.0, 0.0]);
        let (cp, cq) = (coords[p], coords[q]);
        coords.push([
            0.5 * (cp[0] + cq[0]),
            0.5 * (cp[1] + cq[1]),
            0.5 * (cp[2] + cq[2]),
        ]);
    }
    let mut a = SymmetricCsc::from_columns(cols);
    a.values = vals;
    (a, coords)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_is_symmetric_upper_with_diagonal_last() {
        let (a, coords) = grid_3d(3, 2, 2, 3, Stencil::Point27);
        assert_eq!(a.n, 36);
        assert_eq!(coords.len(), 36);
        for j in 0..a.n {
            let rows = &a.row_idx[a.col_ptr[j]..a.col_ptr[j + 1]];
            assert!(rows.windows(2).all(|w| w[0] < w[1]));
            assert_eq!(*rows.last().unwrap(), j);
        }
        // Neumann: A * ones = 0
        let (an, _) = grid_3d_neumann(3, 3, 2, 3, Stencil::Point7);
        let ones = vec![1.0; an.n];
        let mut y = vec![0.0; an.n];
        an.mul_vec(&ones, &mut y);
        assert!(y.iter().all(|v| v.abs() < 1e-12));
        // Dirichlet-like: A * ones > 0 on the boundary (here: every node)
        let ones = vec![1.0; a.n];
        let mut y = vec![0.0; a.n];
        a.mul_vec(&ones, &mut y);
        assert!(y.iter().all(|v| *v > 0.5));
    }
}
