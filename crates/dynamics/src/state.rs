//! The 20 states of the base model, in the paper's order (docs/model.md, "The state").
//!
//! Indices are constants so that code reads `x[V_X]`, not `x[3]`. Effects append their
//! coefficients after index 19, in the order the model was assembled.

/// Platform error angle about East, rad.
pub const PHI_X: usize = 0;
/// Platform error angle about North, rad.
pub const PHI_Y: usize = 1;
/// Platform error angle about Up, rad.
pub const PHI_Z: usize = 2;
/// East velocity, m/s.
pub const V_X: usize = 3;
/// North velocity, m/s.
pub const V_Y: usize = 4;
/// Latitude, rad.
pub const LAT: usize = 5;
/// Longitude, rad.
pub const LON: usize = 6;
/// x gyro constant drift, rad/s. `KG0X + 3 * axis` for axis y (1) and z (2).
pub const KG0X: usize = 7;
/// x gyro drift per unit fx.
pub const KG11X: usize = 8;
/// x gyro drift per unit fy.
pub const KG12X: usize = 9;
/// y gyro constant drift.
pub const KG0Y: usize = 10;
/// z gyro constant drift.
pub const KG0Z: usize = 13;
/// x accelerometer bias, m/s^2.
pub const KA0X: usize = 16;
/// x accelerometer scale factor.
pub const KA1X: usize = 17;
/// y accelerometer bias, m/s^2.
pub const KA0Y: usize = 18;
/// y accelerometer scale factor.
pub const KA1Y: usize = 19;

/// Number of navigation states (attitude errors, velocity, position): the only ones with a
/// non-zero derivative in the base model.
pub const NAV_DIM: usize = 7;
/// Number of states of the base model.
pub const BASE_DIM: usize = 20;
/// Number of error coefficients of the base model.
pub const BASE_COEFFICIENTS: usize = BASE_DIM - NAV_DIM;

/// Names of the base states, as in `docs/model.md` and the dataset's `truth.csv`.
pub const BASE_NAMES: [&str; BASE_DIM] = [
    "phi_x", "phi_y", "phi_z", "v_x", "v_y", "L", "lambda", "Kg0x", "Kg11x", "Kg12x", "Kg0y",
    "Kg11y", "Kg12y", "Kg0z", "Kg11z", "Kg12z", "Ka0x", "Ka1x", "Ka0y", "Ka1y",
];

/// Unit of each base state, for reports.
pub const BASE_UNITS: [&str; BASE_DIM] = [
    "rad",
    "rad",
    "rad",
    "m/s",
    "m/s",
    "rad",
    "rad",
    "rad/s",
    "rad/s/(m/s^2)",
    "rad/s/(m/s^2)",
    "rad/s",
    "rad/s/(m/s^2)",
    "rad/s/(m/s^2)",
    "rad/s",
    "rad/s/(m/s^2)",
    "rad/s/(m/s^2)",
    "m/s^2",
    "1",
    "m/s^2",
    "1",
];

/// One line of meaning of each base state, for `navkf effects` and reports (the error model of
/// docs/model.md eqs. (5), (6): `eps_i = Kg0i + Kg11i fx + Kg12i fy`,
/// `nab_x = Ka0x + Ka1x fx`, `nab_y = Ka0y + Ka1y fy`).
pub const BASE_MEANINGS: [&str; BASE_DIM] = [
    "platform error angle about East",
    "platform error angle about North",
    "platform error angle about Up (heading error)",
    "East velocity",
    "North velocity",
    "latitude",
    "longitude",
    "x (East) gyro: constant drift",
    "x gyro: drift per unit fx",
    "x gyro: drift per unit fy",
    "y (North) gyro: constant drift",
    "y gyro: drift per unit fx",
    "y gyro: drift per unit fy",
    "z (Up) gyro: constant drift",
    "z gyro: drift per unit fx",
    "z gyro: drift per unit fy",
    "x accelerometer: bias",
    "x accelerometer: scale factor on fx",
    "y accelerometer: bias",
    "y accelerometer: scale factor on fy",
];

/// Measurement channels, in the order of `Z = [v_x, v_y, L, lambda]` (docs/model.md eq. (13)).
pub const MEASUREMENT_NAMES: [&str; 4] = ["v_x", "v_y", "L", "lambda"];
/// Size of the full measurement vector.
pub const MEAS_DIM: usize = 4;
