//! `accel-quadratic`: accelerometer second-order scale error,
//! `nab_x += Ka2x fx^2`, `nab_y += Ka2y fy^2`: docs/model.md eq. (38).

use crate::effect::{Effect, PhysicalBound, Terms};
use crate::linear_rates::{Feature, LinearRate};
use crate::sensor_classes::ACCEL_NONLINEARITY;
use crate::state::{V_X, V_Y};

/// `nab_x += Ka2x fx^2`, `nab_y += Ka2y fy^2`.
const TERMS: &[LinearRate] = &[
    LinearRate {
        row: V_X,
        coefficient: 0,
        feature: Feature::SpecificForceSquared(0),
    },
    LinearRate {
        row: V_Y,
        coefficient: 1,
        feature: Feature::SpecificForceSquared(1),
    },
];

/// See the module documentation.
#[derive(Debug, Default, Clone)]
pub struct AccelQuadratic;

impl Effect for AccelQuadratic {
    fn name(&self) -> &str {
        "accel-quadratic"
    }
    fn description(&self) -> &str {
        "nab_x += Ka2x fx^2, nab_y += Ka2y fy^2 (second-order accelerometer scale error)"
    }
    fn terms(&self) -> Terms {
        Terms::linear(TERMS)
    }
    fn coefficient_names(&self) -> &[&str] {
        &["Ka2x", "Ka2y"]
    }
    fn coefficient_units(&self) -> &[&str] {
        &["1/(m/s^2)"; 2]
    }
    fn coefficient_sigma(&self) -> &[f64] {
        // 50 ug/g^2 = 4.9e-4 m/s^2 per (9.81 m/s^2)^2.
        &[5.1e-6; 2]
    }
    fn coefficient_bounds(&self) -> &[PhysicalBound] {
        &[ACCEL_NONLINEARITY; 2]
    }
}
