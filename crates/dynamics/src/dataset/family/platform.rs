//! The stabilised platform's dataset (`docs/data-format.md`): navigation-frame specific
//! forces in `inputs.csv`, an odometer's East and North velocity, the paper's coefficients
//! and the platform catalogue's effects.

use super::{FamilyFiles, Odometer};
use crate::dataset::read::{known_coefficients, read_inputs};
use crate::dataset::{
    DataWarning, Dataset, InputSample, INPUTS_FILE, INPUT_COLUMNS, MEASUREMENT_COLUMNS,
};
use crate::declared::EffectDeclaration;
use crate::effects::Registry;
use crate::error::DynamicsError;
use crate::model_kind::ModelKind;
use crate::state::{BASE_NAMES, NAV_DIM};
use std::path::Path;

/// The platform family's files.
pub(super) struct PlatformFiles;

impl FamilyFiles for PlatformFiles {
    fn kind(&self) -> ModelKind {
        ModelKind::Platform
    }
    fn inputs_file(&self) -> &'static str {
        INPUTS_FILE
    }
    fn input_columns(&self) -> &'static [&'static str] {
        &INPUT_COLUMNS
    }
    fn read_inputs(&self, path: &Path) -> Result<Vec<InputSample>, DynamicsError> {
        read_inputs(path)
    }
    fn specific_force(&self, s: &InputSample) -> [f64; 3] {
        [s.f[0], s.f[1], s.f[2]]
    }
    fn planar_force_words(&self) -> &'static str {
        "horizontal specific force"
    }
    fn turn_rate(&self) -> Option<fn(&InputSample) -> f64> {
        None
    }
    fn odometer(&self) -> Odometer {
        Odometer::VelocityEastNorth
    }
    fn measurement_columns(&self) -> &'static [&'static str] {
        &MEASUREMENT_COLUMNS
    }
    fn heading_word(&self) -> &'static str {
        "azimuth"
    }
    fn declare(
        &self,
        registry: &mut Registry,
        declared: &[EffectDeclaration],
    ) -> Result<Vec<String>, DynamicsError> {
        registry.declare(declared)?;
        Ok(known_coefficients(registry))
    }
    fn navigation_names(&self) -> &'static [&'static str] {
        &BASE_NAMES[..NAV_DIM]
    }
    fn initial_refused(&self) -> Option<&'static str> {
        Some(
            "a platform dataset has no attitude to state (its tilt is an error, stated by \
             [prior]); expected [model] kind = \"strapdown\" or no [initial]",
        )
    }
    fn has_pseudo_measurements(&self) -> bool {
        false
    }
    fn declaration_terms(&self) -> &'static str {
        "`rates` and `measurement` terms"
    }
    fn states_own_terms(&self, declaration: &EffectDeclaration) -> bool {
        !declaration.rates.is_empty() || !declaration.measurement.is_empty()
    }
    fn warnings(&self, dataset: &Dataset) -> Vec<DataWarning> {
        dataset.platform_warnings()
    }
}
