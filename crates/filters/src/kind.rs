//! The one list of filters: every filter's name, one line about it, and how to build it.
//!
//! The study's filter names, the CLI's help, the benches and every test that runs "all
//! filters" iterate over [`FilterKind::ALL`], so a new filter is its file plus one variant
//! here (the `match`es below then refuse to compile until it is named, documented and
//! built).
//!
//! ```
//! use navkf_dynamics::{NoiseConfig, PlatformModel};
//! use navkf_filters::{FilterKind, SigmaScaling};
//! use std::sync::Arc;
//!
//! let model = Arc::new(PlatformModel::base(&NoiseConfig::default()));
//! for kind in FilterKind::ALL {
//!     let filter = kind.build(model.clone(), SigmaScaling::default()).unwrap();
//!     assert_eq!(filter.name(), kind.name());
//!     assert_eq!(kind.name().parse::<FilterKind>().unwrap(), kind);
//! }
//! assert!("kalman".parse::<FilterKind>().is_err());
//! ```

use crate::error::FilterError;
use crate::filter::Filter;
use crate::sigma_points::SigmaScaling;
use crate::{Ekf, SquareRootUkf, Ukf};
use navkf_dynamics::SystemModel;
use std::fmt;
use std::str::FromStr;
use std::sync::Arc;

/// A filter the harness has.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum FilterKind {
    /// [`Ekf`].
    Ekf,
    /// [`Ukf::standard`].
    StandardUkf,
    /// [`Ukf::standard_process_only`].
    StandardUkf25,
    /// [`Ukf::simplified`].
    SimplifiedUkf,
    /// [`SquareRootUkf`].
    SquareRootUkf,
}

impl FilterKind {
    /// Every filter, in the order reports list them.
    pub const ALL: [FilterKind; 5] = [
        FilterKind::Ekf,
        FilterKind::StandardUkf,
        FilterKind::StandardUkf25,
        FilterKind::SimplifiedUkf,
        FilterKind::SquareRootUkf,
    ];

    /// Its name, as study files, the CLI and reports write it.
    pub fn name(self) -> &'static str {
        match self {
            FilterKind::Ekf => "ekf",
            FilterKind::StandardUkf => "standard_ukf",
            FilterKind::StandardUkf25 => "standard_ukf_25",
            FilterKind::SimplifiedUkf => "simplified_ukf",
            FilterKind::SquareRootUkf => "square_root_ukf",
        }
    }

    /// One line about it.
    pub fn doc(self) -> &'static str {
        match self {
            FilterKind::Ekf => "extended Kalman filter, exact Jacobian of the RK4 step",
            FilterKind::StandardUkf => {
                "the paper's standard UKF, state augmented with process and measurement noise"
            }
            FilterKind::StandardUkf25 => {
                "the standard UKF augmented with the process noise only (additive R)"
            }
            FilterKind::SimplifiedUkf => {
                "the paper's simplified UKF: additive Q, linear update while h is linear"
            }
            FilterKind::SquareRootUkf => {
                "the simplified UKF carrying a Cholesky factor instead of the covariance"
            }
        }
    }

    /// Every name, comma-separated (for messages and help).
    pub fn names() -> String {
        Self::ALL.map(Self::name).join(", ")
    }

    /// Builds it for `model` with `scaling` (the EKF ignores the scaling).
    pub fn build<M: SystemModel + ?Sized + 'static>(
        self,
        model: Arc<M>,
        scaling: SigmaScaling,
    ) -> Result<Box<dyn Filter>, FilterError> {
        Ok(match self {
            FilterKind::Ekf => Box::new(Ekf::new(model)),
            FilterKind::StandardUkf => Box::new(Ukf::standard(model, scaling)?),
            FilterKind::StandardUkf25 => Box::new(Ukf::standard_process_only(model, scaling)?),
            FilterKind::SimplifiedUkf => Box::new(Ukf::simplified(model, scaling)?),
            FilterKind::SquareRootUkf => Box::new(SquareRootUkf::new(model, scaling)?),
        })
    }
}

impl fmt::Display for FilterKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for FilterKind {
    type Err = FilterError;
    fn from_str(s: &str) -> Result<Self, FilterError> {
        Self::ALL
            .into_iter()
            .find(|k| k.name() == s)
            .ok_or_else(|| {
                FilterError::Invalid(format!(
                    "unknown filter `{s}`; expected one of {}",
                    Self::names()
                ))
            })
    }
}

/// Study files write a filter by its name; an unknown name is refused with the list.
impl serde::Serialize for FilterKind {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

impl<'de> serde::Deserialize<'de> for FilterKind {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let name = String::deserialize(d)?;
        name.parse().map_err(serde::de::Error::custom)
    }
}
