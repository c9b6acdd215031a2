//! Where a study builds its model family's parts ([`navkf_dynamics::family`]): the truth
//! simulator and the filters' model, from the study file's `[model]`, `[truth]`, `[noise]`
//! and `[filter]` tables. This is the one place that names the families; everything after
//! it runs on their traits.

use crate::config::StudyConfig;
use crate::error::StudyError;
use navkf_dynamics::effect_spec::EffectSpec;
use navkf_dynamics::prior::typical_sigma;
use navkf_dynamics::state::NAV_DIM;
use navkf_dynamics::strapdown::effect_list::StrapdownEffectList;
use navkf_dynamics::strapdown::model::StrapdownModel;
use navkf_dynamics::strapdown::simulate::StrapdownSimulator;
use navkf_dynamics::{
    Attitude, FamilyModel, ModelKind, NoiseConfig, PlatformModel, Registry, Simulator, SystemModel,
    Trajectory, TruthSimulation,
};
use std::sync::Arc;

/// The filters' model in a given attitude form.
type ModelInAttitude = Box<dyn Fn(Attitude) -> Result<Arc<dyn FamilyModel>, StudyError>>;

/// A family's parts for one study.
pub(super) struct FamilyParts {
    /// The truth simulator.
    pub sim: Box<dyn TruthSimulation>,
    /// The filters' model in `[filter] attitude`.
    pub filter_model: Arc<dyn FamilyModel>,
    /// The filters' model in another attitude form (a variant's).
    pub filter_model_in: ModelInAttitude,
}

/// The parts of `config`'s family, on `trajectory`.
pub(super) fn parts(
    config: &StudyConfig,
    trajectory: Arc<Trajectory>,
) -> Result<FamilyParts, StudyError> {
    match config.model.kind {
        ModelKind::Platform => platform(config, trajectory),
        ModelKind::Strapdown => strapdown(config, trajectory),
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

fn platform(config: &StudyConfig, trajectory: Arc<Trajectory>) -> Result<FamilyParts, StudyError> {
    let noise = config.noise;
    let registry = config.registry().map_err(StudyError::Other)?;
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

/// A strapdown study: the unit class sets the biases' and the effects' typical sizes (scaled
/// by `truth.coefficient_scale`) and the reading noise's densities; `[noise]` the odometer's,
/// the GPS's and the constraint's sigmas; `truth.effects` and `filter.effects` name strapdown
/// effects ([`StrapdownEffectList`]). The configuration's checks
/// ([`StudyConfig::validate`]) have refused what this family does not read.
fn strapdown(config: &StudyConfig, trajectory: Arc<Trajectory>) -> Result<FamilyParts, StudyError> {
    let class = config.model.unit_class();
    let unit = class.errors();
    let scale = config.truth.coefficient_scale;
    let drawn = navkf_dynamics::strapdown::unit_class::UnitErrors {
        gyro_bias: unit.gyro_bias * scale,
        accel_bias: unit.accel_bias * scale,
        ..unit
    };
    let noise = config.truth_noise();
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
