//! Jacobians of a strapdown model with effects, from the same source as its values: the
//! rates and the measurement of [`super::errors`] evaluated on dual numbers, eight state
//! directions at a time, so that a model of any number of coefficients (up to
//! [`MAX_DIM`] states) needs no allocation and no hand-written derivative per effect.
//!
//! The base model keeps its written-out rate Jacobian ([`super::jacobian`]), which is the
//! speed of the EKF's step; these serve the models with effects, whose extra columns no
//! hand-written code covers. The tests hold both to finite differences.

use super::errors::{measurement_with, ErrorLayout, MAX_DIM};
use super::model::MEAS_DIM;
use super::rates::{rates_with_effects, ImuReading};
use super::state::BASE_DIM;
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
    assert!(n <= MAX_DIM && rows <= BASE_DIM && stride >= n && jac.len() >= rows * stride);
    let mut xd = [Dual::<CHUNK>::constant(0.0); MAX_DIM];
    for (d, v) in xd.iter_mut().zip(x) {
        *d = Dual::constant(*v);
    }
    let mut out = [Dual::<CHUNK>::constant(0.0); BASE_DIM];
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

/// Writes `d(rates)/dx` (`dynamic` rows) of the model with `layout` at `x` under `imu`.
pub fn rate_jacobian(
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

/// Writes `d(measurement)/dx` of the model with `layout` at `x`.
pub fn measurement_jacobian(layout: &ErrorLayout, x: &[f64], h: &mut [f64]) {
    jacobian_by_chunks(x, MEAS_DIM, h, x.len(), |xd, z| {
        measurement_with(layout, xd, z)
    });
}
