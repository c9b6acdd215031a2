//! `gyro-fz`: gyro drift proportional to the vertical specific force,
//! `eps_i += Kg13i fz` for i = x, y, z (a g-sensitive drift along the spin-axis direction):
//! docs/model.md eq. (37).
//!
//! On a level vehicle `fz` is nearly constant (gravity), so on a flat trajectory this term is
//! almost indistinguishable from the constant drift `Kg0i`: the diagnosis reports that.

use crate::effect::{Effect, PhysicalBound, Terms};
use crate::linear_rates::{Feature, LinearRate};
use crate::sensor_classes::GYRO_G_SENSITIVITY;
use crate::state::{PHI_X, PHI_Y, PHI_Z};

/// `eps_i += Kg13i fz`.
const TERMS: &[LinearRate] = &[
    LinearRate {
        row: PHI_X,
        coefficient: 0,
        feature: Feature::SpecificForce(2),
    },
    LinearRate {
        row: PHI_Y,
        coefficient: 1,
        feature: Feature::SpecificForce(2),
    },
    LinearRate {
        row: PHI_Z,
        coefficient: 2,
        feature: Feature::SpecificForce(2),
    },
];

/// See the module documentation.
#[derive(Debug, Default, Clone)]
pub struct GyroFz;

impl Effect for GyroFz {
    fn name(&self) -> &str {
        "gyro-fz"
    }
    fn description(&self) -> &str {
        "eps_i += Kg13i fz (gyro drift per unit vertical specific force)"
    }
    fn terms(&self) -> Terms {
        Terms::linear(TERMS)
    }
    fn coefficient_names(&self) -> &[&str] {
        &["Kg13x", "Kg13y", "Kg13z"]
    }
    fn coefficient_units(&self) -> &[&str] {
        &["rad/s/(m/s^2)"; 3]
    }
    fn coefficient_sigma(&self) -> &[f64] {
        // 0.02 deg/h per g.
        &[9.9e-9; 3]
    }
    fn coefficient_bounds(&self) -> &[PhysicalBound] {
        &[GYRO_G_SENSITIVITY; 3]
    }
}
