//! The strapdown family's 13 states (docs/model.md, "The strapdown family"): attitude,
//! horizontal velocity and position, then the gyro and accelerometer biases in body axes.

/// Roll `phi`, rad (right side down positive).
pub const ROLL: usize = 0;
/// Pitch `theta`, rad (nose up positive).
pub const PITCH: usize = 1;
/// Heading `psi`, rad (from North, clockwise towards East).
pub const HEADING: usize = 2;
/// East velocity, m/s.
pub const V_E: usize = 3;
/// North velocity, m/s.
pub const V_N: usize = 4;
/// Latitude, rad.
pub const LAT: usize = 5;
/// Longitude, rad.
pub const LON: usize = 6;
/// Gyro bias about body x (forward), rad/s; `+1`, `+2` about y (left) and z (up).
pub const BG_X: usize = 7;
/// Accelerometer bias along body x, m/s^2; `+1`, `+2` along y and z.
pub const BA_X: usize = 10;
/// States with a derivative: attitude, velocity and position.
pub const NAV_DIM: usize = 7;
/// States of the base model (no effects).
pub const BASE_DIM: usize = 13;

/// The states' names, as files and reports write them.
pub const STATE_NAMES: [&str; BASE_DIM] = [
    "roll", "pitch", "heading", "v_e", "v_n", "L", "lambda", "bgx", "bgy", "bgz", "bax", "bay",
    "baz",
];

/// The states' units.
pub const STATE_UNITS: [&str; BASE_DIM] = [
    "rad", "rad", "rad", "m/s", "m/s", "rad", "rad", "rad/s", "rad/s", "rad/s", "m/s^2", "m/s^2",
    "m/s^2",
];

/// The gyro biases' departures from their turn-on values when they wander, x, y, z
/// (docs/model.md eq. (69)); they follow the base states, before the effects' coefficients.
pub const GYRO_DEPARTURE_NAMES: [&str; 3] = ["dbgx", "dbgy", "dbgz"];

/// The accelerometer biases' departures.
pub const ACCEL_DEPARTURE_NAMES: [&str; 3] = ["dbax", "dbay", "dbaz"];
