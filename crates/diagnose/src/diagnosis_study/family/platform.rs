//! A diagnosis study of the stabilised platform (the default): its catalogue with the
//! study's declared effects, sizes drawn from each coefficient's typical sigma, and datasets
//! made as `navkf simulate` makes them, with the platform's own content classes (MEMS noise,
//! a misaligned start, a column in the wrong unit) applied.

use super::{declaration_message, EffectDraw, PairFits, StudyFamily};
use crate::diagnosis_study::hidden::{log_uniform, misstate, sign, Hidden, Planned};
use crate::diagnosis_study::rates::{self, EffectScale};
use crate::diagnosis_study::{ContentClass, DiagnosisStudyConfig};
use crate::error::DiagnoseError;
use navkf_dynamics::dataset::Dataset;
use navkf_dynamics::outside::{AccelWarmUp, Drag};
use navkf_dynamics::simulate::Prior;
use navkf_dynamics::{NoiseConfig, PlatformModel, Registry, Simulator, Trajectory, TruthConfig};
use rand::Rng;
use std::collections::BTreeMap;
use std::sync::Arc;

/// The platform family.
pub(super) struct Platform;

impl StudyFamily for Platform {
    fn effect_names(&self, config: &DiagnosisStudyConfig) -> Result<Vec<String>, DiagnoseError> {
        Ok(config.registry::<Registry>()?.names())
    }

    fn validate(&self, config: &DiagnosisStudyConfig) -> Result<(), String> {
        if config.model.unit.is_some() {
            return Err(
                "model.unit: a unit class is a strapdown study's; expected no `unit` with \
                 kind = \"platform\""
                    .into(),
            );
        }
        if config.noise.nhc_m_s.is_some() || config.noise.zupt_m_s.is_some() {
            return Err(
                "noise.nhc_m_s, noise.zupt_m_s: the constraints are a strapdown study's; \
                 expected neither with kind = \"platform\""
                    .into(),
            );
        }
        config
            .registry::<Registry>()
            .map(drop)
            .map_err(declaration_message)
    }

    fn refuses_class(&self, _: &ContentClass) -> Option<&'static str> {
        None
    }

    fn pair_fits(&self, config: &DiagnosisStudyConfig) -> Result<PairFits, DiagnoseError> {
        let registry = config.registry::<Registry>()?;
        let noise = NoiseConfig::default();
        Ok(Box::new(move |pair| {
            PlatformModel::new(registry.build_all(&pair)?, &noise)?;
            Ok(())
        }))
    }

    fn effect_scales(&self, config: &DiagnosisStudyConfig) -> Vec<EffectScale> {
        config
            .registry::<Registry>()
            .map(|r| rates::platform_scales(&r))
            .unwrap_or_default()
    }

    fn effect_draw<'a>(
        &self,
        config: &'a DiagnosisStudyConfig,
    ) -> Result<EffectDraw<'a>, DiagnoseError> {
        let registry = config.registry::<Registry>()?;
        Ok(Box::new(move |rng, name, range| {
            draw_effect(rng, name, range, &registry)
        }))
    }

    /// Gyro, accelerometer, odometer, GPS.
    fn noise_sources(&self) -> usize {
        4
    }

    fn simulate(
        &self,
        config: &DiagnosisStudyConfig,
        trajectory: &Arc<Trajectory>,
        p: &Planned,
    ) -> Result<Dataset, DiagnoseError> {
        simulate(config, trajectory, p)
    }

    fn unit_words(&self, _: &DiagnosisStudyConfig) -> String {
        String::new()
    }
}

/// A catalogued effect of size drawn from `range` (multiples of typical).
fn draw_effect<R: Rng>(
    rng: &mut R,
    name: &str,
    range: [f64; 2],
    registry: &Registry,
) -> Result<Hidden, DiagnoseError> {
    let effect = registry.build(name)?;
    let multiple = log_uniform(rng, range);
    let mut values = BTreeMap::new();
    if effect.coefficient_names().is_empty() {
        // A noise-only effect: its density scales with the square of the size in sigma.
        let typical = effect.process_noise().first().map_or(0.0, |c| c.psd);
        values.insert("density".to_string(), typical * multiple * multiple);
    } else {
        for (c, s) in effect
            .coefficient_names()
            .iter()
            .zip(effect.coefficient_sigma())
        {
            values.insert(c.to_string(), sign(rng) * multiple * s);
        }
    }
    Ok(Hidden::Effect {
        name: name.to_string(),
        multiple,
        values,
    })
}

/// Simulates planned dataset `p` on the platform.
fn simulate(
    config: &DiagnosisStudyConfig,
    trajectory: &Arc<Trajectory>,
    p: &Planned,
) -> Result<Dataset, DiagnoseError> {
    let catalogue = config.registry::<Registry>()?;
    let noise = config.noise;
    let mut effects: Vec<Box<dyn navkf_dynamics::DynEffect>> = Vec::new();
    let mut coefficients = BTreeMap::new();
    let mut warm_up = None;
    let mut faults = Vec::new();
    let mut stated = noise;
    let mut true_noise = noise;
    let mut attitude = navkf_dynamics::Attitude::SmallAngle;
    let mut initial_tilt = config.truth.initial_tilt;
    let mut azimuth_prior = None;
    let mut wrong_unit = None;
    for h in &p.hidden {
        match h {
            Hidden::Effect { name, values, .. } => {
                let mut e = catalogue.build(name)?;
                if e.coefficient_names().is_empty() {
                    if let Some(&q) = values.get("density") {
                        e.set_parameter(q).map_err(DiagnoseError::Content)?;
                    }
                } else {
                    for (c, v) in values {
                        coefficients.insert(c.clone(), Prior::fixed(*v));
                    }
                }
                effects.push(e);
            }
            Hidden::Drag { kd, .. } => {
                effects.push(Box::new(Drag));
                coefficients.insert("kd".to_string(), Prior::fixed(*kd));
            }
            Hidden::AccelWarmUp {
                amplitude,
                time_constant_s,
                ..
            } => {
                warm_up = Some(AccelWarmUp {
                    amplitude: *amplitude,
                    time_constant_s: *time_constant_s,
                });
            }
            Hidden::Fault { fault, .. } => faults.push(*fault),
            Hidden::MisstatedNoise { factors } => stated = misstate(&noise, factors),
            Hidden::MemsNoise { factors } => {
                // The truth's gyro and accelerometer are the MEMS unit's; the dataset states
                // the navigation-grade defaults.
                let f = |i: usize| factors.get(i).copied().unwrap_or(1.0);
                true_noise.gyro_psd *= f(0) * f(0);
                true_noise.accel_psd *= f(1) * f(1);
            }
            Hidden::Misaligned { sigma_deg, .. } => {
                // Levelled as usual, but the azimuth drawn with degrees of sigma, which the
                // dataset states as its prior; only exact attitude equations carry it.
                attitude = navkf_dynamics::Attitude::Exact;
                let sigma = sigma_deg.to_radians();
                initial_tilt = navkf_dynamics::simulate::InitialTilt {
                    azimuth_rad: sigma,
                    alignment: navkf_dynamics::simulate::Alignment::Independent,
                    ..Default::default()
                };
                azimuth_prior = Some(sigma);
            }
            Hidden::WrongUnit { unit } => wrong_unit = Some(*unit),
        }
    }
    let model = Arc::new(PlatformModel::new(effects, &true_noise)?.with_attitude(attitude));
    let t = &config.truth;
    let truth_cfg = TruthConfig {
        rate_hz: t.rate_hz,
        input_rate_hz: t.input_rate_hz,
        measurement_rate_hz: t.measurement_rate_hz,
        initial_tilt,
        coefficients,
    };
    let mut sim = Simulator::new(model, trajectory.clone(), truth_cfg, true_noise)?;
    if let Some(w) = warm_up {
        sim = sim.with_specific_force_error(move |t| w.at(t));
    }
    let run = sim.run(config.study.seed, p.index as u64);
    let mut ds = sim.dataset(&format!("dataset-{}", p.index), config.study.seed, &run);
    for fault in faults {
        fault.apply(&mut ds).map_err(DiagnoseError::Content)?;
    }
    ds.noise = stated;
    if azimuth_prior.is_some() {
        ds.prior.azimuth_rad = azimuth_prior;
    }
    if let Some(unit) = wrong_unit {
        unit.apply(&mut ds);
    }
    // Every dataset states the study's declarations, whatever it hides: they are candidates
    // of each diagnosis, the clean datasets' included.
    ds.effects = config.effect.clone();
    Ok(ds)
}
