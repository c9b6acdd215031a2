//! The stabilised platform as a study runs it (docs/model.md): the paper's coefficients and
//! the platform catalogue's effects, drawn at `truth.coefficient_scale` times their typical
//! sigma, integrated at `truth.rate_hz`.

mod simulation;

use super::{filter_noise, FamilyParts, StudyFamily};
use crate::config::StudyConfig;
use crate::error::StudyError;
use crate::simulation::request::{Ready, SimulationRequest};
use navkf_dynamics::effect_spec::EffectSpec;
use navkf_dynamics::prior::typical_sigma;
use navkf_dynamics::state::NAV_DIM;
use navkf_dynamics::{
    Attitude, FamilyModel, NoiseConfig, PlatformModel, Registry, Simulator, SystemModel, Trajectory,
};
use navkf_report::SettingNames;
use std::sync::Arc;

/// The platform family.
pub(super) struct Platform;

impl StudyFamily for Platform {
    fn truth_line(&self, c: &StudyConfig, effects: &str) -> String {
        format!(
            "truth: effects {effects}; integration {} Hz, inputs {} Hz, measurements {} Hz; coefficients drawn at {} x their typical sigma",
            c.truth.rate_hz,
            c.truth.input_rate_hz,
            c.truth.measurement_rate_hz,
            c.truth.coefficient_scale
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

/// The platform model of the effect list at study key `key` (`truth.effects`), with the
/// coefficients it fixes. A bad entry is refused with its index: `truth.effects[1]: ...`.
fn platform_model(
    registry: &Registry,
    key: &str,
    effects: &[String],
    noise: &NoiseConfig,
    attitude: Attitude,
) -> Result<
    (
        Arc<PlatformModel>,
        std::collections::BTreeMap<String, navkf_dynamics::Prior>,
    ),
    StudyError,
> {
    let EffectSpec { effects, fixed } = EffectSpec::parse_entries(effects, registry)
        .map_err(|(i, e)| StudyError::Other(format!("{key}[{i}]: {e}")))?;
    Ok((
        Arc::new(PlatformModel::new(effects, noise)?.with_attitude(attitude)),
        fixed,
    ))
}

fn parts(config: &StudyConfig, trajectory: Arc<Trajectory>) -> Result<FamilyParts, StudyError> {
    let noise = config.noise;
    let registry = config.registry::<Registry>().map_err(StudyError::Other)?;
    let (truth_model, truth_fixed) = platform_model(
        &registry,
        "truth.effects",
        &config.truth.effects,
        &noise,
        config.truth.attitude,
    )?;
    let mut sim_cfg = config.truth.sim_config();
    // Typical sigmas scaled, then the effect list's fixed values, then explicit priors.
    let scale = config.truth.coefficient_scale;
    for i in NAV_DIM..truth_model.dim() {
        let name = &truth_model.state_names()[i];
        let typical = typical_sigma(&truth_model, i);
        sim_cfg
            .coefficients
            .entry(name.clone())
            .or_insert(navkf_dynamics::Prior::zero_mean(typical * scale));
    }
    for (k, v) in &truth_fixed {
        sim_cfg.coefficients.insert(k.clone(), *v);
    }
    for (k, v) in &config.truth.coefficients {
        sim_cfg.coefficients.insert(k.clone(), *v);
    }
    let sim = Simulator::new(truth_model, trajectory, sim_cfg, noise)?;
    let filter_noise = filter_noise(config, noise);
    let effects = config.filter.effects.clone();
    let filter_model_in = move |attitude| {
        platform_model(
            &registry,
            "filter.effects",
            &effects,
            &filter_noise,
            attitude,
        )
        .map(|(m, _)| m as Arc<dyn FamilyModel>)
    };
    Ok(FamilyParts {
        sim: Box::new(sim),
        filter_model: filter_model_in(config.filter.attitude)?,
        filter_model_in: Box::new(filter_model_in),
    })
}
