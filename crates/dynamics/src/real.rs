//! The number types the model's physics is written over: `f64` for one state, [`Lanes`] for
//! eight states at once.
//!
//! The rates of the model (docs/model.md eqs. (5)-(10)) and of every effect are written once,
//! generic over [`Real`]. The truth simulator and the EKF evaluate them on `f64`; the UKFs
//! push their sigma points through them eight at a time as [`Lanes`], whose element-wise
//! arithmetic the compiler turns into SIMD instructions. Because both run the same source,
//! operation for operation, a sigma point propagated in a batch lands where the same point
//! propagated alone lands, up to the `sin`/`cos` of the latitude (see [`crate::kinematics`]).
//!
//! ```
//! use navkf_dynamics::real::{Lanes, Real};
//!
//! /// Written once...
//! fn drag<T: Real>(v: T, kd: T) -> T {
//!     -(kd * v)
//! }
//! // ...evaluated on one number or on eight.
//! assert_eq!(drag(2.0, 0.5), -1.0);
//! let v = Lanes::from_fn(|l| l as f64);
//! assert_eq!(drag(v, Lanes::splat(0.5)).0[6], -3.0);
//! ```

use std::fmt::Debug;
use std::ops::{Add, AddAssign, Div, Mul, MulAssign, Neg, Sub, SubAssign};

/// A number the physics can be evaluated on: a field's arithmetic, element-wise for batches,
/// with constants (`f64`) broadcast by [`Real::splat`] or mixed in directly.
pub trait Real:
    Copy
    + Debug
    + Send
    + Sync
    + 'static
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + Add<f64, Output = Self>
    + Sub<f64, Output = Self>
    + Mul<f64, Output = Self>
    + AddAssign
    + SubAssign
    + MulAssign
{
    /// The constant `v` (in every lane).
    fn splat(v: f64) -> Self;
    /// `[1/a, 1/b, 1/c]`. One number divides three times; a batch divides once and multiplies
    /// (a vector division costs about ten multiplications), which rounds differently in the
    /// last bits.
    fn reciprocals(a: Self, b: Self, c: Self) -> [Self; 3];
    /// `(sin self, cos self)` of any angle ([`crate::trig::sin_cos_angle`]; a batch agrees with
    /// one number bit for bit).
    fn sin_cos(self) -> (Self, Self);
    /// `self * a + b` with one rounding (a fused multiply-add instruction).
    fn mul_add(self, a: Self, b: Self) -> Self;
    /// The square root (correctly rounded, lane by lane).
    fn sqrt(self) -> Self;
}

impl<T: Real> crate::trig::PolynomialArithmetic for T {
    #[inline(always)]
    fn constant(v: f64) -> Self {
        T::splat(v)
    }
    #[inline(always)]
    fn fused_mul_add(self, a: Self, b: Self) -> Self {
        Real::mul_add(self, a, b)
    }
}

impl Real for f64 {
    #[inline(always)]
    fn splat(v: f64) -> Self {
        v
    }
    #[inline(always)]
    fn reciprocals(a: f64, b: f64, c: f64) -> [f64; 3] {
        [1.0 / a, 1.0 / b, 1.0 / c]
    }
    #[inline(always)]
    fn sin_cos(self) -> (f64, f64) {
        crate::trig::sin_cos_angle(self)
    }
    #[inline(always)]
    fn mul_add(self, a: f64, b: f64) -> f64 {
        f64::mul_add(self, a, b)
    }
    #[inline(always)]
    fn sqrt(self) -> f64 {
        f64::sqrt(self)
    }
}

/// Lanes of a batch: how many states [`Lanes`] carries.
pub const LANES: usize = 8;

/// Eight numbers operated on together, element by element. Aligned to a cache line so that a
/// block of them is whole SIMD registers.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
#[repr(C, align(64))]
pub struct Lanes(pub [f64; LANES]);

impl Lanes {
    /// Lanes from a function of the lane index.
    #[inline(always)]
    pub fn from_fn(f: impl FnMut(usize) -> f64) -> Self {
        Lanes(std::array::from_fn(f))
    }
    /// Applies `f` to every lane.
    #[inline(always)]
    pub fn map(self, mut f: impl FnMut(f64) -> f64) -> Self {
        Lanes(self.0.map(&mut f))
    }
}

impl Real for Lanes {
    #[inline(always)]
    fn splat(v: f64) -> Self {
        Lanes([v; LANES])
    }
    #[inline(always)]
    fn reciprocals(a: Lanes, b: Lanes, c: Lanes) -> [Lanes; 3] {
        let bc = b * c;
        let inv = Lanes::splat(1.0) / (a * bc);
        [bc * inv, a * c * inv, a * b * inv]
    }
    #[inline(always)]
    fn sin_cos(self) -> (Lanes, Lanes) {
        let mut s = Lanes::default();
        let mut c = Lanes::default();
        // Small angles (the level errors always, the azimuth error mostly) need no reduction:
        // the same bits in half the operations (`trig::sin_cos_quarter`). One test for the
        // whole batch keeps the loops branch-free.
        let mut small = true;
        for l in 0..LANES {
            small &= self.0[l].abs() <= crate::trig::QUARTER_TURN_FREE;
        }
        if small {
            return crate::trig::sin_cos_quarter(self);
        }
        let mut wild = false;
        // Branch-free per lane, so the loop vectorises; the rare lane beyond the reduction's
        // range (or NaN) is redone by libm after it, as one f64 would be.
        for l in 0..LANES {
            (s.0[l], c.0[l]) = crate::trig::sin_cos_quadrant(self.0[l]);
            wild |= !(self.0[l].abs() <= crate::trig::ANGLE_LIMIT);
        }
        if wild {
            for l in 0..LANES {
                (s.0[l], c.0[l]) = crate::trig::sin_cos_angle(self.0[l]);
            }
        }
        (s, c)
    }
    #[inline(always)]
    fn mul_add(self, a: Lanes, b: Lanes) -> Lanes {
        let mut out = self;
        for l in 0..LANES {
            out.0[l] = self.0[l].mul_add(a.0[l], b.0[l]);
        }
        out
    }
    #[inline(always)]
    fn sqrt(self) -> Lanes {
        let mut out = self;
        for l in 0..LANES {
            out.0[l] = self.0[l].sqrt();
        }
        out
    }
}

// The element-wise operations are plain loops over the lanes: written with
// `std::array::from_fn`, whose closure sits behind a `try` adaptor, the inliner left some of
// them as calls, one per lane, once the exact-attitude kernel grew (it then cost twice as
// much).
macro_rules! lane_op {
    ($trait:ident, $method:ident, $aop:tt, $assign:ident, $assign_method:ident) => {
        impl $trait for Lanes {
            type Output = Lanes;
            #[inline(always)]
            fn $method(mut self, rhs: Lanes) -> Lanes {
                for l in 0..LANES {
                    self.0[l] $aop rhs.0[l];
                }
                self
            }
        }
        impl $trait<f64> for Lanes {
            type Output = Lanes;
            #[inline(always)]
            fn $method(mut self, rhs: f64) -> Lanes {
                for l in 0..LANES {
                    self.0[l] $aop rhs;
                }
                self
            }
        }
        impl $assign for Lanes {
            #[inline(always)]
            fn $assign_method(&mut self, rhs: Lanes) {
                for (a, b) in self.0.iter_mut().zip(rhs.0) {
                    *a $aop b;
                }
            }
        }
    };
}

lane_op!(Add, add, +=, AddAssign, add_assign);
lane_op!(Sub, sub, -=, SubAssign, sub_assign);
lane_op!(Mul, mul, *=, MulAssign, mul_assign);

impl Div for Lanes {
    type Output = Lanes;
    #[inline(always)]
    fn div(mut self, rhs: Lanes) -> Lanes {
        for l in 0..LANES {
            self.0[l] /= rhs.0[l];
        }
        self
    }
}

impl Neg for Lanes {
    type Output = Lanes;
    #[inline(always)]
    fn neg(mut self) -> Lanes {
        for l in 0..LANES {
            self.0[l] = -self.0[l];
        }
        self
    }
}
