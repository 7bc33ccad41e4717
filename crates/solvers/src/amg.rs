//! Smoothed-aggregation algebraic multigrid (SA-AMG) for 3D elasticity,
//! used as the preconditioner `"amg"` of [`crate::CgSolver`].
//!
//! # Hierarchy
//!
//! Level 0 is the assembled matrix `A_0` (both triangles in CSR). Its
//! equations are grouped into *nodes* (the 3 dofs of a mesh node, fewer
//! where dofs are constrained); coarse levels have one node per aggregate
//! (up to 6 dofs). For each level `l`:
//!
//! 1. **Strength of connection** on nodal blocks: with `||.||_F` the
//!    Frobenius norm of the block `A_IJ` between nodes `I != J`, `J` is a
//!    strong neighbour of `I` when
//!    `||A_IJ||_F^2 > θ^2 ||A_II||_F ||A_JJ||_F`, with `θ = theta` (0 by
//!    default: every non-zero block) when `I` and `J` belong to the same
//!    *body*, and `θ = theta_interface` (0.25) when they belong to different
//!    bodies (solids joined only by interface elements, see
//!    [`junta_core::EquationLayout`]). A stiff bond (penalty `d a` large
//!    against the solid's nodal stiffness) couples its node pairs strongly
//!    and is aggregated across, like one body; a soft, damaged or failed
//!    interface is weak, and no aggregate crosses it.
//! 2. **Aggregation** (Vaněk, Mandel, Brezina 1996), three passes over the
//!    node graph: (i) a node whose strong neighbours are all free forms an
//!    aggregate with them; (ii) every remaining node joins the aggregate of
//!    a strong neighbour; (iii) what is left forms aggregates with its free
//!    strong neighbours (a node without any is an aggregate alone).
//! 3. **Near-null space** `B_0` (`n × 6`): the rigid-body modes from the
//!    node coordinates `x` (relative to the centroid, scaled by the model
//!    size): translations `e_1, e_2, e_3` and rotations `θ × (x - x_c)`,
//!    evaluated at the node and component of each equation. A rigid motion
//!    of one body is a null vector of that body's stiffness; when bodies are
//!    joined only by soft or failed interfaces these are near-null vectors
//!    of the whole system. Because aggregates stay inside such bodies, the
//!    coarse spaces contain the rigid modes of every body separately (the
//!    per-body near-null space) without storing more than six columns.
//! 4. **Tentative prolongator** `T`: per aggregate `a`, the rows of `B_l`
//!    of its equations, `B_a = Q_a R_a` by modified Gram-Schmidt (twice),
//!    dropping columns whose remainder is below `1e-8` of their norm (an
//!    aggregate of one 3-dof node has rank 3, not 6). `T` holds the blocks
//!    `Q_a` (orthonormal columns, disjoint rows); the coarse near-null space
//!    is `B_{l+1} = [R_a]`, so `T B_{l+1} = B_l` *exactly*: the hierarchy
//!    interpolates the rigid modes without error on every level.
//! 5. **Smoothed prolongator** `P = (I - ω D^-1 A) T` with `D = diag(A)`,
//!    `ω = 4 / (3 ρ)` and `ρ` a power-iteration estimate of the spectral
//!    radius of `D^-1 A` (12 steps, times 1.1).
//! 6. **Galerkin coarse matrix** `A_{l+1} = P^T A P` (two sparse products,
//!    rows in parallel).
//!
//! Coarsening stops when a level has at most `max_coarse` equations, when
//! it no longer shrinks by 10 %, or after `max_levels` levels. The coarsest
//! matrix is factorised densely (Cholesky).
//!
//! # Cycle
//!
//! One V-cycle per application, `z = M^-1 r`: on each level a Chebyshev
//! smoother of degree `k` (polynomial in `D^-1 A` optimal on the interval
//! `[ρ/30, 1.1 ρ]`, Adams et al. 2003), restriction `P^T`, the coarse
//! correction, prolongation `P` and the same Chebyshev polynomial after.
//! Pre- and post-smoother being the same `A`-self-adjoint polynomial, the
//! cycle is a symmetric positive-definite operator, as CG requires.
//!
//! # Set-up and refresh
//!
//! Aggregates and tentative prolongators depend on the pattern, the
//! layout and the first matrix's strength of connection; they are kept.
//! [`Amg::refresh`] recomputes only numeric values for a new matrix of the
//! same pattern (diagonals, spectral radii, `P`, Galerkin products and the
//! coarse factor), as the Newton driver asks on each iteration.

use junta_core::{EquationLayout, SolverError, SymmetricCsc};
use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;

/// Columns of the near-null space (3 translations, 3 rotations).
pub const NULL_DIM: usize = 6;

/// Parameters of the hierarchy.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AmgSettings {
    /// Strength threshold `θ` (0: every non-zero block is strong).
    pub theta: f64,
    /// Strength threshold between nodes of different bodies (joined by
    /// interface elements): a bond this strong is aggregated across, a
    /// weaker (soft, damaged, failed) one is not.
    pub theta_interface: f64,
    /// Stop coarsening at this many equations (dense coarse solve).
    pub max_coarse: usize,
    /// Maximum number of levels.
    pub max_levels: usize,
    /// Degree of the Chebyshev smoother.
    pub degree: usize,
}

impl Default for AmgSettings {
    fn default() -> Self {
        AmgSettings {
            theta: 0.0,
            theta_interface: 0.25,
            max_coarse: 1500,
            max_levels: 12,
            degree: 2,
        }
    }
}

/// Compressed sparse rows with `u32` column indices.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Csr {
    /// Rows.
    pub n_rows: usize,
    /// Columns.
    pub n_cols: usize,
    /// Row starts (`n_rows + 1`).
    pub row_ptr: Vec<usize>,
    /// Column of each entry (increasing within a row).
    pub col: Vec<u32>,
    /// Values.
    pub val: Vec<f64>,
}

impl Csr {
    /// Both triangles of `m`, and for each entry its index in `m.values`.
    pub fn from_symmetric(m: &SymmetricCsc) -> (Csr, Vec<usize>) {
        let n = m.n;
        let (row_ptr, col, src) = crate::common::symmetric_to_full_pattern(m);
        let val = src.iter().map(|&p| m.values[p]).collect();
        (
            Csr {
                n_rows: n,
                n_cols: n,
                row_ptr,
                col,
                val,
            },
            src,
        )
    }

    /// `y = A x`, rows in parallel.
    pub fn mul(&self, x: &[f64], y: &mut [f64]) {
        y.par_chunks_mut(512).enumerate().for_each(|(c, chunk)| {
            let base = c * 512;
            for (k, yi) in chunk.iter_mut().enumerate() {
                let i = base + k;
                let mut acc = 0.0;
                for p in self.row_ptr[i]..self.row_ptr[i + 1] {
                    acc += self.val[p] * x[self.col[p] as usize];
                }
                *yi = acc;
            }
        });
    }

    /// Diagonal entries (0 where absent).
    pub fn diagonal(&self) -> Vec<f64> {
        (0..self.n_rows)
            .map(|i| {
                (self.row_ptr[i]..self.row_ptr[i + 1])
                    .find(|&p| self.col[p] as usize == i)
                    .map_or(0.0, |p| self.val[p])
            })
            .collect()
    }

    /// Transpose.
    pub fn transpose(&self) -> Csr {
        let mut count = vec![0usize; self.n_cols + 1];
        for &j in &self.col {
            count[j as usize + 1] += 1;
        }
        for j in 0..self.n_cols {
            count[j + 1] += count[j];
        }
        let row_ptr = count.clone();
        let mut next = count;
        let mut col = vec![0u32; self.col.len()];
        let mut val = vec![0.0; self.col.len()];
        for i in 0..self.n_rows {
            for p in self.row_ptr[i]..self.row_ptr[i + 1] {
                let j = self.col[p] as usize;
                col[next[j]] = i as u32;
                val[next[j]] = self.val[p];
                next[j] += 1;
            }
        }
        Csr {
            n_rows: self.n_cols,
            n_cols: self.n_rows,
            row_ptr,
            col,
            val,
        }
    }

    /// `self * b` (Gustavson, row blocks in parallel, one dense
    /// accumulator per block).
    pub fn matmul(&self, b: &Csr) -> Csr {
        let n = self.n_rows;
        let chunk = (n / (8 * rayon::current_num_threads().max(1))).max(256);
        let parts: Vec<(Vec<usize>, Vec<u32>, Vec<f64>)> = (0..n.div_ceil(chunk))
            .into_par_iter()
            .map(|c| {
                let (r0, r1) = (c * chunk, ((c + 1) * chunk).min(n));
                let mut marker = vec![usize::MAX; b.n_cols];
                let mut acc = vec![0.0; b.n_cols];
                let mut lens = Vec::with_capacity(r1 - r0);
                let mut cols: Vec<u32> = Vec::new();
                let mut vals = Vec::new();
                for i in r0..r1 {
                    let start = cols.len();
                    for p in self.row_ptr[i]..self.row_ptr[i + 1] {
                        let a = self.val[p];
                        let k = self.col[p] as usize;
                        for q in b.row_ptr[k]..b.row_ptr[k + 1] {
                            let j = b.col[q] as usize;
                            if marker[j] != i {
                                marker[j] = i;
                                cols.push(j as u32);
                                acc[j] = a * b.val[q];
                            } else {
                                acc[j] += a * b.val[q];
                            }
                        }
                    }
                    cols[start..].sort_unstable();
                    vals.extend(cols[start..].iter().map(|&j| acc[j as usize]));
                    lens.push(cols.len() - start);
                }
                (lens, cols, vals)
            })
            .collect();
        let mut row_ptr = Vec::with_capacity(n + 1);
        row_ptr.push(0);
        let total: usize = parts.iter().map(|p| p.1.len()).sum();
        let mut col = Vec::with_capacity(total);
        let mut val = Vec::with_capacity(total);
        for (lens, c, v) in parts {
            for l in lens {
                row_ptr.push(row_ptr.last().unwrap() + l);
            }
            col.extend(c);
            val.extend(v);
        }
        Csr {
            n_rows: n,
            n_cols: b.n_cols,
            row_ptr,
            col,
            val,
        }
    }
}

/// One level of the hierarchy.
#[derive(Debug, Clone, Default)]
pub struct Level {
    /// Matrix of this level.
    pub a: Csr,
    /// Equation ranges of the nodes of this level.
    pub node_ptr: Vec<usize>,
    /// Body of each node.
    pub node_body: Vec<u32>,
    /// Near-null space, `NULL_DIM` values per equation.
    pub b: Vec<[f64; NULL_DIM]>,
    /// Tentative prolongator to the next level (none on the coarsest).
    pub t: Csr,
    /// Smoothed prolongator and its transpose.
    pub p: Csr,
    pub r: Csr,
    /// `1 / diag(A)`.
    pub inv_diag: Vec<f64>,
    /// Estimated spectral radius of `D^-1 A`.
    pub rho: f64,
    /// Aggregate of each node (towards the next level).
    pub aggregate: Vec<usize>,
    // scratch of the cycle
    x: Vec<f64>,
    rhs: Vec<f64>,
    res: Vec<f64>,
    d: Vec<f64>,
}

/// The SA-AMG hierarchy (see the module docs).
#[derive(Debug, Clone, Default)]
pub struct Amg {
    settings: AmgSettings,
    /// Levels, finest first.
    pub levels: Vec<Level>,
    src0: Vec<usize>,
    coarse: Option<nalgebra::Cholesky<f64, nalgebra::Dyn>>,
}

fn nonpd(detail: String) -> SolverError {
    SolverError::NotPositiveDefinite { detail }
}

/// Rigid-body modes of each equation: translations and rotations about
/// the centroid of all equations, coordinates scaled by the model size. One
/// set for all bodies: the span of a body's rigid modes does not depend on
/// the centre of rotation, and per-body modes arise from aggregates that
/// stay inside bodies.
pub fn rigid_modes(coords: &[[f64; 3]], layout: &EquationLayout) -> Vec<[f64; NULL_DIM]> {
    let n = coords.len();
    let mut c = [0.0f64; 3];
    for x in coords {
        for k in 0..3 {
            c[k] += x[k] / n.max(1) as f64;
        }
    }
    let size = coords.iter().fold(0.0f64, |m, x| {
        (0..3).fold(m, |m, k| m.max((x[k] - c[k]).abs()))
    });
    let scale = if size > 0.0 { 1.0 / size } else { 1.0 };
    (0..n)
        .map(|i| {
            let x = (coords[i][0] - c[0]) * scale;
            let y = (coords[i][1] - c[1]) * scale;
            let z = (coords[i][2] - c[2]) * scale;
            let mut row = [0.0; NULL_DIM];
            match layout.component[i] {
                0 => {
                    row[0] = 1.0;
                    row[4] = z;
                    row[5] = -y;
                }
                1 => {
                    row[1] = 1.0;
                    row[3] = -z;
                    row[5] = x;
                }
                _ => {
                    row[2] = 1.0;
                    row[3] = y;
                    row[4] = -x;
                }
            }
            row
        })
        .collect()
}

/// Strong neighbours of every node (CSR over nodes).
fn strength(
    a: &Csr,
    node_ptr: &[usize],
    body: &[u32],
    theta: f64,
    theta_interface: f64,
) -> (Vec<usize>, Vec<u32>) {
    let nn = node_ptr.len() - 1;
    let mut node_of = vec![0u32; a.n_rows];
    for k in 0..nn {
        for e in node_of.iter_mut().take(node_ptr[k + 1]).skip(node_ptr[k]) {
            *e = k as u32;
        }
    }
    // squared Frobenius norm of the diagonal blocks
    let dnorm: Vec<f64> = (0..nn)
        .into_par_iter()
        .map(|k| {
            let mut s = 0.0;
            for i in node_ptr[k]..node_ptr[k + 1] {
                for p in a.row_ptr[i]..a.row_ptr[i + 1] {
                    if node_of[a.col[p] as usize] as usize == k {
                        s += a.val[p] * a.val[p];
                    }
                }
            }
            s.sqrt()
        })
        .collect();
    let t2 = theta * theta;
    let ti2 = theta_interface * theta_interface;
    let chunk = 1024;
    let parts: Vec<(Vec<usize>, Vec<u32>)> = (0..nn.div_ceil(chunk))
        .into_par_iter()
        .map(|c| {
            let (k0, k1) = (c * chunk, ((c + 1) * chunk).min(nn));
            let mut marker = vec![usize::MAX; nn];
            let mut acc = vec![0.0f64; nn];
            let mut lens = Vec::new();
            let mut out = Vec::new();
            let mut seen: Vec<u32> = Vec::new();
            for k in k0..k1 {
                seen.clear();
                for i in node_ptr[k]..node_ptr[k + 1] {
                    for p in a.row_ptr[i]..a.row_ptr[i + 1] {
                        let m = node_of[a.col[p] as usize] as usize;
                        if m == k {
                            continue;
                        }
                        if marker[m] != k {
                            marker[m] = k;
                            acc[m] = 0.0;
                            seen.push(m as u32);
                        }
                        acc[m] += a.val[p] * a.val[p];
                    }
                }
                let start = out.len();
                for &m in &seen {
                    let s = acc[m as usize];
                    let t = if body[m as usize] == body[k] { t2 } else { ti2 };
                    if s > 0.0 && s > t * dnorm[k] * dnorm[m as usize] {
                        out.push(m);
                    }
                }
                out[start..].sort_unstable();
                lens.push(out.len() - start);
            }
            (lens, out)
        })
        .collect();
    let mut ptr = vec![0usize];
    let mut adj = Vec::new();
    for (lens, out) in parts {
        for l in lens {
            ptr.push(ptr.last().unwrap() + l);
        }
        adj.extend(out);
    }
    (ptr, adj)
}

/// Standard three-pass aggregation; returns the aggregate of each node and
/// the number of aggregates.
fn aggregate(ptr: &[usize], adj: &[u32]) -> (Vec<usize>, usize) {
    let nn = ptr.len() - 1;
    const FREE: usize = usize::MAX;
    let mut agg = vec![FREE; nn];
    let mut count = 0;
    // pass 1
    for k in 0..nn {
        if agg[k] != FREE {
            continue;
        }
        let nb = &adj[ptr[k]..ptr[k + 1]];
        if nb.is_empty() || nb.iter().any(|&m| agg[m as usize] != FREE) {
            continue;
        }
        agg[k] = count;
        for &m in nb {
            agg[m as usize] = count;
        }
        count += 1;
    }
    // pass 2: join a neighbouring aggregate of pass 1
    let first = agg.clone();
    for k in 0..nn {
        if agg[k] != FREE {
            continue;
        }
        if let Some(&m) = adj[ptr[k]..ptr[k + 1]]
            .iter()
            .find(|&&m| first[m as usize] != FREE)
        {
            agg[k] = first[m as usize];
        }
    }
    // pass 3: leftovers with their free neighbours
    for k in 0..nn {
        if agg[k] != FREE {
            continue;
        }
        agg[k] = count;
        for &m in &adj[ptr[k]..ptr[k + 1]] {
            if agg[m as usize] == FREE {
                agg[m as usize] = count;
            }
        }
        count += 1;
    }
    (agg, count)
}

/// Tentative prolongator and coarse near-null space, coarse node ranges
/// and bodies, from the aggregates.
#[allow(clippy::type_complexity)]
fn tentative(
    level: &Level,
    agg: &[usize],
    n_agg: usize,
) -> (Csr, Vec<[f64; NULL_DIM]>, Vec<usize>, Vec<u32>) {
    let nn = level.node_ptr.len() - 1;
    // equations of each aggregate
    let mut members: Vec<Vec<usize>> = vec![Vec::new(); n_agg];
    for k in 0..nn {
        members[agg[k]].extend(level.node_ptr[k]..level.node_ptr[k + 1]);
    }
    let mut body = vec![0u32; n_agg];
    for k in 0..nn {
        body[agg[k]] = level.node_body[k];
    }
    // per aggregate: orthonormal Q (columns over the members) and R rows
    #[allow(clippy::type_complexity)]
    let blocks: Vec<(Vec<Vec<f64>>, Vec<[f64; NULL_DIM]>)> = members
        .par_iter()
        .map(|eqs| {
            let m = eqs.len();
            let mut q: Vec<Vec<f64>> = Vec::new();
            for c in 0..NULL_DIM {
                let mut v: Vec<f64> = eqs.iter().map(|&i| level.b[i][c]).collect();
                let n0 = v.iter().map(|x| x * x).sum::<f64>().sqrt();
                if n0 == 0.0 {
                    continue;
                }
                for _ in 0..2 {
                    for qk in &q {
                        let r: f64 = qk.iter().zip(&v).map(|(a, b)| a * b).sum();
                        for (vi, qi) in v.iter_mut().zip(qk) {
                            *vi -= r * qi;
                        }
                    }
                }
                let nv = v.iter().map(|x| x * x).sum::<f64>().sqrt();
                if nv > 1e-8 * n0 && q.len() < m {
                    for vi in &mut v {
                        *vi /= nv;
                    }
                    q.push(v);
                }
            }
            let r: Vec<[f64; NULL_DIM]> = q
                .iter()
                .map(|qk| {
                    let mut row = [0.0; NULL_DIM];
                    for (c, rc) in row.iter_mut().enumerate() {
                        *rc = qk.iter().zip(eqs).map(|(qi, &i)| qi * level.b[i][c]).sum();
                    }
                    row
                })
                .collect();
            (q, r)
        })
        .collect();
    let mut coarse_start = vec![0usize; n_agg + 1];
    for a in 0..n_agg {
        coarse_start[a + 1] = coarse_start[a] + blocks[a].0.len();
    }
    let nc = coarse_start[n_agg];
    // T rows: each fine equation has one entry per Q column of its aggregate
    let n = level.a.n_rows;
    let mut pos_in_agg = vec![0usize; n];
    let mut agg_of = vec![0usize; n];
    for (a, eqs) in members.iter().enumerate() {
        for (p, &i) in eqs.iter().enumerate() {
            pos_in_agg[i] = p;
            agg_of[i] = a;
        }
    }
    let mut row_ptr = vec![0usize; n + 1];
    let mut col = Vec::new();
    let mut val = Vec::new();
    for i in 0..n {
        let a = agg_of[i];
        for (k, qk) in blocks[a].0.iter().enumerate() {
            col.push((coarse_start[a] + k) as u32);
            val.push(qk[pos_in_agg[i]]);
        }
        row_ptr[i + 1] = col.len();
    }
    let mut bc = Vec::with_capacity(nc);
    for (_, r) in &blocks {
        bc.extend_from_slice(r);
    }
    (
        Csr {
            n_rows: n,
            n_cols: nc,
            row_ptr,
            col,
            val,
        },
        bc,
        coarse_start,
        body,
    )
}

/// Power-iteration estimate of the spectral radius of `D^-1 A` (times 1.1).
fn spectral_radius(a: &Csr, inv_diag: &[f64]) -> f64 {
    let n = a.n_rows;
    let mut v: Vec<f64> = (0..n)
        .map(|i| 1.0 + ((i.wrapping_mul(2654435761) % 1000) as f64) / 1000.0)
        .collect();
    let mut w = vec![0.0; n];
    let mut lam = 0.0;
    for _ in 0..12 {
        let nv = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        if nv == 0.0 {
            break;
        }
        v.iter_mut().for_each(|x| *x /= nv);
        a.mul(&v, &mut w);
        w.iter_mut().zip(inv_diag).for_each(|(x, d)| *x *= d);
        lam = w.iter().map(|x| x * x).sum::<f64>().sqrt();
        std::mem::swap(&mut v, &mut w);
    }
    1.1 * lam
}

fn inverse_diagonal(a: &Csr, level: usize) -> Result<Vec<f64>, SolverError> {
    a.diagonal()
        .iter()
        .enumerate()
        .map(|(i, &d)| {
            if d > 0.0 && d.is_finite() {
                Ok(1.0 / d)
            } else {
                Err(nonpd(format!(
                    ": amg level {level}: diagonal entry {i} is {d:e}"
                )))
            }
        })
        .collect()
}

impl Amg {
    /// Build the hierarchy for `m` with `coords` (one point per equation)
    /// and `layout` (node, component and body of each equation).
    pub fn setup(
        m: &SymmetricCsc,
        coords: &[[f64; 3]],
        layout: &EquationLayout,
        settings: AmgSettings,
    ) -> Result<Amg, SolverError> {
        let n = m.n;
        if coords.len() != n || layout.node.len() != n {
            return Err(SolverError::Usage(format!(
                "amg: {} coordinates and {} layout entries for {n} equations",
                coords.len(),
                layout.node.len()
            )));
        }
        let (a0, src0) = Csr::from_symmetric(m);
        let mut node_ptr = vec![0usize];
        let mut node_body = Vec::new();
        for i in 0..n {
            if i > 0 && layout.node[i] != layout.node[i - 1] {
                node_ptr.push(i);
            }
            if i == 0 || layout.node[i] != layout.node[i - 1] {
                node_body.push(layout.body[i]);
            }
        }
        if n > 0 {
            node_ptr.push(n);
        }
        let levels = vec![Level {
            a: a0,
            node_ptr,
            node_body,
            b: rigid_modes(coords, layout),
            ..Default::default()
        }];
        let mut amg = Amg {
            settings,
            levels,
            src0,
            coarse: None,
        };
        loop {
            let levels = &mut amg.levels;
            let l = levels.len() - 1;
            let cur = &levels[l];
            let nl = cur.a.n_rows;
            if nl <= settings.max_coarse || levels.len() >= settings.max_levels {
                break;
            }
            let (ptr, adj) = strength(
                &cur.a,
                &cur.node_ptr,
                &cur.node_body,
                settings.theta,
                settings.theta_interface,
            );
            let (agg, n_agg) = aggregate(&ptr, &adj);
            let (t, bc, cptr, cbody) = tentative(cur, &agg, n_agg);
            if t.n_cols as f64 > 0.9 * nl as f64 {
                break;
            }
            let cur = &mut levels[l];
            cur.t = t;
            cur.aggregate = agg;
            levels.push(Level {
                node_ptr: cptr,
                node_body: cbody,
                b: bc,
                ..Default::default()
            });
            amg.numeric_level(l)?;
        }
        let last = amg.levels.len() - 1;
        amg.numeric_level(last)?;
        amg.factor_coarsest()?;
        Ok(amg)
    }

    /// Recompute the numeric values for a new matrix of the same pattern.
    pub fn refresh(&mut self, m: &SymmetricCsc) -> Result<(), SolverError> {
        let a0 = &mut self.levels[0].a;
        if m.n != a0.n_rows || self.src0.iter().any(|&p| p >= m.values.len()) {
            return Err(SolverError::Usage(
                "amg: refresh with another pattern".into(),
            ));
        }
        a0.val
            .par_iter_mut()
            .zip(self.src0.par_iter())
            .for_each(|(v, &p)| *v = m.values[p]);
        self.numeric()
    }

    fn numeric(&mut self) -> Result<(), SolverError> {
        for l in 0..self.levels.len() {
            self.numeric_level(l)?;
        }
        self.factor_coarsest()
    }

    /// Diagonal, spectral radius and scratch of level `l`; with a next
    /// level, its prolongator and the next level's Galerkin matrix.
    fn numeric_level(&mut self, l: usize) -> Result<(), SolverError> {
        let nl = self.levels.len();
        {
            let inv_diag = inverse_diagonal(&self.levels[l].a, l)?;
            let rho = spectral_radius(&self.levels[l].a, &inv_diag);
            let lev = &mut self.levels[l];
            lev.inv_diag = inv_diag;
            lev.rho = rho;
            let n = lev.a.n_rows;
            lev.x = vec![0.0; n];
            lev.rhs = vec![0.0; n];
            lev.res = vec![0.0; n];
            lev.d = vec![0.0; n];
            if l + 1 == nl {
                return Ok(());
            }
            // P = T - ω D^-1 A T
            let omega = 4.0 / (3.0 * rho);
            let mut at = lev.a.matmul(&lev.t);
            for i in 0..n {
                let s = -omega * lev.inv_diag[i];
                for p in at.row_ptr[i]..at.row_ptr[i + 1] {
                    at.val[p] *= s;
                }
            }
            // add T (its pattern is contained in that of A T when diag(A) != 0)
            for i in 0..n {
                let (s, e) = (at.row_ptr[i], at.row_ptr[i + 1]);
                for q in lev.t.row_ptr[i]..lev.t.row_ptr[i + 1] {
                    let j = lev.t.col[q];
                    let p = s + at.col[s..e].partition_point(|&c| c < j);
                    at.val[p] += lev.t.val[q];
                }
            }
            lev.p = at;
            lev.r = lev.p.transpose();
            let ap = lev.a.matmul(&lev.p);
            let ac = lev.r.matmul(&ap);
            self.levels[l + 1].a = ac;
        }
        Ok(())
    }

    /// Dense Cholesky factor of the coarsest matrix.
    fn factor_coarsest(&mut self) -> Result<(), SolverError> {
        let nl = self.levels.len();
        let last = &self.levels[nl - 1].a;
        let nc = last.n_rows;
        let mut dense = DMatrix::<f64>::zeros(nc, nc);
        for i in 0..nc {
            for p in last.row_ptr[i]..last.row_ptr[i + 1] {
                dense[(i, last.col[p] as usize)] = last.val[p];
            }
        }
        let dense = (&dense + dense.transpose()) * 0.5;
        self.coarse = Some(dense.cholesky().ok_or_else(|| {
            nonpd(format!(
                ": amg coarsest level ({nc} equations, level {}) is not positive definite",
                nl - 1
            ))
        })?);
        Ok(())
    }

    /// Number of levels.
    pub fn num_levels(&self) -> usize {
        self.levels.len()
    }

    /// Operator complexity: sum of the non-zeros of all levels over those
    /// of the finest.
    pub fn operator_complexity(&self) -> f64 {
        let total: usize = self.levels.iter().map(|l| l.a.val.len()).sum();
        total as f64 / self.levels[0].a.val.len().max(1) as f64
    }

    /// Equations per level, finest first.
    pub fn sizes(&self) -> Vec<usize> {
        self.levels.iter().map(|l| l.a.n_rows).collect()
    }

    /// `z = M^-1 r` (one V-cycle from zero).
    pub fn apply(&mut self, r: &[f64], z: &mut [f64]) {
        self.levels[0].rhs.copy_from_slice(r);
        self.cycle(0);
        z.copy_from_slice(&self.levels[0].x);
    }

    fn cycle(&mut self, l: usize) {
        let nl = self.levels.len();
        if l + 1 == nl {
            let lev = &mut self.levels[l];
            let rhs = DVector::from_column_slice(&lev.rhs);
            let x = self.coarse.as_ref().expect("factorised").solve(&rhs);
            lev.x.copy_from_slice(x.as_slice());
            return;
        }
        let degree = self.settings.degree;
        {
            let lev = &mut self.levels[l];
            lev.x.iter_mut().for_each(|v| *v = 0.0);
            chebyshev(lev, degree);
            // residual
            lev.a.mul(&lev.x, &mut lev.res);
            lev.res
                .par_iter_mut()
                .zip(lev.rhs.par_iter())
                .for_each(|(r, b)| *r = b - *r);
        }
        {
            let (fine, coarse) = self.levels.split_at_mut(l + 1);
            fine[l].r.mul(&fine[l].res, &mut coarse[0].rhs);
        }
        self.cycle(l + 1);
        {
            let (fine, coarse) = self.levels.split_at_mut(l + 1);
            let lev = &mut fine[l];
            lev.p.mul(&coarse[0].x, &mut lev.d);
            lev.x
                .par_iter_mut()
                .zip(lev.d.par_iter())
                .for_each(|(x, d)| *x += d);
            chebyshev(lev, degree);
        }
    }
}

/// Chebyshev smoothing of `A x = rhs` from the current `x`, polynomial in
/// `D^-1 A` on `[ρ/30, ρ]` (Saad, Iterative Methods, Alg. 12.1).
fn chebyshev(lev: &mut Level, degree: usize) {
    let upper = lev.rho;
    let lower = upper / 30.0;
    let theta = 0.5 * (upper + lower);
    let delta = 0.5 * (upper - lower);
    let sigma = theta / delta;
    let mut rho = 1.0 / sigma;
    let Level {
        a,
        x,
        rhs,
        res,
        d,
        inv_diag,
        ..
    } = lev;
    a.mul(x, res);
    res.par_iter_mut()
        .zip(rhs.par_iter())
        .for_each(|(r, b)| *r = b - *r);
    d.par_iter_mut()
        .zip(res.par_iter().zip(inv_diag.par_iter()))
        .for_each(|(di, (r, id))| *di = r * id / theta);
    for k in 0..degree {
        x.par_iter_mut()
            .zip(d.par_iter())
            .for_each(|(xi, di)| *xi += di);
        if k + 1 == degree {
            break;
        }
        a.mul(x, res);
        res.par_iter_mut()
            .zip(rhs.par_iter())
            .for_each(|(r, b)| *r = b - *r);
        let rho_new = 1.0 / (2.0 * sigma - rho);
        let c1 = rho_new * rho;
        let c2 = 2.0 * rho_new / delta;
        d.par_iter_mut()
            .zip(res.par_iter().zip(inv_diag.par_iter()))
            .for_each(|(di, (r, id))| *di = c1 * *di + c2 * r * id);
        rho = rho_new;
    }
}

/// Layout without information from the model: equations grouped by equal
/// coordinates (consecutive), components counted within the group, one
/// body.
pub fn layout_from_coords(coords: &[[f64; 3]]) -> EquationLayout {
    let n = coords.len();
    let mut node = Vec::with_capacity(n);
    let mut component = Vec::with_capacity(n);
    let mut k = 0usize;
    let mut c = 0u8;
    for i in 0..n {
        if i > 0 {
            if coords[i] != coords[i - 1] || c == 2 {
                k += 1;
                c = 0;
            } else {
                c += 1;
            }
        }
        node.push(k);
        component.push(c);
    }
    EquationLayout {
        node,
        component,
        body: vec![0; n],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matmul_and_transpose_match_dense() {
        let a = Csr {
            n_rows: 2,
            n_cols: 3,
            row_ptr: vec![0, 2, 3],
            col: vec![0, 2, 1],
            val: vec![1.0, 2.0, 3.0],
        };
        let at = a.transpose();
        let c = a.matmul(&at); // 2x2: [[5, 0], [0, 9]]
        assert_eq!(c.row_ptr, vec![0, 1, 2]);
        assert_eq!(c.val, vec![5.0, 9.0]);
        let d = at.matmul(&a); // 3x3
        assert_eq!(d.n_rows, 3);
        assert_eq!(d.val, vec![1.0, 2.0, 9.0, 2.0, 4.0]);
    }
}
