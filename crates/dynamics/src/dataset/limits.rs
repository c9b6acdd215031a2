//! The bounds of the implausibility checks. Their reasons are given with the checks that
//! use them ([`super::implausible`]); the words that report a breach ([`super::implausibility`])
//! quote them.

use crate::earth::meridian_radius;
use crate::sensor_classes::ROAD_SPEED_MAX;

/// The odometer's speed is multiplied by this before it bounds a GPS jump.
pub const SPEED_MARGIN: f64 = 2.0;
/// A GPS jump must exceed this many times the GPS's own fix-to-fix scatter.
pub const SCATTER_SIGMAS: f64 = 10.0;
/// The least a GPS jump must exceed, m: multipath in a street canyon reaches tens of metres.
pub const GNSS_FLOOR_M: f64 = 100.0;
/// A specific force below this fraction of gravity is a fall.
pub const FALL_FRACTION: f64 = 0.5;
/// A specific force above this many g is no road vehicle's.
pub const OVERLOAD_G: f64 = 3.0;
/// A fall or an overload must last this long, s.
pub const SUSTAINED_S: f64 = 3.0;
/// The nearest a fix may lie to a pole, m (module documentation).
pub const POLE_DISTANCE_M: f64 = 100.0 * ROAD_SPEED_MAX * 1.0;
/// The largest |latitude| (degrees) the model takes: [`POLE_DISTANCE_M`] from the pole.
pub fn latitude_limit_deg() -> f64 {
    90.0 - (POLE_DISTANCE_M / meridian_radius(1.0)).to_degrees()
}
