//! What a user asks for when they name a filter: its kind, the sigma-point scaling and the
//! attitude equations of the model it runs on. Parsed once at the edge (a study file's
//! `[filter]` table and its variants, a diagnosis study's `[diagnosis]`, the CLI's `--filter`)
//! and passed as this one value everywhere after, so no code below the edge handles a
//! filter's name as a string.
//!
//! ```
//! use navkf_dynamics::{Attitude, NoiseConfig, PlatformModel};
//! use navkf_filters::{FilterKind, FilterSpec};
//! use std::sync::Arc;
//!
//! let spec = FilterSpec {
//!     attitude: Attitude::Exact,
//!     ..FilterSpec::new(FilterKind::SimplifiedUkf)
//! };
//! // The model is built in the spec's attitude equations, then the filter on it.
//! let model = Arc::new(PlatformModel::base(&NoiseConfig::default()).with_attitude(spec.attitude));
//! let filter = spec.build(model).unwrap();
//! assert_eq!(filter.name(), "simplified_ukf");
//! assert_eq!(FilterSpec::default().kind, FilterKind::Ekf);
//! ```

use crate::error::FilterError;
use crate::filter::Filter;
use crate::kind::FilterKind;
use crate::sigma_points::SigmaScaling;
use navkf_dynamics::{Attitude, SystemModel};
use std::sync::Arc;

/// A filter as a user specifies it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FilterSpec {
    /// Which filter.
    pub kind: FilterKind,
    /// Sigma-point scaling (the UKFs'; the EKF ignores it).
    pub scaling: SigmaScaling,
    /// The attitude equations of the model the filter runs on: the small-angle form
    /// (docs/model.md eqs. (8), (9)) or the exact variant (docs/model.md eqs. (45)-(48)).
    pub attitude: Attitude,
}

impl FilterSpec {
    /// `kind` with the paper's scaling on the small-angle model.
    pub fn new(kind: FilterKind) -> Self {
        FilterSpec {
            kind,
            scaling: SigmaScaling::default(),
            attitude: Attitude::SmallAngle,
        }
    }

    /// Builds the filter for `model`, which the caller has built in [`FilterSpec::attitude`].
    pub fn build<M: SystemModel + ?Sized + 'static>(
        &self,
        model: Arc<M>,
    ) -> Result<Box<dyn Filter>, FilterError> {
        self.kind.build(model, self.scaling)
    }
}

impl Default for FilterSpec {
    /// The EKF on the small-angle model: on the platform model it gives the UKFs' likelihood
    /// to 1e-3 of 7e4 (the paper study finds the filters equal to four digits), and with
    /// effects that add rates it costs about half a sigma-point filter's step (docs/speed.md).
    fn default() -> Self {
        FilterSpec::new(FilterKind::Ekf)
    }
}
