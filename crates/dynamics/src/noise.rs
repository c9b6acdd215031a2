//! Sensor and process noise: the `[noise]` table of `dataset.toml`, with the project's
//! documented defaults (data-format.md): the densities `q_g`, `q_a` of docs/model.md eq. (12)
//! and the measurement sigmas of docs/model.md eq. (14).

use crate::earth::{meridian_radius, prime_vertical_radius};
use crate::state::MEAS_DIM;
use serde::{Deserialize, Serialize};

/// Noise densities and sensor accuracies. Field names are the keys of `dataset.toml`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct NoiseConfig {
    /// `q_g`, gyro white-noise spectral density, rad^2/s (1e-14: angle random walk of
    /// 1e-7 rad/sqrt(s), about 0.00034 deg/sqrt(h), navigation grade).
    pub gyro_psd: f64,
    /// `q_a`, accelerometer white-noise spectral density, (m/s^2)^2/s (1e-8: velocity random
    /// walk 1e-4 m/s/sqrt(s), about 10 ug/sqrt(Hz)).
    pub accel_psd: f64,
    /// Odometer relative accuracy (paper: 2 per mille).
    pub odometer_rel: f64,
    /// Odometer accuracy floor at low speed, m/s.
    pub odometer_floor: f64,
    /// GPS horizontal position one-sigma, metres (paper: 3 m).
    pub gps_m: f64,
    /// One-sigma of the non-holonomic constraint's pseudo-measurements, m/s (the strapdown
    /// family, docs/model.md eq. (60)); absent: the constraint is not used.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub nhc_m_s: Option<f64>,
    /// One-sigma of the zero-velocity update's pseudo-measurements at a standstill, m/s (the
    /// strapdown family, docs/model.md eq. (61)); absent: `odometer_floor`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub zupt_m_s: Option<f64>,
}

impl Default for NoiseConfig {
    fn default() -> Self {
        NoiseConfig {
            gyro_psd: 1.0e-14,
            accel_psd: 1.0e-8,
            odometer_rel: 0.002,
            odometer_floor: 0.01,
            gps_m: 3.0,
            nhc_m_s: None,
            zupt_m_s: None,
        }
    }
}

impl NoiseConfig {
    /// Checks that every value is finite and positive; names the offending key.
    pub fn validate(&self) -> Result<(), String> {
        for (key, v) in [
            ("gyro_psd", self.gyro_psd),
            ("accel_psd", self.accel_psd),
            ("odometer_rel", self.odometer_rel),
            ("odometer_floor", self.odometer_floor),
            ("gps_m", self.gps_m),
            ("nhc_m_s", self.nhc_m_s.unwrap_or(1.0)),
            ("zupt_m_s", self.zupt_m_s.unwrap_or(1.0)),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(format!("noise.{key} = {v}: expected a finite number > 0"));
            }
        }
        Ok(())
    }

    /// One-sigma of the zero-velocity update's rows, m/s: `zupt_m_s`, else the odometer's
    /// floor.
    pub fn zupt_sigma(&self) -> f64 {
        self.zupt_m_s.unwrap_or(self.odometer_floor)
    }

    /// One-sigma of the odometer's velocity at speed `speed` (m/s), per axis.
    #[inline]
    pub fn odometer_sigma(&self, speed: f64) -> f64 {
        (self.odometer_rel * speed).max(self.odometer_floor)
    }

    /// Measurement standard deviations `[v_x, v_y, L, lambda]` at speed `speed` and latitude
    /// `lat` (rad): `sigma_L = gps / RM`, `sigma_lambda = gps / (RN cos L)`
    /// (docs/model.md eq. (14)).
    pub fn measurement_sigmas(&self, speed: f64, lat: f64) -> [f64; MEAS_DIM] {
        let (s, c) = lat.sin_cos();
        let sv = self.odometer_sigma(speed);
        [
            sv,
            sv,
            self.gps_m / meridian_radius(s),
            self.gps_m / (prime_vertical_radius(s) * c),
        ]
    }
}
