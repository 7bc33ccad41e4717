//! Lagrange and serendipity shape functions of quadrilaterals and hexahedra,
//! Lagrange shape functions of triangles and wedges, with their derivatives
//! in natural coordinates.
//!
//! Node orders are those of [`junta_core::topology`] (VTK order): the
//! natural coordinates of node `a` are `QUAD9_NODES[a]` / `HEX27_NODES[a]`,
//! and the first 4 / 8 (Q4, Q8) or 8 / 20 (H8, H20) entries serve the lower
//! orders.
//!
//! ```text
//! Quadrilateral (Q4 / Q8 / Q9)            Hexahedron (H8 / H20 / H27)
//!
//!   eta                                          7 ------14------ 6
//!    |                                          /|               /|
//!    3 ----- 6 ----- 2                        15 |    25       13 |
//!    |               |                        /  19    23     /   18
//!    |               |                       4 ------12------ 5   |
//!    7       8       5 --- xi                | 20|     26     | 21|
//!    |               |                       |   3 ------10---|-- 2
//!    |               |                      16  /    22      17  /
//!    0 ----- 4 ----- 1                       | 11     24      | 9
//!                                            |/               |/
//!                                            0 ------ 8------ 1
//! ```
//!
//! ## The functions
//!
//! With the 1D functions on `[-1, 1]`, for a node at `a`:
//!
//! * linear: `l_a(x) = (1 + a x) / 2` for `a = ±1`;
//! * quadratic Lagrange: `q_{-1}(x) = x (x - 1) / 2`, `q_0(x) = 1 - x^2`,
//!   `q_{+1}(x) = x (x + 1) / 2`;
//!
//! the shapes are, for node `a` at `(xi_a, eta_a[, zeta_a])`:
//!
//! * **Q4, H8** (bi/trilinear): `N_a = l(xi) l(eta) [l(zeta)]`
//!   `= (1 + xi xi_a)(1 + eta eta_a)[(1 + zeta zeta_a)] / 4 [/ 8]`.
//! * **Q9, H27** (bi/triquadratic Lagrange): `N_a = q(xi) q(eta) [q(zeta)]`.
//! * **Q8** (serendipity): corners
//!   `N_a = (1 + xi xi_a)(1 + eta eta_a)(xi xi_a + eta eta_a - 1) / 4`;
//!   mid-sides with `xi_a = 0`: `N_a = (1 - xi^2)(1 + eta eta_a) / 2`, and
//!   symmetrically for `eta_a = 0`.
//! * **H20** (serendipity): corners
//!   `N_a = (1 + xi xi_a)(1 + eta eta_a)(1 + zeta zeta_a)(xi xi_a + eta eta_a + zeta zeta_a - 2) / 8`;
//!   mid-edges with `xi_a = 0`: `N_a = (1 - xi^2)(1 + eta eta_a)(1 + zeta zeta_a) / 4`,
//!   and symmetrically for `eta_a = 0`, `zeta_a = 0`.
//!
//! * **Tri3 / Tri6** ([`tri_shape`]; natural coordinates `(r, s)`, `r, s >=
//!   0`, `r + s <= 1`, nodes [`junta_core::topology::TRI6_NODES`]) with the
//!   area coordinates `L = (1 - r - s, r, s)`: Tri3 `N_i = L_i`; Tri6
//!   corners `N_i = L_i (2 L_i - 1)`, mid-edge of edge `i-j`
//!   `N = 4 L_i L_j`.
//!
//! All satisfy `N_a(x_b) = delta_ab` and `sum_a N_a = 1`, and reproduce
//! linear fields exactly; Q8, Q9, H20, H27 also reproduce complete quadratic
//! polynomials.
//!
//! The functions write into caller buffers (`n.len() >= num_nodes`,
//! `dn.len() >= num_nodes`) and never allocate. `dn[a][j] = dN_a / d xi_j`.

use junta_core::topology::{CellShape, HEX27_NODES, QUAD9_NODES, TRI6_NODES};

/// 1D linear function of the node at `a = ±1` and its derivative.
#[inline(always)]
fn lin(a: f64, x: f64) -> (f64, f64) {
    (0.5 * (1.0 + a * x), 0.5 * a)
}

/// 1D quadratic Lagrange function of the node at `a ∈ {-1, 0, 1}` and its derivative.
#[inline(always)]
fn quad(a: f64, x: f64) -> (f64, f64) {
    if a < -0.5 {
        (0.5 * x * (x - 1.0), x - 0.5)
    } else if a > 0.5 {
        (0.5 * x * (x + 1.0), x + 0.5)
    } else {
        (1.0 - x * x, -2.0 * x)
    }
}

/// Shape functions of a quadrilateral (Q4, Q8 or Q9) at `xi = [xi, eta]`.
///
/// Writes `n[a] = N_a(xi)` and `dn[a] = [dN_a/dxi, dN_a/deta]` for the
/// `shape.num_nodes()` nodes in [`junta_core::topology`] order. This is the
/// function the interface elements use on each face of INTER8/16/18.
///
/// # Panics
/// If `shape` is not `Quad4`, `Quad8` or `Quad9`, or a buffer is shorter than
/// the node count (both are programming errors).
pub fn quad_shape(shape: CellShape, xi: [f64; 2], n: &mut [f64], dn: &mut [[f64; 2]]) {
    let [x, y] = xi;
    match shape {
        CellShape::Quad4 => {
            for (a, p) in QUAD9_NODES[..4].iter().enumerate() {
                let (fx, dx) = lin(p[0], x);
                let (fy, dy) = lin(p[1], y);
                n[a] = fx * fy;
                dn[a] = [dx * fy, fx * dy];
            }
        }
        CellShape::Quad9 => {
            for (a, p) in QUAD9_NODES.iter().enumerate() {
                let (fx, dx) = quad(p[0], x);
                let (fy, dy) = quad(p[1], y);
                n[a] = fx * fy;
                dn[a] = [dx * fy, fx * dy];
            }
        }
        CellShape::Quad8 => {
            for (a, p) in QUAD9_NODES[..8].iter().enumerate() {
                let (xa, ya) = (p[0], p[1]);
                if xa != 0.0 && ya != 0.0 {
                    // corner: (1 + x xa)(1 + y ya)(x xa + y ya - 1) / 4
                    let (px, py) = (1.0 + x * xa, 1.0 + y * ya);
                    let s = x * xa + y * ya - 1.0;
                    n[a] = 0.25 * px * py * s;
                    dn[a] = [0.25 * xa * py * (s + px), 0.25 * ya * px * (s + py)];
                } else if xa == 0.0 {
                    // mid-side on eta = ya: (1 - x^2)(1 + y ya) / 2
                    let py = 1.0 + y * ya;
                    n[a] = 0.5 * (1.0 - x * x) * py;
                    dn[a] = [-x * py, 0.5 * (1.0 - x * x) * ya];
                } else {
                    // mid-side on xi = xa: (1 + x xa)(1 - y^2) / 2
                    let px = 1.0 + x * xa;
                    n[a] = 0.5 * px * (1.0 - y * y);
                    dn[a] = [0.5 * xa * (1.0 - y * y), -y * px];
                }
            }
        }
        s => panic!("quad_shape called with non-quadrilateral shape {s:?}"),
    }
}

/// Shape functions of a triangle (Tri3 or Tri6) at `xi = [r, s]` (`r, s >=
/// 0`, `r + s <= 1`), in the node order of
/// [`junta_core::topology::TRI6_NODES`] (the bottom triangle of a wedge:
/// corners 0, 1, 2 at (0,0), (1,0), (0,1); mid-edges 3: 0-1, 4: 1-2, 5: 2-0).
///
/// With the area coordinates `L = (1 - r - s, r, s)`:
///
/// ```text
/// Tri3:  N_i = L_i
/// Tri6:  corner i    N_i = L_i (2 L_i - 1),   dN_i = (4 L_i - 1) dL_i
///        edge i-j    N   = 4 L_i L_j,         dN   = 4 (L_j dL_i + L_i dL_j)
/// ```
///
/// `dn[a] = [dN_a/dr, dN_a/ds]`. This is the function the interface
/// elements use on each side of INTER6 / INTER12.
///
/// # Panics
/// If `shape` is not `Tri3` or `Tri6`, or a buffer is shorter than the node
/// count (both are programming errors).
pub fn tri_shape(shape: CellShape, xi: [f64; 2], n: &mut [f64], dn: &mut [[f64; 2]]) {
    let [r, s] = xi;
    let l = [1.0 - r - s, r, s];
    // dL_i/d(r, s)
    const DL: [[f64; 2]; 3] = [[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]];
    match shape {
        CellShape::Tri3 => {
            n[..3].copy_from_slice(&l);
            dn[..3].copy_from_slice(&DL);
        }
        CellShape::Tri6 => {
            for i in 0..3 {
                n[i] = l[i] * (2.0 * l[i] - 1.0);
                let d = 4.0 * l[i] - 1.0;
                dn[i] = [d * DL[i][0], d * DL[i][1]];
            }
            for (k, (i, j)) in [(0, 1), (1, 2), (2, 0)].into_iter().enumerate() {
                n[3 + k] = 4.0 * l[i] * l[j];
                dn[3 + k] = [
                    4.0 * (l[j] * DL[i][0] + l[i] * DL[j][0]),
                    4.0 * (l[j] * DL[i][1] + l[i] * DL[j][1]),
                ];
            }
        }
        s => panic!("tri_shape called with non-triangular shape {s:?}"),
    }
}

/// Shape functions of a line (Line2 or Line3) at natural coordinate `xi`
/// in `[-1, 1]`: Line2 `N_0 = (1 - xi) / 2`, `N_1 = (1 + xi) / 2`; Line3
/// (nodes at -1, 1, 0) `N_0 = xi (xi - 1) / 2`, `N_1 = xi (xi + 1) / 2`,
/// `N_2 = 1 - xi^2`. Writes `n[a]` and `dn[a] = dN_a/dxi`.
///
/// # Panics
/// If `shape` is not a line (a programming error).
pub fn line_shape(shape: CellShape, xi: f64, n: &mut [f64], dn: &mut [f64]) {
    match shape {
        CellShape::Line2 => {
            n[..2].copy_from_slice(&[0.5 * (1.0 - xi), 0.5 * (1.0 + xi)]);
            dn[..2].copy_from_slice(&[-0.5, 0.5]);
        }
        CellShape::Line3 => {
            n[..3].copy_from_slice(&[0.5 * xi * (xi - 1.0), 0.5 * xi * (xi + 1.0), 1.0 - xi * xi]);
            dn[..3].copy_from_slice(&[xi - 0.5, xi + 0.5, -2.0 * xi]);
        }
        s => panic!("line_shape called with non-line shape {s:?}"),
    }
}

/// Shape functions of any surface (quadrilateral or triangle, or the plane
/// cell of the same order) or line: dispatches to [`quad_shape`],
/// [`tri_shape`] or [`line_shape`]. `xi` is `(xi, eta)` in `[-1, 1]^2` for
/// quadrilaterals, `(r, s)` in the unit triangle for triangles, `(xi, _)`
/// for lines (whose `dn[a][1]` is 0).
pub fn surface_shape(shape: CellShape, xi: [f64; 2], n: &mut [f64], dn: &mut [[f64; 2]]) {
    let shape = shape.plane_reference().unwrap_or(shape);
    match shape {
        CellShape::Tri3 | CellShape::Tri6 => tri_shape(shape, xi, n, dn),
        CellShape::Line2 | CellShape::Line3 => {
            let mut d = [0.0; 3];
            line_shape(shape, xi[0], n, &mut d);
            for (a, da) in d.iter().enumerate().take(shape.num_nodes()) {
                dn[a] = [*da, 0.0];
            }
        }
        _ => quad_shape(shape, xi, n, dn),
    }
}

/// Shape functions of a hexahedron (H8, H20 or H27) at `xi = [xi, eta, zeta]`.
///
/// Writes `n[a] = N_a(xi)` and `dn[a] = [dN_a/dxi, dN_a/deta, dN_a/dzeta]`
/// for the `shape.num_nodes()` nodes in [`junta_core::topology`] order.
///
/// # Panics
/// If `shape` is not `Hex8`, `Hex20` or `Hex27`, or a buffer is shorter than
/// the node count (both are programming errors).
pub fn hex_shape(shape: CellShape, xi: [f64; 3], n: &mut [f64], dn: &mut [[f64; 3]]) {
    let [x, y, z] = xi;
    match shape {
        CellShape::Hex8 => {
            for (a, p) in HEX27_NODES[..8].iter().enumerate() {
                let (fx, dx) = lin(p[0], x);
                let (fy, dy) = lin(p[1], y);
                let (fz, dz) = lin(p[2], z);
                n[a] = fx * fy * fz;
                dn[a] = [dx * fy * fz, fx * dy * fz, fx * fy * dz];
            }
        }
        CellShape::Hex27 => {
            for (a, p) in HEX27_NODES.iter().enumerate() {
                let (fx, dx) = quad(p[0], x);
                let (fy, dy) = quad(p[1], y);
                let (fz, dz) = quad(p[2], z);
                n[a] = fx * fy * fz;
                dn[a] = [dx * fy * fz, fx * dy * fz, fx * fy * dz];
            }
        }
        CellShape::Hex20 => {
            for (a, p) in HEX27_NODES[..20].iter().enumerate() {
                let (xa, ya, za) = (p[0], p[1], p[2]);
                if a < 8 {
                    // corner: (1 + x xa)(1 + y ya)(1 + z za)(x xa + y ya + z za - 2) / 8
                    let (px, py, pz) = (1.0 + x * xa, 1.0 + y * ya, 1.0 + z * za);
                    let s = x * xa + y * ya + z * za - 2.0;
                    n[a] = 0.125 * px * py * pz * s;
                    dn[a] = [
                        0.125 * xa * py * pz * (s + px),
                        0.125 * ya * px * pz * (s + py),
                        0.125 * za * px * py * (s + pz),
                    ];
                } else {
                    // mid-edge: the coordinate with a_i = 0 gets (1 - t^2), the
                    // two others (1 + t t_a); N = product / 4
                    let mut f = [0.0; 3];
                    let mut d = [0.0; 3];
                    for (i, (&t, &ta)) in [x, y, z].iter().zip([xa, ya, za].iter()).enumerate() {
                        if ta == 0.0 {
                            f[i] = 1.0 - t * t;
                            d[i] = -2.0 * t;
                        } else {
                            f[i] = 1.0 + t * ta;
                            d[i] = ta;
                        }
                    }
                    n[a] = 0.25 * f[0] * f[1] * f[2];
                    dn[a] = [
                        0.25 * d[0] * f[1] * f[2],
                        0.25 * f[0] * d[1] * f[2],
                        0.25 * f[0] * f[1] * d[2],
                    ];
                }
            }
        }
        s => panic!("hex_shape called with non-hexahedral shape {s:?}"),
    }
}

/// Shape functions of a wedge (Wedge6 or Wedge15) at `xi = [r, s, zeta]`
/// (triangle `r, s >= 0, r + s <= 1`, `zeta` in `[-1, 1]`), in the node order
/// of [`junta_core::topology::WEDGE15_NODES`].
///
/// With the area coordinates `L = (1 - r - s, r, s)` of the triangle corners
/// and `zeta_a = ±1` the level of node `a`:
///
/// ```text
/// Wedge6:   N_a = L_i (1 + zeta zeta_a) / 2
/// Wedge15:  corner        N_a = L_i (2 L_i - 1)(1 + zeta zeta_a) / 2 - L_i (1 - zeta^2) / 2
///           triangle edge N_a = 2 L_i L_j (1 + zeta zeta_a)
///           vertical edge N_a = L_i (1 - zeta^2)
/// ```
///
/// # Panics
/// If `shape` is not a wedge or a buffer is too short (programming errors).
pub fn wedge_shape(shape: CellShape, xi: [f64; 3], n: &mut [f64], dn: &mut [[f64; 3]]) {
    let [r, s, z] = xi;
    let l = [1.0 - r - s, r, s];
    // dL_i/d(r, s)
    let dl = [[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]];
    let corner = |a: usize| (a % 3, if a < 3 { -1.0 } else { 1.0 });
    match shape {
        CellShape::Wedge6 => {
            for a in 0..6 {
                let (i, za) = corner(a);
                let h = 0.5 * (1.0 + z * za);
                n[a] = l[i] * h;
                dn[a] = [dl[i][0] * h, dl[i][1] * h, l[i] * 0.5 * za];
            }
        }
        CellShape::Wedge15 => {
            let b = 1.0 - z * z;
            for a in 0..6 {
                let (i, za) = corner(a);
                let h = 1.0 + z * za;
                let li = l[i];
                let q = li * (2.0 * li - 1.0);
                let dq = 4.0 * li - 1.0;
                n[a] = 0.5 * q * h - 0.5 * li * b;
                let dli = |d: f64| 0.5 * dq * d * h - 0.5 * d * b;
                dn[a] = [dli(dl[i][0]), dli(dl[i][1]), 0.5 * q * za + li * z];
            }
            // triangle mid-edges: (i, j, zeta_a)
            const EDGES: [(usize, usize, f64); 6] = [
                (0, 1, -1.0),
                (1, 2, -1.0),
                (2, 0, -1.0),
                (0, 1, 1.0),
                (1, 2, 1.0),
                (2, 0, 1.0),
            ];
            for (k, &(i, j, za)) in EDGES.iter().enumerate() {
                let h = 1.0 + z * za;
                let a = 6 + k;
                n[a] = 2.0 * l[i] * l[j] * h;
                let d = |c: usize| 2.0 * (dl[i][c] * l[j] + l[i] * dl[j][c]) * h;
                dn[a] = [d(0), d(1), 2.0 * l[i] * l[j] * za];
            }
            for i in 0..3 {
                let a = 12 + i;
                n[a] = l[i] * b;
                dn[a] = [dl[i][0] * b, dl[i][1] * b, -2.0 * z * l[i]];
            }
        }
        s => panic!("wedge_shape called with non-wedge shape {s:?}"),
    }
}

/// Shape functions of any solid (hexahedron or wedge): dispatches to
/// [`hex_shape`] or [`wedge_shape`].
pub fn solid_shape(shape: CellShape, xi: [f64; 3], n: &mut [f64], dn: &mut [[f64; 3]]) {
    match shape {
        CellShape::Wedge6 | CellShape::Wedge15 => wedge_shape(shape, xi, n, dn),
        _ => hex_shape(shape, xi, n, dn),
    }
}

/// Natural coordinates of node `a` of a quadrilateral, triangle, hexahedron
/// or wedge, padded
/// with zeros to three components.
pub fn natural_node(shape: CellShape, a: usize) -> [f64; 3] {
    let shape = shape.plane_reference().unwrap_or(shape);
    match shape {
        CellShape::Line2 | CellShape::Line3 => [[-1.0, 1.0, 0.0][a], 0.0, 0.0],
        CellShape::Quad4 | CellShape::Quad8 | CellShape::Quad9 => {
            [QUAD9_NODES[a][0], QUAD9_NODES[a][1], 0.0]
        }
        CellShape::Tri3 | CellShape::Tri6 => [TRI6_NODES[a][0], TRI6_NODES[a][1], 0.0],
        CellShape::Wedge6 | CellShape::Wedge15 => junta_core::topology::WEDGE15_NODES[a],
        _ => HEX27_NODES[a],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const QUADS: [CellShape; 3] = [CellShape::Quad4, CellShape::Quad8, CellShape::Quad9];
    const HEXES: [CellShape; 3] = [CellShape::Hex8, CellShape::Hex20, CellShape::Hex27];

    /// A few sample points inside the reference cell (not on a symmetry plane).
    const SAMPLES: [[f64; 3]; 5] = [
        [0.0, 0.0, 0.0],
        [0.3, -0.7, 0.45],
        [-0.91, 0.2, -0.33],
        [0.77, 0.61, -0.95],
        [-0.5, -0.5, 0.9],
    ];

    fn eval_hex(s: CellShape, x: [f64; 3]) -> ([f64; 27], [[f64; 3]; 27]) {
        let mut n = [0.0; 27];
        let mut dn = [[0.0; 3]; 27];
        hex_shape(s, x, &mut n, &mut dn);
        (n, dn)
    }
    fn eval_quad(s: CellShape, x: [f64; 2]) -> ([f64; 9], [[f64; 2]; 9]) {
        let mut n = [0.0; 9];
        let mut dn = [[0.0; 2]; 9];
        quad_shape(s, x, &mut n, &mut dn);
        (n, dn)
    }

    #[test]
    fn partition_of_unity() {
        for s in HEXES {
            for x in SAMPLES {
                let (n, dn) = eval_hex(s, x);
                let nn = s.num_nodes();
                assert!((n[..nn].iter().sum::<f64>() - 1.0).abs() < 1e-14, "{s:?}");
                for j in 0..3 {
                    assert!(
                        dn[..nn].iter().map(|d| d[j]).sum::<f64>().abs() < 1e-13,
                        "{s:?}"
                    );
                }
            }
        }
        for s in QUADS {
            for x in SAMPLES {
                let (n, dn) = eval_quad(s, [x[0], x[1]]);
                let nn = s.num_nodes();
                assert!((n[..nn].iter().sum::<f64>() - 1.0).abs() < 1e-14, "{s:?}");
                for j in 0..2 {
                    assert!(
                        dn[..nn].iter().map(|d| d[j]).sum::<f64>().abs() < 1e-13,
                        "{s:?}"
                    );
                }
            }
        }
    }

    #[test]
    fn kronecker_delta_at_nodes() {
        for s in HEXES {
            let nn = s.num_nodes();
            for (b, &xb) in HEX27_NODES[..nn].iter().enumerate() {
                let (n, _) = eval_hex(s, xb);
                for (a, v) in n[..nn].iter().enumerate() {
                    let e = if a == b { 1.0 } else { 0.0 };
                    assert!((v - e).abs() < 1e-15, "{s:?} N_{a}(x_{b}) = {v}");
                }
            }
        }
        for s in QUADS {
            let nn = s.num_nodes();
            for (b, &xb) in QUAD9_NODES[..nn].iter().enumerate() {
                let (n, _) = eval_quad(s, xb);
                for (a, v) in n[..nn].iter().enumerate() {
                    let e = if a == b { 1.0 } else { 0.0 };
                    assert!((v - e).abs() < 1e-15, "{s:?} N_{a}(x_{b}) = {v}");
                }
            }
        }
    }

    #[test]
    fn derivatives_match_finite_differences() {
        let h = 1e-6;
        for s in HEXES {
            let nn = s.num_nodes();
            for x in SAMPLES {
                let (_, dn) = eval_hex(s, x);
                for j in 0..3 {
                    let (mut xp, mut xm) = (x, x);
                    xp[j] += h;
                    xm[j] -= h;
                    let (np, _) = eval_hex(s, xp);
                    let (nm, _) = eval_hex(s, xm);
                    for a in 0..nn {
                        let fd = (np[a] - nm[a]) / (2.0 * h);
                        assert!(
                            (fd - dn[a][j]).abs() < 1e-8,
                            "{s:?} a={a} j={j}: {fd} vs {}",
                            dn[a][j]
                        );
                    }
                }
            }
        }
        for s in QUADS {
            let nn = s.num_nodes();
            for x in SAMPLES {
                let x = [x[0], x[1]];
                let (_, dn) = eval_quad(s, x);
                for j in 0..2 {
                    let (mut xp, mut xm) = (x, x);
                    xp[j] += h;
                    xm[j] -= h;
                    let (np, _) = eval_quad(s, xp);
                    let (nm, _) = eval_quad(s, xm);
                    for a in 0..nn {
                        let fd = (np[a] - nm[a]) / (2.0 * h);
                        assert!((fd - dn[a][j]).abs() < 1e-8, "{s:?} a={a} j={j}");
                    }
                }
            }
        }
    }

    /// Monomials x^i y^j z^k of total degree <= `deg` (plus, for the full
    /// Lagrange shapes, what they span beyond) must be reproduced exactly.
    fn check_hex_completeness(s: CellShape, deg: u32) {
        let nn = s.num_nodes();
        for i in 0..=deg {
            for j in 0..=(deg - i) {
                for k in 0..=(deg - i - j) {
                    let f = |p: [f64; 3]| {
                        p[0].powi(i as i32) * p[1].powi(j as i32) * p[2].powi(k as i32)
                    };
                    let df = |p: [f64; 3]| {
                        let d = |e: u32, t: f64| {
                            if e == 0 {
                                0.0
                            } else {
                                e as f64 * t.powi(e as i32 - 1)
                            }
                        };
                        [
                            d(i, p[0]) * p[1].powi(j as i32) * p[2].powi(k as i32),
                            p[0].powi(i as i32) * d(j, p[1]) * p[2].powi(k as i32),
                            p[0].powi(i as i32) * p[1].powi(j as i32) * d(k, p[2]),
                        ]
                    };
                    for x in SAMPLES {
                        let (n, dn) = eval_hex(s, x);
                        let v: f64 = (0..nn).map(|a| n[a] * f(HEX27_NODES[a])).sum();
                        assert!((v - f(x)).abs() < 1e-13, "{s:?} x^{i} y^{j} z^{k}");
                        let g = df(x);
                        for c in 0..3 {
                            let gv: f64 = (0..nn).map(|a| dn[a][c] * f(HEX27_NODES[a])).sum();
                            assert!((gv - g[c]).abs() < 1e-12, "{s:?} d/dx{c} x^{i} y^{j} z^{k}");
                        }
                    }
                }
            }
        }
    }

    fn check_quad_completeness(s: CellShape, deg: u32) {
        let nn = s.num_nodes();
        for i in 0..=deg {
            for j in 0..=(deg - i) {
                let f = |p: [f64; 2]| p[0].powi(i as i32) * p[1].powi(j as i32);
                for x in SAMPLES {
                    let x = [x[0], x[1]];
                    let (n, _) = eval_quad(s, x);
                    let v: f64 = (0..nn).map(|a| n[a] * f(QUAD9_NODES[a])).sum();
                    assert!((v - f(x)).abs() < 1e-13, "{s:?} x^{i} y^{j}");
                }
            }
        }
    }

    #[test]
    fn completeness() {
        check_hex_completeness(CellShape::Hex8, 1);
        check_hex_completeness(CellShape::Hex20, 2);
        check_hex_completeness(CellShape::Hex27, 2);
        check_quad_completeness(CellShape::Quad4, 1);
        check_quad_completeness(CellShape::Quad8, 2);
        check_quad_completeness(CellShape::Quad9, 2);
    }

    #[test]
    fn lagrange_shapes_reproduce_their_tensor_products() {
        // H8 spans xyz, H27 spans x^2 y^2 z^2, Q9 spans x^2 y^2
        let (n, _) = eval_hex(CellShape::Hex8, SAMPLES[1]);
        let v: f64 = (0..8)
            .map(|a| n[a] * HEX27_NODES[a].iter().product::<f64>())
            .sum();
        assert!((v - SAMPLES[1].iter().product::<f64>()).abs() < 1e-14);
        let f = |p: [f64; 3]| (p[0] * p[1] * p[2]).powi(2);
        let (n, _) = eval_hex(CellShape::Hex27, SAMPLES[2]);
        let v: f64 = (0..27).map(|a| n[a] * f(HEX27_NODES[a])).sum();
        assert!((v - f(SAMPLES[2])).abs() < 1e-14);
        let (n, _) = eval_quad(CellShape::Quad9, [0.3, -0.8]);
        let v: f64 = (0..9)
            .map(|a| n[a] * (QUAD9_NODES[a][0] * QUAD9_NODES[a][1]).powi(2))
            .sum();
        assert!((v - (0.3f64 * -0.8f64).powi(2)).abs() < 1e-14);
    }

    #[test]
    #[should_panic(expected = "non-hexahedral")]
    fn hex_shape_rejects_quads() {
        let mut n = [0.0; 27];
        let mut dn = [[0.0; 3]; 27];
        hex_shape(CellShape::Quad4, [0.0; 3], &mut n, &mut dn);
    }

    fn eval_tri(s: CellShape, x: [f64; 2]) -> ([f64; 6], [[f64; 2]; 6]) {
        let mut n = [0.0; 6];
        let mut dn = [[0.0; 2]; 6];
        tri_shape(s, x, &mut n, &mut dn);
        (n, dn)
    }

    /// Triangles: Kronecker delta at the nodes, partition of unity (and
    /// zero-sum derivatives), derivatives against central differences,
    /// complete polynomials of the shape's degree reproduced with their
    /// gradients, and the Tri6 functions equal to the Wedge15 bottom
    /// triangle's at zeta = -1 (the interface and the solid interpolate a
    /// wedge face alike).
    #[test]
    fn triangle_shapes() {
        const TRIS: [(CellShape, u32); 2] = [(CellShape::Tri3, 1), (CellShape::Tri6, 2)];
        const INSIDE: [[f64; 2]; 5] = [
            [1.0 / 3.0, 1.0 / 3.0],
            [0.1, 0.2],
            [0.7, 0.25],
            [0.05, 0.9],
            [0.45, 0.0],
        ];
        for (s, deg) in TRIS {
            let nn = s.num_nodes();
            for (b, &xb) in TRI6_NODES[..nn].iter().enumerate() {
                let (n, _) = eval_tri(s, xb);
                for (a, v) in n[..nn].iter().enumerate() {
                    let e = if a == b { 1.0 } else { 0.0 };
                    assert!((v - e).abs() < 1e-15, "{s:?} N_{a}(x_{b}) = {v}");
                }
            }
            for x in INSIDE {
                let (n, dn) = eval_tri(s, x);
                assert!((n[..nn].iter().sum::<f64>() - 1.0).abs() < 1e-14, "{s:?}");
                for j in 0..2 {
                    assert!(dn[..nn].iter().map(|d| d[j]).sum::<f64>().abs() < 1e-13);
                }
                let h = 1e-6;
                for j in 0..2 {
                    let (mut xp, mut xm) = (x, x);
                    xp[j] += h;
                    xm[j] -= h;
                    let (np, _) = eval_tri(s, xp);
                    let (nm, _) = eval_tri(s, xm);
                    for a in 0..nn {
                        let fd = (np[a] - nm[a]) / (2.0 * h);
                        assert!((fd - dn[a][j]).abs() < 1e-8, "{s:?} dN_{a}/dx{j}");
                    }
                }
                // r^i s^j, i + j <= degree, and its gradient
                for i in 0..=deg {
                    for j in 0..=(deg - i) {
                        let f = |p: [f64; 2]| p[0].powi(i as i32) * p[1].powi(j as i32);
                        let d = |e: u32, t: f64| {
                            if e == 0 {
                                0.0
                            } else {
                                e as f64 * t.powi(e as i32 - 1)
                            }
                        };
                        let g = [
                            d(i, x[0]) * x[1].powi(j as i32),
                            x[0].powi(i as i32) * d(j, x[1]),
                        ];
                        let v: f64 = (0..nn).map(|a| n[a] * f(TRI6_NODES[a])).sum();
                        assert!((v - f(x)).abs() < 1e-14, "{s:?} r^{i} s^{j}");
                        for c in 0..2 {
                            let gv: f64 = (0..nn).map(|a| dn[a][c] * f(TRI6_NODES[a])).sum();
                            assert!((gv - g[c]).abs() < 1e-13, "{s:?} grad r^{i} s^{j}");
                        }
                    }
                }
                // the wedge's bottom triangle at zeta = -1
                let wedge = if s == CellShape::Tri3 {
                    CellShape::Wedge6
                } else {
                    CellShape::Wedge15
                };
                let mut nw = [0.0; 15];
                let mut dw = [[0.0; 3]; 15];
                wedge_shape(wedge, [x[0], x[1], -1.0], &mut nw, &mut dw);
                for (a, w) in [0, 1, 2, 6, 7, 8][..nn].iter().enumerate() {
                    assert!((nw[*w] - n[a]).abs() < 1e-14, "{s:?} node {a}");
                    for c in 0..2 {
                        assert!((dw[*w][c] - dn[a][c]).abs() < 1e-13, "{s:?} node {a}");
                    }
                }
            }
            // surface_shape dispatches
            let mut n2 = [0.0; 6];
            let mut d2 = [[0.0; 2]; 6];
            surface_shape(s, [0.2, 0.3], &mut n2, &mut d2);
            assert_eq!((n2, d2), eval_tri(s, [0.2, 0.3]));
        }
    }

    #[test]
    #[should_panic(expected = "non-triangular")]
    fn tri_shape_rejects_quads() {
        let mut n = [0.0; 9];
        let mut dn = [[0.0; 2]; 9];
        tri_shape(CellShape::Quad4, [0.0; 2], &mut n, &mut dn);
    }

    #[test]
    fn wedge_shapes_are_kronecker_partition_of_unity_and_derivatives_match() {
        use junta_core::topology::WEDGE15_NODES;
        for shape in [CellShape::Wedge6, CellShape::Wedge15] {
            let nn = shape.num_nodes();
            let eval = |x: [f64; 3]| {
                let mut n = [0.0; 15];
                let mut dn = [[0.0; 3]; 15];
                wedge_shape(shape, x, &mut n, &mut dn);
                (n, dn)
            };
            for (b, &xb) in WEDGE15_NODES[..nn].iter().enumerate() {
                let (n, _) = eval(xb);
                for (a, &v) in n[..nn].iter().enumerate() {
                    let want = if a == b { 1.0 } else { 0.0 };
                    assert!((v - want).abs() < 1e-14, "{shape:?} N_{a}(node {b}) = {v}");
                }
            }
            for x in [[0.2, 0.3, 0.1], [0.6, 0.1, -0.7], [0.05, 0.8, 0.9]] {
                let (n, dn) = eval(x);
                assert!((n[..nn].iter().sum::<f64>() - 1.0).abs() < 1e-14);
                let h = 1e-6;
                for c in 0..3 {
                    let (mut xp, mut xm) = (x, x);
                    xp[c] += h;
                    xm[c] -= h;
                    let (np, _) = eval(xp);
                    let (nm, _) = eval(xm);
                    for a in 0..nn {
                        let fd = (np[a] - nm[a]) / (2.0 * h);
                        assert!((fd - dn[a][c]).abs() < 1e-8, "{shape:?} dN_{a}/dx{c}");
                    }
                }
            }
        }
    }
}
