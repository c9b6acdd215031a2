//! The strapdown unit's dataset (`docs/data-format.md`, "Strapdown datasets"): body rates
//! and specific forces in `imu.csv` (as rates or increments), an odometer's forward speed,
//! the unit's biases and the strapdown catalogue's effects.

use super::{FamilyFiles, Odometer};
use crate::dataset::read::{read_imu, strapdown_coefficients};
use crate::dataset::{
    DataWarning, Dataset, InputSample, IMU_FILE, IMU_RATE_COLUMNS, SPEED_MEASUREMENT_COLUMNS,
};
use crate::declared::{EffectCatalogue, EffectDeclaration};
use crate::effects::Registry;
use crate::error::DynamicsError;
use crate::model_kind::ModelKind;
use crate::strapdown::effects::StrapdownRegistry;
use crate::strapdown::state::{ACCEL_DEPARTURE_NAMES, GYRO_DEPARTURE_NAMES, NAV_DIM, STATE_NAMES};
use std::path::Path;

/// The states of the bias instabilities' departures (docs/model.md eq. (69)).
const DEPARTURE_NAMES: [&str; 6] = [
    GYRO_DEPARTURE_NAMES[0],
    GYRO_DEPARTURE_NAMES[1],
    GYRO_DEPARTURE_NAMES[2],
    ACCEL_DEPARTURE_NAMES[0],
    ACCEL_DEPARTURE_NAMES[1],
    ACCEL_DEPARTURE_NAMES[2],
];

/// The strapdown family's files.
pub(super) struct StrapdownFiles;

impl FamilyFiles for StrapdownFiles {
    fn kind(&self) -> ModelKind {
        ModelKind::Strapdown
    }
    fn inputs_file(&self) -> &'static str {
        IMU_FILE
    }
    /// The writer writes rates; the reader takes increments too.
    fn input_columns(&self) -> &'static [&'static str] {
        &IMU_RATE_COLUMNS
    }
    fn read_inputs(&self, path: &Path) -> Result<Vec<InputSample>, DynamicsError> {
        read_imu(path)
    }
    /// A sample holds the body rate first (docs/model.md eq. (50)).
    fn specific_force(&self, s: &InputSample) -> [f64; 3] {
        [s.f[3], s.f[4], s.f[5]]
    }
    fn planar_force_words(&self) -> &'static str {
        "specific force in the unit's x-y plane"
    }
    /// The rate about the unit's up axis (the Earth's rate, 0.004 deg/s, is noise here).
    fn turn_rate(&self) -> Option<fn(&InputSample) -> f64> {
        Some(|s| s.f[2])
    }
    fn odometer(&self) -> Odometer {
        Odometer::ForwardSpeed
    }
    fn measurement_columns(&self) -> &'static [&'static str] {
        &SPEED_MEASUREMENT_COLUMNS
    }
    fn heading_word(&self) -> &'static str {
        "heading"
    }
    /// The platform `registry` is left as it is: the strapdown effects are another
    /// catalogue's.
    fn declare(
        &self,
        _: &mut Registry,
        declared: &[EffectDeclaration],
    ) -> Result<Vec<String>, DynamicsError> {
        let catalogue = StrapdownRegistry::with_declared(declared)?;
        Ok(strapdown_coefficients(&catalogue))
    }
    fn navigation_names(&self) -> &'static [&'static str] {
        &STATE_NAMES[..NAV_DIM]
    }
    fn other_truth_names(&self) -> &'static [&'static str] {
        &DEPARTURE_NAMES
    }
    fn initial_refused(&self) -> Option<&'static str> {
        None
    }
    fn has_pseudo_measurements(&self) -> bool {
        true
    }
    fn declaration_terms(&self) -> &'static str {
        "`places`"
    }
    fn states_own_terms(&self, declaration: &EffectDeclaration) -> bool {
        !declaration.places.is_empty()
    }
    fn warnings(&self, dataset: &Dataset) -> Vec<DataWarning> {
        dataset.strapdown_warnings()
    }
}
