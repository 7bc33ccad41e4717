//! Numerical integration on `[-1, 1]^d`: Gauss-Legendre and Gauss-Lobatto
//! rules in 1D and their tensor products in 2D and 3D; symmetric rules on
//! the unit triangle and their products with a line rule on the wedge.
//!
//! * Gauss-Legendre with `n = 1..=5` points integrates polynomials of degree
//!   `2n - 1` exactly: `∫_{-1}^{1} p(x) dx = Σ_i w_i p(x_i)`.
//! * Gauss-Lobatto with `n = 2..=5` points (end points included) integrates
//!   polynomials of degree `2n - 3` exactly.
//!
//! A tensor-product rule in `d` dimensions, `∫ f dξ ≈ Σ_{i,j,k} w_i w_j w_k
//! f(x_i, x_j, x_k)`, integrates exactly every polynomial whose degree in
//! *each* variable is at most the 1D degree. Points are ordered with the
//! first coordinate varying fastest: index `(k n + j) n + i`.
//!
//! Triangle rules ([`triangle_rule`]) on `r, s >= 0, r + s <= 1` (weights
//! summing to the area 1/2) integrate exactly every polynomial `r^i s^j`
//! of total degree `i + j` at most their degree, whose integral is
//! `i! j! / (i + j + 2)!`.
//!
//! Rules are built once (when an element is built) and then only read.

use thiserror::Error;

/// An unsupported rule was requested.
#[derive(Debug, Error, Clone, PartialEq, Eq)]
pub enum QuadratureError {
    /// No rule of that family with that many points.
    #[error("no {family} rule with {n} points; valid point counts: {valid}")]
    UnsupportedPoints {
        /// The family asked for (`"Gauss-Legendre"`, `"Gauss-Lobatto"`,
        /// `"triangle"`).
        family: &'static str,
        /// The number of points asked for.
        n: usize,
        /// The point counts the family supports, comma-separated.
        valid: &'static str,
    },
}

/// Which 1D family a rule belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Family {
    /// Gauss-Legendre (interior points, degree `2n - 1`).
    GaussLegendre,
    /// Gauss-Lobatto (end points included, degree `2n - 3`).
    GaussLobatto,
}

/// A 1D rule on `[-1, 1]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rule1D {
    /// Family of the rule.
    pub family: Family,
    /// Abscissae, ascending.
    pub points: &'static [f64],
    /// Weights (sum 2).
    pub weights: &'static [f64],
    /// Highest polynomial degree integrated exactly.
    pub degree: usize,
}

impl Rule1D {
    /// Number of points.
    pub fn len(&self) -> usize {
        self.points.len()
    }
    /// Never true (every rule has at least one point).
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }
    /// `Σ_i w_i f(x_i)`.
    pub fn integrate(&self, f: impl Fn(f64) -> f64) -> f64 {
        self.points
            .iter()
            .zip(self.weights)
            .map(|(&x, &w)| w * f(x))
            .sum()
    }
}

// Gauss-Legendre abscissae and weights (closed forms, rounded to the nearest f64).
const GL1_X: [f64; 1] = [0.0];
const GL1_W: [f64; 1] = [2.0];
const GL2_X: [f64; 2] = [-0.5773502691896257, 0.5773502691896257];
const GL2_W: [f64; 2] = [1.0, 1.0];
const GL3_X: [f64; 3] = [-0.7745966692414834, 0.0, 0.7745966692414834];
const GL3_W: [f64; 3] = [0.5555555555555556, 0.8888888888888888, 0.5555555555555556];
const GL4_X: [f64; 4] = [
    -0.8611363115940526,
    -0.33998104358485626,
    0.33998104358485626,
    0.8611363115940526,
];
const GL4_W: [f64; 4] = [
    0.34785484513745385,
    0.6521451548625461,
    0.6521451548625461,
    0.34785484513745385,
];
const GL5_X: [f64; 5] = [
    -0.906179845938664,
    -0.5384693101056831,
    0.0,
    0.5384693101056831,
    0.906179845938664,
];
const GL5_W: [f64; 5] = [
    0.23692688505618908,
    0.47862867049936647,
    0.5688888888888889,
    0.47862867049936647,
    0.23692688505618908,
];

// Gauss-Lobatto abscissae and weights.
const GLL2_X: [f64; 2] = [-1.0, 1.0];
const GLL2_W: [f64; 2] = [1.0, 1.0];
const GLL3_X: [f64; 3] = [-1.0, 0.0, 1.0];
const GLL3_W: [f64; 3] = [0.3333333333333333, 1.3333333333333333, 0.3333333333333333];
const GLL4_X: [f64; 4] = [-1.0, -0.4472135954999579, 0.4472135954999579, 1.0];
const GLL4_W: [f64; 4] = [
    0.16666666666666666,
    0.8333333333333334,
    0.8333333333333334,
    0.16666666666666666,
];
const GLL5_X: [f64; 5] = [-1.0, -0.6546536707079772, 0.0, 0.6546536707079772, 1.0];
const GLL5_W: [f64; 5] = [
    0.1,
    0.5444444444444444,
    0.7111111111111111,
    0.5444444444444444,
    0.1,
];

/// The `n`-point Gauss-Legendre rule, `n = 1..=5` (exact to degree `2n - 1`).
pub fn gauss_legendre(n: usize) -> Result<Rule1D, QuadratureError> {
    let (points, weights): (&'static [f64], &'static [f64]) = match n {
        1 => (&GL1_X, &GL1_W),
        2 => (&GL2_X, &GL2_W),
        3 => (&GL3_X, &GL3_W),
        4 => (&GL4_X, &GL4_W),
        5 => (&GL5_X, &GL5_W),
        _ => {
            return Err(QuadratureError::UnsupportedPoints {
                family: "Gauss-Legendre",
                n,
                valid: "1, 2, 3, 4, 5",
            })
        }
    };
    Ok(Rule1D {
        family: Family::GaussLegendre,
        points,
        weights,
        degree: 2 * n - 1,
    })
}

/// The `n`-point Gauss-Lobatto rule, `n = 2..=5` (exact to degree `2n - 3`).
pub fn gauss_lobatto(n: usize) -> Result<Rule1D, QuadratureError> {
    let (points, weights): (&'static [f64], &'static [f64]) = match n {
        2 => (&GLL2_X, &GLL2_W),
        3 => (&GLL3_X, &GLL3_W),
        4 => (&GLL4_X, &GLL4_W),
        5 => (&GLL5_X, &GLL5_W),
        _ => {
            return Err(QuadratureError::UnsupportedPoints {
                family: "Gauss-Lobatto",
                n,
                valid: "2, 3, 4, 5",
            })
        }
    };
    Ok(Rule1D {
        family: Family::GaussLobatto,
        points,
        weights,
        degree: 2 * n - 3,
    })
}

/// A rule in `D` dimensions on `[-1, 1]^D`.
#[derive(Debug, Clone, PartialEq)]
pub struct Rule<const D: usize> {
    /// Points in natural coordinates.
    pub points: Vec<[f64; D]>,
    /// Weights (sum `2^D`).
    pub weights: Vec<f64>,
}

impl<const D: usize> Rule<D> {
    /// Number of points.
    pub fn len(&self) -> usize {
        self.points.len()
    }
    /// True if the rule has no point.
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }
    /// `(point, weight)` pairs.
    pub fn iter(&self) -> impl Iterator<Item = (&[f64; D], f64)> + '_ {
        self.points.iter().zip(self.weights.iter().copied())
    }
    /// `Σ_q w_q f(x_q)`.
    pub fn integrate(&self, f: impl Fn([f64; D]) -> f64) -> f64 {
        self.iter().map(|(&x, w)| w * f(x)).sum()
    }
}

/// Tensor product of a 1D rule with itself in 2D (`xi` fastest).
pub fn tensor_2d(r: &Rule1D) -> Rule<2> {
    let n = r.len();
    let mut points = Vec::with_capacity(n * n);
    let mut weights = Vec::with_capacity(n * n);
    for j in 0..n {
        for i in 0..n {
            points.push([r.points[i], r.points[j]]);
            weights.push(r.weights[i] * r.weights[j]);
        }
    }
    Rule { points, weights }
}

/// Tensor product of a 1D rule with itself in 3D (`xi` fastest, `zeta` slowest).
pub fn tensor_3d(r: &Rule1D) -> Rule<3> {
    let n = r.len();
    let mut points = Vec::with_capacity(n * n * n);
    let mut weights = Vec::with_capacity(n * n * n);
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                points.push([r.points[i], r.points[j], r.points[k]]);
                weights.push(r.weights[i] * r.weights[j] * r.weights[k]);
            }
        }
    }
    Rule { points, weights }
}

/// `n x n` Gauss-Legendre rule on the square.
pub fn gauss_legendre_2d(n: usize) -> Result<Rule<2>, QuadratureError> {
    Ok(tensor_2d(&gauss_legendre(n)?))
}

/// `n x n x n` Gauss-Legendre rule on the cube.
pub fn gauss_legendre_3d(n: usize) -> Result<Rule<3>, QuadratureError> {
    Ok(tensor_3d(&gauss_legendre(n)?))
}

/// `n x n` Gauss-Lobatto rule on the square (e.g. nodal integration of interfaces).
pub fn gauss_lobatto_2d(n: usize) -> Result<Rule<2>, QuadratureError> {
    Ok(tensor_2d(&gauss_lobatto(n)?))
}

/// `n x n x n` Gauss-Lobatto rule on the cube.
pub fn gauss_lobatto_3d(n: usize) -> Result<Rule<3>, QuadratureError> {
    Ok(tensor_3d(&gauss_lobatto(n)?))
}

// Triangle rules: (point, weight) on the unit triangle, weights sum 1/2.
const TRI1: [([f64; 2], f64); 1] = [([1.0 / 3.0, 1.0 / 3.0], 0.5)];
const TRI3: [([f64; 2], f64); 3] = [
    ([1.0 / 6.0, 1.0 / 6.0], 1.0 / 6.0),
    ([2.0 / 3.0, 1.0 / 6.0], 1.0 / 6.0),
    ([1.0 / 6.0, 2.0 / 3.0], 1.0 / 6.0),
];
// Strang-Fix / Dunavant degree 4: a = (8 - sqrt 10 + sqrt(38 - 44 sqrt(2/5)))
// / 18, b = the same with - before the last sqrt; weights (620 +- sqrt(213125
// - 53320 sqrt 10)) / 3720 times the area 1/2 (values to 30 digits with
// mpmath, rounded to f64).
const TRI6_A: f64 = 0.445_948_490_915_964_9;
const TRI6_B: f64 = 0.091_576_213_509_770_74;
const TRI6_WA: f64 = 0.111_690_794_839_005_74;
const TRI6_WB: f64 = 0.054_975_871_827_660_935;
const TRI6: [([f64; 2], f64); 6] = [
    ([TRI6_A, TRI6_A], TRI6_WA),
    ([1.0 - 2.0 * TRI6_A, TRI6_A], TRI6_WA),
    ([TRI6_A, 1.0 - 2.0 * TRI6_A], TRI6_WA),
    ([TRI6_B, TRI6_B], TRI6_WB),
    ([1.0 - 2.0 * TRI6_B, TRI6_B], TRI6_WB),
    ([TRI6_B, 1.0 - 2.0 * TRI6_B], TRI6_WB),
];
const TRI_VERTEX: [([f64; 2], f64); 3] = [
    ([0.0, 0.0], 1.0 / 6.0),
    ([1.0, 0.0], 1.0 / 6.0),
    ([0.0, 1.0], 1.0 / 6.0),
];

fn tri_table(n: usize) -> Result<&'static [([f64; 2], f64)], QuadratureError> {
    match n {
        1 => Ok(&TRI1),
        3 => Ok(&TRI3),
        6 => Ok(&TRI6),
        n => Err(QuadratureError::UnsupportedPoints {
            family: "triangle",
            n,
            valid: "1, 3, 6",
        }),
    }
}

/// Degree of the `n`-point [`triangle_rule`] (the highest total degree it
/// integrates exactly), `None` for an unsupported count.
pub fn triangle_rule_degree(n: usize) -> Option<usize> {
    match n {
        1 => Some(1),
        3 => Some(2),
        6 => Some(4),
        _ => None,
    }
}

/// Symmetric Gauss rule on the unit triangle `r, s >= 0, r + s <= 1`
/// (weights sum to the area 1/2), interior points only:
///
/// * `n = 1`: the centroid, weight 1/2 (degree 1);
/// * `n = 3`: (1/6, 1/6), (2/3, 1/6), (1/6, 2/3), weights 1/6 (degree 2,
///   Strang-Fix; the rule CalculiX uses for C3D15);
/// * `n = 6`: the orbits of (a, a) and (b, b), a = 0.44594849..., b =
///   0.09157621..., weights 0.11169079... and 0.05497587... (degree 4,
///   Strang-Fix / Dunavant 1985).
pub fn triangle_rule(n: usize) -> Result<Rule<2>, QuadratureError> {
    let t = tri_table(n)?;
    Ok(Rule {
        points: t.iter().map(|p| p.0).collect(),
        weights: t.iter().map(|p| p.1).collect(),
    })
}

/// Vertex (nodal, Newton-Cotes) rule on the unit triangle: the three
/// corners, weights 1/6 (degree 1). The triangle's analogue of the 2x2
/// Gauss-Lobatto rule: nodal integration of a linear triangle.
pub fn triangle_vertex_rule() -> Rule<2> {
    Rule {
        points: TRI_VERTEX.iter().map(|p| p.0).collect(),
        weights: TRI_VERTEX.iter().map(|p| p.1).collect(),
    }
}

/// Wedge rule: a triangle rule ([`triangle_rule`]: `n_tri` = 1, 3 or 6
/// points) times an `n_line`-point Gauss-Legendre rule in `zeta`.
pub fn wedge_rule(n_tri: usize, n_line: usize) -> Result<Rule<3>, QuadratureError> {
    let line = gauss_legendre(n_line)?;
    let tri = tri_table(n_tri)?;
    let mut points = Vec::with_capacity(tri.len() * line.len());
    let mut weights = Vec::with_capacity(tri.len() * line.len());
    for (&z, &wz) in line.points.iter().zip(line.weights) {
        for &([r, s], w) in tri {
            points.push([r, s, z]);
            weights.push(w * wz);
        }
    }
    Ok(Rule { points, weights })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ∫_{-1}^{1} x^k dx.
    fn exact(k: usize) -> f64 {
        if k % 2 == 1 {
            0.0
        } else {
            2.0 / (k as f64 + 1.0)
        }
    }

    fn check_1d(r: &Rule1D) {
        assert!((r.weights.iter().sum::<f64>() - 2.0).abs() < 1e-15);
        for k in 0..=r.degree {
            let v = r.integrate(|x| x.powi(k as i32));
            assert!(
                (v - exact(k)).abs() < 1e-15,
                "{:?} n={} degree {k}: {v}",
                r.family,
                r.len()
            );
        }
        // and not one degree more (the even degree just above is missed)
        let k = if r.degree % 2 == 1 {
            r.degree + 1
        } else {
            r.degree + 2
        };
        let v = r.integrate(|x| x.powi(k as i32));
        assert!(
            (v - exact(k)).abs() > 1e-6,
            "{:?} n={} unexpectedly exact at {k}",
            r.family,
            r.len()
        );
    }

    #[test]
    fn gauss_legendre_exactness() {
        for n in 1..=5 {
            let r = gauss_legendre(n).unwrap();
            assert_eq!(r.len(), n);
            assert_eq!(r.degree, 2 * n - 1);
            check_1d(&r);
        }
    }

    #[test]
    fn gauss_lobatto_exactness() {
        for n in 2..=5 {
            let r = gauss_lobatto(n).unwrap();
            assert_eq!(r.points[0], -1.0);
            assert_eq!(r.points[n - 1], 1.0);
            assert_eq!(r.degree, 2 * n - 3);
            check_1d(&r);
        }
    }

    #[test]
    fn unsupported_counts_are_errors() {
        assert!(matches!(
            gauss_legendre(0),
            Err(QuadratureError::UnsupportedPoints { .. })
        ));
        assert!(gauss_legendre(6).is_err());
        let e = gauss_lobatto(1).unwrap_err();
        assert!(e.to_string().contains("2, 3, 4, 5"), "{e}");
    }

    /// `∫ r^i s^j` over the unit triangle: `i! j! / (i + j + 2)!`.
    fn tri_exact(i: u32, j: u32) -> f64 {
        let f = |k: u32| (1..=k).map(f64::from).product::<f64>();
        f(i) * f(j) / f(i + j + 2)
    }

    /// Every triangle rule integrates the monomials of its degree exactly
    /// (closed form above) and misses some monomial of the next degree; the
    /// vertex rule is exact to degree 1; the wedge rule is the product.
    #[test]
    fn triangle_rules_are_exact_to_their_degree() {
        let check = |r: &Rule<2>, deg: u32, name: &str| {
            assert!(
                (r.weights.iter().sum::<f64>() - 0.5).abs() < 1e-15,
                "{name}"
            );
            for p in &r.points {
                assert!(p[0] >= 0.0 && p[1] >= 0.0 && p[0] + p[1] <= 1.0, "{name}");
            }
            for i in 0..=deg {
                for j in 0..=(deg - i) {
                    let v = r.integrate(|p| p[0].powi(i as i32) * p[1].powi(j as i32));
                    assert!(
                        (v - tri_exact(i, j)).abs() < 1e-16,
                        "{name} r^{i} s^{j}: {v} vs {}",
                        tri_exact(i, j)
                    );
                }
            }
            let k = deg + 1;
            let missed = (0..=k).any(|i| {
                let v = r.integrate(|p| p[0].powi(i as i32) * p[1].powi((k - i) as i32));
                (v - tri_exact(i, k - i)).abs() > 1e-8
            });
            assert!(missed, "{name} unexpectedly exact at degree {k}");
        };
        for n in [1, 3, 6] {
            let r = triangle_rule(n).unwrap();
            assert_eq!(r.len(), n);
            let deg = triangle_rule_degree(n).unwrap() as u32;
            check(&r, deg, &format!("triangle {n}"));
        }
        check(&triangle_vertex_rule(), 1, "vertex");
        let e = triangle_rule(4).unwrap_err().to_string();
        assert!(e.contains("1, 3, 6"), "{e}");
        assert_eq!(triangle_rule_degree(7), None);
        // wedge: triangle x line, r^2 s^2 z^4 with the 6 x 3 rule
        let w = wedge_rule(6, 3).unwrap();
        assert_eq!(w.len(), 18);
        let v = w.integrate(|p| (p[0] * p[1]).powi(2) * p[2].powi(4));
        assert!((v - tri_exact(2, 2) * exact(4)).abs() < 1e-16);
    }

    #[test]
    fn tensor_products_are_exact_per_variable_degree() {
        for n in 1..=5 {
            let r1 = gauss_legendre(n).unwrap();
            let d = r1.degree;
            let r2 = tensor_2d(&r1);
            let r3 = tensor_3d(&r1);
            assert_eq!(r3.len(), n * n * n);
            assert!((r3.weights.iter().sum::<f64>() - 8.0).abs() < 1e-14);
            for (i, j, k) in [(d, d, d), (d, 0, d), (d.saturating_sub(1), d, 0), (0, 0, 0)] {
                let v2 = r2.integrate(|p| p[0].powi(i as i32) * p[1].powi(j as i32));
                assert!((v2 - exact(i) * exact(j)).abs() < 1e-14);
                let v3 = r3
                    .integrate(|p| p[0].powi(i as i32) * p[1].powi(j as i32) * p[2].powi(k as i32));
                assert!(
                    (v3 - exact(i) * exact(j) * exact(k)).abs() < 1e-14,
                    "n={n} {i} {j} {k}"
                );
            }
        }
        let l = gauss_lobatto_3d(3).unwrap();
        let v = l.integrate(|p| p[0].powi(2) * p[1].powi(3) * p[2].powi(2));
        assert!(v.abs() < 1e-15);
        let v = l.integrate(|p| p[0].powi(2) * p[2].powi(2));
        assert!((v - 2.0 * (2.0 / 3.0) * (2.0 / 3.0)).abs() < 1e-14);
        // point order: xi fastest
        let g = gauss_legendre_3d(2).unwrap();
        assert!(g.points[1][0] > g.points[0][0] && g.points[1][1] == g.points[0][1]);
        assert!(g.points[4][2] > g.points[0][2]);
    }
}
