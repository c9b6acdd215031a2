//! The filters a study can compare, built by name: [`FilterKind`] is the one list.

use navkf_dynamics::PlatformModel;
use navkf_filters::{Filter, FilterError, FilterKind, SigmaScaling};
use std::sync::Arc;

/// Whether `name` names a filter.
pub fn is_known(name: &str) -> bool {
    name.parse::<FilterKind>().is_ok()
}

/// Every filter name, comma-separated (for messages).
pub fn names() -> String {
    FilterKind::names()
}

/// Builds the filter called `name` for `model`.
pub fn build(
    name: &str,
    model: Arc<PlatformModel>,
    scaling: SigmaScaling,
) -> Result<Box<dyn Filter>, FilterError> {
    name.parse::<FilterKind>()?.build(model, scaling)
}
