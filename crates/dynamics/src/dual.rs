//! Dual numbers: a value with its derivatives along `N` directions, carried through every
//! operation (forward-mode automatic differentiation). They implement [`Real`], so physics
//! written once over [`Real`] gives its exact Jacobian on them: the strapdown family's
//! measurement Jacobian, and the check of its written-out rate Jacobian; see docs/model.md,
//! "The strapdown family".
//!
//! ```
//! use navkf_dynamics::dual::Dual;
//! use navkf_dynamics::real::Real;
//!
//! // d/dx (x sin x) at x = 2 is sin 2 + 2 cos 2.
//! let x = Dual::<1>::variable(2.0, 0);
//! let (s, _) = x.sin_cos();
//! let y = x * s;
//! assert!((y.d[0] - (2f64.sin() + 2.0 * 2f64.cos())).abs() < 1e-15);
//! ```
//!
//! The value part runs the same operations as `f64` (the same [`crate::trig::sin_cos_angle`],
//! the same fused multiply-add), so it equals the `f64` evaluation bit for bit.

use crate::real::Real;
use std::ops::{Add, AddAssign, Div, Mul, MulAssign, Neg, Sub, SubAssign};

/// A value `v` and its derivatives `d` along `N` directions.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Dual<const N: usize> {
    /// The value.
    pub v: f64,
    /// Its derivatives.
    pub d: [f64; N],
}

impl<const N: usize> Dual<N> {
    /// A constant: no derivative.
    pub fn constant(v: f64) -> Self {
        Dual { v, d: [0.0; N] }
    }
    /// The variable of direction `i`: derivative 1 there, 0 elsewhere.
    pub fn variable(v: f64, i: usize) -> Self {
        let mut d = [0.0; N];
        d[i] = 1.0;
        Dual { v, d }
    }
    fn map(self, v: f64, slope: f64) -> Self {
        Dual {
            v,
            d: self.d.map(|d| slope * d),
        }
    }
}

impl<const N: usize> Add for Dual<N> {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        Dual {
            v: self.v + o.v,
            d: std::array::from_fn(|i| self.d[i] + o.d[i]),
        }
    }
}

impl<const N: usize> Sub for Dual<N> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        Dual {
            v: self.v - o.v,
            d: std::array::from_fn(|i| self.d[i] - o.d[i]),
        }
    }
}

impl<const N: usize> Mul for Dual<N> {
    type Output = Self;
    // The product rule adds.
    #[allow(clippy::suspicious_arithmetic_impl)]
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        Dual {
            v: self.v * o.v,
            d: std::array::from_fn(|i| self.d[i] * o.v + self.v * o.d[i]),
        }
    }
}

impl<const N: usize> Div for Dual<N> {
    type Output = Self;
    // The quotient rule subtracts and multiplies.
    #[allow(clippy::suspicious_arithmetic_impl)]
    #[inline(always)]
    fn div(self, o: Self) -> Self {
        let inv = 1.0 / o.v;
        let v = self.v / o.v;
        Dual {
            v,
            d: std::array::from_fn(|i| (self.d[i] - v * o.d[i]) * inv),
        }
    }
}

impl<const N: usize> Neg for Dual<N> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        Dual {
            v: -self.v,
            d: self.d.map(|d| -d),
        }
    }
}

impl<const N: usize> Add<f64> for Dual<N> {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: f64) -> Self {
        Dual {
            v: self.v + o,
            d: self.d,
        }
    }
}

impl<const N: usize> Sub<f64> for Dual<N> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: f64) -> Self {
        Dual {
            v: self.v - o,
            d: self.d,
        }
    }
}

impl<const N: usize> Mul<f64> for Dual<N> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, o: f64) -> Self {
        self.map(self.v * o, o)
    }
}

impl<const N: usize> AddAssign for Dual<N> {
    #[inline(always)]
    fn add_assign(&mut self, o: Self) {
        *self = *self + o;
    }
}

impl<const N: usize> SubAssign for Dual<N> {
    #[inline(always)]
    fn sub_assign(&mut self, o: Self) {
        *self = *self - o;
    }
}

impl<const N: usize> MulAssign for Dual<N> {
    #[inline(always)]
    fn mul_assign(&mut self, o: Self) {
        *self = *self * o;
    }
}

impl<const N: usize> Real for Dual<N> {
    #[inline(always)]
    fn splat(v: f64) -> Self {
        Dual::constant(v)
    }
    #[inline(always)]
    fn reciprocals(a: Self, b: Self, c: Self) -> [Self; 3] {
        [a, b, c].map(|x| {
            let r = 1.0 / x.v;
            x.map(r, -r * r)
        })
    }
    #[inline(always)]
    fn sin_cos(self) -> (Self, Self) {
        let (s, c) = crate::trig::sin_cos_angle(self.v);
        (self.map(s, c), self.map(c, -s))
    }
    #[inline(always)]
    fn mul_add(self, a: Self, b: Self) -> Self {
        Dual {
            v: self.v.mul_add(a.v, b.v),
            d: std::array::from_fn(|i| self.d[i] * a.v + self.v * a.d[i] + b.d[i]),
        }
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        let r = self.v.sqrt();
        // d sqrt(x) = dx / (2 sqrt x); at 0 the slope is infinite, as it is.
        self.map(r, 0.5 / r)
    }
}
