//! Figures of a diagnosis (drawn once the plotting module lands; until then none).

use super::{Diagnosis, Fit};
use crate::error::StudyError;
use navkf_dynamics::dataset::Dataset;
use std::path::Path;

/// Draws the diagnosis figures into `dir`; returns `(title, relative path)` of each.
pub fn draw(
    _ds: &Dataset,
    _d: &Diagnosis,
    _fit: &Fit,
    _dir: &Path,
) -> Result<Vec<(String, String)>, StudyError> {
    Ok(Vec::new())
}
