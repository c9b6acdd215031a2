//! Plausibility of a strapdown unit's readings (`imu.csv`): values that parse, yet look
//! written in the wrong unit, axes or form. Each check compares the readings with what a
//! unit on a road vehicle must feel, whatever the vehicle does:
//!
//! - **specific force not in m/s^2**: its median magnitude against gravity (in g it is near
//!   1, in mg near 1000);
//! - **increments read as rates**: that median is gravity times the sample interval (a
//!   velocity increment over `dt` written under the rates' header: 0.098 at 100 Hz); at
//!   about 10 Hz that is also about 1 g, and the warning says both;
//! - **upside down**: the median force along the unit's up axis is near `-g`, not `+g`
//!   (mounted upside down, or forward-right-down axes written as forward-left-up);
//! - **rates in deg/s**: the 99th percentile of the rate's magnitude beyond 3 rad/s (172
//!   deg/s); a road vehicle turns, pitches and rolls below 1 rad/s;
//! - **times in milliseconds**: a median sample interval beyond 1.5 s;
//! - **odometer speed in km/h or mph** (`measurements.csv`): the speed integrated over spans
//!   of 10 s or more between GPS fixes, against the fixes' chords: 3.6 or 2.24 times as far.

use super::plausibility::{
    median, median_interval, speed_unit_doubt, GRAVITY_TOLERANCE, SLOWEST_INPUT_S,
};
use super::read::odometer_displacement;
use super::{DataWarning, Dataset, Doubt, IMU_FILE, MEASUREMENTS_FILE};

/// Rates whose 99th percentile exceeds this (rad/s) are no road vehicle's.
const ROAD_RATE_MAX: f64 = 3.0;

impl Dataset {
    /// The warnings of a strapdown dataset (module documentation).
    pub(super) fn strapdown_warnings(&self) -> Vec<DataWarning> {
        let mut out = Vec::new();
        let warn = |doubt, column: &str, message: String| DataWarning {
            doubt,
            file: IMU_FILE.to_owned(),
            column: column.to_owned(),
            message,
        };
        let g = self.local_gravity();
        let dt = median_interval(self.inputs.iter().map(|i| i.t));
        if let Some(dt) = dt.filter(|dt| *dt > SLOWEST_INPUT_S) {
            out.push(warn(
                Doubt::TimesInMilliseconds,
                "t",
                format!(
                    "readings every {dt} (median interval): times in milliseconds? An IMU \
                     records at 10-1000 Hz; expected seconds"
                ),
            ));
        }
        let force = median(self.inputs.iter().map(|i| {
            let f = self.specific_force(i);
            f[0].hypot(f[1]).hypot(f[2])
        }));
        let near = |value: f64, target: f64| (value / target - 1.0).abs() < GRAVITY_TOLERANCE;
        if let Some(f) = force.filter(|f| !near(*f, g)) {
            let increments = dt.filter(|dt| near(f, g * dt));
            let (doubt, hint) = match increments {
                // At about 10 Hz a sample interval's gravity is also about 1 g: say both.
                Some(dt) if near(f, 1.0) => (
                    Doubt::SpecificForceNotGravity,
                    format!(
                        " It is near 1: in g (multiply by 9.81), or velocity increments over \
                         the {dt}-s sample interval (write them under the header \
                         t,dtheta_x,dtheta_y,dtheta_z,dv_x,dv_y,dv_z)?"
                    ),
                ),
                Some(dt) => (
                    Doubt::IncrementsReadAsRates,
                    format!(
                        " It is gravity times the sample interval ({dt} s): velocity \
                         increments? Write them under the header \
                         t,dtheta_x,dtheta_y,dtheta_z,dv_x,dv_y,dv_z"
                    ),
                ),
                _ if near(f, 1.0) => (
                    Doubt::SpecificForceNotGravity,
                    " It is near 1: in g? Multiply by 9.81.".to_owned(),
                ),
                _ if near(f, 1000.0) => (
                    Doubt::SpecificForceNotGravity,
                    " It is near 1000: in mg? Multiply by 0.00981.".to_owned(),
                ),
                _ => (Doubt::SpecificForceNotGravity, String::new()),
            };
            out.push(warn(
                doubt,
                "f_x,f_y,f_z",
                format!(
                    "the median magnitude of the specific force is {f:.4e}, far from gravity \
                     here ({g:.3} m/s^2); a unit on a road vehicle feels about g.{hint} \
                     Expected m/s^2, gravity included"
                ),
            ));
        } else if let Some(up) = median(self.inputs.iter().map(|i| self.specific_force(i)[2])) {
            if near(-up, g) {
                out.push(warn(
                    Doubt::UpsideDown,
                    "f_z",
                    format!(
                        "the median specific force along z is {up:.3} m/s^2, minus gravity: \
                         the unit's z axis points down. Upside down, or forward-right-down \
                         axes? Expected forward-left-up (negate y and z of both the rates \
                         and the forces)"
                    ),
                ));
            }
        }
        let mut rates: Vec<f64> = self
            .inputs
            .iter()
            .map(|i| i.f[0].hypot(i.f[1]).hypot(i.f[2]))
            .filter(|w| w.is_finite())
            .collect();
        rates.sort_by(f64::total_cmp);
        if let Some(&p99) = rates.get(rates.len() * 99 / 100) {
            if p99 > ROAD_RATE_MAX {
                out.push(warn(
                    Doubt::RatesInDegrees,
                    "w_x,w_y,w_z",
                    format!(
                        "1 % of the readings turn faster than {p99:.1} per second, beyond any \
                         road vehicle (below 1 rad/s): deg/s? Expected rad/s (multiply deg/s \
                         by pi/180)"
                    ),
                ));
            }
        }
        // The speed as a track: the platform's integrator gives its path length.
        let track = self.odometer_track();
        let (odometer, gps) =
            self.travel_over_spans(|ta, tb| odometer_displacement(&track, ta, tb));
        if let Some(message) = speed_unit_doubt(odometer, gps, "integrated, the odometer speed") {
            out.push(DataWarning {
                doubt: Doubt::OdometerNotMetresPerSecond,
                file: MEASUREMENTS_FILE.to_owned(),
                column: "speed".to_owned(),
                message,
            });
        }
        out
    }
}
