//! What implausible data are, as the report says them: [`Implausibility`], one variant per
//! check of [`super::implausible`] (where its bounds and their reasons are), each with where it
//! is (file, columns, times, values) and the words that say it.

use super::family::files_of;
use super::limits::{
    FALL_FRACTION, GNSS_FLOOR_M, OVERLOAD_G, POLE_DISTANCE_M, SCATTER_SIGMAS, SPEED_MARGIN,
    SUSTAINED_S,
};
use super::{CONFIG_FILE, MEASUREMENTS_FILE};
use crate::model_kind::ModelKind;
use crate::sensor_classes::ROAD_SPEED_MAX;
use serde::{Deserialize, Serialize};
use std::fmt;

/// How a GPS jump looks.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum JumpShape {
    /// Displaced, but by no flip: a wrong fix, a spliced file, a change of datum.
    Step,
    /// Across the pole: its neighbour's latitude with the longitude half a turn away.
    AcrossPole,
    /// The latitude's sign flipped (the other hemisphere).
    LatitudeSign,
    /// The longitude's sign flipped.
    LongitudeSign,
    /// Latitude and longitude swapped.
    Swapped,
}

/// Something the record cannot be, with where it is (times, file, columns, values).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum Implausibility {
    /// Inputs missing for longer than a filter period; the longest such gap.
    InputGap {
        /// Time of the last input before the gap, s.
        start_s: f64,
        /// Time of the first input after it, s.
        end_s: f64,
        /// The longest interval that is not a gap, s.
        limit_s: f64,
        /// How many gaps.
        count: usize,
        /// The dataset's family (its file of inputs and columns); the platform unwritten.
        #[serde(default, skip_serializing_if = "ModelKind::is_platform")]
        family: ModelKind,
    },
    /// Consecutive GPS fixes farther apart than the vehicle could move; the first such jump.
    PositionJump {
        /// Time of the fix before the jump, s.
        from_s: f64,
        /// Time of the fix after it, s.
        to_s: f64,
        /// The fix before, degrees.
        from_deg: [f64; 2],
        /// The fix after, degrees.
        to_deg: [f64; 2],
        /// The distance between them, m.
        distance_m: f64,
        /// The most the vehicle could have moved, m.
        allowed_m: f64,
        /// The odometer's fastest reading around the interval, m/s (`None`: no odometer).
        speed_m_s: Option<f64>,
        /// How the jump looks.
        shape: JumpShape,
        /// How many jumps in all.
        count: usize,
    },
    /// The specific force far from gravity for a sustained span; the longest such span.
    OffGround {
        /// First sample of the span, s.
        start_s: f64,
        /// Last sample of the span, s.
        end_s: f64,
        /// Median magnitude of the specific force over the span, m/s^2.
        force: f64,
        /// Gravity there, m/s^2.
        gravity: f64,
        /// How many such spans.
        count: usize,
        /// The dataset's family (its file of inputs and columns); the platform unwritten.
        #[serde(default, skip_serializing_if = "ModelKind::is_platform")]
        family: ModelKind,
    },
    /// The odometer reads faster than any road vehicle.
    OdometerTooFast {
        /// First such reading, s.
        start_s: f64,
        /// Last such reading, s.
        end_s: f64,
        /// The fastest reading, m/s.
        speed_m_s: f64,
        /// [`ROAD_SPEED_MAX`].
        limit_m_s: f64,
        /// How many such readings.
        count: usize,
        /// The dataset's family (its file of inputs and columns); the platform unwritten.
        #[serde(default, skip_serializing_if = "ModelKind::is_platform")]
        family: ModelKind,
    },
    /// A stated `[noise]` level that no real sensor has.
    NoiseBeyondSensors {
        /// The key of `dataset.toml`'s `[noise]` table.
        key: String,
        /// Its stated value.
        value: f64,
        /// The smallest plausible value.
        min: f64,
        /// The largest plausible value.
        max: f64,
        /// The key's unit.
        unit: String,
        /// The real sensors' span, in words.
        classes: String,
    },
    /// GPS fixes too close to a pole for the model; the first such fix.
    NearPole {
        /// Its time, s.
        t_s: f64,
        /// Its latitude, degrees.
        latitude_deg: f64,
        /// The largest |latitude| the model takes, degrees.
        limit_deg: f64,
        /// How many such fixes.
        count: usize,
    },
}

impl Implausibility {
    /// The file it is in.
    pub fn file(&self) -> &'static str {
        match self {
            Implausibility::InputGap { family, .. } | Implausibility::OffGround { family, .. } => {
                files_of(*family).inputs_file()
            }
            Implausibility::NoiseBeyondSensors { .. } => CONFIG_FILE,
            _ => MEASUREMENTS_FILE,
        }
    }
    /// The columns (or key) it is in.
    pub fn column(&self) -> String {
        match self {
            Implausibility::InputGap { .. } => "t".into(),
            Implausibility::OffGround { family, .. } => {
                let columns = files_of(*family).input_columns();
                let force = columns.iter().filter(|c| c.starts_with("f_"));
                force.copied().collect::<Vec<_>>().join(",")
            }
            Implausibility::PositionJump { .. } => "lat_deg,lon_deg".into(),
            Implausibility::NearPole { .. } => "lat_deg".into(),
            Implausibility::OdometerTooFast { family, .. } => {
                let columns = files_of(*family).measurement_columns();
                columns[1..columns.len() - 2].join(",")
            }
            Implausibility::NoiseBeyondSensors { key, .. } => format!("noise.{key}"),
        }
    }
}

/// `x` to four significant digits (exponent form when very large or small).
fn g4(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let magnitude = x.abs().log10().floor();
    if !(-3.0..6.0).contains(&magnitude) {
        return format!("{x:.3e}");
    }
    let decimals = (3.0 - magnitude).max(0.0) as usize;
    let s = format!("{x:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_owned()
    } else {
        s
    }
}

/// `, N in all` when there is more than one.
fn in_all(count: usize, what: &str) -> String {
    if count > 1 {
        format!(" ({count} {what} in all)")
    } else {
        String::new()
    }
}

impl fmt::Display for Implausibility {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (file, column) = (self.file(), self.column());
        match self {
            Implausibility::InputGap {
                start_s,
                end_s,
                limit_s,
                count,
                ..
            } => write!(
                f,
                "{file}: column `{column}`: no input from t = {} s to t = {} s ({} s, longer \
                 than a filter period: at most {} s){}; the filter would predict across it \
                 from a force interpolated between its ends",
                g4(*start_s),
                g4(*end_s),
                g4(end_s - start_s),
                g4(*limit_s),
                in_all(*count, "gaps")
            ),
            Implausibility::PositionJump {
                from_s,
                to_s,
                from_deg,
                to_deg,
                distance_m,
                allowed_m,
                speed_m_s,
                shape,
                count,
            } => {
                let speed = match speed_m_s {
                    Some(v) => format!("the odometer reads at most {} m/s", g4(*v)),
                    None => {
                        format!("no odometer; a road vehicle drives at most {ROAD_SPEED_MAX} m/s")
                    }
                };
                let how = match shape {
                    JumpShape::Step => "",
                    JumpShape::AcrossPole => {
                        " It lies across the pole: the latitude kept, the longitude half a turn away."
                    }
                    JumpShape::LatitudeSign => " Its latitude's sign is flipped.",
                    JumpShape::LongitudeSign => " Its longitude's sign is flipped.",
                    JumpShape::Swapped => " Its latitude and longitude are swapped.",
                };
                write!(
                    f,
                    "{file}: columns `{column}`: the GPS fix at t = {} s ({}, {}) lies {} m from \
                     the one at t = {} s ({}, {}), but {speed}: the vehicle moves at most {} m in \
                     {} s ({} times that speed, plus {} times the GPS's own scatter, at least \
                     {} m).{how}{}",
                    g4(*to_s),
                    to_deg[0],
                    to_deg[1],
                    g4(*distance_m),
                    g4(*from_s),
                    from_deg[0],
                    from_deg[1],
                    g4(*allowed_m),
                    g4(to_s - from_s),
                    SPEED_MARGIN,
                    SCATTER_SIGMAS,
                    GNSS_FLOOR_M,
                    in_all(*count, "such jumps")
                )
            }
            Implausibility::OffGround {
                start_s,
                end_s,
                force,
                gravity,
                count,
                ..
            } => write!(
                f,
                "{file}: columns `{column}`: from t = {} s to t = {} s the specific force is {} \
                 m/s^2 (median magnitude) against gravity {} m/s^2: {}{}",
                g4(*start_s),
                g4(*end_s),
                g4(*force),
                g4(*gravity),
                if *force < *gravity {
                    format!(
                        "free fall (below {FALL_FRACTION} g for {SUSTAINED_S} s or more); a \
                         vehicle on a road feels gravity through its wheels"
                    )
                } else {
                    format!(
                        "above {OVERLOAD_G} g for {SUSTAINED_S} s or more, more than tyres on \
                         a road can hold"
                    )
                },
                in_all(*count, "such spans")
            ),
            Implausibility::OdometerTooFast {
                start_s,
                end_s,
                speed_m_s,
                limit_m_s,
                count,
                ..
            } => write!(
                f,
                "{file}: {}`{column}`: the odometer reads up to {} m/s, faster than any \
                 road vehicle (at most {} m/s; the fastest production car reached 136 m/s), \
                 from t = {} s to t = {} s ({count} readings): a stuck or wrongly scaled \
                 odometer (in mm/s? km/h?)",
                if column.contains(',') {
                    "columns "
                } else {
                    "column "
                },
                g4(*speed_m_s),
                g4(*limit_m_s),
                g4(*start_s),
                g4(*end_s)
            ),
            Implausibility::NoiseBeyondSensors {
                value,
                min,
                max,
                unit,
                classes,
                ..
            } => write!(
                f,
                "{file}: `{column}` = {value:e} {unit} is {} any real sensor: real ones span \
                 {classes}, and a stated level outside {:.1e}-{:.1e} {unit} (a hundred times \
                 past either end, in sigma) is no sensor's",
                if value < min { "below" } else { "above" },
                min,
                max
            ),
            Implausibility::NearPole {
                t_s,
                latitude_deg,
                limit_deg,
                count,
            } => write!(
                f,
                "{file}: column `{column}`: the fix at t = {} s is at latitude {latitude_deg} \
                 deg, closer to the pole than the model holds (|latitude| <= {} deg: it divides \
                 by cos(latitude), and its North-pointing frame cannot follow a vehicle within \
                 {} km of the pole){}",
                g4(*t_s),
                g4(*limit_deg),
                POLE_DISTANCE_M / 1000.0,
                in_all(*count, "such fixes")
            ),
        }
    }
}
