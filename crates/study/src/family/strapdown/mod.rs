//! A strapdown unit as a study runs it (docs/model.md, "The strapdown family"): the unit
//! class's biases and reading noise, the strapdown catalogue's effects, the truth read off
//! the path itself.

mod simulation;

use super::{filter_noise, FamilyParts, StudyFamily};
use crate::config::StudyConfig;
use crate::error::StudyError;
use crate::simulation::request::{Ready, SimulationRequest};
use navkf_dynamics::strapdown::effect_list::StrapdownEffectList;
use navkf_dynamics::strapdown::model::StrapdownModel;
use navkf_dynamics::strapdown::simulate::StrapdownSimulator;
use navkf_dynamics::{FamilyModel, NoiseConfig, Trajectory};
use navkf_report::SettingNames;
use std::sync::Arc;

/// The strapdown family.
pub(super) struct Strapdown;

impl StudyFamily for Strapdown {
    fn truth_line(&self, c: &StudyConfig, effects: &str) -> String {
        let unit = c.model.unit_class();
        let e = unit.errors();
        // Six decimals, without trailing zeros (50 deg/h, not 50.000).
        let rounded = |x: f64| (x * 1e6).round() / 1e6;
        format!(
            "truth: a strapdown {} unit (biases {} deg/h and {} mg one sigma, effects {effects}, drawn at {} x their typical sigma) on the path itself; IMU read at {} Hz, measurements {} Hz",
            unit.name(),
            rounded(e.gyro_bias.to_degrees() * 3600.0),
            rounded(e.accel_bias / (navkf_dynamics::earth::STANDARD_GRAVITY * 1e-3)),
            c.truth.coefficient_scale,
            c.truth.input_rate_hz,
            c.truth.measurement_rate_hz
        )
    }

    fn parts(
        &self,
        config: &StudyConfig,
        trajectory: Arc<Trajectory>,
    ) -> Result<FamilyParts, StudyError> {
        parts(config, trajectory)
    }

    fn prepare(&self, req: &SimulationRequest, names: SettingNames) -> Result<Ready, StudyError> {
        simulation::prepare(req, names)
    }
}

/// A strapdown study: the unit class sets the biases' and the effects' typical sizes (scaled
/// by `truth.coefficient_scale`) and the reading noise's densities; `[noise]` the odometer's,
/// the GPS's and the constraint's sigmas; `truth.effects` and `filter.effects` name strapdown
/// effects ([`StrapdownEffectList`]). The configuration's checks
/// ([`StudyConfig::validate`]) have refused what this family does not read.
fn parts(config: &StudyConfig, trajectory: Arc<Trajectory>) -> Result<FamilyParts, StudyError> {
    let class = config.model.unit_class();
    let unit = class.errors();
    let scale = config.truth.coefficient_scale;
    let drawn = navkf_dynamics::strapdown::unit_class::UnitErrors {
        gyro_bias: unit.gyro_bias * scale,
        accel_bias: unit.accel_bias * scale,
        ..unit
    };
    let noise = config.truth_noise();
    let registry = config
        .registry::<navkf_dynamics::strapdown::effects::StrapdownRegistry>()
        .map_err(StudyError::Other)?;
    let list = |key: &str, entries: &[String]| {
        StrapdownEffectList::parse_entries(entries, &registry)
            .map_err(|(i, e)| StudyError::Other(format!("{key}[{i}]: {e}")))
    };
    let model = |list: &StrapdownEffectList, noise: &NoiseConfig| {
        StrapdownModel::base(noise)
            .with_unit(drawn)
            .with_effects(list, class, scale)
    };
    let truth_list = list("truth.effects", &config.truth.effects)?;
    let truth_model = Arc::new(model(&truth_list, &noise)?);
    let mut coefficients = truth_list.fixed.clone();
    for (k, v) in &config.truth.coefficients {
        coefficients.insert(k.clone(), *v);
    }
    let sim = StrapdownSimulator::new(
        truth_model,
        trajectory,
        config.truth.input_rate_hz,
        config.truth.measurement_rate_hz,
        drawn,
        &coefficients,
        noise,
    )?;
    let filter_list = list("filter.effects", &config.filter.effects)?;
    let filter_model: Arc<dyn FamilyModel> =
        Arc::new(model(&filter_list, &filter_noise(config, noise))?);
    let same = filter_model.clone();
    Ok(FamilyParts {
        sim: Box::new(sim),
        filter_model,
        filter_model_in: Box::new(move |_| Ok(same.clone())),
    })
}
