//! `gyro-bias-walk`: the constant drifts `Kg0x, Kg0y, Kg0z` wander as random walks of
//! spectral density `q_b` (rad^2/s^3), docs/model.md eq. (44). No coefficients: it changes
//! the noise model only.

use crate::effect::{Effect, NoiseChannel, Terms};
use crate::state::KG0X;

/// See the module documentation.
#[derive(Debug, Clone)]
pub struct GyroBiasWalk {
    /// `q_b`, rad^2/s^3.
    pub psd: f64,
}

impl GyroBiasWalk {
    /// Default `q_b = 1e-18 rad^2/s^3`: over the 2400 s test the drift wanders by
    /// `sqrt(q_b T)` = 4.9e-8 rad/s, about 0.01 deg/h, a navigation-grade bias instability.
    pub const DEFAULT_PSD: f64 = 1.0e-18;
}

impl Default for GyroBiasWalk {
    fn default() -> Self {
        GyroBiasWalk {
            psd: Self::DEFAULT_PSD,
        }
    }
}

impl Effect for GyroBiasWalk {
    fn name(&self) -> &str {
        "gyro-bias-walk"
    }
    fn description(&self) -> &str {
        "Kg0x, Kg0y, Kg0z wander as random walks of density q_b (rad^2/s^3)"
    }
    fn terms(&self) -> Terms {
        Terms::NOISE
    }
    fn process_noise(&self) -> Vec<NoiseChannel> {
        ["w_bx", "w_by", "w_bz"]
            .iter()
            .enumerate()
            .map(|(a, name)| NoiseChannel {
                name: name.to_string(),
                state: KG0X + 3 * a,
                psd: self.psd,
            })
            .collect()
    }
    fn set_parameter(&mut self, value: f64) -> Result<(), String> {
        if value.is_finite() && value >= 0.0 {
            self.psd = value;
            Ok(())
        } else {
            Err(format!(
                "gyro-bias-walk density {value}: expected a finite q_b >= 0 in rad^2/s^3"
            ))
        }
    }
}
