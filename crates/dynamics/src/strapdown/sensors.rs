//! The strapdown family's sensors as a [`MeasurementModel`]: a record's odometer speed, GPS
//! fix and (when the dataset gives `nhc_m_s`) the non-holonomic constraint's two zeros
//! become the five rows of docs/model.md eqs. (59), (60), with the platform's sigmas
//! (docs/model.md eq. (14)): `max(odometer_rel |s|, odometer_floor)` for the speed, `gps_m`
//! per horizontal axis for the fix, `nhc_m_s` for the constraint.
//!
//! The constraint holds whenever the vehicle's wheels are on the road, so it is applied at
//! each odometer time (a record without a speed has no constraint rows either: the spec ties
//! the constraint to the odometer's clock).
//!
//! **At a standstill** (a speed of exactly zero: a wheel that does not turn gives no count)
//! the vehicle's velocity is zero in every frame, and the record's speed and constraint rows
//! give way to the zero-velocity update: `v_e = v_n = 0` with the odometer's floor sigma
//! (docs/model.md eq. (61)). The body-frame rows say the same thing through the attitude,
//! and a filter linearising them at its own velocity estimate (a few cm/s off zero) reads
//! heading information into them that the data do not hold (docs/model.md eq. (61) says
//! how much).

use super::model::MEAS_DIM;
use super::state::LAT;
use crate::dataset::Measurement;
use crate::noise::NoiseConfig;
use crate::sensors::{write_observation, MeasurementModel};

/// The strapdown family's sensors, described by the dataset's noise table.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StrapdownSensors {
    /// Measurement sigmas (and `nhc_m_s`, whether the constraint is used).
    pub noise: NoiseConfig,
}

impl StrapdownSensors {
    /// The observation of `m` for an estimate at latitude `lat` (used for the GPS sigma when
    /// the record has no fix): `[s, L, lambda, 0, 0]`, sigmas and which rows are present.
    pub fn observation_of(
        &self,
        m: &Measurement,
        lat: f64,
    ) -> ([f64; MEAS_DIM], [f64; MEAS_DIM], [bool; MEAS_DIM]) {
        let mut z = [0.0; MEAS_DIM];
        let mut available = [false; MEAS_DIM];
        let mut lat = lat;
        if let Some(p) = m.gps_rad() {
            z[1] = p[0];
            z[2] = p[1];
            available[1] = true;
            available[2] = true;
            lat = p[0];
        }
        let speed = m.speed.unwrap_or(0.0);
        let gps = self.noise.measurement_sigmas(speed.abs(), lat);
        let nhc = self.noise.nhc_m_s.unwrap_or(f64::INFINITY);
        if m.speed == Some(0.0) {
            let [east, north] = m.zupt.unwrap_or([0.0, 0.0]);
            z[5] = east;
            z[6] = north;
            available[5] = true;
            available[6] = true;
        } else if m.speed.is_some() {
            z[0] = speed;
            available[0] = true;
            if self.noise.nhc_m_s.is_some() {
                let [lateral, vertical] = m.nhc.unwrap_or([0.0, 0.0]);
                z[3] = lateral;
                z[4] = vertical;
                available[3] = true;
                available[4] = true;
            }
        }
        let zupt = self.noise.zupt_sigma();
        let sigma = [
            self.noise.odometer_sigma(speed.abs()),
            gps[2],
            gps[3],
            nhc,
            nhc,
            zupt,
            zupt,
        ];
        (z, sigma, available)
    }
}

impl MeasurementModel for StrapdownSensors {
    type Record = Measurement;
    fn dim(&self) -> usize {
        MEAS_DIM
    }
    fn time(&self, record: &Measurement) -> f64 {
        record.t
    }
    fn observe(
        &self,
        record: &Measurement,
        state: &[f64],
        z: &mut [f64],
        sigma: &mut [f64],
        available: &mut [bool],
    ) {
        let lat = state.get(LAT).copied().unwrap_or(0.0);
        write_observation(self.observation_of(record, lat), z, sigma, available);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(speed: Option<f64>, fix: Option<[f64; 2]>) -> Measurement {
        Measurement {
            t: 1.0,
            velocity: None,
            speed,
            nhc: None,
            zupt: None,
            position_deg: fix,
        }
    }

    #[test]
    fn the_constraint_rides_on_the_odometer_and_only_when_stated() {
        let without = StrapdownSensors {
            noise: NoiseConfig::default(),
        };
        let with = StrapdownSensors {
            noise: NoiseConfig {
                nhc_m_s: Some(0.1),
                ..NoiseConfig::default()
            },
        };
        let full = record(Some(-2.0), Some([45.0, 7.0]));
        let (z, s, a) = with.observation_of(&full, 0.0);
        assert_eq!(a, [true, true, true, true, true, false, false]);
        assert_eq!(z[0], -2.0);
        assert!((z[1] - 45f64.to_radians()).abs() < 1e-15);
        assert_eq!([s[3], s[4]], [0.1, 0.1]);
        // A reversing vehicle's speed sigma grows with |s|, never negative.
        assert_eq!(s[0], (0.002f64 * 2.0).max(0.01));
        let (_, _, a) = without.observation_of(&full, 0.0);
        assert_eq!(a, [true, true, true, false, false, false, false]);
        let (_, _, a) = with.observation_of(&record(None, Some([45.0, 7.0])), 0.0);
        assert_eq!(a, [false, true, true, false, false, false, false]);
        let (_, _, a) = with.observation_of(&record(Some(3.0), None), 0.0);
        assert_eq!(a, [true, false, false, true, true, false, false]);
        // At a standstill the velocity is zero in every frame: the update is made in n.
        let (z, s, a) = without.observation_of(&record(Some(0.0), Some([45.0, 7.0])), 0.0);
        assert_eq!(a, [false, true, true, false, false, true, true]);
        assert_eq!([z[5], z[6], s[5]], [0.0, 0.0, 0.01]);
        // A barely moving vehicle is not standing: the odometer's row, not the update.
        let (_, _, a) = with.observation_of(&record(Some(1e-9), None), 0.0);
        assert_eq!(a, [true, false, false, true, true, false, false]);
    }
}
