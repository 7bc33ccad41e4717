//! [`Dual3`]: forward-mode automatic differentiation with three partial
//! derivatives, for the consistent tangents of interface laws.
//!
//! A dual number `a + sum_i a_i e_i` (with `e_i e_j = 0`) carries a value
//! and its gradient with respect to three seeds (the jump components
//! `delta_1, delta_2, delta_3` in the laws). Every operation applies the
//! chain rule, so a law written once in `Dual3` yields its traction and the
//! exact derivative `d t / d delta` (to round-off), with no hand-derived
//! tangent to get wrong in one of its regimes. Branches (loading or
//! unloading, open or closed) are taken on the values, which gives the
//! one-sided derivative of the branch taken, the consistent tangent of a
//! return-mapping law.
//!
//! Where a derivative is infinite (the square root or a fractional power at
//! zero), the derivative is set to zero: such points are only reached where
//! the law does not depend on them (e.g. a zero jump), and a NaN would
//! poison the whole tangent.

use std::ops::{Add, Div, Mul, Neg, Sub};

/// A value with its gradient with respect to three seeds.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Dual3 {
    /// Value.
    pub v: f64,
    /// Partial derivatives.
    pub d: [f64; 3],
}

impl Dual3 {
    /// A constant (zero gradient).
    #[inline]
    pub const fn cst(v: f64) -> Self {
        Dual3 { v, d: [0.0; 3] }
    }
    /// The `i`-th seed with value `v` (gradient `e_i`).
    #[inline]
    pub fn seed(v: f64, i: usize) -> Self {
        let mut d = [0.0; 3];
        d[i] = 1.0;
        Dual3 { v, d }
    }
    /// The three seeds of a vector: `x_i` with gradient `e_i`.
    #[inline]
    pub fn seeds(x: [f64; 3]) -> [Self; 3] {
        [
            Self::seed(x[0], 0),
            Self::seed(x[1], 1),
            Self::seed(x[2], 2),
        ]
    }
    #[inline]
    fn chain(self, v: f64, dv: f64) -> Self {
        Dual3 {
            v,
            d: [self.d[0] * dv, self.d[1] * dv, self.d[2] * dv],
        }
    }
    /// Square root (derivative 0 at 0).
    #[inline]
    pub fn sqrt(self) -> Self {
        let s = self.v.sqrt();
        self.chain(s, if s > 0.0 { 0.5 / s } else { 0.0 })
    }
    /// `self^p` for a constant exponent (value and derivative 0 at a zero
    /// base for `p > 0`).
    #[inline]
    pub fn powf(self, p: f64) -> Self {
        if self.v == 0.0 {
            return Dual3::cst(if p == 0.0 { 1.0 } else { 0.0 });
        }
        let v = self.v.powf(p);
        self.chain(v, p * v / self.v)
    }
    /// Exponential.
    #[inline]
    pub fn exp(self) -> Self {
        let e = self.v.exp();
        self.chain(e, e)
    }
    /// Natural logarithm.
    #[inline]
    pub fn ln(self) -> Self {
        self.chain(self.v.ln(), 1.0 / self.v)
    }
    /// The larger of two (by value; ties take `self`).
    #[inline]
    pub fn max(self, o: Self) -> Self {
        if o.v > self.v {
            o
        } else {
            self
        }
    }
    /// The smaller of two (by value; ties take `self`).
    #[inline]
    pub fn min(self, o: Self) -> Self {
        if o.v < self.v {
            o
        } else {
            self
        }
    }
    /// `max(self, 0)` (Macaulay bracket).
    #[inline]
    pub fn pos(self) -> Self {
        if self.v > 0.0 {
            self
        } else {
            Dual3::cst(0.0)
        }
    }
    /// Absolute value (derivative of `+x` at 0).
    #[inline]
    pub fn abs(self) -> Self {
        if self.v < 0.0 {
            -self
        } else {
            self
        }
    }
}

impl From<f64> for Dual3 {
    fn from(v: f64) -> Self {
        Dual3::cst(v)
    }
}

impl Add for Dual3 {
    type Output = Dual3;
    #[inline]
    fn add(self, o: Self) -> Self {
        Dual3 {
            v: self.v + o.v,
            d: [self.d[0] + o.d[0], self.d[1] + o.d[1], self.d[2] + o.d[2]],
        }
    }
}
impl Sub for Dual3 {
    type Output = Dual3;
    #[inline]
    fn sub(self, o: Self) -> Self {
        Dual3 {
            v: self.v - o.v,
            d: [self.d[0] - o.d[0], self.d[1] - o.d[1], self.d[2] - o.d[2]],
        }
    }
}
impl Mul for Dual3 {
    type Output = Dual3;
    #[inline]
    fn mul(self, o: Self) -> Self {
        Dual3 {
            v: self.v * o.v,
            d: [
                self.d[0] * o.v + self.v * o.d[0],
                self.d[1] * o.v + self.v * o.d[1],
                self.d[2] * o.v + self.v * o.d[2],
            ],
        }
    }
}
impl Div for Dual3 {
    type Output = Dual3;
    #[inline]
    fn div(self, o: Self) -> Self {
        let inv = 1.0 / o.v;
        let q = self.v * inv;
        Dual3 {
            v: q,
            d: [
                (self.d[0] - q * o.d[0]) * inv,
                (self.d[1] - q * o.d[1]) * inv,
                (self.d[2] - q * o.d[2]) * inv,
            ],
        }
    }
}
impl Neg for Dual3 {
    type Output = Dual3;
    #[inline]
    fn neg(self) -> Self {
        Dual3 {
            v: -self.v,
            d: [-self.d[0], -self.d[1], -self.d[2]],
        }
    }
}
impl Add<f64> for Dual3 {
    type Output = Dual3;
    #[inline]
    fn add(self, o: f64) -> Self {
        Dual3 {
            v: self.v + o,
            d: self.d,
        }
    }
}
impl Sub<f64> for Dual3 {
    type Output = Dual3;
    #[inline]
    fn sub(self, o: f64) -> Self {
        Dual3 {
            v: self.v - o,
            d: self.d,
        }
    }
}
impl Mul<f64> for Dual3 {
    type Output = Dual3;
    #[inline]
    fn mul(self, o: f64) -> Self {
        Dual3 {
            v: self.v * o,
            d: [self.d[0] * o, self.d[1] * o, self.d[2] * o],
        }
    }
}
impl Div<f64> for Dual3 {
    type Output = Dual3;
    #[inline]
    fn div(self, o: f64) -> Self {
        self * (1.0 / o)
    }
}
impl Add<Dual3> for f64 {
    type Output = Dual3;
    #[inline]
    fn add(self, o: Dual3) -> Dual3 {
        o + self
    }
}
impl Sub<Dual3> for f64 {
    type Output = Dual3;
    #[inline]
    fn sub(self, o: Dual3) -> Dual3 {
        -o + self
    }
}
impl Mul<Dual3> for f64 {
    type Output = Dual3;
    #[inline]
    fn mul(self, o: Dual3) -> Dual3 {
        o * self
    }
}
impl Div<Dual3> for f64 {
    type Output = Dual3;
    #[inline]
    fn div(self, o: Dual3) -> Dual3 {
        Dual3::cst(self) / o
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Derivatives against central differences of the same expression.
    #[test]
    fn chain_rule_matches_finite_differences() {
        let f = |x: [Dual3; 3]| {
            let r = (x[0] * x[0] + x[1] * x[1]).sqrt();
            (r * x[2].exp() / (1.0 + x[1]).powf(2.5)).ln() - x[0].max(x[2]) * 3.0
        };
        let x0 = [0.7, 0.3, -0.2];
        let g = f(Dual3::seeds(x0));
        for i in 0..3 {
            let h = 1e-6;
            let (mut a, mut b) = (x0, x0);
            a[i] += h;
            b[i] -= h;
            let fd = (f(a.map(Dual3::cst)).v - f(b.map(Dual3::cst)).v) / (2.0 * h);
            assert!((fd - g.d[i]).abs() < 1e-8, "d/dx{i}: {fd} vs {}", g.d[i]);
        }
    }

    #[test]
    fn singular_points_give_zero_derivatives_not_nan() {
        let z = Dual3::seed(0.0, 0);
        assert_eq!(z.sqrt().d, [0.0; 3]);
        assert_eq!(z.powf(0.5).d, [0.0; 3]);
        assert_eq!(z.powf(0.0).v, 1.0);
    }
}
