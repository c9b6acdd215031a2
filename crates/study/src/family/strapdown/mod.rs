//! A strapdown unit as a study runs it (docs/model.md, "The strapdown family"): the unit
//! class's biases and reading noise, the strapdown catalogue's effects, the truth read off
//! the path itself.

mod simulation;

use super::{filter_noise, FamilyParts, StudyFamily};
use crate::config::StudyConfig;
use crate::error::StudyError;
use crate::report::rounded;
use crate::simulation::{Ready, SettingNames, SimulationRequest};
use navkf_dynamics::strapdown::effect_list::StrapdownEffectList;
use navkf_dynamics::strapdown::model::StrapdownModel;
use navkf_dynamics::strapdown::simulate::StrapdownSimulator;
use navkf_dynamics::{Attitude, FamilyModel, NoiseConfig, Trajectory};
use std::sync::Arc;

/// The strapdown family.
pub(super) struct Strapdown;

impl StudyFamily for Strapdown {
    fn check(&self, config: &StudyConfig) -> Result<(), String> {
        let refuse =
            |key: &str, why: &str| Err(format!("{key}: {why} (model.kind = \"strapdown\")"));
        let defaults = NoiseConfig::default();
        let registry = config.strapdown_registry()?;
        for (key, effects) in [
            ("truth.effects", &config.truth.effects),
            ("filter.effects", &config.filter.effects),
        ] {
            StrapdownEffectList::parse_entries(effects, &registry)
                .map_err(|(i, e)| format!("{key}[{i}]: {e} (model.kind = \"strapdown\")"))?;
        }
        let attitudes = [
            ("truth.attitude", config.truth.attitude),
            ("filter.attitude", config.filter.attitude),
        ]
        .into_iter()
        .chain(
            config
                .filter
                .variants
                .iter()
                .filter_map(|(label, v)| v.attitude.map(|a| (label.as_str(), a))),
        );
        for (key, a) in attitudes {
            if a != Attitude::SmallAngle {
                return refuse(
                    key,
                    "the attitude equations are the platform's choice; the strapdown \
                     family's are exact Euler angles (docs/model.md eqs. (53)-(55)), \
                     expected no attitude key",
                );
            }
        }
        if config.truth.initial_tilt.alignment != Default::default() {
            return refuse(
                "truth.initial_tilt.alignment",
                "a MEMS unit cannot gyrocompass, and the strapdown start is drawn around \
                 the true attitude; expected no alignment key",
            );
        }
        if config.truth.rate_hz != crate::config::TruthSection::default().rate_hz {
            return refuse(
                "truth.rate_hz",
                "the strapdown truth is the path itself, nothing is integrated to make \
                 it; expected no truth.rate_hz (truth.input_rate_hz is the IMU's rate)",
            );
        }
        if config.noise.gyro_psd != defaults.gyro_psd
            || config.noise.accel_psd != defaults.accel_psd
        {
            return refuse(
                "noise.gyro_psd / noise.accel_psd",
                "the reading noise's densities come from model.unit; expected neither \
                 key (filter.process_noise_scale mis-states them on purpose)",
            );
        }
        Ok(())
    }

    fn truth_noise(&self, config: &StudyConfig) -> NoiseConfig {
        config.model.unit_class().errors().noise(config.noise)
    }

    fn truth_line(&self, c: &StudyConfig, effects: &str) -> String {
        let unit = c.model.unit_class();
        let e = unit.errors();
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

    fn heading_word(&self) -> &'static str {
        "heading"
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
    let noise = Strapdown.truth_noise(config);
    let registry = config.strapdown_registry().map_err(StudyError::Other)?;
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
