//! Display units of the figures: coefficients in the units engineers quote (deg/h, ug,
//! ppm), not the model's SI.

use crate::monte_carlo::Study;
use navkf_dynamics::ModelKind;

const G: f64 = navkf_dynamics::earth::STANDARD_GRAVITY;

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

/// Settings whose key does not say their unit ([`crate::sweep::axis`] reads it from the key's
/// suffix), or says only part of it (a turn rate's `_deg` is deg/s): the unit a swept axis
/// shows them in.
const UNSAID_UNITS: [(&str, &str); 9] = [
    ("to", "m/s"),
    ("cruise_speed", "m/s"),
    ("turn_speed", "m/s"),
    ("odometer_floor", "m/s"),
    ("velocity_sigma", "m/s"),
    ("accel", "m/s^2"),
    ("peak_accel", "m/s^2"),
    ("rate_deg", "deg/s"),
    ("peak_turn_rate_deg", "deg/s"),
];

/// The swept `key` as a figure's x axis: [`crate::sweep::axis`] (its path in words, in the
/// unit engineers quote, and the factor to it), with the unit of the settings whose key does
/// not say it: a segment's `to` is a speed, "trajectory: segment 2: to (m/s)". A strapdown
/// unit's `azimuth` prior is its heading's, and is called so.
pub(super) fn swept_axis(key: &str, model: ModelKind) -> (String, f64) {
    let (words, factor) = crate::sweep::axis(key);
    let leaf = key.rsplit('.').next().unwrap_or(key);
    let (words, factor) = match UNSAID_UNITS.iter().find(|(name, _)| *name == leaf) {
        Some((_, unit)) => {
            let bare = words.strip_suffix(" (deg)").unwrap_or(&words);
            (format!("{bare} ({unit})"), factor)
        }
        None => (words, factor),
    };
    let heading = navkf_dynamics::dataset::files_of(model).heading_word();
    (words.replace("azimuth", heading), factor)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_strapdown_sweep_of_the_azimuth_prior_is_called_the_heading() {
        let key = "truth.initial_tilt.azimuth_rad";
        let (platform, factor) = swept_axis(key, ModelKind::Platform);
        assert_eq!(platform, "truth: initial tilt: azimuth (deg)");
        let (strapdown, same) = swept_axis(key, ModelKind::Strapdown);
        assert_eq!(strapdown, "truth: initial tilt: heading (deg)");
        assert_eq!(factor, same);
        let speed = swept_axis("trajectory.segment[1].to", ModelKind::Strapdown).0;
        assert_eq!(speed, "trajectory: segment 2: to (m/s)");
    }
}
