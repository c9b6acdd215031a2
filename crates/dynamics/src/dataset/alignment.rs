//! Aligning a strapdown unit from its own data, for a dataset without `[initial]`: level
//! from the mean specific force at the first standstill, heading from the first GPS track
//! driven above walking speed, each with the one-sigma it has.
//!
//! **Level.** At rest the unit feels gravity only: `f = g [sin theta, sin phi cos theta,
//! cos phi cos theta]` in forward-left-up axes (docs/model.md eq. (49) applied to `[0, 0, g]`),
//! so `phi = atan2(f_y, f_z)` and `theta = atan2(f_x, hypot(f_y, f_z))` from the mean force
//! over the standstill: the readings from the odometer's first reading to its last leading
//! zero (readings before the odometer starts are of a unit whose motion nothing records).
//! An accelerometer bias `b` tilts that answer by `b / g`, which no averaging removes: the
//! level's sigma is the stated `[prior] level_rad`, or a MEMS unit's 5 mg over g when the
//! dataset states none.
//!
//! **Heading.** A MEMS unit cannot find North by itself (its gyro bias hides the Earth's
//! rate), so the heading comes from the vehicle's track: the bearing of the GPS chord from
//! the first fix taken above walking speed to the first fix far enough on (at least
//! [`TRACK_CHORD_GPS_SIGMAS`] GPS sigmas) while the unit turned less than [`STRAIGHT_DEG`].
//! Its sigma is the chord's, `sqrt(2) gps_m / length`. The heading at the first reading is
//! that bearing minus what the gyro turned in between (`psi' = -w_z` for a level unit), and
//! its sigma grows by the gyro bias over that time (the stated or MEMS-class bias).

use super::{Dataset, InitialAttitude, InputSample};
use crate::earth::{meridian_radius, prime_vertical_radius};
use crate::strapdown::unit_class::UnitClass;

/// The shortest standstill the level is taken from, s.
pub const MIN_STANDSTILL_S: f64 = 5.0;
/// Walking speed, m/s: a track above it is the vehicle's, not GPS wander.
pub const WALKING_SPEED: f64 = 1.5;
/// The track's chord must be at least this many GPS sigmas long.
pub const TRACK_CHORD_GPS_SIGMAS: f64 = 20.0;
/// The unit may turn at most this much along the chord, deg.
pub const STRAIGHT_DEG: f64 = 2.0;

/// An alignment found in the data.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DataAlignment {
    /// The attitude at the first reading.
    pub attitude: InitialAttitude,
    /// One-sigma of roll and pitch, rad.
    pub level_sigma: f64,
    /// One-sigma of the heading, rad.
    pub heading_sigma: f64,
    /// The standstill the level came from, s.
    pub level_from: [f64; 2],
    /// The track the heading came from, s.
    pub heading_from: [f64; 2],
}

/// Why no alignment could be found.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum NoAlignment {
    /// No standstill of [`MIN_STANDSTILL_S`] at the start of the odometer's record.
    NoStandstill,
    /// No straight track long enough above walking speed.
    NoTrack,
}

impl std::fmt::Display for NoAlignment {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            NoAlignment::NoStandstill => write!(
                f,
                "no standstill of {MIN_STANDSTILL_S} s or more (odometer speed exactly 0) at \
                 the start to level from; state [initial] roll_deg, pitch_deg, heading_deg"
            ),
            NoAlignment::NoTrack => write!(
                f,
                "no straight GPS track above walking speed ({WALKING_SPEED} m/s) long enough \
                 ({TRACK_CHORD_GPS_SIGMAS} GPS sigmas) to take the heading from; state \
                 [initial] heading_deg"
            ),
        }
    }
}

impl Dataset {
    /// The alignment of a strapdown dataset from its data (module documentation).
    pub fn align_from_data(&self) -> Result<DataAlignment, NoAlignment> {
        let mems = UnitClass::Mems.errors();
        let g = crate::earth::STANDARD_GRAVITY;
        // The first standstill: the odometer's leading run of exact zeros, from its first
        // reading (readings before it are of a unit whose motion nothing records).
        let mut zeros = self
            .measurements
            .iter()
            .filter(|m| m.speed.is_some())
            .take_while(|m| m.speed == Some(0.0))
            .map(|m| m.t);
        let t_first = self.inputs.first().map_or(0.0, |s| s.t);
        let still_start = zeros.next().ok_or(NoAlignment::NoStandstill)?;
        let still_end = zeros.last().unwrap_or(still_start);
        if still_end - still_start < MIN_STANDSTILL_S {
            return Err(NoAlignment::NoStandstill);
        }
        let mut sum = [0.0; 3];
        let mut count = 0.0;
        let still = |s: &&InputSample| (still_start..=still_end).contains(&s.t);
        for s in self.inputs.iter().filter(still) {
            let f = self.specific_force(s);
            for (a, v) in sum.iter_mut().zip(f) {
                *a += v;
            }
            count += 1.0;
        }
        // No reading inside the standstill (a gap in imu.csv across it): nothing to level from.
        if count == 0.0 {
            return Err(NoAlignment::NoStandstill);
        }
        let f = sum.map(|v| v / count);
        let roll = f[1].atan2(f[2]);
        let pitch = f[0].atan2(f[1].hypot(f[2]));
        let level_sigma = self.prior.level_rad.unwrap_or(mems.accel_bias / g);
        // The track: the first fix above walking speed, and the first one far enough on.
        let fixes: Vec<(f64, [f64; 2], f64)> = self
            .measurements
            .iter()
            .filter_map(|m| {
                m.position_deg
                    .map(|p| (m.t, p, m.speed.unwrap_or(0.0).abs()))
            })
            .collect();
        let gps = self.noise.gps_m;
        let chord = |a: [f64; 2], b: [f64; 2]| {
            let lat = (0.5 * (a[0] + b[0])).to_radians();
            let north = (b[0] - a[0]).to_radians() * meridian_radius(lat.sin());
            let east = (b[1] - a[1]).to_radians() * prime_vertical_radius(lat.sin()) * lat.cos();
            (north, east)
        };
        // The angle the unit turned up to each reading (psi' = -w_z for a level unit;
        // trapezoids), so that any interval's turn is a difference.
        let mut turn = Vec::with_capacity(self.inputs.len());
        let mut acc = 0.0;
        for (k, s) in self.inputs.iter().enumerate() {
            if k > 0 {
                let p = &self.inputs[k - 1];
                acc -= 0.5 * (p.f[2] + s.f[2]) * (s.t - p.t);
            }
            turn.push(acc);
        }
        let turned_by = |t: f64| {
            let k = self.inputs.partition_point(|s| s.t <= t).saturating_sub(1);
            turn.get(k).copied().unwrap_or(0.0)
        };
        let gyro_bias = self
            .prior
            .coefficients
            .get("bgz")
            .copied()
            .unwrap_or(mems.gyro_bias);
        for (i, &(ta, pa, sa)) in fixes.iter().enumerate() {
            if sa < WALKING_SPEED {
                continue;
            }
            for &(tb, pb, _) in &fixes[i + 1..] {
                if (turned_by(tb) - turned_by(ta)).abs() > STRAIGHT_DEG.to_radians() {
                    break;
                }
                let (north, east) = chord(pa, pb);
                let length = north.hypot(east);
                if length < TRACK_CHORD_GPS_SIGMAS * gps {
                    continue;
                }
                // The bearing holds at the chord's middle; back to the first reading.
                let t_mid = 0.5 * (ta + tb);
                let heading = east.atan2(north) - (turned_by(t_mid) - turned_by(t_first));
                let heading_sigma =
                    (std::f64::consts::SQRT_2 * gps / length).hypot(gyro_bias * (t_mid - t_first));
                let heading_deg = heading.to_degrees();
                return Ok(DataAlignment {
                    attitude: InitialAttitude {
                        roll_deg: roll.to_degrees(),
                        pitch_deg: pitch.to_degrees(),
                        heading_deg: heading_deg - 360.0 * ((heading_deg + 180.0) / 360.0).floor(),
                    },
                    level_sigma,
                    heading_sigma,
                    level_from: [still_start, still_end],
                    heading_from: [ta, tb],
                });
            }
        }
        Err(NoAlignment::NoTrack)
    }
}
