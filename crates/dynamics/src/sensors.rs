//! The sensor side of a model: how a recorded measurement becomes what a filter updates on.
//!
//! The filters' runner is generic over [`MeasurementModel`] and never names the platform. The
//! platform's sensors (odometer velocity and GPS position, docs/model.md eqs. (13), (14)) are
//! described by its [`NoiseConfig`], which implements the trait for [`Measurement`] records:
//! the measured values, their sigmas from the noise model (the odometer's grow with speed, the
//! GPS's depend on latitude) and which channels are present.

use crate::dataset::Measurement;
use crate::noise::NoiseConfig;
use crate::state::{LAT, MEAS_DIM};

/// How records of type [`MeasurementModel::Record`] are observed.
pub trait MeasurementModel {
    /// One recorded measurement.
    type Record;
    /// Number of measurement channels.
    fn dim(&self) -> usize;
    /// The record's time, s.
    fn time(&self, record: &Self::Record) -> f64;
    /// Writes the observation of `record` for a filter whose current estimate is `state`: the
    /// measured values `z`, their one-sigmas and which channels are present (each
    /// [`MeasurementModel::dim`] long).
    fn observe(
        &self,
        record: &Self::Record,
        state: &[f64],
        z: &mut [f64],
        sigma: &mut [f64],
        available: &mut [bool],
    );
}

/// The observation of `m`: `[v_e, v_n, L, lambda]` (rad), sigmas from `noise`, and which
/// sensors are present. `fallback_lat` is used for the GPS sigma when GPS is absent.
pub fn observation_of(
    m: &Measurement,
    noise: &NoiseConfig,
    fallback_lat: f64,
) -> ([f64; MEAS_DIM], [f64; MEAS_DIM], [bool; MEAS_DIM]) {
    let mut z = [0.0; MEAS_DIM];
    let mut avail = [false; MEAS_DIM];
    let mut speed = 0.0;
    let mut lat = fallback_lat;
    if let Some(v) = m.velocity {
        z[0] = v[0];
        z[1] = v[1];
        avail[0] = true;
        avail[1] = true;
        speed = v[0].hypot(v[1]);
    }
    if let Some(p) = m.gps_rad() {
        z[2] = p[0];
        z[3] = p[1];
        avail[2] = true;
        avail[3] = true;
        lat = p[0];
    }
    (z, noise.measurement_sigmas(speed, lat), avail)
}

impl MeasurementModel for NoiseConfig {
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
        write_observation(observation_of(record, self, lat), z, sigma, available);
    }
}

/// Writes an observation `(z, sigma, available)` of `N` rows into a runner's buffers (the
/// first `N` of each), as [`MeasurementModel::observe`] does.
pub fn write_observation<const N: usize>(
    (zz, ss, aa): ([f64; N], [f64; N], [bool; N]),
    z: &mut [f64],
    sigma: &mut [f64],
    available: &mut [bool],
) {
    z[..N].copy_from_slice(&zz);
    sigma[..N].copy_from_slice(&ss);
    available[..N].copy_from_slice(&aa);
}
