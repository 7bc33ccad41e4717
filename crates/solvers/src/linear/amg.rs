//! Smoothed-aggregation algebraic multigrid (SA-AMG) for 3D elasticity,
//! used as the preconditioner `"amg"` of [`crate::CgSolver`].
//!
//! # Hierarchy
//!
//! Level 0 is the assembled matrix `A_0` (both triangles in CSR). Its
//! equations are grouped into *nodes* (the 3 dofs of a mesh node, fewer
//! where dofs are constrained); coarse levels have one node per aggregate
//! (up to 6 dofs).
//!
//! **Bonded clusters.** Mesh nodes at one point (the two faces of a
//! zero-thickness interface) whose coupling is strong by the interface
//! threshold below are made *one* node of level 0 (`3 k` equations; level 0
//! is renumbered so that they are consecutive, [`Amg::perm`]). A stiff
//! penalty `d` puts `d a` on the diagonals of both nodes and `-d a`
//! between them; smoothed node by node, the pair's common motion is scaled
//! by the penalty in the diagonal and barely corrected, so the iteration
//! count grew with the penalty (3 bonded plates, 16x16x4 H8 each: 17, 103
//! and 604 iterations at d = 1e7, 1e9, 1e11). As one node the pair is
//! smoothed by one block that holds the penalty, and aggregated together:
//! 17, 18, 18 and 18 at the advisor's d_op = 1.3e12.
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
//! 5. **Smoothed prolongator** `P = (I - ω D^-1 A) T` with `D` the nodal
//!    block diagonal (the `A_II` of every node, inverted per node),
//!    `ω = 4 / (3 ρ)` and `ρ` a power-iteration estimate of the spectral
//!    radius of `D^-1 A` (12 steps, times 1.1).
//! 6. **Galerkin coarse matrix** `A_{l+1} = P^T A P`, one coarse row at a
//!    time (`(R_I A) P` with `R = P^T`, coarse rows in parallel), so that
//!    neither `A P` nor `R A` is stored; `P` itself is built row by row
//!    from `A` and `T` without forming `A T`.
//!
//! Coarsening stops when a level has at most `max_coarse` equations, when
//! it no longer shrinks by 10 %, or after `max_levels` levels. The coarsest
//! matrix is factorised densely (Cholesky; LU when
//! [`AmgSettings::indefinite`] and Cholesky fails).
//!
//! # Cycle
//!
//! One V-cycle per application, `z = M^-1 r`: on each level a Chebyshev
//! smoother of degree `k` (polynomial in `D^-1 A`, `D` the nodal block
//! diagonal, optimal on the interval
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
//! same pattern (block inverses, spectral radii, `P`, Galerkin products and
//! the coarse factor); [`Amg::update_finest`] only level 0's matrix, block
//! inverse and spectral radius, keeping the coarse levels of an earlier
//! matrix (what `cg` and `gmres` do across Newton iterations until the
//! iteration count grows, see `amg_reuse`).

use crate::common::{update, PAR_MIN_LEN};
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
    /// Make nodes at one point tied by a strong bond one node of level 0
    /// (see [`Amg::bonded_clusters`]).
    pub bonded_clusters: bool,
    /// The matrix may be indefinite (a softening tangent, for GMRES): the
    /// nodal blocks are inverted with partial pivoting and the coarsest
    /// level by LU when Cholesky fails, so that only a singular block or
    /// level is an error. The cycle is then not positive definite and
    /// cannot precondition CG.
    pub indefinite: bool,
}

impl Default for AmgSettings {
    fn default() -> Self {
        AmgSettings {
            theta: 0.0,
            theta_interface: 0.25,
            max_coarse: 1500,
            max_levels: 12,
            degree: 2,
            bonded_clusters: true,
            indefinite: false,
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
        let val = src.par_iter().map(|&p| m.values[p]).collect();
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

    /// `y = A x`, rows in parallel (on the calling thread for small
    /// matrices).
    pub fn mul(&self, x: &[f64], y: &mut [f64]) {
        if self.n_rows < PAR_MIN_LEN {
            for (i, yi) in y.iter_mut().enumerate() {
                let mut acc = 0.0;
                for p in self.row_ptr[i]..self.row_ptr[i + 1] {
                    acc += self.val[p] * x[self.col[p] as usize];
                }
                *yi = acc;
            }
            return;
        }
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

    /// Transpose ([`crate::common::transpose_pattern`], values gathered in
    /// parallel): the same for any number of threads.
    pub fn transpose(&self) -> Csr {
        let (row_ptr, col, src) =
            crate::common::transpose_pattern(&self.row_ptr, self.n_cols, |q| self.col[q] as usize);
        let val = src.par_iter().map(|&q| self.val[q]).collect();
        Csr {
            n_rows: self.n_cols,
            n_cols: self.n_rows,
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
    /// Smoothed prolongator to the next level, `P = T - omega D^-1 A T`
    /// with `omega = 4 / (3 rho)` (empty on the coarsest).
    pub p: Csr,
    /// Restriction from this level, `R = P^T`.
    pub r: Csr,
    /// Inverses of the nodal diagonal blocks `D` of `A`.
    pub dinv: BlockInverse,
    /// Estimated spectral radius of `D^-1 A`.
    pub rho: f64,
    /// Aggregate of each node (towards the next level).
    pub aggregate: Vec<usize>,
    // scratch of the cycle
    x: Vec<f64>,
    rhs: Vec<f64>,
    res: Vec<f64>,
    d: Vec<f64>,
    z: Vec<f64>,
}

/// The SA-AMG hierarchy (see the module docs).
#[derive(Debug, Clone, Default)]
pub struct Amg {
    settings: AmgSettings,
    /// Levels, finest first.
    pub levels: Vec<Level>,
    /// Level 0's equation order: `perm[i]` is the caller's equation of
    /// level-0 equation `i` (empty: the caller's order).
    pub perm: Vec<usize>,
    /// Level-0 nodes made of several mesh nodes.
    clusters: usize,
    src0: Vec<usize>,
    coarse: Option<CoarseFactor>,
}

/// Dense factor of the coarsest level.
#[derive(Debug, Clone)]
enum CoarseFactor {
    Cholesky(nalgebra::Cholesky<f64, nalgebra::Dyn>),
    /// With [`AmgSettings::indefinite`], when Cholesky fails.
    Lu(nalgebra::LU<f64, nalgebra::Dyn, nalgebra::Dyn>),
}

fn nonpd(detail: String) -> SolverError {
    SolverError::NotPositiveDefinite { detail }
}

/// Body label of a node or aggregate whose members belong to several
/// bodies, joined by a strong bond across an interface.
pub const MIXED_BODY: u32 = u32::MAX;

/// Inverses of the diagonal blocks of a level's nodes: `D = blockdiag(A_II)`
/// over the nodes `I` (3 equations on level 0, up to 6 on coarse levels, a
/// bonded cluster's `3 k` on level 0). Stored per equation: the row of the
/// inverse that gives `(D^-1 r)_i`, so that applying it is one parallel loop
/// over equations.
#[derive(Debug, Clone, Default)]
pub struct BlockInverse {
    /// First equation of the node of each equation.
    start: Vec<u32>,
    /// Offset in `inv` of each equation's row of its block's inverse.
    row: Vec<usize>,
    /// Size of the block of each equation.
    size: Vec<u8>,
    /// Rows of the inverses, node after node.
    inv: Vec<f64>,
}

/// In-place inverse of the `bs × bs` block `a` (row-major, `bs <= 255`)
/// by Gauss-Jordan elimination. Without `pivoting` the block must be
/// symmetric positive definite: its pivots are Schur complements of an SPD
/// matrix, hence positive, and a pivot that is not positive and finite
/// gives `false`. With `pivoting` (an indefinite block) each step takes the
/// largest entry of its column as pivot and `false` means singular to
/// working precision; the row interchanges of `A` become column
/// interchanges of `A^-1`, applied at the end in reverse order.
fn invert_block(a: &mut [f64], bs: usize, pivoting: bool) -> bool {
    let scale = a.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let mut swaps = [0u8; 256];
    for k in 0..bs {
        if pivoting {
            let p = (k..bs)
                .max_by(|&i, &j| a[i * bs + k].abs().total_cmp(&a[j * bs + k].abs()))
                .unwrap_or(k);
            if p != k {
                for j in 0..bs {
                    a.swap(k * bs + j, p * bs + j);
                }
            }
            swaps[k] = p as u8;
        }
        let pivot = a[k * bs + k];
        let ok = if pivoting {
            pivot.abs() > 1e-13 * scale
        } else {
            pivot > 0.0
        };
        if !(ok && pivot.is_finite()) {
            return false;
        }
        let inv = 1.0 / pivot;
        a[k * bs + k] = 1.0;
        for j in 0..bs {
            a[k * bs + j] *= inv;
        }
        for i in 0..bs {
            if i == k {
                continue;
            }
            let f = a[i * bs + k];
            if f == 0.0 {
                continue;
            }
            a[i * bs + k] = 0.0;
            for j in 0..bs {
                a[i * bs + j] -= f * a[k * bs + j];
            }
        }
    }
    if pivoting {
        for k in (0..bs).rev() {
            let p = swaps[k] as usize;
            if p != k {
                for i in 0..bs {
                    a.swap(i * bs + k, i * bs + p);
                }
            }
        }
    }
    true
}

impl BlockInverse {
    /// The inverses of the diagonal blocks of `a` over the nodes
    /// `node_ptr`; a block that is not positive definite is an error naming
    /// the level and the node.
    fn new(
        a: &Csr,
        node_ptr: &[usize],
        level: usize,
        indefinite: bool,
    ) -> Result<BlockInverse, SolverError> {
        let nn = node_ptr.len() - 1;
        let n = a.n_rows;
        let mut start = vec![0u32; n];
        let mut row = vec![0usize; n];
        let mut size = vec![0u8; n];
        let mut node_offset = vec![0usize; nn + 1];
        for k in 0..nn {
            let (s, e) = (node_ptr[k], node_ptr[k + 1]);
            let bs = e - s;
            if bs > u8::MAX as usize {
                return Err(SolverError::Usage(format!(
                    "amg level {level}: node {k} has {bs} equations (at most 255)"
                )));
            }
            for i in s..e {
                start[i] = s as u32;
                size[i] = bs as u8;
                row[i] = node_offset[k] + (i - s) * bs;
            }
            node_offset[k + 1] = node_offset[k] + bs * bs;
        }
        const CHUNK: usize = 512;
        let parts: Vec<Result<Vec<f64>, SolverError>> = (0..nn.div_ceil(CHUNK))
            .into_par_iter()
            .map(|c| {
                let (k0, k1) = (c * CHUNK, ((c + 1) * CHUNK).min(nn));
                let mut out = vec![0.0; node_offset[k1] - node_offset[k0]];
                for k in k0..k1 {
                    let (s, e) = (node_ptr[k], node_ptr[k + 1]);
                    let bs = e - s;
                    let blk = &mut out[node_offset[k] - node_offset[k0]..][..bs * bs];
                    for i in s..e {
                        for p in a.row_ptr[i]..a.row_ptr[i + 1] {
                            let j = a.col[p] as usize;
                            if (s..e).contains(&j) {
                                blk[(i - s) * bs + (j - s)] = a.val[p];
                            }
                        }
                    }
                    // symmetrise (the Galerkin products are symmetric only
                    // to round-off)
                    for i in 0..bs {
                        for j in 0..i {
                            let m = 0.5 * (blk[i * bs + j] + blk[j * bs + i]);
                            blk[i * bs + j] = m;
                            blk[j * bs + i] = m;
                        }
                    }
                    if !invert_block(blk, bs, indefinite) {
                        return Err(nonpd(format!(
                            ": amg level {level}: the diagonal block of node {k} (equations {s}..{e}) is {}",
                            if indefinite {
                                "singular"
                            } else {
                                "not positive definite"
                            }
                        )));
                    }
                }
                Ok(out)
            })
            .collect();
        let mut inv = Vec::with_capacity(node_offset[nn]);
        for part in parts {
            inv.extend(part?);
        }
        Ok(BlockInverse {
            start,
            row,
            size,
            inv,
        })
    }

    /// `(D^-1 r)_i`.
    #[inline]
    fn row_times(&self, i: usize, r: &[f64]) -> f64 {
        let s = self.start[i] as usize;
        let bs = self.size[i] as usize;
        let row = &self.inv[self.row[i]..self.row[i] + bs];
        row.iter().zip(&r[s..s + bs]).map(|(a, b)| a * b).sum()
    }

    /// `z = D^-1 r`, equations in parallel.
    fn apply(&self, r: &[f64], z: &mut [f64]) {
        update(z, |i, _| self.row_times(i, r));
    }
}

/// Node of every equation.
fn node_of_equations(node_ptr: &[usize], n: usize) -> Vec<u32> {
    let mut node_of = vec![0u32; n];
    for k in 0..node_ptr.len() - 1 {
        for e in node_of.iter_mut().take(node_ptr[k + 1]).skip(node_ptr[k]) {
            *e = k as u32;
        }
    }
    node_of
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
    let node_of = node_of_equations(node_ptr, a.n_rows);
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
                    let (bm, bk) = (body[m as usize], body[k]);
                    let same = bm == bk || bm == MIXED_BODY || bk == MIXED_BODY;
                    let t = if same { t2 } else { ti2 };
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
    // body of each aggregate: its members' body, or MIXED_BODY
    const UNSET: u32 = u32::MAX - 1;
    let mut body = vec![UNSET; n_agg];
    for k in 0..nn {
        let b = &mut body[agg[k]];
        *b = if *b == UNSET || *b == level.node_body[k] {
            level.node_body[k]
        } else {
            MIXED_BODY
        };
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
fn spectral_radius(a: &Csr, dinv: &BlockInverse) -> f64 {
    let n = a.n_rows;
    let mut v: Vec<f64> = (0..n)
        .map(|i| 1.0 + ((i.wrapping_mul(2654435761) % 1000) as f64) / 1000.0)
        .collect();
    let mut av = vec![0.0; n];
    let mut w = vec![0.0; n];
    let mut lam = 0.0;
    for _ in 0..12 {
        let nv = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        if nv == 0.0 {
            break;
        }
        v.iter_mut().for_each(|x| *x /= nv);
        a.mul(&v, &mut av);
        dinv.apply(&av, &mut w);
        lam = w.iter().map(|x| x * x).sum::<f64>().sqrt();
        std::mem::swap(&mut v, &mut w);
    }
    1.1 * lam
}

/// `P = T - ω D^-1 A T` with `D^-1` the nodal block inverse, node by node
/// without forming `A T`: row `i` of node `I` is
/// `T_i - ω Σ_k v_ik T_k` with `v_ik = Σ_{j ∈ I} (D^-1)_ij a_jk`. The rows of
/// one node share the pattern of `v` (the union of the node's rows of `A`)
/// and hence of `P`, so the pattern is gathered and sorted once per node and
/// the node's rows are accumulated together (`bs` values per column).
fn smoothed_prolongator(
    a: &Csr,
    t: &Csr,
    dinv: &BlockInverse,
    node_ptr: &[usize],
    omega: f64,
) -> Csr {
    let nn = node_ptr.len() - 1;
    let (n, nc) = (a.n_rows, t.n_cols);
    const CHUNK: usize = 256;
    let parts = par_chunks_with_state(
        nn.div_ceil(CHUNK),
        || {
            (
                vec![usize::MAX; n],
                vec![usize::MAX; nc],
                Vec::<u32>::new(),
                Vec::<u32>::new(),
                Vec::<(u32, usize)>::new(),
            )
        },
        |(slot_f, slot_c, fine, pattern, order), c| {
            let (k0, k1) = (c * CHUNK, ((c + 1) * CHUNK).min(nn));
            let mut lens = Vec::new();
            let mut cols: Vec<u32> = Vec::new();
            let mut vals = Vec::new();
            // v: bs values per fine column of the node (slot order)
            let mut v: Vec<f64> = Vec::new();
            // coarse accumulators: bs values per coarse column (slot order)
            let mut w: Vec<f64> = Vec::new();
            let mut dcol: Vec<f64> = Vec::new();
            for node in k0..k1 {
                let (s, e) = (node_ptr[node], node_ptr[node + 1]);
                let bs = e - s;
                // fine pattern of the node and slots
                fine.clear();
                for j in s..e {
                    for q in a.row_ptr[j]..a.row_ptr[j + 1] {
                        let k = a.col[q] as usize;
                        if slot_f[k] == usize::MAX {
                            slot_f[k] = fine.len();
                            fine.push(k as u32);
                        }
                    }
                }
                v.clear();
                v.resize(fine.len() * bs, 0.0);
                for (jj, j) in (s..e).enumerate() {
                    // column jj of the node's block of D^-1
                    dcol.clear();
                    dcol.extend((0..bs).map(|r| dinv.inv[dinv.row[s + r] + jj]));
                    for q in a.row_ptr[j]..a.row_ptr[j + 1] {
                        let slot = slot_f[a.col[q] as usize] * bs;
                        let ajk = a.val[q];
                        for (vr, d) in v[slot..slot + bs].iter_mut().zip(&dcol) {
                            *vr += d * ajk;
                        }
                    }
                }
                // coarse pattern: T's columns of the fine pattern (and of
                // the node's own rows, contained in it when a_ii != 0)
                pattern.clear();
                for k in fine.iter().map(|&k| k as usize).chain(s..e) {
                    for q in t.row_ptr[k]..t.row_ptr[k + 1] {
                        let jc = t.col[q] as usize;
                        if slot_c[jc] == usize::MAX {
                            slot_c[jc] = pattern.len();
                            pattern.push(jc as u32);
                        }
                    }
                }
                w.clear();
                w.resize(pattern.len() * bs, 0.0);
                for r in 0..bs {
                    let i = s + r;
                    for q in t.row_ptr[i]..t.row_ptr[i + 1] {
                        w[slot_c[t.col[q] as usize] * bs + r] += t.val[q];
                    }
                }
                for (slot, &k) in fine.iter().enumerate() {
                    let k = k as usize;
                    for q in t.row_ptr[k]..t.row_ptr[k + 1] {
                        let base = slot_c[t.col[q] as usize] * bs;
                        let tv = -omega * t.val[q];
                        let vk = &v[slot * bs..(slot + 1) * bs];
                        for (wr, vr) in w[base..base + bs].iter_mut().zip(vk) {
                            *wr += tv * vr;
                        }
                    }
                    slot_f[k] = usize::MAX;
                }
                // rows of the node, columns sorted
                order.clear();
                order.extend(pattern.iter().map(|&jc| (jc, slot_c[jc as usize])));
                order.sort_unstable_by_key(|o| o.0);
                for &jc in pattern.iter() {
                    slot_c[jc as usize] = usize::MAX;
                }
                for r in 0..bs {
                    cols.extend(order.iter().map(|o| o.0));
                    vals.extend(order.iter().map(|o| w[o.1 * bs + r]));
                    lens.push(order.len());
                }
            }
            (lens, cols, vals)
        },
    );
    concat_rows(parts, n, nc)
}

/// Galerkin product `R A P` (`R = P^T`) by groups of coarse rows: the
/// rows of a coarse node (the columns of one aggregate's tentative basis)
/// share one pattern, so for each group `G` of consecutive rows with equal
/// patterns (at most [`GALERKIN_GROUP`]) the sparse block `W = R_G A` is
/// accumulated in a slot-indexed buffer (one slot per fine column reached,
/// `|G|` values per slot), then `W P` in one per coarse column. Each index
/// of `A` and `P` is read once per group instead of once per row, and
/// neither `A P` nor `R A` is stored (on level 0 of a 3D mesh `A P` would
/// be the largest array of the set-up). Rows and their order, and the
/// arithmetic of each entry, are those of the row-by-row product.
fn galerkin(r: &Csr, a: &Csr, p: &Csr) -> Csr {
    let (nc, n) = (r.n_rows, a.n_rows);
    let groups = equal_pattern_groups(r, GALERKIN_GROUP);
    let ng = groups.len() - 1;
    let chunk = (ng / (8 * rayon::current_num_threads().max(1))).clamp(4, 64);
    let parts = par_chunks_with_state(
        ng.div_ceil(chunk),
        || GalerkinScratch::new(n, nc),
        |scratch, c| {
            let mut out = (Vec::new(), Vec::new(), Vec::new());
            for g in c * chunk..((c + 1) * chunk).min(ng) {
                scratch.group(r, a, p, groups[g]..groups[g + 1], &mut out);
            }
            out
        },
    );
    concat_rows(parts, nc, p.n_cols)
}

/// Most coarse rows multiplied together by [`galerkin`] (the near-null
/// space of 3D elasticity has six vectors).
const GALERKIN_GROUP: usize = 8;

/// Starts of the groups of consecutive rows of `m` with identical column
/// patterns, at most `max` rows each (the last entry is `n_rows`).
fn equal_pattern_groups(m: &Csr, max: usize) -> Vec<usize> {
    let row = |i: usize| &m.col[m.row_ptr[i]..m.row_ptr[i + 1]];
    let mut starts = vec![0];
    for i in 1..m.n_rows {
        let s = *starts.last().unwrap();
        if i - s >= max || row(i) != row(s) {
            starts.push(i);
        }
    }
    if m.n_rows > 0 {
        starts.push(m.n_rows);
    }
    starts
}

/// Scratch of one thread of [`galerkin`]: slots of the fine and coarse
/// columns reached by the current group, and their accumulators.
struct GalerkinScratch {
    slot_f: Vec<u32>,
    slot_c: Vec<u32>,
    fine: Vec<u32>,
    coarse: Vec<u32>,
    acc_f: Vec<f64>,
    acc_c: Vec<f64>,
    order: Vec<(u32, u32)>,
}

impl GalerkinScratch {
    const FREE: u32 = u32::MAX;

    fn new(n: usize, nc: usize) -> Self {
        GalerkinScratch {
            slot_f: vec![Self::FREE; n],
            slot_c: vec![Self::FREE; nc],
            fine: Vec::new(),
            coarse: Vec::new(),
            acc_f: Vec::new(),
            acc_c: Vec::new(),
            order: Vec::new(),
        }
    }

    /// Rows `rows` of `R A P` (one pattern in `R`), appended to `out` as
    /// (row lengths, columns, values).
    fn group(
        &mut self,
        r: &Csr,
        a: &Csr,
        p: &Csr,
        rows: std::ops::Range<usize>,
        out: &mut (Vec<usize>, Vec<u32>, Vec<f64>),
    ) {
        let bs = rows.len();
        let first = r.row_ptr[rows.start];
        let len = r.row_ptr[rows.start + 1] - first;
        let mut rv = [0.0; GALERKIN_GROUP];
        // W = R_G A, slot by slot
        self.fine.clear();
        self.acc_f.clear();
        for off in 0..len {
            for (g, i) in rows.clone().enumerate() {
                rv[g] = r.val[r.row_ptr[i] + off];
            }
            let k = r.col[first + off] as usize;
            for t in a.row_ptr[k]..a.row_ptr[k + 1] {
                let j = a.col[t] as usize;
                let slot = slot_of(&mut self.slot_f[j], &mut self.fine, &mut self.acc_f, j, bs);
                let av = a.val[t];
                for (w, r) in self.acc_f[slot..slot + bs].iter_mut().zip(&rv) {
                    *w += r * av;
                }
            }
        }
        // W P, slot by slot
        self.coarse.clear();
        self.acc_c.clear();
        for (sf, &j) in self.fine.iter().enumerate() {
            let j = j as usize;
            for t in p.row_ptr[j]..p.row_ptr[j + 1] {
                let jc = p.col[t] as usize;
                let slot = slot_of(
                    &mut self.slot_c[jc],
                    &mut self.coarse,
                    &mut self.acc_c,
                    jc,
                    bs,
                );
                let pv = p.val[t];
                let w = &self.acc_f[sf * bs..(sf + 1) * bs];
                for (c, wg) in self.acc_c[slot..slot + bs].iter_mut().zip(w) {
                    *c += wg * pv;
                }
            }
            self.slot_f[j] = Self::FREE;
        }
        // the group's rows, columns sorted
        self.order.clear();
        self.order
            .extend(self.coarse.iter().map(|&jc| (jc, self.slot_c[jc as usize])));
        self.order.sort_unstable_by_key(|o| o.0);
        for &jc in &self.coarse {
            self.slot_c[jc as usize] = Self::FREE;
        }
        let (lens, cols, vals) = out;
        for g in 0..bs {
            cols.extend(self.order.iter().map(|o| o.0));
            vals.extend(self.order.iter().map(|o| self.acc_c[o.1 as usize + g]));
            lens.push(self.order.len());
        }
    }
}

/// The accumulator offset of column `j` (`bs` values per slot), opening a
/// zeroed slot when `j` is new (`slot` is `j`'s marker).
#[inline]
fn slot_of(slot: &mut u32, list: &mut Vec<u32>, acc: &mut Vec<f64>, j: usize, bs: usize) -> usize {
    if *slot == GalerkinScratch::FREE {
        *slot = (list.len() * bs) as u32;
        list.push(j as u32);
        acc.resize(acc.len() + bs, 0.0);
    }
    *slot as usize
}

/// `f(state, c)` for every chunk `c < chunks`, in parallel, results in
/// chunk order. The chunks are dealt out in a few contiguous groups (four
/// per thread), and each group builds its scratch `state` once: scratch of
/// the size of a level (accumulators, markers) would otherwise be allocated
/// and cleared per stolen job, which on a million-equation level costs more
/// than the work itself.
fn par_chunks_with_state<S, R: Send>(
    chunks: usize,
    init: impl Fn() -> S + Sync,
    f: impl Fn(&mut S, usize) -> R + Sync,
) -> Vec<R> {
    let groups = (4 * rayon::current_num_threads().max(1)).min(chunks.max(1));
    let per = chunks.div_ceil(groups.max(1)).max(1);
    let nested: Vec<Vec<R>> = (0..groups)
        .into_par_iter()
        .map(|g| {
            let mut state = init();
            (g * per..((g + 1) * per).min(chunks))
                .map(|c| f(&mut state, c))
                .collect()
        })
        .collect();
    nested.into_iter().flatten().collect()
}

/// One CSR from row blocks `(row lengths, columns, values)` in order.
fn concat_rows(parts: Vec<(Vec<usize>, Vec<u32>, Vec<f64>)>, n_rows: usize, n_cols: usize) -> Csr {
    let mut row_ptr = Vec::with_capacity(n_rows + 1);
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
        n_rows,
        n_cols,
        row_ptr,
        col,
        val,
    }
}

/// Most nodes in one bonded cluster (a corner where several interfaces
/// meet has a few; more is not a zero-thickness interface).
const MAX_CLUSTER: usize = 8;

/// Bonded clusters of level 0: nodes at the same point (the two faces of a
/// zero-thickness interface) whose coupling is strong by the interface
/// threshold. A stiff penalty ties such nodes together; smoothed node by
/// node, their common motion sees only the penalty in the diagonal and is
/// barely corrected, so the iteration count grows with the penalty. Made
/// one node of the hierarchy, they are smoothed by one block (the penalty
/// inside it) and always aggregated together. Returns the nodes in the new
/// order (each cluster's nodes consecutive, clusters where their first
/// node was) and the start of each new node in it, or `None` without any
/// cluster.
fn bonded_clusters(
    a: &Csr,
    node_ptr: &[usize],
    coords: &[[f64; 3]],
    theta_interface: f64,
) -> Option<(Vec<usize>, Vec<usize>)> {
    let nn = node_ptr.len() - 1;
    if nn == 0 {
        return None;
    }
    let (ptr, adj) = strength(a, node_ptr, &vec![0; nn], theta_interface, theta_interface);
    let point = |k: usize| coords[node_ptr[k]];
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for x in coords {
        for c in 0..3 {
            lo[c] = lo[c].min(x[c]);
            hi[c] = hi[c].max(x[c]);
        }
    }
    let extent = (0..3).fold(0.0f64, |m, c| m.max(hi[c] - lo[c]));
    let tol = 1e-9 * extent;
    let mut parent: Vec<usize> = (0..nn).collect();
    let mut size = vec![1usize; nn];
    fn find(parent: &mut [usize], mut k: usize) -> usize {
        while parent[k] != k {
            parent[k] = parent[parent[k]];
            k = parent[k];
        }
        k
    }
    let mut joined = false;
    for k in 0..nn {
        for &m in &adj[ptr[k]..ptr[k + 1]] {
            let m = m as usize;
            if m <= k {
                continue;
            }
            let (xk, xm) = (point(k), point(m));
            if (0..3).any(|c| (xk[c] - xm[c]).abs() > tol) {
                continue;
            }
            let (rk, rm) = (find(&mut parent, k), find(&mut parent, m));
            if rk != rm && size[rk] + size[rm] <= MAX_CLUSTER {
                parent[rm] = rk;
                size[rk] += size[rm];
                joined = true;
            }
        }
    }
    if !joined {
        return None;
    }
    // order by the first node of each cluster, then by node
    let mut leader = vec![usize::MAX; nn];
    let mut key = vec![0usize; nn];
    for k in 0..nn {
        let r = find(&mut parent, k);
        if leader[r] == usize::MAX {
            leader[r] = k;
        }
        key[k] = leader[r];
    }
    let mut order: Vec<usize> = (0..nn).collect();
    order.sort_by_key(|&k| (key[k], k));
    let mut starts = vec![0usize];
    for p in 1..nn {
        if key[order[p]] != key[order[p - 1]] {
            starts.push(p);
        }
    }
    starts.push(nn);
    Some((order, starts))
}

impl Csr {
    /// `A(perm, perm)` of a square matrix (`perm[new] = old`) and, for each
    /// entry of the result, the index of the entry of `self` it copies.
    fn permuted(&self, perm: &[usize]) -> (Csr, Vec<usize>) {
        let n = self.n_rows;
        let mut iperm = vec![0u32; n];
        for (new, &old) in perm.iter().enumerate() {
            iperm[old] = new as u32;
        }
        let mut row_ptr = Vec::with_capacity(n + 1);
        row_ptr.push(0);
        let mut entries: Vec<(u32, usize)> = Vec::with_capacity(self.col.len());
        for &old in perm {
            let start = entries.len();
            for p in self.row_ptr[old]..self.row_ptr[old + 1] {
                entries.push((iperm[self.col[p] as usize], p));
            }
            entries[start..].sort_unstable_by_key(|e| e.0);
            row_ptr.push(entries.len());
        }
        let col = entries.iter().map(|e| e.0).collect();
        let val = entries.iter().map(|e| self.val[e.1]).collect();
        let map = entries.iter().map(|e| e.1).collect();
        (
            Csr {
                n_rows: n,
                n_cols: n,
                row_ptr,
                col,
                val,
            },
            map,
        )
    }
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
        let t_start = std::time::Instant::now();
        let (mut a0, mut src0) = Csr::from_symmetric(m);
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
        let mut b = rigid_modes(coords, layout);
        let mut perm = Vec::new();
        let mut clusters = 0;
        let found = if settings.bonded_clusters {
            bonded_clusters(&a0, &node_ptr, coords, settings.theta_interface)
        } else {
            None
        };
        if let Some((order, starts)) = found {
            // level 0 in cluster order: one node per cluster
            let mut new_ptr = vec![0usize];
            let mut new_body = Vec::with_capacity(starts.len());
            perm.reserve(n);
            for w in starts.windows(2) {
                let members = &order[w[0]..w[1]];
                clusters += usize::from(members.len() > 1);
                for &k in members {
                    perm.extend(node_ptr[k]..node_ptr[k + 1]);
                }
                new_ptr.push(perm.len());
                let first = node_body[members[0]];
                let same = members.iter().all(|&k| node_body[k] == first);
                new_body.push(if same { first } else { MIXED_BODY });
            }
            let (pa, map) = a0.permuted(&perm);
            a0 = pa;
            src0 = map.iter().map(|&q| src0[q]).collect();
            b = perm.iter().map(|&i| b[i]).collect();
            node_ptr = new_ptr;
            node_body = new_body;
        }
        tracing::debug!(
            "amg: level 0 matrix, rigid-body modes and bonded clusters {:.3} s",
            t_start.elapsed().as_secs_f64()
        );
        let levels = vec![Level {
            a: a0,
            node_ptr,
            node_body,
            b,
            ..Default::default()
        }];
        let mut amg = Amg {
            settings,
            levels,
            perm,
            clusters,
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
            let t0 = std::time::Instant::now();
            let (ptr, adj) = strength(
                &cur.a,
                &cur.node_ptr,
                &cur.node_body,
                settings.theta,
                settings.theta_interface,
            );
            let t1 = t0.elapsed().as_secs_f64();
            let (agg, n_agg) = aggregate(&ptr, &adj);
            let t2 = t0.elapsed().as_secs_f64();
            let (t, bc, cptr, cbody) = tentative(cur, &agg, n_agg);
            tracing::debug!(
                "amg level {l}: strength {t1:.3} s, aggregation {:.3} s, tentative prolongator {:.3} s",
                t2 - t1,
                t0.elapsed().as_secs_f64() - t2
            );
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

    /// Take a new matrix of the same pattern on level 0 only: its values,
    /// block inverse and spectral radius follow `m`, while the prolongators
    /// and coarse levels stay those of the matrix the hierarchy was built
    /// or refreshed for. The cycle stays symmetric and, for a matrix close
    /// to that one (the next Newton iteration), nearly as effective, at a
    /// small part of the cost of [`Amg::refresh`].
    pub fn update_finest(&mut self, m: &SymmetricCsc) -> Result<(), SolverError> {
        if self.levels.len() < 2 {
            return self.refresh(m);
        }
        self.copy_finest(m)?;
        let lev = &mut self.levels[0];
        lev.dinv = BlockInverse::new(&lev.a, &lev.node_ptr, 0, self.settings.indefinite)?;
        lev.rho = spectral_radius(&lev.a, &lev.dinv);
        Ok(())
    }

    fn copy_finest(&mut self, m: &SymmetricCsc) -> Result<(), SolverError> {
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
        Ok(())
    }

    /// Recompute the numeric values for a new matrix of the same pattern.
    pub fn refresh(&mut self, m: &SymmetricCsc) -> Result<(), SolverError> {
        self.copy_finest(m)?;
        self.numeric()
    }

    fn numeric(&mut self) -> Result<(), SolverError> {
        for l in 0..self.levels.len() {
            self.numeric_level(l)?;
        }
        self.factor_coarsest()
    }

    /// Block diagonal, spectral radius and scratch of level `l`; with a
    /// next level, its prolongator and the next level's Galerkin matrix.
    fn numeric_level(&mut self, l: usize) -> Result<(), SolverError> {
        let nl = self.levels.len();
        let lev = &mut self.levels[l];
        let n = lev.a.n_rows;
        lev.x = vec![0.0; n];
        lev.rhs = vec![0.0; n];
        if l + 1 == nl {
            // the coarsest level is solved directly
            return Ok(());
        }
        lev.res = vec![0.0; n];
        lev.d = vec![0.0; n];
        lev.z = vec![0.0; n];
        let t0 = std::time::Instant::now();
        lev.dinv = BlockInverse::new(&lev.a, &lev.node_ptr, l, self.settings.indefinite)?;
        lev.rho = spectral_radius(&lev.a, &lev.dinv);
        let t1 = t0.elapsed().as_secs_f64();
        let omega = 4.0 / (3.0 * lev.rho);
        lev.p = smoothed_prolongator(&lev.a, &lev.t, &lev.dinv, &lev.node_ptr, omega);
        let t2 = t0.elapsed().as_secs_f64();
        lev.r = lev.p.transpose();
        let t3 = t0.elapsed().as_secs_f64();
        self.levels[l + 1].a = galerkin(&lev.r, &lev.a, &lev.p);
        tracing::debug!(
            "amg level {l}: block inverse and spectral radius {t1:.3} s, smoothed prolongator {:.3} s ({} entries), transpose {:.3} s, Galerkin product {:.3} s ({} entries)",
            t2 - t1,
            self.levels[l].p.val.len(),
            t3 - t2,
            t0.elapsed().as_secs_f64() - t3,
            self.levels[l + 1].a.val.len()
        );
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
        let fail = || {
            nonpd(format!(
                ": amg coarsest level ({nc} equations, level {}) is {}",
                nl - 1,
                if self.settings.indefinite {
                    "singular"
                } else {
                    "not positive definite"
                }
            ))
        };
        self.coarse = Some(match dense.clone().cholesky() {
            Some(c) => CoarseFactor::Cholesky(c),
            None if self.settings.indefinite => {
                let lu = dense.lu();
                if !lu.is_invertible() {
                    return Err(fail());
                }
                CoarseFactor::Lu(lu)
            }
            None => return Err(fail()),
        });
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

    /// `z = M^-1 r` (one V-cycle from zero), vectors in the caller's
    /// equation order.
    pub fn apply(&mut self, r: &[f64], z: &mut [f64]) {
        if self.perm.is_empty() {
            self.apply_in_level_order(r, z);
            return;
        }
        let perm = &self.perm;
        update(&mut self.levels[0].rhs, |k, _| r[perm[k]]);
        self.cycle(0);
        for (&i, &v) in self.perm.iter().zip(&self.levels[0].x) {
            z[i] = v;
        }
    }

    /// `z = M^-1 r` with `r` and `z` in level 0's order (`perm`): for a
    /// Krylov method that multiplies by `levels[0].a` itself.
    pub fn apply_in_level_order(&mut self, r: &[f64], z: &mut [f64]) {
        self.levels[0].rhs.copy_from_slice(r);
        self.cycle(0);
        z.copy_from_slice(&self.levels[0].x);
    }

    /// Nodes of level 0 that are bonded clusters (several mesh nodes at one
    /// point, tied by a stiff interface).
    pub fn bonded_clusters(&self) -> usize {
        self.clusters
    }

    fn cycle(&mut self, l: usize) {
        let nl = self.levels.len();
        if l + 1 == nl {
            let lev = &mut self.levels[l];
            let rhs = DVector::from_column_slice(&lev.rhs);
            let x = match self.coarse.as_ref().expect("factorised") {
                CoarseFactor::Cholesky(c) => c.solve(&rhs),
                CoarseFactor::Lu(lu) => lu.solve(&rhs).unwrap_or(rhs),
            };
            lev.x.copy_from_slice(x.as_slice());
            return;
        }
        let degree = self.settings.degree;
        {
            let lev = &mut self.levels[l];
            lev.x.iter_mut().for_each(|v| *v = 0.0);
            chebyshev(lev, degree, true);
            // residual
            lev.a.mul(&lev.x, &mut lev.res);
            let rhs = &lev.rhs;
            update(&mut lev.res, |i, r| rhs[i] - r);
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
            let d = &lev.d;
            update(&mut lev.x, |i, x| x + d[i]);
            chebyshev(lev, degree, false);
        }
    }
}

/// Chebyshev smoothing of `A x = rhs` from the current `x`, polynomial in
/// `D^-1 A` (`D` the nodal block diagonal) on `[ρ/30, ρ]` (Saad, Iterative
/// Methods, Alg. 12.1). With `from_zero` (`x` is zero: the pre-smoothing)
/// the first residual is `rhs` itself, without a product with `A`.
fn chebyshev(lev: &mut Level, degree: usize, from_zero: bool) {
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
        z,
        dinv,
        ..
    } = lev;
    if from_zero {
        res.copy_from_slice(rhs);
    } else {
        a.mul(x, res);
        update(res, |i, r| rhs[i] - r);
    }
    dinv.apply(res, z);
    update(d, |i, _| z[i] / theta);
    for k in 0..degree {
        update(x, |i, xi| xi + d[i]);
        if k + 1 == degree {
            break;
        }
        a.mul(x, res);
        update(res, |i, r| rhs[i] - r);
        dinv.apply(res, z);
        let rho_new = 1.0 / (2.0 * sigma - rho);
        let c1 = rho_new * rho;
        let c2 = 2.0 * rho_new / delta;
        update(d, |i, di| c1 * di + c2 * z[i]);
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

    fn dense(m: &Csr) -> DMatrix<f64> {
        let mut d = DMatrix::zeros(m.n_rows, m.n_cols);
        for i in 0..m.n_rows {
            for p in m.row_ptr[i]..m.row_ptr[i + 1] {
                d[(i, m.col[p] as usize)] += m.val[p];
            }
        }
        d
    }

    fn from_dense(d: &DMatrix<f64>) -> Csr {
        let mut m = Csr {
            n_rows: d.nrows(),
            n_cols: d.ncols(),
            row_ptr: vec![0],
            ..Default::default()
        };
        for i in 0..d.nrows() {
            for j in 0..d.ncols() {
                if d[(i, j)] != 0.0 {
                    m.col.push(j as u32);
                    m.val.push(d[(i, j)]);
                }
            }
            m.row_ptr.push(m.col.len());
        }
        m
    }

    /// A sparse SPD matrix of 5 nodes (3 equations each, the middle node's
    /// 6: a bonded pair) and a tentative prolongator onto 2 aggregates.
    fn small_level() -> (Csr, Vec<usize>, Csr) {
        let n = 18;
        let mut a = DMatrix::<f64>::zeros(n, n);
        for i in 0..n {
            a[(i, i)] = 10.0 + i as f64;
            for j in 0..n {
                if i != j && (i as i64 - j as i64).abs() <= 4 {
                    a[(i, j)] = -0.5 - 0.01 * ((i * j) % 7) as f64;
                }
            }
        }
        let a = (&a + a.transpose()) * 0.5;
        let node_ptr = vec![0, 3, 6, 12, 15, 18];
        let mut t = DMatrix::<f64>::zeros(n, 4);
        for i in 0..n {
            let agg = usize::from(i >= 9);
            t[(i, 2 * agg + i % 2)] = 0.3 + 0.05 * i as f64;
        }
        (from_dense(&a), node_ptr, from_dense(&t))
    }

    #[test]
    fn block_inverse_inverts_every_nodal_block() {
        let (a, node_ptr, _) = small_level();
        let inv = BlockInverse::new(&a, &node_ptr, 0, false).unwrap();
        let ad = dense(&a);
        for k in 0..node_ptr.len() - 1 {
            let (s, e) = (node_ptr[k], node_ptr[k + 1]);
            let blk = ad.view((s, s), (e - s, e - s)).clone_owned();
            for i in s..e {
                // row i of the inverse times the block gives row i of I
                for j in s..e {
                    let v: f64 = (s..e)
                        .map(|m| inv.inv[inv.row[i] + (m - s)] * blk[(m - s, j - s)])
                        .sum();
                    let want = if i == j { 1.0 } else { 0.0 };
                    assert!((v - want).abs() < 1e-12, "node {k}: ({i}, {j}) = {v}");
                }
            }
        }
        let mut bad = vec![1.0, 2.0, 2.0, 1.0]; // eigenvalues 3 and -1
        assert!(!invert_block(&mut bad, 2, false));
        // with pivoting: indefinite blocks, one with a zero leading entry
        let m = DMatrix::from_row_slice(3, 3, &[0.0, 2.0, 1.0, 2.0, -1.0, 0.5, 1.0, 0.5, 3.0]);
        let mut b: Vec<f64> = m.transpose().as_slice().to_vec(); // row-major
        assert!(invert_block(&mut b, 3, true));
        let inv = DMatrix::from_row_slice(3, 3, &b);
        assert!((&inv * &m - DMatrix::<f64>::identity(3, 3)).amax() < 1e-14);
        let mut singular = vec![1.0, 2.0, 2.0, 4.0];
        assert!(!invert_block(&mut singular, 2, true));
    }

    #[test]
    fn smoothed_prolongator_and_galerkin_product_match_dense_formulas() {
        let (a, node_ptr, t) = small_level();
        let dinv = BlockInverse::new(&a, &node_ptr, 0, false).unwrap();
        let omega = 0.7;
        let p = smoothed_prolongator(&a, &t, &dinv, &node_ptr, omega);
        let (ad, td) = (dense(&a), dense(&t));
        let mut dd = DMatrix::<f64>::zeros(18, 18);
        for k in 0..node_ptr.len() - 1 {
            let (s, e) = (node_ptr[k], node_ptr[k + 1]);
            let blk = ad.view((s, s), (e - s, e - s)).clone_owned();
            dd.view_mut((s, s), (e - s, e - s))
                .copy_from(&blk.try_inverse().unwrap());
        }
        let want = &td - (&dd * &ad * &td) * omega;
        assert!((dense(&p) - &want).amax() < 1e-12);
        let r = p.transpose();
        let ac = galerkin(&r, &a, &p);
        let want_c = want.transpose() * &ad * &want;
        assert!((dense(&ac) - want_c).amax() < 1e-11);
        // and the permutation of a level
        let perm: Vec<usize> = (0..18).rev().collect();
        let (pa, map) = a.permuted(&perm);
        let pd = dense(&pa);
        for i in 0..18 {
            for j in 0..18 {
                assert_eq!(pd[(i, j)], ad[(perm[i], perm[j])]);
            }
        }
        assert!(map.iter().zip(&pa.val).all(|(&q, &v)| a.val[q] == v));
    }

    #[test]
    fn transpose_matches_dense() {
        let a = Csr {
            n_rows: 2,
            n_cols: 3,
            row_ptr: vec![0, 2, 3],
            col: vec![0, 2, 1],
            val: vec![1.0, 2.0, 3.0],
        };
        let at = a.transpose();
        assert_eq!(dense(&at), dense(&a).transpose());
        assert_eq!(at.row_ptr, vec![0, 1, 2, 3]);
    }

    /// Above the parallel threshold the rows are split among the threads:
    /// with three threads the transpose is still exact, and each of its
    /// rows lists its columns in increasing order.
    #[test]
    fn parallel_transpose_matches_the_entries() {
        let (n, m) = (3001, 517);
        let mut a = Csr {
            n_rows: n,
            n_cols: m,
            row_ptr: vec![0],
            ..Default::default()
        };
        for i in 0..n {
            for j in (0..m).filter(|j| (i * 7 + j * 13) % 29 < 1 + i % 5) {
                a.col.push(j as u32);
                a.val.push((i * m + j) as f64);
            }
            a.row_ptr.push(a.col.len());
        }
        assert!(a.col.len() > PAR_MIN_LEN, "{} entries", a.col.len());
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(3)
            .build()
            .unwrap();
        let at = pool.install(|| a.transpose());
        assert_eq!((at.n_rows, at.n_cols, at.col.len()), (m, n, a.col.len()));
        for j in 0..m {
            let row = &at.col[at.row_ptr[j]..at.row_ptr[j + 1]];
            assert!(row.windows(2).all(|w| w[0] < w[1]), "row {j} unsorted");
            for (q, &i) in row.iter().enumerate() {
                assert_eq!(at.val[at.row_ptr[j] + q], (i as usize * m + j) as f64);
            }
        }
    }
}
