//! `accel-cross-axis`: accelerometer cross-axis sensitivity (input-axis misalignment),
//! `nab_x += Ka12x fy`, `nab_y += Ka12y fx`: docs/model.md eq. (39).
//!
//! Its antisymmetric part, `Ka12x = -Ka12y = k`, adds `k [fy, -fx]`: the accelerometer pair
//! turned about the vertical, which is the term an azimuth error `phi_z = k` adds to the
//! velocity rates (docs/model.md eq. (9)). The initial azimuth error takes it up, so no
//! vehicle test sees it (on the paper's drive, `Ka12x = -Ka12y = 5e-3`, fifty typical sigmas,
//! fits no better than nothing: BIC gain -18, where `Ka12x = Ka12y = 5e-3` gains 3900). Only
//! the symmetric part, a non-orthogonality, is the effect's own.

use crate::effect::{Effect, PhysicalBound, Terms, UnseenCombination};
use crate::linear_rates::{Feature, LinearRate};
use crate::sensor_classes::SCALE;
use crate::state::{V_X, V_Y};

/// `nab_x += Ka12x fy`, `nab_y += Ka12y fx`.
const TERMS: &[LinearRate] = &[
    LinearRate {
        row: V_X,
        coefficient: 0,
        feature: Feature::SpecificForce(1),
    },
    LinearRate {
        row: V_Y,
        coefficient: 1,
        feature: Feature::SpecificForce(0),
    },
];

/// See the module documentation.
#[derive(Debug, Default, Clone)]
pub struct AccelCrossAxis;

impl Effect for AccelCrossAxis {
    fn name(&self) -> &str {
        "accel-cross-axis"
    }
    fn description(&self) -> &str {
        "nab_x += Ka12x fy, nab_y += Ka12y fx (accelerometer cross-axis coupling)"
    }
    fn terms(&self) -> Terms {
        Terms::linear(TERMS)
    }
    fn coefficient_names(&self) -> &[&str] {
        &["Ka12x", "Ka12y"]
    }
    fn coefficient_units(&self) -> &[&str] {
        &["1"; 2]
    }
    fn coefficient_sigma(&self) -> &[f64] {
        // 20 arcsec of input-axis misalignment.
        &[1.0e-4; 2]
    }
    fn coefficient_bounds(&self) -> &[PhysicalBound] {
        &[SCALE; 2]
    }
    fn unseen_combinations(&self) -> &[UnseenCombination] {
        &[UnseenCombination {
            weights: &[1.0, -1.0],
            why: "`Ka12x = -Ka12y` (the accelerometers turned about the vertical), which the \
                  initial azimuth error takes up",
        }]
    }
}
