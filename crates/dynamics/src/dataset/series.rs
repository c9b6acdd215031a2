//! A dataset's measurements as the time series its checks and its summary read: GPS fixes,
//! odometer velocities, odometer speeds, and the odometer as a track to integrate.
//!
//! Why one place: the plausibility checks, the implausibility checks and the summary each
//! picked these out of the rows themselves, and a strapdown odometer (a forward speed, not
//! an East-North velocity) was turned into a velocity in two ways. Each series is said once
//! here, with what it holds for each family.

use super::Dataset;

impl Dataset {
    /// The GPS fixes (degrees) with their times.
    pub(in crate::dataset) fn gps_fixes(&self) -> Vec<(f64, [f64; 2])> {
        self.measurements
            .iter()
            .filter_map(|m| m.position_deg.map(|p| (m.t, p)))
            .collect()
    }

    /// The platform odometer's East-North velocities with their times (empty for a
    /// strapdown odometer, which reads a speed).
    pub(in crate::dataset) fn odometer_velocities(&self) -> Vec<(f64, [f64; 2])> {
        self.measurements
            .iter()
            .filter_map(|m| m.velocity.map(|v| (m.t, v)))
            .collect()
    }

    /// The odometer's unsigned speeds with their times
    /// ([`super::Measurement::odometer_speed`]).
    pub(in crate::dataset) fn odometer_speeds(&self) -> Vec<(f64, f64)> {
        self.measurements
            .iter()
            .filter_map(|m| m.odometer_speed().map(|s| (m.t, s)))
            .collect()
    }

    /// The odometer as a velocity to integrate into a path: the platform's East-North
    /// velocity, or a strapdown unit's unsigned forward speed laid along North (its length
    /// is the path's; its direction means nothing).
    pub(in crate::dataset) fn odometer_track(&self) -> Vec<(f64, [f64; 2])> {
        self.measurements
            .iter()
            .filter_map(|m| {
                m.velocity
                    .or(m.speed.map(|s| [0.0, s.abs()]))
                    .map(|v| (m.t, v))
            })
            .collect()
    }
}
