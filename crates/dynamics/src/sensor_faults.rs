//! Sensor faults outside the catalogue, applied to a simulated dataset's measurements: what
//! a real vehicle test meets that no catalogued effect carries, hidden in simulated data so
//! that the diagnosis can be measured on misfits it has no candidate for. It must then name
//! nothing; each of these, on real drives, has been taken for a catalogued effect (a lever
//! arm for `gps-latency`, say, which at constant speed it resembles).
//!
//! - [`SensorFault::GpsStep`]: multipath, the fixes off by metres for minutes, then back.
//! - [`SensorFault::OdometerSlip`]: the wheels slip while the vehicle accelerates, so the
//!   odometer reads more than the true speed (`(1 + gain a)` times it, `a > 0` the forward
//!   acceleration).
//! - [`SensorFault::GpsLeverArm`]: the antenna is not at the platform: each fix is the
//!   platform's position plus the lever arm turned with the vehicle's heading. Unlike a
//!   latency it does not vanish at a stop.
//!
//! A fault works on the measurements alone, from the true states at their times
//! (`truth.csv`): the inputs, the truth and the noise are those of the clean run, so the
//! clean run and the faulty one differ only by the fault.

use crate::dataset::{Dataset, Truth};
use crate::earth::{meridian_radius, prime_vertical_radius};
use crate::state::{LAT, V_X, V_Y};

// Both families' truths keep East and North velocity and latitude at the same indices, so a
// fault reads either's.
const _: () = assert!(
    V_X == crate::strapdown::state::V_E
        && V_Y == crate::strapdown::state::V_N
        && LAT == crate::strapdown::state::LAT
);
use serde::{Deserialize, Serialize};

/// A fault of the recorded measurements (as a diagnosis study's `summary.json` records it,
/// tagged `fault`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "fault", rename_all = "kebab-case")]
pub enum SensorFault {
    /// GPS fixes off by `offset_m` (East, North, metres) from `start_s` for `duration_s`.
    GpsStep {
        /// Offset, East and North, m.
        offset_m: [f64; 2],
        /// Start, s of the record.
        start_s: f64,
        /// Duration, s.
        duration_s: f64,
    },
    /// The odometer's velocity times `1 + gain_s2_m * a` while the forward acceleration `a`
    /// (m/s^2) is positive.
    OdometerSlip {
        /// Slip per unit acceleration, s^2/m (0.02: 2 % at 1 m/s^2).
        gain_s2_m: f64,
    },
    /// The GPS antenna `forward_m` ahead of and `right_m` to the right of the platform.
    GpsLeverArm {
        /// Ahead, m.
        forward_m: f64,
        /// To the right, m.
        right_m: f64,
    },
}

impl SensorFault {
    /// Typical multipath offset, m per axis.
    pub const TYPICAL_STEP_M: f64 = 3.0;
    /// Typical slip gain, s^2/m: 2 % more at 1 m/s^2.
    pub const TYPICAL_SLIP_S2_M: f64 = 0.02;
    /// Typical lever arm, m: an antenna on the roof, a car's length from the unit.
    pub const TYPICAL_LEVER_ARM_M: f64 = 1.5;

    /// Its name in tables.
    pub fn label(&self) -> &'static str {
        match self {
            SensorFault::GpsStep { .. } => "GPS multipath step",
            SensorFault::OdometerSlip { .. } => "odometer slip",
            SensorFault::GpsLeverArm { .. } => "GPS lever arm",
        }
    }

    /// Applies the fault to `ds`'s measurements, from its truth at their times. Refused
    /// (nothing changed) when `ds` has no truth at a measurement's time or a size is not
    /// finite.
    pub fn apply(&self, ds: &mut Dataset) -> Result<(), String> {
        let finite = match *self {
            SensorFault::GpsStep {
                offset_m,
                start_s,
                duration_s,
            } => offset_m.iter().all(|v| v.is_finite()) && start_s.is_finite() && duration_s >= 0.0,
            SensorFault::OdometerSlip { gain_s2_m } => gain_s2_m.is_finite(),
            SensorFault::GpsLeverArm { forward_m, right_m } => {
                forward_m.is_finite() && right_m.is_finite()
            }
        };
        if !finite {
            return Err(format!("{self:?}: sizes must be finite"));
        }
        let truth = ds.truth.as_ref().ok_or("the dataset has no truth")?;
        let states = truth_at_measurements(truth, ds)?;
        let mut heading = 0.0;
        let mut previous: Option<(f64, f64)> = None;
        for (m, x) in ds.measurements.iter_mut().zip(&states) {
            let (v_e, v_n) = (x[V_X], x[V_Y]);
            let speed = v_e.hypot(v_n);
            // At a stop the heading is the last one moving.
            if speed > 0.1 {
                heading = v_e.atan2(v_n);
            }
            let accel = previous.map_or(0.0, |(t, s)| (speed - s) / (m.t - t));
            previous = Some((m.t, speed));
            match *self {
                SensorFault::GpsStep {
                    offset_m,
                    start_s,
                    duration_s,
                } => {
                    if (start_s..start_s + duration_s).contains(&m.t) {
                        shift(&mut m.position_deg, x[LAT], offset_m);
                    }
                }
                SensorFault::OdometerSlip { gain_s2_m } => {
                    // The platform's odometer reads a velocity, a strapdown unit's a speed.
                    let k = 1.0 + gain_s2_m * accel.max(0.0);
                    if let Some(v) = m.velocity.as_mut() {
                        *v = [v[0] * k, v[1] * k];
                    }
                    if let Some(s) = m.speed.as_mut() {
                        *s *= k;
                    }
                }
                SensorFault::GpsLeverArm { forward_m, right_m } => {
                    let (s, c) = heading.sin_cos();
                    // Forward is (sin psi, cos psi) in East-North; right is (cos psi, -sin psi).
                    let offset = [forward_m * s + right_m * c, forward_m * c - right_m * s];
                    shift(&mut m.position_deg, x[LAT], offset);
                }
            }
        }
        Ok(())
    }
}

/// The true state at every measurement's time (the simulator stores one per measurement).
fn truth_at_measurements<'a>(truth: &'a Truth, ds: &Dataset) -> Result<Vec<&'a [f64]>, String> {
    let mut out = Vec::with_capacity(ds.measurements.len());
    let mut k = 0;
    for m in &ds.measurements {
        while k < truth.t.len() && truth.t[k] < m.t - 1e-9 {
            k += 1;
        }
        match truth.t.get(k) {
            Some(t) if (t - m.t).abs() <= 1e-9 => out.push(truth.states[k].as_slice()),
            _ => return Err(format!("no true state at t = {} s", m.t)),
        }
    }
    Ok(out)
}

/// Moves a fix by `offset_m` (East, North, metres) at latitude `lat` (rad).
fn shift(position_deg: &mut Option<[f64; 2]>, lat: f64, offset_m: [f64; 2]) {
    if let Some(p) = position_deg.as_mut() {
        let sin_l = lat.sin();
        p[0] += (offset_m[1] / meridian_radius(sin_l)).to_degrees();
        p[1] += (offset_m[0] / (prime_vertical_radius(sin_l) * lat.cos())).to_degrees();
    }
}
