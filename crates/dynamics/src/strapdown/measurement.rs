//! The strapdown measurement without effects (docs/model.md eqs. (59)-(61)): its rows and
//! the function, written once over [`Real`] for the filters, the simulator and the dual
//! numbers of the Jacobians.

use super::attitude::{body_to_nav, rotate_back};
use super::state::*;
use crate::real::Real;

/// Rows of the measurement: odometer speed, GPS latitude and longitude, the two
/// non-holonomic pseudo-measurements (lateral and vertical body velocity, zero) and the
/// zero-velocity update's two (East and North velocity, zero at a standstill).
pub const MEASUREMENT_NAMES: [&str; 7] = [
    "speed",
    "L",
    "lambda",
    "nhc_lateral",
    "nhc_vertical",
    "zupt_east",
    "zupt_north",
];
/// Measurement dimension.
pub const MEAS_DIM: usize = 7;

/// The measurement, docs/model.md eqs. (59)-(61): the body-frame velocity's forward
/// component (the odometer), the position (the GPS), the lateral and vertical components
/// (zero for a wheeled vehicle), and the navigation-frame velocity (zero at a standstill).
#[inline(always)]
pub fn measurement<T: Real>(x: &[T], z: &mut [T]) {
    let cbn = body_to_nav([x[ROLL], x[PITCH], x[HEADING]]);
    let v_b = rotate_back(&cbn, [x[V_E], x[V_N], T::splat(0.0)]);
    z[0] = v_b[0];
    z[1] = x[LAT];
    z[2] = x[LON];
    z[3] = v_b[1];
    z[4] = v_b[2];
    z[5] = x[V_E];
    z[6] = x[V_N];
}
