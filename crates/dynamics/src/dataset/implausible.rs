//! Implausible data: values in the right units that no road vehicle, no real sensor, or not
//! this model can produce. [`super::plausibility`] asks whether a column is written in the
//! wrong unit; this asks whether the record can be what it claims at all. A diagnosis of such
//! data names no effect (its verdict says the data are implausible, and where): any effect it
//! named would stand in for the defect, as a GPS latency of 207 s stands in for a 10 km step
//! in the GPS, or one of -0.5 s for a vehicle in free fall.
//!
//! Every check compares the record with physics or with itself, never with a bound tuned to
//! an example:
//! - **Input gaps** ([`Implausibility::InputGap`]): an interval between input samples longer
//!   than the filter period (the measurements' median interval) and than two nominal input
//!   intervals (one dropped sample), plus half a nominal interval for clock jitter. Across
//!   such a gap the filters integrate a specific force interpolated from its ends
//!   (`navkf_filters::Runner`): the manoeuvres inside are lost, and the misfit they leave
//!   looks like noise or an effect.
//! - **Position jumps** ([`Implausibility::PositionJump`]): consecutive GPS fixes farther
//!   apart than the vehicle could move: [`SPEED_MARGIN`] times the odometer's fastest reading
//!   around the interval (its velocity's magnitude on the platform, its speed for strapdown;
//!   an odometer 100 % slow, five times the worst scale error a tyre allows) times the time
//!   between the fixes, plus [`SCATTER_SIGMAS`] times the GPS's own fix-to-fix scatter
//!   (measured from the data where the odometer gives a displacement, so a mis-stated
//!   `gps_m` does not move it; the stated sigma for a strapdown odometer's speed),
//!   and at least [`GNSS_FLOOR_M`]. Without an odometer the speed is
//!   [`ROAD_SPEED_MAX`]. A jump whose far fix lands back on its neighbour once its latitude's
//!   or longitude's sign is flipped, its columns swapped or its longitude turned by half a
//!   turn (across the pole) is named as that flip ([`JumpShape`]).
//! - **Off the ground** ([`Implausibility::OffGround`]): the specific force's magnitude below
//!   [`FALL_FRACTION`] of gravity (free fall) or above [`OVERLOAD_G`] g for at least
//!   [`SUSTAINED_S`]. A vehicle on a road feels gravity through its wheels: road grades (cos
//!   of a 35 % grade is 0.94) and crests taken at speed (`v^2/r`: 30 m/s over a 200 m crest is
//!   0.46 g) stay above half of it, and tyre friction (mu < 1.5) keeps the total below
//!   sqrt(1 + mu^2) = 1.8 g. A bump lasts a few tenths of a second, a rally car's longest jump
//!   one or two; three seconds of fall drop 44 m.
//! - **Odometer faster than any road vehicle** ([`Implausibility::OdometerTooFast`]): a speed
//!   above [`ROAD_SPEED_MAX`] that the GPS does not confirm (a stuck counter, a speed in mm/s
//!   or km/h). One the GPS confirms is the record's own: in this model's truth the vehicle
//!   moves with its platform's errors (a simulated platform misaligned by 10 deg drives the
//!   paper's test at up to 160 m/s), and the checks judge records, not the model.
//! - **Stated noise beyond any real sensor** ([`Implausibility::NoiseBeyondSensors`]):
//!   `dataset.toml`'s `[noise]` outside [`crate::sensor_classes::NOISE_BOUNDS`].
//! - **Too close to a pole** ([`Implausibility::NearPole`]): a fix within [`POLE_DISTANCE_M`]
//!   of a pole. The model's North-pointing frame turns about the vertical at
//!   `v_x tanL / RN` and its longitude moves at `v_x / (RN cosL)`: within distance `r` of the
//!   pole one filter period (1 s, model.md) at road speed (up to [`ROAD_SPEED_MAX`]) changes
//!   `cosL` by `v dt / r`. Beyond 1 % per step the step's linearisation (the EKF's Jacobian,
//!   RK4 over the step) no longer holds, and at the pole itself `1/cosL` is 1.6e16 and the
//!   filters return NaN: so `r >= 100 x 150 m/s x 1 s = 15 km` (|latitude| up to
//!   89.87 deg; of road vehicles only the South Pole Traverse's tractors drive nearer).

use super::implausibility::{Implausibility, JumpShape};
use super::limits::*;
use super::plausibility::{median, median_interval};
use super::read::odometer_east_north;
use super::Dataset;
use crate::earth::{meridian_radius, normal_gravity, prime_vertical_radius};
use crate::noise::NoiseConfig;
use crate::sensor_classes::{noise_out_of_bounds, ROAD_SPEED_MAX};

/// Median of a Rayleigh distribution in units of its per-axis sigma, `sqrt(2 ln 2)`.
const RAYLEIGH_MEDIAN: f64 = 1.177_410_022_515_474_7;

/// The stated levels of `noise` that no real sensor has ([`NOISE_BOUNDS`]).
pub fn noise_beyond_sensors(noise: &NoiseConfig) -> Vec<Implausibility> {
    noise_out_of_bounds(noise)
        .map(|(b, value)| Implausibility::NoiseBeyondSensors {
            key: b.key.to_owned(),
            value,
            min: b.min(),
            max: b.max(),
            unit: b.unit.to_owned(),
            classes: b.classes.to_owned(),
        })
        .collect()
}

impl Dataset {
    /// What these data cannot be (module documentation); empty for a record a road vehicle
    /// with real sensors could have made where the model holds.
    pub fn implausibilities(&self) -> Vec<Implausibility> {
        let mut out = noise_beyond_sensors(&self.noise);
        out.extend(self.near_pole());
        out.extend(self.input_gap());
        out.extend(self.off_ground());
        out.extend(self.odometer_too_fast());
        out.extend(self.position_jump());
        out
    }

    /// The filter period: the measurements' median interval (1 s with a single row).
    fn filter_period(&self) -> f64 {
        median_interval(self.measurements.iter().map(|m| m.t)).unwrap_or(1.0)
    }

    fn near_pole(&self) -> Option<Implausibility> {
        let limit = latitude_limit_deg();
        let near: Vec<(f64, f64)> = self
            .gps_fixes()
            .into_iter()
            .filter(|(_, p)| !(p[0].abs() <= limit))
            .map(|(t, p)| (t, p[0]))
            .collect();
        let &(t_s, latitude_deg) = near.first()?;
        Some(Implausibility::NearPole {
            t_s,
            latitude_deg,
            limit_deg: limit,
            count: near.len(),
        })
    }

    fn input_gap(&self) -> Option<Implausibility> {
        let nominal = median_interval(self.inputs.iter().map(|i| i.t))?;
        let limit = self.filter_period().max(2.0 * nominal) + 0.5 * nominal;
        let mut count = 0;
        let mut longest: Option<(f64, f64)> = None;
        for w in self.inputs.windows(2) {
            let (a, b) = (w[0].t, w[1].t);
            if b - a > limit {
                count += 1;
                if longest.is_none_or(|(s, e)| b - a > e - s) {
                    longest = Some((a, b));
                }
            }
        }
        let (start_s, end_s) = longest?;
        Some(Implausibility::InputGap {
            start_s,
            end_s,
            limit_s: limit,
            count,
            family: self.model,
        })
    }

    fn off_ground(&self) -> Option<Implausibility> {
        let lat = self.gps_fixes().first().map_or(45.0, |(_, p)| p[0]);
        let gravity = normal_gravity(lat.to_radians().sin());
        // -1: fall, 1: overload, 0: on the ground.
        let side = |f: f64| {
            if !(f >= FALL_FRACTION * gravity) {
                -1
            } else if f > OVERLOAD_G * gravity {
                1
            } else {
                0
            }
        };
        let magnitude: Vec<f64> = self
            .inputs
            .iter()
            .map(|i| {
                let f = self.specific_force(i);
                f[0].hypot(f[1]).hypot(f[2])
            })
            .collect();
        let mut count = 0;
        let mut longest: Option<(f64, f64, f64)> = None;
        let mut i = 0;
        while i < magnitude.len() {
            let s = side(magnitude[i]);
            let mut j = i;
            while s != 0 && j + 1 < magnitude.len() && side(magnitude[j + 1]) == s {
                j += 1;
            }
            let (a, b) = (self.inputs[i].t, self.inputs[j].t);
            if s != 0 && b - a >= SUSTAINED_S {
                count += 1;
                if longest.is_none_or(|(x, y, _)| b - a > y - x) {
                    longest = Some((
                        a,
                        b,
                        median(magnitude[i..=j].iter().copied()).unwrap_or(f64::NAN),
                    ));
                }
            }
            i = j + 1;
        }
        let (start_s, end_s, force) = longest?;
        Some(Implausibility::OffGround {
            start_s,
            end_s,
            force,
            gravity,
            count,
            family: self.model,
        })
    }

    fn odometer_too_fast(&self) -> Option<Implausibility> {
        let fast = self.odometer_beyond_road();
        let (first, last) = (fast.first()?, fast.last()?);
        Some(Implausibility::OdometerTooFast {
            start_s: first.0,
            end_s: last.0,
            speed_m_s: fast.iter().map(|x| x.1).fold(0.0, f64::max),
            limit_m_s: ROAD_SPEED_MAX,
            count: fast.len(),
            family: self.model,
        })
    }

    /// The odometer readings (time, speed) faster than [`ROAD_SPEED_MAX`] that the GPS does not
    /// confirm: the fixes around the reading move at less than `1 / SPEED_MARGIN` of its speed
    /// (or there are no two fixes). A speed both sensors show is the record's: the model's
    /// truth moves with its platform's errors, and a simulated platform misaligned by 10 deg
    /// drives the paper's test at up to 160 m/s, odometer and GPS agreeing.
    pub(super) fn odometer_beyond_road(&self) -> Vec<(f64, f64)> {
        let fixes = self.gps_fixes();
        let gps_speed = |t: f64| -> Option<f64> {
            // Two fixes or more (with one, `clamp(1, 0)` would panic).
            if fixes.len() < 2 {
                return None;
            }
            let i = fixes
                .partition_point(|(tf, _)| *tf < t)
                .clamp(1, fixes.len() - 1);
            let ((ta, a), (tb, b)) = (fixes[i - 1], fixes[i]);
            Some(distance_m(a, b) / (tb - ta))
        };
        self.odometer_speeds()
            .into_iter()
            .filter(|&(t, s)| {
                !(s <= ROAD_SPEED_MAX) && !gps_speed(t).is_some_and(|g| g * SPEED_MARGIN >= s)
            })
            .collect()
    }

    fn position_jump(&self) -> Option<Implausibility> {
        let fixes = self.gps_fixes();
        let odometer = self.odometer_velocities();
        let speeds = self.odometer_speeds();
        let period = self.filter_period();
        // The GPS's own fix-to-fix scatter, per axis: the median distance between its
        // displacement and the odometer's over the same interval (a Rayleigh median), or the
        // stated sigma when no interval has both (a strapdown odometer reads a speed, not a
        // displacement).
        let residuals: Vec<f64> = fixes
            .windows(2)
            .filter_map(|w| {
                let d = odometer_east_north(&odometer, w[0].0, w[1].0)?;
                let g = east_north_m(w[0].1, w[1].1);
                Some((g[0] - d[0]).hypot(g[1] - d[1]))
            })
            .collect();
        let scatter = if residuals.is_empty() {
            std::f64::consts::SQRT_2 * self.noise.gps_m
        } else {
            median(residuals.into_iter()).unwrap_or(f64::NAN) / RAYLEIGH_MEDIAN
        };
        let noise_allowance = (SCATTER_SIGMAS * scatter).max(GNSS_FLOOR_M);
        let mut first = None;
        let mut count = 0;
        for w in fixes.windows(2) {
            let ((ta, a), (tb, b)) = (w[0], w[1]);
            let lo = speeds.partition_point(|(t, _)| *t < ta - period);
            let hi = speeds.partition_point(|(t, _)| *t <= tb + period);
            let speed = speeds[lo..hi].iter().map(|(_, s)| *s).reduce(f64::max);
            let allowed =
                SPEED_MARGIN * speed.unwrap_or(ROAD_SPEED_MAX) * (tb - ta) + noise_allowance;
            let distance = distance_m(a, b);
            if !(distance > allowed) {
                continue;
            }
            count += 1;
            if first.is_none() {
                let near = |p: [f64; 2]| p[0].abs() <= 90.0 && distance_m(a, p) <= allowed;
                let shape = [
                    (JumpShape::AcrossPole, [b[0], b[1] + 180.0]),
                    (JumpShape::LatitudeSign, [-b[0], b[1]]),
                    (JumpShape::LongitudeSign, [b[0], -b[1]]),
                    (JumpShape::Swapped, [b[1], b[0]]),
                ]
                .into_iter()
                .find(|(_, p)| near(*p))
                .map_or(JumpShape::Step, |(s, _)| s);
                first = Some(Implausibility::PositionJump {
                    from_s: ta,
                    to_s: tb,
                    from_deg: a,
                    to_deg: b,
                    distance_m: distance,
                    allowed_m: allowed,
                    speed_m_s: speed,
                    shape,
                    count: 0,
                });
            }
        }
        let mut jump = first?;
        if let Implausibility::PositionJump { count: c, .. } = &mut jump {
            *c = count;
        }
        Some(jump)
    }
}

/// East and North displacement (m) from `a` to `b` (degrees) on the local tangent plane, the
/// longitude difference taken the short way round.
fn east_north_m(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    let lat = (0.5 * (a[0] + b[0])).to_radians();
    let s = lat.sin();
    let dlon = (b[1] - a[1]) - 360.0 * ((b[1] - a[1]) / 360.0).round();
    [
        dlon.to_radians() * prime_vertical_radius(s) * lat.cos(),
        (b[0] - a[0]).to_radians() * meridian_radius(s),
    ]
}

/// Distance (m) from `a` to `b` (degrees) on the local tangent plane.
fn distance_m(a: [f64; 2], b: [f64; 2]) -> f64 {
    let d = east_north_m(a, b);
    d[0].hypot(d[1])
}
