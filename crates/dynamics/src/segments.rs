//! A vehicle test written as a list of segments, instead of the paper's O-A-B-C-O path:
//! what a user plans a test with (`navkf plan`).
//!
//! ```toml
//! [trajectory]
//! duration_s = 1800.0
//! [[trajectory.segment]]
//! kind = "hold"            # stand still
//! duration_s = 120.0
//! [[trajectory.segment]]
//! kind = "repeat"          # ten stop-and-go cycles
//! count = 10
//! segments = [
//!   { kind = "speed", to = 12.0, accel = 2.0 },   # accelerate to 12 m/s, peak 2 m/s^2
//!   { kind = "cruise", distance_m = 200.0, climb_m = 5.0 },  # with a 5 m climb
//!   { kind = "speed", to = 0.0, accel = 2.0 },    # brake to a stop
//!   { kind = "hold", duration_s = 10.0 },
//! ]
//! [[trajectory.segment]]
//! kind = "figure_eight"    # a full right circle, then a full left one
//! rate_deg = 10.0
//! ```
//!
//! Kinds: `hold` (at rest), `speed` (to a speed at a peak acceleration: a `sin^2` profile
//! of duration `2 |dv| / accel`), `cruise` (for `duration_s` or `distance_m`), `turn`
//! (`angle_deg`, positive to the right, at a peak `rate_deg`), `figure_eight` (two opposite
//! full turns at `rate_deg`), `slalom` (`count` pairs of turns by `+-angle_deg`) and `repeat`
//! (`count` times its `segments`). A `speed`, `cruise` or `turn` may carry `climb_m`: the road
//! rises (or falls) by that much over it, along a smooth profile. The model keeps zero vertical velocity, so a
//! grade reaches it only through the specific force: `fz = g + a_up`.
//!
//! After the last segment the vehicle keeps doing what it did (holds or cruises) until
//! `duration_s`. Each segment is checked where it stands (`trajectory.segment[3].accel`,
//! `trajectory.segment[1].segments[2].to`): a turn or a cruise at rest, a hold while moving,
//! a speed change to the speed already held, or a test longer than `duration_s` are refused.

use crate::error::DynamicsError;
use crate::trajectory::Motion;
use serde::{Deserialize, Serialize};

/// One entry of `[[trajectory.segment]]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum SegmentSpec {
    /// Stand still for `duration_s`.
    Hold {
        /// Duration, s.
        duration_s: f64,
    },
    /// Accelerate or brake to `to` (m/s) at a peak acceleration `accel` (m/s^2).
    Speed {
        /// Final speed, m/s.
        to: f64,
        /// Peak acceleration of the `sin^2` profile, m/s^2.
        accel: f64,
        /// Rise of the road over the segment, m.
        #[serde(default)]
        climb_m: f64,
    },
    /// Hold speed and heading for `duration_s` or `distance_m` (one of them).
    Cruise {
        /// Duration, s.
        duration_s: Option<f64>,
        /// Distance, m.
        distance_m: Option<f64>,
        /// Rise of the road over the segment, m.
        #[serde(default)]
        climb_m: f64,
    },
    /// Turn by `angle_deg` (positive to the right) at a peak rate `rate_deg` (deg/s).
    Turn {
        /// Heading change, deg.
        angle_deg: f64,
        /// Peak turn rate, deg/s.
        rate_deg: f64,
        /// Rise of the road over the segment, m.
        #[serde(default)]
        climb_m: f64,
    },
    /// A full turn to the right, then a full turn to the left, at a peak rate `rate_deg`.
    FigureEight {
        /// Peak turn rate, deg/s.
        rate_deg: f64,
    },
    /// `count` pairs of turns, by `+angle_deg` then `-angle_deg`, at a peak rate `rate_deg`.
    Slalom {
        /// Number of left-right pairs.
        count: usize,
        /// Heading change of each turn, deg.
        angle_deg: f64,
        /// Peak turn rate, deg/s.
        rate_deg: f64,
    },
    /// `segments`, `count` times over.
    Repeat {
        /// Repetitions.
        count: usize,
        /// The segments repeated.
        segments: Vec<SegmentSpec>,
    },
}

/// A segment laid out: its duration, motion, the road's rise over it, and a label.
pub(crate) struct Laid {
    pub(crate) duration: f64,
    pub(crate) motion: Motion,
    pub(crate) climb: f64,
    pub(crate) label: &'static str,
}

/// Most segments a list may expand to (a `repeat` of a `repeat` multiplies).
pub const MAX_SEGMENTS: usize = 100_000;

fn err(key: &str, message: String) -> DynamicsError {
    DynamicsError::Config {
        key: key.to_string(),
        message,
    }
}

fn positive(key: &str, name: &str, v: f64) -> Result<f64, DynamicsError> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(err(
            &format!("{key}.{name}"),
            format!("{v}: expected a finite number > 0"),
        ))
    }
}

/// Lays out `specs` (at the key `key`, e.g. `trajectory.segment`) from rest: the segments
/// with their motions, in order. The speed carried between segments is checked against what
/// each needs.
pub(crate) fn lay_out(specs: &[SegmentSpec], key: &str) -> Result<Vec<Laid>, DynamicsError> {
    let mut out = Vec::new();
    let mut speed = 0.0;
    lay(specs, key, &mut speed, &mut out)?;
    Ok(out)
}

fn lay(
    specs: &[SegmentSpec],
    key: &str,
    speed: &mut f64,
    out: &mut Vec<Laid>,
) -> Result<(), DynamicsError> {
    for (i, spec) in specs.iter().enumerate() {
        let k = format!("{key}[{i}]");
        let climb_ok = |c: f64| {
            if c.is_finite() {
                Ok(c)
            } else {
                Err(err(
                    &format!("{k}.climb_m"),
                    format!("{c}: expected a finite number"),
                ))
            }
        };
        let moving = |what: &str| {
            if *speed > 0.0 {
                Ok(*speed)
            } else {
                Err(err(
                    &k,
                    format!("a {what} at rest: expected a `speed` segment before it"),
                ))
            }
        };
        let turn =
            |angle_deg: f64, rate_deg: f64, s: f64, climb: f64| -> Result<Laid, DynamicsError> {
                if !(angle_deg.is_finite() && angle_deg != 0.0) {
                    return Err(err(
                        &format!("{k}.angle_deg"),
                        format!("{angle_deg}: expected a finite non-zero angle"),
                    ));
                }
                let rate = positive(&k, "rate_deg", rate_deg)?;
                Ok(Laid {
                    duration: 2.0 * angle_deg.abs() / rate,
                    motion: Motion::Turn {
                        speed: s,
                        delta: angle_deg.to_radians(),
                    },
                    climb,
                    label: "turn",
                })
            };
        match spec {
            SegmentSpec::Hold { duration_s } => {
                if *speed > 0.0 {
                    return Err(err(
                        &k,
                        format!(
                            "a hold while moving at {speed} m/s: expected a `speed` segment to 0 \
                             before it"
                        ),
                    ));
                }
                out.push(Laid {
                    duration: positive(&k, "duration_s", *duration_s)?,
                    motion: Motion::Standstill,
                    climb: 0.0,
                    label: "hold",
                });
            }
            SegmentSpec::Speed { to, accel, climb_m } => {
                if !(to.is_finite() && *to >= 0.0) {
                    return Err(err(
                        &format!("{k}.to"),
                        format!("{to}: expected a speed >= 0, m/s"),
                    ));
                }
                if *to == *speed {
                    return Err(err(
                        &format!("{k}.to"),
                        format!("{to} m/s is the speed already held: expected a change"),
                    ));
                }
                let a = positive(&k, "accel", *accel)?;
                out.push(Laid {
                    duration: 2.0 * (to - *speed).abs() / a,
                    motion: Motion::SpeedChange {
                        from: *speed,
                        to: *to,
                    },
                    climb: climb_ok(*climb_m)?,
                    label: if *to > *speed { "accelerate" } else { "brake" },
                });
                *speed = *to;
            }
            SegmentSpec::Cruise {
                duration_s,
                distance_m,
                climb_m,
            } => {
                let s = moving("cruise")?;
                let duration = match (duration_s, distance_m) {
                    (Some(d), None) => positive(&k, "duration_s", *d)?,
                    (None, Some(m)) => positive(&k, "distance_m", *m)? / s,
                    _ => {
                        return Err(err(
                            &k,
                            "expected exactly one of duration_s and distance_m".into(),
                        ))
                    }
                };
                out.push(Laid {
                    duration,
                    motion: Motion::Cruise { speed: s },
                    climb: climb_ok(*climb_m)?,
                    label: "cruise",
                });
            }
            SegmentSpec::Turn {
                angle_deg,
                rate_deg,
                climb_m,
            } => {
                let s = moving("turn")?;
                out.push(turn(*angle_deg, *rate_deg, s, climb_ok(*climb_m)?)?);
            }
            SegmentSpec::FigureEight { rate_deg } => {
                let s = moving("figure_eight")?;
                out.push(turn(360.0, *rate_deg, s, 0.0)?);
                out.push(turn(-360.0, *rate_deg, s, 0.0)?);
            }
            SegmentSpec::Slalom {
                count,
                angle_deg,
                rate_deg,
            } => {
                let s = moving("slalom")?;
                if *count == 0 {
                    return Err(err(&format!("{k}.count"), "0: expected at least 1".into()));
                }
                for _ in 0..*count {
                    out.push(turn(*angle_deg, *rate_deg, s, 0.0)?);
                    out.push(turn(-*angle_deg, *rate_deg, s, 0.0)?);
                    if out.len() > MAX_SEGMENTS {
                        return Err(err(&k, format!("expands beyond {MAX_SEGMENTS} segments")));
                    }
                }
            }
            SegmentSpec::Repeat { count, segments } => {
                if *count == 0 || segments.is_empty() {
                    return Err(err(
                        &k,
                        "expected count >= 1 and at least one segment to repeat".into(),
                    ));
                }
                for _ in 0..*count {
                    lay(segments, &format!("{k}.segments"), speed, out)?;
                    if out.len() > MAX_SEGMENTS {
                        return Err(err(&k, format!("expands beyond {MAX_SEGMENTS} segments")));
                    }
                }
            }
        }
    }
    Ok(())
}
