//! `torquer-scale`: scale error of the platform's torquing commands,
//! `phi' += diag(kt) w_cmd`, `w_cmd = [-v_y/RM, wie cosL + v_x/RN, wie sinL + v_x tanL/RN]`:
//! docs/model.md eq. (40), with `w_cmd` of docs/model.md eq. (7).
//!
//! This is where the navigation-frame rate terms of the paper's printed attitude equations
//! come back (docs/model.md, "Where the project departs from the paper", item 2): the
//! platform follows the commanded rate only up to the torquer's scale factor.

use crate::effect::{Effect, PhysicalBound, Terms};
use crate::linear_rates::{Feature, LinearRate};
use crate::sensor_classes::SCALE;
use crate::state::{PHI_X, PHI_Y, PHI_Z};

/// `phi_i' += kt_i w_cmd_i` (the partials of `w_cmd` are [`Feature::CommandedRate`]'s).
const TERMS: &[LinearRate] = &[
    LinearRate {
        row: PHI_X,
        coefficient: 0,
        feature: Feature::CommandedRate(0),
    },
    LinearRate {
        row: PHI_Y,
        coefficient: 1,
        feature: Feature::CommandedRate(1),
    },
    LinearRate {
        row: PHI_Z,
        coefficient: 2,
        feature: Feature::CommandedRate(2),
    },
];

/// See the module documentation.
#[derive(Debug, Default, Clone)]
pub struct TorquerScale;

impl Effect for TorquerScale {
    fn name(&self) -> &str {
        "torquer-scale"
    }
    fn description(&self) -> &str {
        "phi' += diag(kt) w_cmd (scale error of the torquing commands)"
    }
    fn terms(&self) -> Terms {
        Terms::linear(TERMS)
    }
    fn coefficient_names(&self) -> &[&str] {
        &["ktx", "kty", "ktz"]
    }
    fn coefficient_units(&self) -> &[&str] {
        &["1"; 3]
    }
    fn coefficient_sigma(&self) -> &[f64] {
        // 300 ppm torquer scale error.
        &[3.0e-4; 3]
    }
    fn coefficient_bounds(&self) -> &[PhysicalBound] {
        &[SCALE; 3]
    }
}
