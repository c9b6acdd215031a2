//! `sin` and `cos` of a latitude, inline.
//!
//! Every derivative of the model starts with `sin L` and `cos L`, and in the EKF they sit on
//! the chain of dependent operations from one RK4 stage to the next: libm's `sincos` is a
//! call (with its register spills) whose latency the EKF's step pays 40 times. For the
//! arguments a latitude takes (`|x| <= 2` here, so every latitude with room to spare) this
//! computes both in registers to within about one unit in the last place, and hands
//! anything else (larger angles, NaN) to libm.
//!
//! Both Taylor series, through `r^17` and `r^18`, are evaluated in Estrin's scheme (a tree of
//! independent products rather than one long chain); for `|r| <= 1` the first omitted terms
//! are below 1e-17, a tenth of an ulp. Angles up to 1 rad (57 deg of latitude) go straight
//! in; larger ones are first reduced by pi/2 towards zero, in two parts so that the
//! subtraction is exact, to `|r| < 0.58`.
//!
//! ```
//! let (s, c) = navkf_dynamics::trig::sin_cos(0.7);
//! assert!((s - 0.7f64.sin()).abs() < 2e-16 && (c - 0.7f64.cos()).abs() < 2e-16);
//! ```

/// Largest `|x|` computed here; beyond it libm answers.
pub const INLINE_LIMIT: f64 = 2.0;

/// `(sin x, cos x)`; see the module documentation.
#[inline(always)]
pub fn sin_cos(x: f64) -> (f64, f64) {
    // Latitudes up to 57 deg need no reduction (the series' accuracy holds for |x| <= 1).
    if x.abs() <= 1.0 {
        return sin_cos_reduced(x);
    }
    // `!(a <= b)` also sends NaN to libm.
    if !(x.abs() <= INLINE_LIMIT) {
        return x.sin_cos();
    }
    // 1 < |x| <= 2: x = k pi/2 + r with k = sign(x), |r| < 0.58. pi/2 = PIO2_HI + PIO2_LO,
    // PIO2_HI the double nearest to it; x is within a factor of two of PIO2_HI, so
    // x - k PIO2_HI is exact.
    const PIO2_HI: f64 = std::f64::consts::FRAC_PI_2;
    const PIO2_LO: f64 = 6.123_233_995_736_766e-17;
    let k = x.signum();
    let r = (x - k * PIO2_HI) - k * PIO2_LO;
    let (s, c) = sin_cos_reduced(r);
    // sin(k pi/2 + r) = k cos r, cos(k pi/2 + r) = -k sin r.
    (k * c, -k * s)
}

/// `1/n!` for n = 0..18: the Taylor coefficients of both series.
const RECIPROCAL_FACTORIALS: [f64; 19] = {
    let mut f = [1.0; 19];
    let mut n = 1;
    while n < 19 {
        f[n] = f[n - 1] / n as f64;
        n += 1;
    }
    f
};

/// Largest `|x|` [`sin_cos_angle`] reduces itself; beyond it libm answers.
pub const ANGLE_LIMIT: f64 = 1.0e5;

/// `(sin x, cos x)` of any angle, computed here for `|x| <= ANGLE_LIMIT` (libm beyond, and
/// for NaN): the attitude angles of the exact-attitude model, which may be anything. The
/// angle is reduced by the nearest multiple `k` of pi/2 (Cody-Waite, pi/2 in two parts whose
/// first has 33 significant bits, so `k PIO2_1` is exact for `|k| < 2^20`) to `|r| <= pi/4`,
/// where Taylor series through `r^15` and `r^16` (first omitted terms below 5e-17) in Horner
/// form with fused multiply-adds give both; the quadrant picks the signs by selects. So eight
/// lanes of it vectorise ([`crate::Real::sin_cos`] on [`crate::Lanes`] runs this per lane,
/// and bit for bit agrees with one `f64`), at about half the operations of the latitude's
/// [`sin_cos`] (whose unfused Estrin form the base model's results are pinned to). Angles
/// within `QUARTER_TURN_FREE` (0.78 rad) skip the reduction, which would leave them as they
/// are: the same bits for half the work (a batch does so when all its lanes are).
///
/// ```
/// use navkf_dynamics::trig::sin_cos_angle;
/// for x in [-3.0, -0.3, 0.0, 0.9, 2.0, 40.0] {
///     let (s, c) = sin_cos_angle(x);
///     assert!((s - x.sin()).abs() < 4e-16 && (c - x.cos()).abs() < 4e-16, "{x}");
/// }
/// ```
#[inline(always)]
pub fn sin_cos_angle(x: f64) -> (f64, f64) {
    if x.abs() <= QUARTER_TURN_FREE {
        return sin_cos_quarter(x);
    }
    if !(x.abs() <= ANGLE_LIMIT) {
        return x.sin_cos();
    }
    sin_cos_quadrant(x)
}

/// Largest `|x|` that [`sin_cos_quadrant`] reduces to itself (`k = 0`, `r = x`), with room
/// below pi/4 so that `x 2/pi` rounds to zero however the product rounds.
pub(crate) const QUARTER_TURN_FREE: f64 = 0.78;

/// [`sin_cos_angle`] without the libm fallback: valid for `|x| <= ANGLE_LIMIT` only.
#[inline(always)]
pub(crate) fn sin_cos_quadrant(x: f64) -> (f64, f64) {
    // fdlibm's split of pi/2: the first 33 bits, and the rest.
    const PIO2_1: f64 = 1.570_796_326_734_125_6;
    const PIO2_1T: f64 = 6.077_100_506_506_192e-11;
    let k = (x * std::f64::consts::FRAC_2_PI).round_ties_even();
    let r = (-k).mul_add(PIO2_1T, (-k).mul_add(PIO2_1, x));
    let (s, c) = sin_cos_quarter(r);
    // The quadrant k mod 4, in floating point (exact: k is an integer below 2^20).
    let m = (-4.0f64).mul_add((k * 0.25).floor(), k);
    let odd = (m == 1.0) | (m == 3.0);
    // sin(r + pi/2) = cos r, cos(r + pi/2) = -sin r; two quarter turns negate both.
    let (s1, c1) = if odd { (c, -s) } else { (s, c) };
    if m >= 2.0 {
        (-s1, -c1)
    } else {
        (s1, c1)
    }
}

/// What the polynomial kernel [`sin_cos_quarter`] needs of its numbers: products and fused
/// multiply-adds, with constants broadcast. Every [`crate::Real`] has them (implemented
/// there), so one number and a batch run the same kernel.
pub trait PolynomialArithmetic: Copy + std::ops::Mul<Output = Self> {
    /// The constant `v` (in every lane).
    fn constant(v: f64) -> Self;
    /// `self * a + b` with one rounding.
    fn fused_mul_add(self, a: Self, b: Self) -> Self;
}

/// `(sin r, cos r)` for `|r| <= pi/4`: the polynomials of [`sin_cos_quadrant`] after its
/// reduction. For `|x| <= QUARTER_TURN_FREE` the reduction is the identity (`k = 0`, so
/// `r = x` exactly and the quadrant selects keep both), and this alone gives the same bits,
/// in about half the operations: what a batch of small attitude angles takes.
///
/// Generic so that a batch runs it as whole-vector operations (lane by lane, LLVM packed it
/// two lanes to a register).
#[inline(always)]
pub(crate) fn sin_cos_quarter<T: PolynomialArithmetic>(r: T) -> (T, T) {
    const F: [f64; 19] = RECIPROCAL_FACTORIALS;
    let c = T::constant;
    let r2 = r * r;
    // sin r = r + r^3 (-1/3! + r^2 (1/5! - ... - r^12/15!))
    let mut sp = c(-F[15]);
    for n in [13, 11, 9, 7, 5] {
        let sign = if n % 4 == 1 { 1.0 } else { -1.0 };
        sp = sp.fused_mul_add(r2, c(sign * F[n]));
    }
    let sp = sp.fused_mul_add(r2, c(-F[3]));
    let sin = (r * r2).fused_mul_add(sp, r);
    // cos r = 1 - r^2/2 + r^4 (1/4! - r^2 (1/6! - ... + r^12/16!))
    let mut cq = c(F[16]);
    for n in [14, 12, 10, 8, 6] {
        let sign = if n % 4 == 0 { 1.0 } else { -1.0 };
        cq = cq.fused_mul_add(r2, c(sign * F[n]));
    }
    let cq = cq.fused_mul_add(r2, c(F[4]));
    let cos = (r2 * r2).fused_mul_add(cq, c(-0.5).fused_mul_add(r2, c(1.0)));
    (sin, cos)
}

/// Taylor series of sin and cos for `|r| <= 1`, in Estrin's scheme.
#[inline(always)]
fn sin_cos_reduced(r: f64) -> (f64, f64) {
    const F: [f64; 19] = RECIPROCAL_FACTORIALS;
    let r2 = r * r;
    let r4 = r2 * r2;
    let r8 = r4 * r4;
    // sin r = r + r^3 (-1/3! + r^2/5! - r^4/7! + ... + r^14/17!)
    let s01 = -F[3] + r2 * F[5];
    let s23 = -F[7] + r2 * F[9];
    let s45 = -F[11] + r2 * F[13];
    let s67 = -F[15] + r2 * F[17];
    let sp = (s01 + r4 * s23) + r8 * (s45 + r4 * s67);
    // (At r = -0 the sum would give +0; libm keeps the sign, and so does the select.)
    let sin = if r == 0.0 { r } else { r + (r * r2) * sp };
    // cos r = (1 - r^2/2) + r^4 (1/4! - r^2/6! + ... + r^14/18!), with the rounding error
    // of 1 - r^2/2 carried into the tail (as fdlibm does): near r = 1 the sum cancels to
    // half its leading term, and a plain `1 + r^2 (...)` loses two or three ulp there.
    let c01 = F[4] - r2 * F[6];
    let c23 = F[8] - r2 * F[10];
    let c45 = F[12] - r2 * F[14];
    let c67 = F[16] - r2 * F[18];
    let cq = (c01 + r4 * c23) + r8 * (c45 + r4 * c67);
    let hz = 0.5 * r2;
    let w = 1.0 - hz;
    let cos = w + (((1.0 - w) - hz) + r4 * cq);
    (sin, cos)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Error of `got` against libm's `want`, in units of `EPSILON * |want|` (one of them is an
    /// ulp or half an ulp); absolute, in units of `EPSILON`, near the zeros of sin and cos.
    fn error(got: f64, want: f64) -> f64 {
        (got - want).abs() / (f64::EPSILON * want.abs().max(1e-3))
    }

    #[test]
    fn agrees_with_libm_to_one_ulp_over_every_latitude() {
        let (mut worst_sin, mut worst_cos) = ((0.0, 0.0), (0.0, 0.0));
        let steps = 400_000;
        for i in 0..=steps {
            let x = -INLINE_LIMIT + 2.0 * INLINE_LIMIT * i as f64 / steps as f64;
            let (s, c) = sin_cos(x);
            let (s0, c0) = x.sin_cos();
            let (es, ec) = (error(s, s0), error(c, c0));
            if es > worst_sin.0 {
                worst_sin = (es, x);
            }
            if ec > worst_cos.0 {
                worst_cos = (ec, x);
            }
        }
        // Both reach 1 where they differ from libm by one bit just above a power of two.
        assert!(worst_sin.0 <= 1.0, "sin: {worst_sin:?}");
        assert!(worst_cos.0 <= 1.0, "cos: {worst_cos:?}");
    }

    #[test]
    fn any_angle_agrees_with_libm() {
        let mut worst: f64 = 0.0;
        let steps = 200_000;
        for i in 0..=steps {
            // -20 .. 20 rad: every quadrant several times over, both signs.
            let x = -20.0 + 40.0 * i as f64 / steps as f64;
            let (s, c) = sin_cos_angle(x);
            let (s0, c0) = x.sin_cos();
            // Absolute error: near the zeros of sin and cos the reduction's rounding shows.
            worst = worst.max((s - s0).abs()).max((c - c0).abs());
        }
        assert!(worst <= 2.0 * f64::EPSILON, "worst {worst:e}");
        // Multiples of pi/2 land on the right quadrant, and large or odd inputs go to libm.
        for k in -8..=8 {
            let x = k as f64 * std::f64::consts::FRAC_PI_2;
            let (s, c) = sin_cos_angle(x);
            let (s0, c0) = x.sin_cos();
            assert!((s - s0).abs() < 1e-15 && (c - c0).abs() < 1e-15, "{k}");
        }
        for x in [2.0e5, -3.0e7] {
            assert_eq!(sin_cos_angle(x), x.sin_cos());
        }
        let (s, c) = sin_cos_angle(f64::NAN);
        assert!(s.is_nan() && c.is_nan());
    }

    #[test]
    fn small_angles_skip_the_reduction_with_the_same_bits() {
        let bits = |(s, c): (f64, f64)| (s.to_bits(), c.to_bits());
        let mut xs: Vec<f64> = (0..=100_000)
            .map(|i| QUARTER_TURN_FREE * (i as f64 / 50_000.0 - 1.0))
            .collect();
        xs.extend([0.0, -0.0, 1e-300, -1e-300, 5e-324, QUARTER_TURN_FREE]);
        xs.push(-QUARTER_TURN_FREE);
        for x in xs {
            assert_eq!(bits(sin_cos_quarter(x)), bits(sin_cos_quadrant(x)), "{x:e}");
        }
        // Where the reduction works (k = 1), the two differ.
        assert_ne!(bits(sin_cos_quarter(1.2)), bits(sin_cos_quadrant(1.2)));
    }

    #[test]
    fn a_batch_gives_each_lane_the_bits_of_one_number() {
        use crate::real::{Lanes, Real, LANES};
        let small = [0.0, -0.0, 1e-4, -2e-4, 0.3, -0.7, 0.78, 1e-300];
        let mixed = [0.1, 2.0, -5.0, 0.78, 0.79, -40.0, 1e-9, 3.2];
        let wild = [0.1, f64::NAN, 2.0e5, -0.5, f64::INFINITY, 1.0, -1.0, 7.0];
        for lanes in [small, mixed, wild] {
            let (s, c) = Lanes(lanes).sin_cos();
            for l in 0..LANES {
                let (s1, c1) = sin_cos_angle(lanes[l]);
                assert_eq!(s.0[l].to_bits(), s1.to_bits(), "sin {}", lanes[l]);
                assert_eq!(c.0[l].to_bits(), c1.to_bits(), "cos {}", lanes[l]);
            }
        }
    }

    #[test]
    fn is_exact_where_it_must_be_and_hands_the_rest_to_libm() {
        assert_eq!(sin_cos(0.0), (0.0, 1.0));
        let tiny = 1e-200;
        assert_eq!(sin_cos(tiny), (tiny, 1.0));
        assert_eq!(sin_cos(-0.0).0.to_bits(), (-0.0f64).to_bits());
        for x in [2.5, -3.0, 1e6] {
            assert_eq!(sin_cos(x), x.sin_cos(), "{x}");
        }
        for x in [f64::NAN, f64::INFINITY] {
            let (s, c) = sin_cos(x);
            assert!(s.is_nan() && c.is_nan(), "{x}");
        }
        // Either side of the switch to the reduced path (|x| = 1), and at +-pi/2.
        let above_one = 1.0f64.next_up();
        for x in [
            1.0,
            above_one,
            -1.0,
            -above_one,
            std::f64::consts::FRAC_PI_2,
            -std::f64::consts::FRAC_PI_2,
        ] {
            let (s, c) = sin_cos(x);
            let (s0, c0) = x.sin_cos();
            assert!((s - s0).abs() <= 2.0 * f64::EPSILON, "{x}: {s} vs {s0}");
            assert!((c - c0).abs() <= 2.0 * f64::EPSILON, "{x}: {c} vs {c0}");
        }
    }
}
