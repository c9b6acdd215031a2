//! A dataset at a glance: what a user checks before running filters on it.
//!
//! Filter results only make sense if the data are what the user thinks they are: the span
//! and rates, whether a sensor dropped out (gaps), whether the vehicle moved and turned (an
//! error model is only observable under manoeuvres), where it drove, and whether truth is
//! there to compare against. [`Dataset::summary`] computes these once; the struct serialises
//! for reports and prints as readable text. It never fails: a dataset built by hand with
//! empty parts simply gives `None`s.

use super::read::chord_m;
use super::{DataWarning, Dataset, Implausibility};
use serde::Serialize;
use std::fmt;

/// An interval more than this many times the median counts as a gap.
pub const GAP_FACTOR: f64 = 2.0;
pub use crate::trajectory::phase_thresholds::{STILL_SPEED, TURN_RATE_DEG_S};
/// Heading is taken from the odometer velocity only at or above this speed (m/s): at rest its
/// direction is noise, and so would be the turn rate.
pub const MIN_HEADING_SPEED: f64 = 0.5;

/// Start, end and duration, s.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Span {
    /// First time, s.
    pub start: f64,
    /// Last time, s.
    pub end: f64,
    /// `end - start`, s.
    pub duration: f64,
}

/// The intervals between consecutive samples of a stream.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct IntervalStats {
    /// Median interval, s.
    pub median: f64,
    /// Shortest interval, s.
    pub min: f64,
    /// Longest interval, s.
    pub max: f64,
    /// `1 / median`, Hz.
    pub rate_hz: f64,
}

/// One interval longer than [`GAP_FACTOR`] times the median.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Gap {
    /// Time of the last sample before the gap, s.
    pub start: f64,
    /// Length of the interval, s.
    pub duration: f64,
}

/// The gaps of a stream.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Gaps {
    /// How many intervals exceed [`GAP_FACTOR`] times the median.
    pub count: usize,
    /// The longest of them.
    pub largest: Option<Gap>,
}

/// A stream of samples: inputs, measurement rows, odometer readings or GPS fixes.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Stream {
    /// Number of samples.
    pub count: usize,
    /// Interval statistics (`None` with fewer than two samples).
    pub interval: Option<IntervalStats>,
    /// Gaps.
    pub gaps: Gaps,
}

/// Speeds from the odometer.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SpeedProfile {
    /// Largest speed, m/s.
    pub max: f64,
    /// Time-weighted mean speed, m/s.
    pub mean: f64,
    /// Fraction of the odometer's time spent below [`STILL_SPEED`].
    pub still_fraction: f64,
}

/// Manoeuvres: the specific force along the inputs' first two axes (horizontal on the
/// platform, the unit's x-y plane for strapdown), the turn rate from the inputs' rate about
/// the vertical where they hold one and otherwise from the odometer's heading.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct TurnProfile {
    /// Largest specific force along the first two axes (`|(f_e, f_n)|` on the platform,
    /// `|(f_x, f_y)|` for strapdown), m/s^2 (`None` without inputs).
    pub max_horizontal_force: Option<f64>,
    /// RMS of that force over the input samples, m/s^2.
    pub rms_horizontal_force: Option<f64>,
    /// Largest |heading rate| between consecutive odometer readings, deg/s (`None` when no
    /// two consecutive readings are both at or above [`MIN_HEADING_SPEED`]).
    pub max_turn_rate_deg_s: Option<f64>,
    /// Time with |heading rate| above [`TURN_RATE_DEG_S`], s.
    pub turning_time: f64,
    /// `turning_time` as a fraction of the span.
    pub turning_fraction: f64,
    /// What the force's two axes are, in words
    /// ([`super::family::FamilyFiles::planar_force_words`]).
    #[serde(skip)]
    pub force_words: &'static str,
}

/// Where the GPS fixes lie.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Extent {
    /// Smallest latitude, deg.
    pub lat_min: f64,
    /// Largest latitude, deg.
    pub lat_max: f64,
    /// Smallest longitude, deg.
    pub lon_min: f64,
    /// Largest longitude, deg.
    pub lon_max: f64,
    /// North-south extent, m.
    pub north_m: f64,
    /// East-west extent (at the middle latitude), m.
    pub east_m: f64,
}

/// The truth file's shape.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TruthSummary {
    /// State names (the columns after `t`).
    pub columns: Vec<String>,
    /// Number of rows.
    pub rows: usize,
}

/// What [`Dataset::summary`] reports; `Display` prints it as text.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DatasetSummary {
    /// The dataset's name.
    pub name: String,
    /// Span of the inputs (of the measurements if there are no inputs).
    pub span: Option<Span>,
    /// Input samples.
    pub inputs: Stream,
    /// Measurement rows (any sensor).
    pub measurements: Stream,
    /// Odometer readings.
    pub odometer: Stream,
    /// GPS fixes.
    pub gps: Stream,
    /// Speeds (`None` without odometer).
    pub speed: Option<SpeedProfile>,
    /// Manoeuvres.
    pub turn: TurnProfile,
    /// Where the GPS fixes lie (`None` without GPS).
    pub extent: Option<Extent>,
    /// The truth's columns (`None` without truth).
    pub truth: Option<TruthSummary>,
    /// Values that look written in the wrong unit ([`Dataset::warnings`]).
    pub warnings: Vec<DataWarning>,
    /// What the record cannot be ([`Dataset::implausibilities`]): a diagnosis names no
    /// effect on such data.
    pub implausible: Vec<Implausibility>,
}

impl Dataset {
    /// Span, rates, gaps, speed and turn profiles, extent and truth at a glance.
    pub fn summary(&self) -> DatasetSummary {
        let input_t: Vec<f64> = self.inputs.iter().map(|s| s.t).collect();
        let meas_t: Vec<f64> = self.measurements.iter().map(|m| m.t).collect();
        let odometer = self.odometer_track();
        let gps = self.gps_fixes();
        let fixes: Vec<[f64; 2]> = gps.iter().map(|(_, p)| *p).collect();
        let gps_t: Vec<f64> = gps.iter().map(|(t, _)| *t).collect();
        let odo_t: Vec<f64> = odometer.iter().map(|(t, _)| *t).collect();

        let span = span_of(&input_t).or_else(|| span_of(&meas_t));
        let duration = span.map_or(0.0, |s| s.duration);
        DatasetSummary {
            name: self.name.clone(),
            span,
            inputs: stream(&input_t),
            measurements: stream(&meas_t),
            odometer: stream(&odo_t),
            gps: stream(&gps_t),
            speed: speed_profile(&odometer),
            turn: self.turn_profile(&odometer, duration),
            extent: extent(&fixes),
            truth: self.truth.as_ref().map(|t| TruthSummary {
                columns: t.names.clone(),
                rows: t.t.len(),
            }),
            warnings: self.warnings(),
            implausible: self.implausibilities(),
        }
    }

    fn turn_profile(&self, odometer: &[(f64, [f64; 2])], duration: f64) -> TurnProfile {
        let horizontal: Vec<f64> = self
            .inputs
            .iter()
            .map(|s| {
                let f = self.specific_force(s);
                f[0].hypot(f[1])
            })
            .collect();
        let max_horizontal_force = horizontal.iter().copied().reduce(f64::max);
        let rms_horizontal_force = (!horizontal.is_empty()).then(|| {
            (horizontal.iter().map(|f| f * f).sum::<f64>() / horizontal.len() as f64).sqrt()
        });
        let mut max_rate: Option<f64> = None;
        let mut turning_time = 0.0;
        // Inputs that read the turn rate give it, each sample standing for the interval
        // after it; otherwise the odometer's heading does.
        let rate_of = super::files_of(self.model).turn_rate();
        if let Some(rate_of) = rate_of {
            for w in self.inputs.windows(2) {
                let rate = rate_of(&w[0]).abs().to_degrees();
                max_rate = Some(max_rate.map_or(rate, |m| m.max(rate)));
                if rate > TURN_RATE_DEG_S {
                    turning_time += w[1].t - w[0].t;
                }
            }
        }
        for w in odometer.windows(2).filter(|_| rate_of.is_none()) {
            let ((t0, v0), (t1, v1)) = (w[0], w[1]);
            let dt = t1 - t0;
            let fast = |v: [f64; 2]| v[0].hypot(v[1]) >= MIN_HEADING_SPEED;
            if !(dt > 0.0 && fast(v0) && fast(v1)) {
                continue;
            }
            // Heading from North towards East; the change wrapped into (-pi, pi].
            let d = v1[0].atan2(v1[1]) - v0[0].atan2(v0[1]);
            let d = d - std::f64::consts::TAU * (d / std::f64::consts::TAU).round();
            let rate = (d / dt).to_degrees().abs();
            max_rate = Some(max_rate.map_or(rate, |m| m.max(rate)));
            if rate > TURN_RATE_DEG_S {
                turning_time += dt;
            }
        }
        TurnProfile {
            max_horizontal_force,
            rms_horizontal_force,
            max_turn_rate_deg_s: max_rate,
            turning_time,
            turning_fraction: if duration > 0.0 {
                turning_time / duration
            } else {
                0.0
            },
            force_words: super::files_of(self.model).planar_force_words(),
        }
    }
}

fn span_of(t: &[f64]) -> Option<Span> {
    let (&start, &end) = (t.first()?, t.last()?);
    Some(Span {
        start,
        end,
        duration: end - start,
    })
}

fn median(values: &[f64]) -> Option<f64> {
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    let n = v.len();
    match n {
        0 => None,
        _ if n % 2 == 1 => v.get(n / 2).copied(),
        _ => Some(0.5 * (v.get(n / 2 - 1)? + v.get(n / 2)?)),
    }
}

fn stream(t: &[f64]) -> Stream {
    let intervals: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).collect();
    let interval = median(&intervals).map(|median| IntervalStats {
        median,
        min: intervals.iter().copied().fold(f64::INFINITY, f64::min),
        max: intervals.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        rate_hz: if median > 0.0 { 1.0 / median } else { 0.0 },
    });
    let mut gaps = Gaps {
        count: 0,
        largest: None,
    };
    if let Some(stats) = interval {
        for (w, &dt) in t.windows(2).zip(&intervals) {
            if dt > GAP_FACTOR * stats.median {
                gaps.count += 1;
                match gaps.largest {
                    Some(g) if g.duration >= dt => {}
                    _ => {
                        gaps.largest = Some(Gap {
                            start: w[0],
                            duration: dt,
                        })
                    }
                }
            }
        }
    }
    Stream {
        count: t.len(),
        interval,
        gaps,
    }
}

fn speed_profile(odometer: &[(f64, [f64; 2])]) -> Option<SpeedProfile> {
    let speeds: Vec<(f64, f64)> = odometer
        .iter()
        .map(|(t, v)| (*t, v[0].hypot(v[1])))
        .collect();
    let max = speeds.iter().map(|(_, s)| *s).reduce(f64::max)?;
    let (mut time, mut distance, mut still) = (0.0, 0.0, 0.0);
    for w in speeds.windows(2) {
        let ((t0, s0), (t1, s1)) = (w[0], w[1]);
        let dt = t1 - t0;
        time += dt;
        distance += 0.5 * (s0 + s1) * dt;
        // Each end of the interval stands for half of it.
        still += 0.5
            * dt
            * (f64::from(u8::from(s0 < STILL_SPEED)) + f64::from(u8::from(s1 < STILL_SPEED)));
    }
    Some(if time > 0.0 {
        SpeedProfile {
            max,
            mean: distance / time,
            still_fraction: still / time,
        }
    } else {
        // A single reading.
        SpeedProfile {
            max,
            mean: max,
            still_fraction: if max < STILL_SPEED { 1.0 } else { 0.0 },
        }
    })
}

fn extent(fixes: &[[f64; 2]]) -> Option<Extent> {
    let first = fixes.first()?;
    let (mut lat_min, mut lat_max, mut lon_min, mut lon_max) =
        (first[0], first[0], first[1], first[1]);
    for [lat, lon] in fixes {
        lat_min = lat_min.min(*lat);
        lat_max = lat_max.max(*lat);
        lon_min = lon_min.min(*lon);
        lon_max = lon_max.max(*lon);
    }
    let mid = 0.5 * (lat_min + lat_max);
    Some(Extent {
        lat_min,
        lat_max,
        lon_min,
        lon_max,
        north_m: chord_m([lat_min, 0.0], [lat_max, 0.0]),
        east_m: chord_m([mid, lon_min], [mid, lon_max]),
    })
}

/// `x` to six significant digits, without trailing zeros; exponent form when very large or
/// small.
fn num(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    if !(1e-4..1e9).contains(&x.abs()) {
        let s = format!("{x:.5e}");
        return match s.split_once('e') {
            Some((m, e)) if m.contains('.') => {
                format!("{}e{e}", m.trim_end_matches('0').trim_end_matches('.'))
            }
            _ => s,
        };
    }
    let decimals = (5 - x.abs().log10().floor() as i32).clamp(0, 12) as usize;
    let s = format!("{x:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_owned()
    } else {
        s
    }
}

fn pct(f: f64) -> String {
    format!("{:.1} %", 100.0 * f)
}

struct StreamText<'a>(&'a Stream, &'a str);

impl fmt::Display for StreamText<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let StreamText(s, noun) = *self;
        write!(f, "{} {noun}", s.count)?;
        if let Some(i) = s.interval {
            write!(
                f,
                ", median interval {} s ({} Hz), min {} s, max {} s",
                num(i.median),
                num(i.rate_hz),
                num(i.min),
                num(i.max)
            )?;
        }
        match s.gaps.largest {
            Some(g) => write!(
                f,
                "; {} gap(s) > {GAP_FACTOR}x median, largest {} s at t = {} s",
                s.gaps.count,
                num(g.duration),
                num(g.start)
            ),
            None => write!(f, "; no gaps"),
        }
    }
}

impl fmt::Display for DatasetSummary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "dataset `{}`", self.name)?;
        for i in &self.implausible {
            writeln!(f, "  IMPLAUSIBLE   {i}")?;
        }
        for w in &self.warnings {
            writeln!(f, "  WARNING       {w}")?;
        }
        match self.span {
            Some(s) => writeln!(
                f,
                "  span          {} s .. {} s ({} s)",
                num(s.start),
                num(s.end),
                num(s.duration)
            )?,
            None => writeln!(f, "  span          empty")?,
        }
        writeln!(f, "  inputs        {}", StreamText(&self.inputs, "rows"))?;
        writeln!(
            f,
            "  measurements  {}",
            StreamText(&self.measurements, "rows")
        )?;
        writeln!(
            f,
            "  odometer      {}",
            StreamText(&self.odometer, "readings")
        )?;
        writeln!(f, "  gps           {}", StreamText(&self.gps, "fixes"))?;
        match self.speed {
            Some(s) => writeln!(
                f,
                "  speed         max {} m/s, mean {} m/s, standing still (< {STILL_SPEED} m/s) {} of the time",
                num(s.max),
                num(s.mean),
                pct(s.still_fraction)
            )?,
            None => writeln!(f, "  speed         no odometer")?,
        }
        let t = &self.turn;
        write!(f, "  turning       ")?;
        match t.max_turn_rate_deg_s {
            Some(r) => write!(
                f,
                "max |heading rate| {} deg/s, turning (> {TURN_RATE_DEG_S} deg/s) {} s ({} of the span)",
                num(r),
                num(t.turning_time),
                pct(t.turning_fraction)
            )?,
            None => write!(f, "no heading rate (odometer below {MIN_HEADING_SPEED} m/s or absent)")?,
        }
        match (t.max_horizontal_force, t.rms_horizontal_force) {
            (Some(max), Some(rms)) => writeln!(
                f,
                "; {} max {} m/s^2, rms {} m/s^2",
                t.force_words,
                num(max),
                num(rms)
            )?,
            _ => writeln!(f)?,
        }
        match self.extent {
            Some(e) => writeln!(
                f,
                "  extent        {} m north-south x {} m east-west (lat {} .. {} deg, lon {} .. {} deg)",
                num(e.north_m),
                num(e.east_m),
                num(e.lat_min),
                num(e.lat_max),
                num(e.lon_min),
                num(e.lon_max)
            )?,
            None => writeln!(f, "  extent        no GPS")?,
        }
        match &self.truth {
            Some(t) => write!(
                f,
                "  truth         {} rows, {} columns: {}",
                t.rows,
                t.columns.len(),
                t.columns.join(", ")
            ),
            None => write!(f, "  truth         none"),
        }
    }
}
