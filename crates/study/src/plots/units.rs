//! Display units of the figures: coefficients in the units engineers quote (deg/h, ug,
//! ppm), not the model's SI.

use crate::monte_carlo::Study;

const G: f64 = 9.80665;

const RAD_S_TO_DEG_H: f64 = 180.0 / std::f64::consts::PI * 3600.0;

/// The factor and unit a state is shown in: deg/h for drifts, deg/h/g for g-sensitive drifts,
/// micro-g for accelerometer biases, ppm for scale factors; other units as they are.
pub fn display_unit(unit: &str) -> (f64, String) {
    match unit {
        "rad/s" => (RAD_S_TO_DEG_H, "deg/h".into()),
        "rad/s/(m/s^2)" => (RAD_S_TO_DEG_H * G, "deg/h/g".into()),
        "m/s^2" => (1e6 / G, "µg".into()),
        "1" => (1e6, "ppm".into()),
        "rad" => (RAD_S_TO_DEG_H, "arcsec".into()),
        "" => (1.0, "-".into()),
        u => (1.0, u.into()),
    }
}

pub(super) fn unit_of(study: &Study, i: usize) -> (f64, String) {
    display_unit(
        study
            .filter_model
            .state_units()
            .get(i)
            .map_or("", String::as_str),
    )
}
