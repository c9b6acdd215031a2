//! The rates of a strapdown model with effects: the base model's state equations under the
//! readings its effects' coefficients correct, and, when a triad's biases wander, the decay
//! of their departures from the constant turn-on biases; docs/model.md eqs. (51)-(58),
//! (63)-(69).

use super::attitude::angle_trig;
use super::errors::{corrected_reading, ErrorLayout};
use super::rates::{nav_rates_corrected, ImuReading};
use super::state::*;
use crate::real::Real;

/// The derivatives of the dynamic states of a model with effects: the navigation states under
/// the readings corrected by the biases and the effects' coefficients, then, when a triad's
/// biases wander, zero for the turn-on biases and `-d / T` for the departures (`dx` holds
/// [`NAV_DIM`] values, or [`ErrorLayout::dynamic_dim`] then); docs/model.md eqs. (51)-(58),
/// (63)-(69).
#[inline(always)]
pub fn rates_with_effects<T: Real>(layout: &ErrorLayout, x: &[T], imu: &ImuReading, dx: &mut [T]) {
    let trig = angle_trig([x[ROLL], x[PITCH], x[HEADING]]);
    rates_with_effects_at(layout, x, imu, &trig, x[LAT].sin_cos(), dx)
}

/// [`rates_with_effects`] with the sines and cosines of the angles ([`angle_trig`]) and of
/// the latitude already evaluated (a batch takes them from series about reference values).
#[inline(always)]
pub fn rates_with_effects_at<T: Real>(
    layout: &ErrorLayout,
    x: &[T],
    imu: &ImuReading,
    trig: &[(T, T); 3],
    lat_trig: (T, T),
    dx: &mut [T],
) {
    let (w, f) = corrected_reading(layout, imu, x);
    nav_rates_corrected(x, w, f, trig, lat_trig, dx);
    if layout.biases_wander() {
        for d in &mut dx[BG_X..BASE_DIM] {
            *d = T::splat(0.0);
        }
        for w in layout.wanders() {
            for i in w.first..w.first + 3 {
                dx[i] = -(x[i] * w.decay);
            }
        }
    }
}
