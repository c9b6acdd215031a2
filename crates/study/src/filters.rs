//! The filters a study can compare, built by name.

use navkf_dynamics::PlatformModel;
use navkf_filters::{
    simplified_ukf, standard_ukf, Ekf, Filter, FilterError, SigmaScaling, SquareRootUkf,
};
use std::sync::Arc;

/// Names a study file may list.
pub const KNOWN: [&str; 5] = [
    "ekf",
    "standard_ukf",
    "standard_ukf_25",
    "simplified_ukf",
    "square_root_ukf",
];

/// Builds the filter called `name` for `model`.
pub fn build(
    name: &str,
    model: Arc<PlatformModel>,
    scaling: SigmaScaling,
) -> Result<Box<dyn Filter>, FilterError> {
    Ok(match name {
        "ekf" => Box::new(Ekf::new(model)),
        "standard_ukf" => Box::new(standard_ukf::new(model, scaling)?),
        "standard_ukf_25" => Box::new(standard_ukf::process_only(model, scaling)?),
        "simplified_ukf" => Box::new(simplified_ukf::new(model, scaling)?),
        "square_root_ukf" => Box::new(SquareRootUkf::new(model, scaling)?),
        other => {
            return Err(FilterError::Invalid(format!(
                "unknown filter `{other}`; expected one of {}",
                KNOWN.join(", ")
            )))
        }
    })
}
