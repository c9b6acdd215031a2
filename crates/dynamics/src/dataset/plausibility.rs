//! Plausibility: values that parse and pass every rule of data-format.md, yet look written in
//! the wrong unit. A diagnosis of such data would name an effect or blame the model with
//! confidence, so `inspect` prints these warnings and `diagnose` puts them at the top of its
//! report, before its verdict.
//!
//! Each check compares two things the file states independently, so that it needs no
//! assumption about the vehicle:
//! - **times in milliseconds**: the odometer's velocity integrated over the time column
//!   against the GPS track (milliseconds make the odometer travel 1000 times too far); without
//!   both, an input interval longer than the 1 s data-format.md allows;
//! - **latitude or longitude in radians**: the odometer's North (East) travel against the GPS
//!   track's, axis by axis (radians read as degrees move 57 times too little), whatever the
//!   other column holds (a track in radians on both axes is refused by the reader);
//! - **odometer speeds in km/h or mph**: the odometer's displacement against the GPS chord,
//!   over spans of 10 s or more between fixes (so that the fixes' noise is small beside the
//!   travel): 3.6 or 2.24 times as far is the unit, not a scale error;
//! - **specific force not in m/s^2**: its median magnitude against the Earth's gravity (a
//!   vehicle on a road feels `|f|` within a few percent of g most of the time).
//!
//! The first two trust the odometer. One that reads faster than any road vehicle, unconfirmed
//! by the GPS ([`crate::sensor_classes::ROAD_SPEED_MAX`]: stuck, or in mm/s), is itself the
//! fault, which [`super::Implausibility::OdometerTooFast`] names; it is then not compared with
//! the GPS (a stuck 300 m/s would otherwise make the GPS longitude look like radians); nor is a
//! GPS track closer to a pole than the model holds ([`super::Implausibility::NearPole`]).

use super::read::{chord_m, odometer_displacement, odometer_east_north};
use super::{Dataset, INPUTS_FILE, MEASUREMENTS_FILE};
use crate::earth::{meridian_radius, normal_gravity, prime_vertical_radius};
use serde::{Deserialize, Serialize};
use std::fmt;

/// What looks wrong.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Doubt {
    /// The time column looks like milliseconds.
    TimesInMilliseconds,
    /// `lat_deg` looks like radians.
    LatitudeInRadians,
    /// `lon_deg` looks like radians.
    LongitudeInRadians,
    /// The specific force is far from gravity: not m/s^2, or not a specific force.
    SpecificForceNotGravity,
    /// A strapdown unit's rates are beyond any road vehicle's: deg/s, not rad/s.
    RatesInDegrees,
    /// A strapdown unit's readings are a sample interval's worth of gravity: increments
    /// written under the rates' header.
    IncrementsReadAsRates,
    /// A strapdown unit's up axis points down: mounted upside down, or its axes are
    /// forward-right-down.
    UpsideDown,
    /// The odometer travels 3.6 (2.24) times as far as the GPS track: km/h (mph), not m/s.
    OdometerNotMetresPerSecond,
}

/// One warning: what, where (file and column), and the evidence.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DataWarning {
    /// What looks wrong.
    pub doubt: Doubt,
    /// The file.
    pub file: String,
    /// The column.
    pub column: String,
    /// The evidence and what was expected.
    pub message: String,
}

impl fmt::Display for DataWarning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}: column `{}`: {}",
            self.file, self.column, self.message
        )
    }
}

/// Travel (m) the odometer must cover before its comparison with the GPS means anything.
const MIN_TRAVEL_M: f64 = 100.0;
/// Odometer travel beyond this many times the GPS track's: the time column is milliseconds
/// (1000 times), not GPS noise or an odometer scale error (a few percent).
const MILLISECONDS_RATIO: f64 = 30.0;
/// Odometer over GPS travel, summed over spans of at least [`SPAN_S`], beyond which the time
/// column is milliseconds (1000) and not GPS written in radians (40-57, read as degrees; the
/// East axis's `cos(lat)` is then read at a latitude near zero).
const MILLISECONDS_SPAN_RATIO: f64 = 250.0;
/// GPS travel on one axis below this fraction of the odometer's: that column is radians
/// (1/57).
const RADIANS_RATIO: f64 = 0.1;
/// A median input interval beyond this (s) is no vehicle test's inertial record: data-format.md
/// asks for inputs at least at the filter rate (1 Hz), while a 10-500 Hz record written in
/// milliseconds shows intervals of 2-100.
pub(super) const SLOWEST_INPUT_S: f64 = 1.5;
/// The median specific force must lie within this fraction of gravity.
pub(super) const GRAVITY_TOLERANCE: f64 = 0.3;

impl Dataset {
    /// Values that parse, yet look written in the wrong unit, axes or form: empty for data
    /// that look as data-format.md says. Each family has its checks
    /// ([`super::FamilyFiles::warnings`]).
    pub fn warnings(&self) -> Vec<DataWarning> {
        super::files_of(self.model).warnings(self)
    }

    /// The warnings of a platform dataset (module documentation).
    pub(super) fn platform_warnings(&self) -> Vec<DataWarning> {
        let mut out = Vec::new();
        let odometer_fast = !self.odometer_beyond_road().is_empty();
        // Nor is a GPS track at a pole, where longitude measures no distance.
        let limit = super::limits::latitude_limit_deg();
        let at_pole = self
            .measurements
            .iter()
            .filter_map(|m| m.position_deg)
            .any(|p| !(p[0].abs() <= limit));
        let odometer = self.odometer_velocities();
        let travel = Travel::of(self, &odometer).filter(|_| !odometer_fast && !at_pole);
        let warn = |doubt, file: &str, column: &str, message: String| DataWarning {
            doubt,
            file: file.to_owned(),
            column: column.to_owned(),
            message,
        };
        // Whether odometer and GPS can tell seconds from milliseconds: then they decide, and
        // the input interval (a weaker hint) is not consulted.
        let compared = travel
            .as_ref()
            .is_some_and(|t| t.odometer[0].hypot(t.odometer[1]) >= MIN_TRAVEL_M);
        let over_spans =
            || self.travel_over_spans(|ta, tb| odometer_displacement(&odometer, ta, tb));
        if let Some(t) = travel.as_ref().filter(|_| compared) {
            let odo = t.odometer[0].hypot(t.odometer[1]);
            // GPS in radians also leaves the odometer far ahead (57 times). Milliseconds
            // show besides in the input interval (2-100 for a 10-500 Hz record) or, over
            // spans where GPS noise adds no travel, in a ratio near 1000. (Spans are measured
            // in the file's units: with fixes every few milliseconds the noise is not averaged
            // out, which the input interval covers.)
            let slow_inputs = median_interval(self.inputs.iter().map(|i| i.t))
                .is_some_and(|dt| dt > SLOWEST_INPUT_S);
            let (odo_spans, gps_spans) = over_spans();
            let not_radians = slow_inputs
                || !(gps_spans > 0.0)
                || odo_spans > MILLISECONDS_SPAN_RATIO * gps_spans;
            if odo > MILLISECONDS_RATIO * t.gps_total && not_radians {
                out.push(warn(
                    Doubt::TimesInMilliseconds,
                    MEASUREMENTS_FILE,
                    "t",
                    format!(
                        "integrated over this time column the odometer travels {odo:.0} m \
                         while the GPS track moves {:.0} m ({:.0} times less): times in \
                         milliseconds (or velocities in mm/s)? Expected seconds and m/s",
                        t.gps_total,
                        odo / t.gps_total.max(1e-9)
                    ),
                ));
            }
        }
        if !compared {
            if let Some(dt) = median_interval(self.inputs.iter().map(|i| i.t)) {
                if dt > SLOWEST_INPUT_S {
                    out.push(warn(
                        Doubt::TimesInMilliseconds,
                        INPUTS_FILE,
                        "t",
                        format!(
                            "inputs every {dt} (median interval) over {} in all: times in \
                             milliseconds? Inputs come at the filter rate (1 Hz) or faster; \
                             expected seconds",
                            self.inputs.last().map_or(0.0, |i| i.t)
                                - self.inputs.first().map_or(0.0, |i| i.t)
                        ),
                    ));
                }
            }
        }
        // Milliseconds stretch the odometer on both axes; radians shrink the GPS on one.
        let in_ms = out.iter().any(|w| w.doubt == Doubt::TimesInMilliseconds);
        if !in_ms && !odometer_fast && !at_pole {
            let (odo, gps) = over_spans();
            if let Some(w) = speed_unit_doubt(odo, gps, "integrated, the odometer") {
                out.push(warn(
                    Doubt::OdometerNotMetresPerSecond,
                    MEASUREMENTS_FILE,
                    "v_e,v_n",
                    w,
                ));
            }
        }
        if let Some(t) = travel.as_ref().filter(|_| !in_ms) {
            for (axis, doubt, column, direction) in [
                (1, Doubt::LatitudeInRadians, "lat_deg", "North-South"),
                (0, Doubt::LongitudeInRadians, "lon_deg", "East-West"),
            ] {
                let (odo, gps) = (t.odometer[axis], t.gps[axis]);
                if odo >= MIN_TRAVEL_M && gps < RADIANS_RATIO * odo {
                    out.push(warn(
                        doubt,
                        MEASUREMENTS_FILE,
                        column,
                        format!(
                            "read as degrees the GPS track moves {gps:.0} m {direction} \
                             while the odometer moves {odo:.0} m: radians? Expected degrees \
                             (multiply radians by 180/pi)"
                        ),
                    ));
                }
            }
        }
        if let Some(f) = median(
            self.inputs
                .iter()
                .map(|i| i.f[0].hypot(i.f[1]).hypot(i.f[2])),
        ) {
            let g = self.local_gravity();
            if !((1.0 - GRAVITY_TOLERANCE) * g..=(1.0 + GRAVITY_TOLERANCE) * g).contains(&f) {
                let hint = if (f - 1.0).abs() < GRAVITY_TOLERANCE {
                    " It is near 1: in g? Multiply by 9.81."
                } else if (f / 1000.0 - 1.0).abs() < GRAVITY_TOLERANCE {
                    " It is near 1000: in mg? Multiply by 0.00981."
                } else {
                    ""
                };
                out.push(warn(
                    Doubt::SpecificForceNotGravity,
                    INPUTS_FILE,
                    "f_e,f_n,f_u",
                    format!(
                        "the median magnitude of the specific force is {f:.4e}, far from \
                         gravity here ({g:.3} m/s^2); a vehicle on a road feels about g.{hint} \
                         Expected m/s^2, gravity included"
                    ),
                ));
            }
        }
        out
    }
}

impl Dataset {
    /// Gravity at the first GPS fix (at 45 deg without one), m/s^2: what a unit on a road
    /// feels, to compare the specific force with.
    pub(super) fn local_gravity(&self) -> f64 {
        let lat = self
            .measurements
            .iter()
            .find_map(|m| m.position_deg)
            .map_or(45.0, |p| p[0]);
        normal_gravity(lat.to_radians().sin())
    }
}

/// Odometer and GPS travel compared over the same intervals (between consecutive GPS fixes
/// that hold odometer samples).
struct Travel {
    /// Odometer travel East and North, m (sums of the absolute displacement per interval).
    odometer: [f64; 2],
    /// GPS travel East and North read as degrees, m (same).
    gps: [f64; 2],
    /// GPS chord length, m.
    gps_total: f64,
}

impl Travel {
    /// From `ds`'s fixes and its `odometer` samples (time, `[v_e, v_n]`).
    fn of(ds: &Dataset, odometer: &[(f64, [f64; 2])]) -> Option<Travel> {
        let fixes: Vec<(f64, [f64; 2])> = ds
            .measurements
            .iter()
            .filter_map(|m| m.position_deg.map(|p| (m.t, p)))
            .collect();
        if odometer.len() < 2 || fixes.len() < 2 {
            return None;
        }
        let mut t = Travel {
            odometer: [0.0; 2],
            gps: [0.0; 2],
            gps_total: 0.0,
        };
        for w in fixes.windows(2) {
            let ((ta, a), (tb, b)) = (w[0], w[1]);
            let Some(d) = odometer_east_north(odometer, ta, tb) else {
                continue;
            };
            t.odometer[0] += d[0].abs();
            t.odometer[1] += d[1].abs();
            let lat = (0.5 * (a[0] + b[0])).to_radians();
            let s = lat.sin();
            t.gps[1] += ((b[0] - a[0]).to_radians() * meridian_radius(s)).abs();
            t.gps[0] += ((b[1] - a[1]).to_radians() * prime_vertical_radius(s) * lat.cos()).abs();
            t.gps_total += chord_m(a, b);
        }
        Some(t)
    }
}

/// The shortest span between the GPS fixes [`Dataset::travel_over_spans`] compares over: long
/// enough that a fix's noise (metres) is small beside the travel, short enough that a turn
/// makes the chord little shorter than the path.
const SPAN_S: f64 = 10.0;

impl Dataset {
    /// The odometer's travel (`odometer(ta, tb)`, m, `None` where it cannot tell) and the GPS
    /// chords, summed over consecutive spans of at least [`SPAN_S`] between fixes.
    pub(super) fn travel_over_spans(
        &self,
        odometer: impl Fn(f64, f64) -> Option<f64>,
    ) -> (f64, f64) {
        let (mut odo, mut gps) = (0.0, 0.0);
        let mut start: Option<(f64, [f64; 2])> = None;
        for m in &self.measurements {
            let Some(p) = m.position_deg else { continue };
            match start {
                None => start = Some((m.t, p)),
                Some((ta, a)) if m.t - ta >= SPAN_S => {
                    if let Some(d) = odometer(ta, m.t) {
                        odo += d;
                        gps += chord_m(a, p);
                    }
                    start = Some((m.t, p));
                }
                Some(_) => {}
            }
        }
        (odo, gps)
    }
}

/// Speed units an odometer is often logged in, with their size in m/s.
const SPEED_UNITS: [(&str, f64); 2] = [("km/h", 1.0 / 3.6), ("mph", 0.447_04)];

/// How close the ratio of odometer to GPS travel must come to a unit's factor (3.6 for km/h,
/// 2.24 for mph) to be called that unit: the two bands do not meet, and a real odometer's
/// scale error (a few percent, [`crate::sensor_classes`]) is far outside both.
const SPEED_UNIT_TOLERANCE: f64 = 0.12;

/// The warning's evidence when `odometer_m` of travel against `gps_m` of GPS track is a speed
/// unit's factor, over at least [`MIN_TRAVEL_M`] of track.
pub(super) fn speed_unit_doubt(odometer_m: f64, gps_m: f64, what: &str) -> Option<String> {
    if !(gps_m >= MIN_TRAVEL_M) {
        return None;
    }
    let ratio = odometer_m / gps_m;
    SPEED_UNITS.iter().find_map(|&(unit, size)| {
        ((ratio * size - 1.0).abs() < SPEED_UNIT_TOLERANCE).then(|| {
            format!(
                "{what} travels {odometer_m:.0} m while the GPS track moves {gps_m:.0} m \
                 ({ratio:.2} times as far): speeds in {unit}? Expected m/s (multiply by \
                 {size})"
            )
        })
    })
}

pub(super) fn median(values: impl Iterator<Item = f64>) -> Option<f64> {
    let mut v: Vec<f64> = values.filter(|x| x.is_finite()).collect();
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied()
}

/// The median interval between consecutive times.
pub(super) fn median_interval(t: impl Iterator<Item = f64>) -> Option<f64> {
    let t: Vec<f64> = t.collect();
    median(t.windows(2).map(|w| w[1] - w[0]))
}
