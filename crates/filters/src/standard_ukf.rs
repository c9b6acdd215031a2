//! The standard UKF of the paper (section 3.1): the state augmented with the process noise
//! and, by default, the measurement noise, `X^a = [X; W; V]` (n = 29 for the base model);
//! every sigma point goes through the dynamics and the measurement function.
//!
//! [`process_only`] builds the variant that augments `W` only (n = 25), which the paper's
//! text counts.

use crate::error::FilterError;
use crate::sigma_points::SigmaScaling;
use crate::ukf::{NoiseHandling, Ukf};
use navkf_dynamics::SystemModel;
use std::sync::Arc;

/// The standard UKF with `X^a = [X; W; V]`.
///
/// ```
/// use navkf_dynamics::{NoiseConfig, PlatformModel};
/// use navkf_filters::{standard_ukf, SigmaScaling};
/// use std::sync::Arc;
/// let model = Arc::new(PlatformModel::base(&NoiseConfig::default()));
/// let ukf = standard_ukf::new(model, SigmaScaling::default()).unwrap();
/// assert_eq!(ukf.sigma_dim(), 29);
/// // The 8 measurement-noise points share the centre's propagation.
/// assert_eq!(ukf.propagated_points(), 2 * 25 + 1);
/// ```
pub fn new<M: SystemModel + ?Sized>(
    model: Arc<M>,
    scaling: SigmaScaling,
) -> Result<Ukf<M>, FilterError> {
    Ukf::new(
        model,
        "standard_ukf",
        NoiseHandling::AugmentProcessAndMeasurement,
        false,
        scaling,
    )
}

/// The standard UKF with `X^a = [X; W]` (n = 25 for the base model) and additive `R`.
pub fn process_only<M: SystemModel + ?Sized>(
    model: Arc<M>,
    scaling: SigmaScaling,
) -> Result<Ukf<M>, FilterError> {
    Ukf::new(
        model,
        "standard_ukf_25",
        NoiseHandling::AugmentProcess,
        false,
        scaling,
    )
}
