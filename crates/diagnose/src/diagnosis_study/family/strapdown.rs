//! A diagnosis study of the strapdown family (`[model] kind = "strapdown"`): its catalogue,
//! the sizes its effects are drawn at, and its datasets, made as `navkf simulate --model
//! strapdown` makes them (docs/model.md, "Simulating a strapdown test"), with the constraint
//! and zero-velocity readings the simulation drew kept (a file would hold exact zeros).
//!
//! An effect's size is a multiple of its typical size for the study's unit class; every
//! coefficient of the effect takes that multiple of its own typical sigma with a random sign,
//! and a bias instability that multiple of its steady sigma. Sizes stop below the smallest
//! bound of the effect's coefficients (the simulator refuses a value no instrument has).

use super::{declaration_message, EffectDraw, PairFits, StudyFamily};
use crate::catalogue::strapdown::{stated_level_sigma, STATED_HEADING_SIGMA};
use crate::diagnosis_study::hidden::{log_uniform, misstate, sign, Hidden, Planned};
use crate::diagnosis_study::rates::EffectScale;
use crate::diagnosis_study::{
    ContentClass, DiagnosisSection, DiagnosisStudyConfig, OutsideEffect, TruthSection,
};
use crate::error::DiagnoseError;
use navkf_dynamics::dataset::Dataset;
use navkf_dynamics::simulate::Alignment;
use navkf_dynamics::strapdown::effect_list::StrapdownEffectList;
use navkf_dynamics::strapdown::effects::{StrapdownRegistry, Triad};
use navkf_dynamics::strapdown::model::StrapdownModel;
use navkf_dynamics::strapdown::simulate::StrapdownSimulator;
use navkf_dynamics::strapdown::unit_class::UnitClass;
use navkf_dynamics::{NoiseConfig, Trajectory};
use rand::Rng;
use std::collections::BTreeMap;
use std::sync::Arc;

/// An effect's typical size for `class` and its unit: its first coefficient's sigma, or a
/// bias instability's steady sigma.
fn typical(registry: &StrapdownRegistry, name: &str, class: UnitClass) -> Option<(f64, String)> {
    let effect = registry.get(name).ok()?;
    if let Some(c) = effect.coefficients.first() {
        return Some((c.sigma_for(class), c.unit.to_string()));
    }
    effect.instability.map(|i| {
        let unit = match i.triad {
            Triad::Gyro => "rad/s",
            Triad::Accel => "m/s^2",
        };
        (i.sigma_for(class), unit.to_string())
    })
}

/// The strapdown family.
pub(super) struct Strapdown;

impl StudyFamily for Strapdown {
    fn effect_names(&self, config: &DiagnosisStudyConfig) -> Result<Vec<String>, DiagnoseError> {
        let registry = config.registry::<StrapdownRegistry>()?;
        Ok(registry.names().into_iter().map(str::to_string).collect())
    }

    fn validate(&self, config: &DiagnosisStudyConfig) -> Result<(), String> {
        validate(config)?;
        config
            .registry::<StrapdownRegistry>()
            .map(drop)
            .map_err(declaration_message)
    }

    fn refuses_class(&self, class: &ContentClass) -> Option<&'static str> {
        match class {
            ContentClass::MemsNoise { .. } | ContentClass::Misaligned { .. } => Some(
                "a platform class (MEMS noise and misalignment are the strapdown family's \
                 normal state, which its own classes cover); expected it in a study with \
                 kind = \"platform\"",
            ),
            ContentClass::WrongUnits { .. } => Some(
                "wrong-units is a platform class for now; expected it in a study with kind = \
                 \"platform\"",
            ),
            _ => None,
        }
    }

    fn pair_fits(&self, config: &DiagnosisStudyConfig) -> Result<PairFits, DiagnoseError> {
        let registry = config.registry::<StrapdownRegistry>()?;
        let class = config.model.unit_class();
        let noise = NoiseConfig::default();
        Ok(Box::new(move |pair| {
            let list = StrapdownEffectList::parse_entries(&pair, &registry).map_err(|(_, e)| e)?;
            StrapdownModel::base(&noise).with_effects(&list, class, 1.0)?;
            Ok(())
        }))
    }

    fn effect_scales(&self, config: &DiagnosisStudyConfig) -> Vec<EffectScale> {
        let Ok(registry) = config.registry::<StrapdownRegistry>() else {
            return Vec::new();
        };
        registry
            .names()
            .into_iter()
            .map(|name| {
                let (typical, unit) = typical(&registry, name, config.model.unit_class())
                    .unwrap_or((f64::NAN, String::new()));
                EffectScale {
                    name: name.to_string(),
                    typical,
                    unit,
                    sigmas: Vec::new(),
                    unseen: Vec::new(),
                }
            })
            .collect()
    }

    fn effect_draw<'a>(
        &self,
        config: &'a DiagnosisStudyConfig,
    ) -> Result<EffectDraw<'a>, DiagnoseError> {
        let registry = config.registry::<StrapdownRegistry>()?;
        let class = config.model.unit_class();
        Ok(Box::new(move |rng, name, range| {
            draw_effect(rng, &registry, name, range, class)
        }))
    }

    /// Gyro, accelerometer, odometer, GPS, the constraint's tolerance and the standstill's.
    fn noise_sources(&self) -> usize {
        6
    }

    fn simulate(
        &self,
        config: &DiagnosisStudyConfig,
        trajectory: &Arc<Trajectory>,
        p: &Planned,
    ) -> Result<Dataset, DiagnoseError> {
        simulate(config, trajectory, p)
    }

    fn unit_words(&self, config: &DiagnosisStudyConfig) -> String {
        format!(" of a strapdown {} unit", config.model.unit_class().name())
    }
}

/// Refuses, by key, what a strapdown diagnosis study does not read.
fn validate(config: &DiagnosisStudyConfig) -> Result<(), String> {
    let (truth, diagnosis, noise) = (
        TruthSection::default(),
        DiagnosisSection::default(),
        NoiseConfig::default(),
    );
    if config.truth.rate_hz != truth.rate_hz {
        return Err(
            "truth.rate_hz: a strapdown study's truth is the path itself, read by the \
                    unit at truth.input_rate_hz; expected no truth.rate_hz"
                .into(),
        );
    }
    let tilt = config.truth.initial_tilt;
    if tilt != truth.initial_tilt && tilt.alignment != Alignment::Independent {
        return Err(
            "truth.initial_tilt.alignment: a strapdown dataset states its start \
                    attitude (level_rad, azimuth_rad are the sigmas it is drawn with); expected \
                    no alignment"
                .into(),
        );
    }
    if config.diagnosis.attitude != diagnosis.attitude {
        return Err(
            "diagnosis.attitude: the strapdown model's attitude is exact already; \
                    expected no attitude"
                .into(),
        );
    }
    // The unit class sets the readings' noise; [noise] gives the aids'.
    if config.noise.gyro_psd != noise.gyro_psd || config.noise.accel_psd != noise.accel_psd {
        return Err(
            "noise.gyro_psd, noise.accel_psd: a strapdown study's reading noise is its \
                    unit class's (model.unit); expected neither"
                .into(),
        );
    }
    for (i, c) in config.content.iter().enumerate() {
        if let ContentClass::Outside { effect, .. } = c {
            if !matches!(effect, OutsideEffect::GpsStep | OutsideEffect::OdometerSlip) {
                return Err(format!(
                    "content[{i}].effect: {effect:?} is not outside a strapdown catalogue or not \
                     simulated for it (gps-lever-arm is catalogued); expected \"gps-step\" or \
                     \"odometer-slip\""
                ));
            }
        }
    }
    Ok(())
}

/// The sigmas the datasets' stated start attitude is drawn with, level and heading:
/// `[truth.initial_tilt]` when the file gives it, otherwise the tilt the unit's accelerometer
/// bias leaves after levelling and the catalogue's stated heading sigma (2 deg).
fn start_sigmas(config: &DiagnosisStudyConfig) -> (f64, f64) {
    let tilt = config.truth.initial_tilt;
    if tilt != TruthSection::default().initial_tilt {
        (tilt.level_rad, tilt.azimuth_rad)
    } else {
        (
            stated_level_sigma(config.model.unit_class()),
            STATED_HEADING_SIGMA,
        )
    }
}

/// Effect `name` at a size drawn from `range` (multiples of its typical size for `class`),
/// the top of the range held below the smallest bound of its coefficients.
fn draw_effect<R: Rng>(
    rng: &mut R,
    registry: &StrapdownRegistry,
    name: &str,
    [lo, hi]: [f64; 2],
    class: UnitClass,
) -> Result<Hidden, DiagnoseError> {
    let effect = registry
        .get(name)
        .map_err(|e| DiagnoseError::Content(e.to_string()))?;
    let cap = effect
        .coefficients
        .iter()
        .map(|c| 0.9 * c.bound.limit / c.sigma_for(class))
        .fold(f64::INFINITY, f64::min);
    let hi = hi.min(cap);
    let multiple = log_uniform(rng, [lo.min(hi), hi]);
    let mut values = BTreeMap::new();
    for c in effect.coefficients {
        values.insert(
            c.name.to_string(),
            sign(rng) * multiple * c.sigma_for(class),
        );
    }
    if let Some(i) = effect.instability {
        values.insert(
            i.parameter_names[1].to_string(),
            multiple * i.sigma_for(class),
        );
    }
    Ok(Hidden::Effect {
        name: name.to_string(),
        multiple,
        values,
    })
}

/// Simulates planned dataset `p` of a strapdown study.
fn simulate(
    config: &DiagnosisStudyConfig,
    trajectory: &Arc<Trajectory>,
    p: &Planned,
) -> Result<Dataset, DiagnoseError> {
    let class = config.model.unit_class();
    let unit = class.errors();
    let noise = unit.noise(config.noise);
    let mut entries = Vec::new();
    let mut faults = Vec::new();
    let mut stated = noise;
    for h in &p.hidden {
        match h {
            Hidden::Effect { name, values, .. } => {
                let mut entry = name.clone();
                for (k, v) in values {
                    entry.push_str(&format!(",{k}={v:e}"));
                }
                entries.push(entry);
            }
            Hidden::Fault { fault, .. } => faults.push(*fault),
            Hidden::MisstatedNoise { factors } => stated = misstate(&noise, factors),
            other => {
                return Err(DiagnoseError::Content(format!(
                    "{}: not simulated for a strapdown unit",
                    other.label()
                )))
            }
        }
    }
    let registry = config.registry::<StrapdownRegistry>()?;
    let list = StrapdownEffectList::parse_entries(&entries, &registry)
        .map_err(|(i, e)| DiagnoseError::Content(format!("{}: {e}", entries[i])))?;
    let model = Arc::new(
        StrapdownModel::base(&noise)
            .with_unit(unit)
            .with_effects(&list, class, 1.0)?,
    );
    let t = &config.truth;
    let sim = StrapdownSimulator::new(
        model,
        trajectory.clone(),
        t.input_rate_hz,
        t.measurement_rate_hz,
        unit,
        &list.fixed,
        noise,
    )?;
    let run = sim.run(config.study.seed, p.index as u64);
    let (level, heading) = start_sigmas(config);
    let mut ds = sim.dataset_with_readings(
        &format!("dataset-{}", p.index),
        config.study.seed,
        &run,
        level,
        heading,
    );
    for fault in faults {
        fault.apply(&mut ds).map_err(DiagnoseError::Content)?;
    }
    ds.noise = stated;
    // Every dataset states the study's declarations, whatever it hides: they are candidates
    // of each diagnosis, the clean datasets' included.
    ds.effects = config.effect.clone();
    Ok(ds)
}
