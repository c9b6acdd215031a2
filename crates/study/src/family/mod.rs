//! What a study needs of a model family beyond [`navkf_dynamics::family`]'s traits: the
//! parts a Monte Carlo study runs ([`FamilyParts`]), the simulator `navkf simulate` writes a
//! dataset with, and the report's line on its truth.
//!
//! Why a trait: everything after these runs on the families' traits, so a new family's
//! studies are one folder here (its implementation of [`StudyFamily`]) and one arm of
//! [`of`], its registration, instead of branches through Monte Carlo, simulation, report and
//! figures. What a study file may say for each family is the file's own business, checked
//! where it is read (`config/model.rs`), below this module: the configuration never depends
//! on what is built from it.

mod platform;
mod strapdown;

use crate::config::StudyConfig;
use crate::error::StudyError;
use crate::simulation::request::{Ready, SimulationRequest};
use navkf_dynamics::{Attitude, FamilyModel, ModelKind, NoiseConfig, Trajectory, TruthSimulation};
use navkf_report::SettingNames;
use std::sync::Arc;

/// The filters' model in a given attitude form.
pub(crate) type ModelInAttitude = Box<dyn Fn(Attitude) -> Result<Arc<dyn FamilyModel>, StudyError>>;

/// A family's parts for one study.
pub(crate) struct FamilyParts {
    /// The truth simulator.
    pub sim: Box<dyn TruthSimulation>,
    /// The filters' model in `[filter] attitude`.
    pub filter_model: Arc<dyn FamilyModel>,
    /// The filters' model in another attitude form (a variant's).
    pub filter_model_in: ModelInAttitude,
}

/// A model family as a study runs it (module documentation).
pub(crate) trait StudyFamily: Sync {
    /// The report's line on the truth (`truth: ...`), its effects already listed.
    fn truth_line(&self, config: &StudyConfig, effects: &str) -> String;

    /// The truth simulator and the filters' model of `config`, on `trajectory`.
    fn parts(
        &self,
        config: &StudyConfig,
        trajectory: Arc<Trajectory>,
    ) -> Result<FamilyParts, StudyError>;

    /// Checks `req` for the family and builds the simulator of `navkf simulate`.
    fn prepare(&self, req: &SimulationRequest, names: SettingNames) -> Result<Ready, StudyError>;
}

/// The family `kind` as a study runs it: the families' registration.
pub(crate) fn of(kind: ModelKind) -> &'static dyn StudyFamily {
    match kind {
        ModelKind::Platform => &platform::Platform,
        ModelKind::Strapdown => &strapdown::Strapdown,
    }
}

/// The noise the filters assume: the truth's with the densities scaled.
fn filter_noise(config: &StudyConfig, noise: NoiseConfig) -> NoiseConfig {
    NoiseConfig {
        gyro_psd: noise.gyro_psd * config.filter.process_noise_scale,
        accel_psd: noise.accel_psd * config.filter.process_noise_scale,
        ..noise
    }
}
