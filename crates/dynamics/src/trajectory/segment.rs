//! One segment of the path: what the vehicle does on it (standstill, speed change, turn,
//! cruise) with its `sin^2` profile, and the motion phase a report names it by.

use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// What the vehicle does on one segment.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Motion {
    /// Standing still.
    Standstill,
    /// Speed changes from `from` to `to` (m/s) along a `sin^2` acceleration profile.
    SpeedChange {
        /// Initial speed.
        from: f64,
        /// Final speed.
        to: f64,
    },
    /// Constant speed and heading.
    Cruise {
        /// Speed, m/s.
        speed: f64,
    },
    /// Heading changes by `delta` (rad, positive to the right) at constant `speed`.
    Turn {
        /// Speed, m/s.
        speed: f64,
        /// Heading change, rad.
        delta: f64,
    },
}

/// The thresholds that sort recorded motion into [`Phase`]s: one definition for `inspect`'s
/// summary and the diagnosis's per-phase NIS.
pub mod phase_thresholds {
    /// Below this speed the vehicle stands still, m/s (ten times the odometer's noise floor).
    pub const STILL_SPEED: f64 = 0.1;
    /// Along-track acceleration beyond which it accelerates or decelerates, m/s^2.
    pub const ALONG_ACCEL: f64 = 0.1;
    /// Heading rate beyond which it turns, deg/s.
    pub const TURN_RATE_DEG_S: f64 = 1.0;
}

/// Motion phase labels, for reports and the diagnosis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Phase {
    /// Not moving.
    Standstill,
    /// Speeding up.
    Accelerating,
    /// Constant speed, straight.
    Cruising,
    /// Turning.
    Turning,
    /// Slowing down.
    Decelerating,
}

/// One piece of the path.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Segment {
    /// Start time, s.
    pub start: f64,
    /// Duration, s.
    pub duration: f64,
    /// Heading at the start, rad from North, clockwise.
    pub heading: f64,
    /// What happens.
    pub motion: Motion,
    /// Label of the corner or leg (`O-A`, `turn A`, ...).
    pub label: &'static str,
    /// Rise of the road over the segment, m (a grade: it reaches the model as vertical
    /// acceleration in `fz`).
    pub climb: f64,
}

impl Segment {
    /// The motion phase of this segment.
    pub fn phase(&self) -> Phase {
        match self.motion {
            Motion::Standstill => Phase::Standstill,
            Motion::SpeedChange { from, to } if to > from => Phase::Accelerating,
            Motion::SpeedChange { .. } => Phase::Decelerating,
            Motion::Cruise { .. } => Phase::Cruising,
            Motion::Turn { .. } => Phase::Turning,
        }
    }

    /// Speed, its rate, heading and its rate at local time `tau` in `[0, duration]`.
    pub(super) fn kinematics(&self, tau: f64) -> (f64, f64, f64, f64) {
        let t = self.duration;
        // Smooth step: u(0) = 0, u(T) = 1, u'(t) = (2/T) sin^2(pi t / T).
        let smooth = |tau: f64| {
            let x = (tau / t).clamp(0.0, 1.0);
            (
                x - (2.0 * PI * x).sin() / (2.0 * PI),
                (1.0 - (2.0 * PI * x).cos()) / t,
            )
        };
        match self.motion {
            Motion::Standstill => (0.0, 0.0, self.heading, 0.0),
            Motion::Cruise { speed } => (speed, 0.0, self.heading, 0.0),
            Motion::SpeedChange { from, to } => {
                let (u, du) = smooth(tau);
                (from + (to - from) * u, (to - from) * du, self.heading, 0.0)
            }
            Motion::Turn { speed, delta } => {
                let (u, du) = smooth(tau);
                (speed, 0.0, self.heading + delta * u, delta * du)
            }
        }
    }

    pub(super) fn end_heading(&self) -> f64 {
        match self.motion {
            Motion::Turn { delta, .. } => self.heading + delta,
            _ => self.heading,
        }
    }
}
