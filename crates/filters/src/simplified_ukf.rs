//! The simplified UKF of the paper (section 3.2): no augmentation, additive `Q_k` on the
//! predicted covariance, and the Kalman filter's linear update `Z = H X` because the base
//! model's measurement is linear. When an effect makes the measurement non-linear
//! (`odometer-scale`, `gps-latency`), the update falls back to sigma points drawn from the
//! prediction.

use crate::error::FilterError;
use crate::sigma_points::SigmaScaling;
use crate::ukf::{NoiseHandling, Ukf};
use navkf_dynamics::SystemModel;
use std::sync::Arc;

/// The simplified UKF.
///
/// ```
/// use navkf_dynamics::{NoiseConfig, PlatformModel, Registry};
/// use navkf_filters::{simplified_ukf, SigmaScaling};
/// use std::sync::Arc;
/// let noise = NoiseConfig::default();
/// let base = Arc::new(PlatformModel::base(&noise));
/// let ukf = simplified_ukf::new(base, SigmaScaling::default()).unwrap();
/// assert_eq!(ukf.sigma_dim(), 20);
/// assert!(ukf.uses_linear_update());
/// let odo = Registry::catalogue().build_all(&["odometer-scale"]).unwrap();
/// let model = Arc::new(PlatformModel::new(odo, &noise).unwrap());
/// assert!(!simplified_ukf::new(model, SigmaScaling::default()).unwrap().uses_linear_update());
/// ```
pub fn new<M: SystemModel + ?Sized>(
    model: Arc<M>,
    scaling: SigmaScaling,
) -> Result<Ukf<M>, FilterError> {
    Ukf::new(
        model,
        "simplified_ukf",
        NoiseHandling::Additive,
        true,
        scaling,
    )
}
