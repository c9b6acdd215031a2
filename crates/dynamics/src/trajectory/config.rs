//! The test's settings as a study file or `simulate --trajectory` gives them, with their
//! defaults (the paper's test) and their checks; what is written back is only what means
//! something for the path chosen.

use crate::error::DynamicsError;
use crate::segments::SegmentSpec;
use serde::{Deserialize, Serialize};

/// The path's settings. Every field has a default, so a study file may set only some.
///
/// Written back (a results folder's "study file as run") with only the settings that mean
/// something: with a segment list, the O-A-B-C-O settings are left out, so the file as run
/// reads back exactly as [`TrajectoryConfig::validate`] accepts it.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct TrajectoryConfig {
    /// Latitude of O, degrees (Harbin, where the paper's authors work).
    pub start_lat_deg: f64,
    /// Longitude of O, degrees.
    pub start_lon_deg: f64,
    /// Total duration of the test, s (paper: 2400 s).
    pub duration_s: f64,
    /// Standstill before moving off, s.
    pub initial_standstill_s: f64,
    /// Cruise speed, m/s.
    pub cruise_speed: f64,
    /// Speed through the turns, m/s.
    pub turn_speed: f64,
    /// Peak longitudinal acceleration of speed changes, m/s^2.
    pub peak_accel: f64,
    /// Peak turn rate, deg/s.
    pub peak_turn_rate_deg: f64,
    /// Length of O-A (heading North), metres: the distance from O to where the first turn
    /// begins.
    pub leg_north_m: f64,
    /// Length of A-B (heading East), metres: from the end of the first turn to the start of
    /// the second. B-C and C-O are solved so that the path closes.
    pub leg_east_m: f64,
    /// A test of the user's own (`[[trajectory.segment]]`, see [`crate::segments`]): when
    /// given, it replaces the O-A-B-C-O path and the settings above other than the start,
    /// the duration and nothing else.
    #[serde(rename = "segment")]
    pub segments: Vec<SegmentSpec>,
}

impl Serialize for TrajectoryConfig {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeStruct;
        let path = self.path_settings();
        let mut st = serializer.serialize_struct("TrajectoryConfig", 3 + path.len() + 1)?;
        st.serialize_field("start_lat_deg", &self.start_lat_deg)?;
        st.serialize_field("start_lon_deg", &self.start_lon_deg)?;
        st.serialize_field("duration_s", &self.duration_s)?;
        if self.segments.is_empty() {
            for (key, v) in path {
                st.serialize_field(key, &v)?;
            }
        } else {
            st.serialize_field("segment", &self.segments)?;
        }
        st.end()
    }
}

impl Default for TrajectoryConfig {
    fn default() -> Self {
        TrajectoryConfig {
            start_lat_deg: 45.78,
            start_lon_deg: 126.63,
            duration_s: 2400.0,
            initial_standstill_s: 120.0,
            cruise_speed: 15.0,
            turn_speed: 5.0,
            peak_accel: 1.0,
            peak_turn_rate_deg: 6.0,
            leg_north_m: 9000.0,
            leg_east_m: 6500.0,
            segments: Vec::new(),
        }
    }
}

impl TrajectoryConfig {
    /// The O-A-B-C-O path's own settings, by key: what a segment list replaces.
    fn path_settings(&self) -> [(&'static str, f64); 7] {
        [
            ("initial_standstill_s", self.initial_standstill_s),
            ("cruise_speed", self.cruise_speed),
            ("turn_speed", self.turn_speed),
            ("peak_accel", self.peak_accel),
            ("peak_turn_rate_deg", self.peak_turn_rate_deg),
            ("leg_north_m", self.leg_north_m),
            ("leg_east_m", self.leg_east_m),
        ]
    }

    /// Checks every value; the error names the key and what was expected.
    pub fn validate(&self) -> Result<(), DynamicsError> {
        // All positive but the standstill (checked below: it may be zero).
        let positive = std::iter::once(("duration_s", self.duration_s))
            .chain(self.path_settings().into_iter().skip(1));
        for (key, v) in positive {
            if !(v.is_finite() && v > 0.0) {
                return Err(config_err(
                    key,
                    format!("{v}: expected a finite number > 0"),
                ));
            }
        }
        if !(self.initial_standstill_s.is_finite() && self.initial_standstill_s >= 0.0) {
            return Err(config_err(
                "initial_standstill_s",
                format!(
                    "{}: expected a finite number >= 0",
                    self.initial_standstill_s
                ),
            ));
        }
        if !self.start_lat_deg.is_finite() || self.start_lat_deg.abs() >= 80.0 {
            return Err(config_err(
                "start_lat_deg",
                format!(
                    "{}: expected a latitude within +-80 deg",
                    self.start_lat_deg
                ),
            ));
        }
        if !(self.start_lon_deg.is_finite() && self.start_lon_deg.abs() <= 360.0) {
            return Err(config_err(
                "start_lon_deg",
                format!(
                    "{}: expected a longitude within +-360 deg",
                    self.start_lon_deg
                ),
            ));
        }
        if !self.segments.is_empty() {
            // The O-A-B-C-O settings mean nothing with a segment list: refuse them rather
            // than ignore them.
            let defaults = TrajectoryConfig::default().path_settings();
            for ((key, v), (_, default)) in self.path_settings().into_iter().zip(defaults) {
                if v != default {
                    return Err(config_err(
                        key,
                        format!(
                            "{v} has no effect with [[trajectory.segment]]: remove it (each \
                             segment sets its own speeds and rates)"
                        ),
                    ));
                }
            }
        }
        if !self.segments.is_empty() {
            // Cheap beside building the path: a sweep checks every point's segments here.
            let laid = crate::segments::lay_out(&self.segments, "trajectory.segment")?;
            check_fits(self, laid.iter().map(|l| l.duration).sum(), SEGMENTS_FIT)?;
        }
        if self.turn_speed > self.cruise_speed {
            return Err(config_err(
                "turn_speed",
                format!(
                    "{} m/s is above cruise_speed {} m/s: expected turn_speed <= cruise_speed",
                    self.turn_speed, self.cruise_speed
                ),
            ));
        }
        Ok(())
    }
}

pub(super) fn config_err(key: &str, message: String) -> DynamicsError {
    DynamicsError::Config {
        key: format!("trajectory.{key}"),
        message,
    }
}

/// What a path that outlasts `duration_s` is called, and what would fix it.
#[derive(Clone, Copy)]
pub(super) struct Fit {
    what: &'static str,
    remedy: &'static str,
}

pub(super) const PATH_FITS: Fit = Fit {
    what: "the path takes",
    remedy: "a longer duration, shorter legs or a higher cruise_speed",
};

pub(super) const SEGMENTS_FIT: Fit = Fit {
    what: "the segments take",
    remedy: "a longer duration or fewer segments",
};

/// Refuses a path of `t` seconds longer than the test.
pub(super) fn check_fits(c: &TrajectoryConfig, t: f64, fit: Fit) -> Result<(), DynamicsError> {
    if t > c.duration_s {
        return Err(config_err(
            "duration_s",
            format!(
                "{} {t:.1} s but the test lasts {} s: expected {}",
                fit.what, c.duration_s, fit.remedy
            ),
        ));
    }
    Ok(())
}
