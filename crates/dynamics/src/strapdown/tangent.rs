//! Jacobians of a strapdown model with effects, from the same source as its values: the
//! rates and the measurement of [`super::errors`] evaluated on dual numbers, eight state
//! directions at a time, so that a model of any number of coefficients (up to
//! [`MAX_DIM`] states) needs no allocation and no hand-written derivative per effect.
//!
//! The rate Jacobian the EKF runs ([`rate_jacobian`]) takes the base model's written-out one
//! ([`super::jacobian`]) at the corrected reading and adds the effects' columns through it by
//! the chain rule; [`rate_jacobian_dual`] is the whole matrix on dual numbers, its check. The
//! tests hold both to finite differences.

use super::effect_rates::rates_with_effects;
use super::errors::{
    corrected_reading, corrected_reading_partials, measurement_with, ErrorLayout, MAX_DIM,
};
use super::jacobian::nav_rate_jacobian_analytic;
use super::measurement::MEAS_DIM;
use super::rates::ImuReading;
use super::state::{BASE_DIM, BA_X, BG_X, NAV_DIM};
use crate::dual::Dual;

/// Directions carried per evaluation.
const CHUNK: usize = 8;

/// Writes the Jacobian of `f` (`rows` outputs of the `x.len()` states) at `x` into `jac`,
/// its rows `stride` apart, by evaluating `f` once per [`CHUNK`] columns.
fn jacobian_by_chunks(
    x: &[f64],
    rows: usize,
    jac: &mut [f64],
    stride: usize,
    f: impl Fn(&[Dual<CHUNK>], &mut [Dual<CHUNK>]),
) {
    let n = x.len();
    assert!(n <= MAX_DIM && rows <= MAX_DIM && stride >= n && jac.len() >= rows * stride);
    let mut xd = [Dual::<CHUNK>::constant(0.0); MAX_DIM];
    for (d, v) in xd.iter_mut().zip(x) {
        *d = Dual::constant(*v);
    }
    let mut out = [Dual::<CHUNK>::constant(0.0); MAX_DIM];
    for row in jac[..rows * stride].chunks_mut(stride) {
        row[n..].fill(0.0);
    }
    for first in (0..n).step_by(CHUNK) {
        let last = (first + CHUNK).min(n);
        for (k, d) in xd[first..last].iter_mut().enumerate() {
            d.d[k] = 1.0;
        }
        f(&xd[..n], &mut out[..rows]);
        for (r, o) in out[..rows].iter().enumerate() {
            jac[r * stride + first..r * stride + last].copy_from_slice(&o.d[..last - first]);
        }
        for d in &mut xd[first..last] {
            d.d = [0.0; CHUNK];
        }
    }
}

/// Writes `d(rates)/dx` (`dynamic` rows) of the model with `layout` at `x` under `imu`, all
/// on dual numbers: the check of [`rate_jacobian`].
pub fn rate_jacobian_dual(
    layout: &ErrorLayout,
    dynamic: usize,
    x: &[f64],
    imu: &ImuReading,
    jac: &mut [f64],
    stride: usize,
) {
    jacobian_by_chunks(x, dynamic, jac, stride, |xd, dx| {
        rates_with_effects(layout, xd, imu, dx)
    });
}

/// Writes `d(rates)/dx` (`dynamic` rows, `stride` apart) of the model with `layout` at `x`
/// under `imu`, by the chain rule: the rates depend on the biases and the reading errors'
/// coefficients only through the corrected reading `(w, f)`, so the base model's written-out
/// Jacobian at that reading gives the navigation columns and `d(rates)/d(w, f)` (minus its
/// bias columns), and [`corrected_reading_partials`] the small `d(w, f)/dx`.
/// [`rate_jacobian_dual`] is the same matrix on dual numbers throughout. Inlined, with what it
/// calls, into both copies of [`crate::dispatch!`] (the EKF's tangent of a model with effects).
#[inline(always)]
pub fn rate_jacobian(
    layout: &ErrorLayout,
    dynamic: usize,
    x: &[f64],
    imu: &ImuReading,
    jac: &mut [f64],
    stride: usize,
) {
    let n = x.len();
    assert!(n <= MAX_DIM && stride >= n && jac.len() >= dynamic * stride);
    jac[..dynamic * stride].fill(0.0);
    // The base model at the corrected reading, its biases zero: d(rates)/d(nav) as they are,
    // and d(rates)/d(w, f) as minus its bias columns.
    let (w, f) = corrected_reading(layout, imu, x);
    let mut at_reading = [0.0; BASE_DIM];
    at_reading[..NAV_DIM].copy_from_slice(&x[..NAV_DIM]);
    let mut base = [0.0; NAV_DIM * BASE_DIM];
    nav_rate_jacobian_analytic(&at_reading, &ImuReading { w, f }, &mut base);
    for r in 0..NAV_DIM {
        jac[r * stride..r * stride + NAV_DIM]
            .copy_from_slice(&base[r * BASE_DIM..r * BASE_DIM + NAV_DIM]);
    }
    corrected_reading_partials(
        layout,
        imu,
        x,
        #[inline(always)]
        |col, dw, df| {
            for r in 0..NAV_DIM {
                let b = &base[r * BASE_DIM..(r + 1) * BASE_DIM];
                jac[r * stride + col] -= b[BG_X] * dw[0]
                    + b[BG_X + 1] * dw[1]
                    + b[BG_X + 2] * dw[2]
                    + b[BA_X] * df[0]
                    + b[BA_X + 1] * df[1]
                    + b[BA_X + 2] * df[2];
            }
        },
    );
    if dynamic > NAV_DIM {
        for w in layout.wanders() {
            for i in w.first..w.first + 3 {
                jac[i * stride + i] = -w.decay;
            }
        }
    }
}

/// Writes `d(measurement)/dx` of the model with `layout` at `x`.
pub fn measurement_jacobian(layout: &ErrorLayout, x: &[f64], h: &mut [f64]) {
    jacobian_by_chunks(x, MEAS_DIM, h, x.len(), |xd, z| {
        measurement_with(layout, xd, z)
    });
}
