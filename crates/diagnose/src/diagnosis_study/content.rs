//! What a dataset of the study hides, drawn at random, and the dataset it makes.
//!
//! Each dataset's draws come from its own stream (study seed, dataset index), so dataset `i`
//! is the same bytes whatever runs beside it. Sizes are drawn log-uniformly between the
//! class's bounds, given as multiples of the effect's typical size (in sigma); every
//! coefficient of an effect takes that size times its own typical sigma, with a random sign.
//! The base coefficients are drawn from their typical sizes and the initial tilt as the
//! study file says (a gyrocompassed platform by default), as a real platform's would be.

use super::hidden::{log_uniform, sign};
pub use super::hidden::{misstate, Class, Hidden, Planned, WrongUnit};
use super::{ContentClass, DiagnosisStudyConfig, OutsideEffect};
use crate::error::DiagnoseError;
use navkf_dynamics::dataset::Dataset;
use navkf_dynamics::outside::{AccelWarmUp, Drag};
use navkf_dynamics::rng::{stream, Purpose};
use navkf_dynamics::sensor_faults::SensorFault;
use navkf_dynamics::simulate::Prior;
use navkf_dynamics::{ModelKind, PlatformModel, Registry, Simulator, Trajectory, TruthConfig};
use rand::Rng;
use std::collections::BTreeMap;
use std::sync::Arc;

/// The stream of a dataset's content draws.
const CONTENT: Purpose = Purpose::Other(40);

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

/// Every dataset of the study, in index order.
pub fn plan(config: &DiagnosisStudyConfig) -> Result<Vec<Planned>, DiagnoseError> {
    let catalogue = config.effect_names();
    let strapdown = config.model.kind == ModelKind::Strapdown;
    let (registry, strapdown_registry) = if strapdown {
        (Registry::catalogue(), config.strapdown_registry()?)
    } else {
        (config.platform_registry()?, Default::default())
    };
    let draw = |rng: &mut _, name: &str, range: [f64; 2]| {
        if strapdown {
            let class = config.model.unit_class();
            super::strapdown::draw_effect(rng, &strapdown_registry, name, range, class)
        } else {
            draw_effect(rng, name, range, &registry)
        }
    };
    // Noise sources a mis-stated noise may put off: the family's.
    let sources = if strapdown { 5 } else { 4 };
    let range = |name: &str| config.size_range(name);
    let mut out = Vec::new();
    let seed = config.study.seed;
    let trajectory_s = config.trajectory.duration_s;
    for class in &config.content {
        let n = class.count(catalogue.len());
        for k in 0..n {
            let index = out.len();
            let mut rng = stream(seed, index as u64, CONTENT);
            let (class_label, hidden) = match class {
                ContentClass::Nothing { .. } => (Class::Nothing, Vec::new()),
                ContentClass::Single { effects, .. } => {
                    // Every effect in turn (the class's, or the whole catalogue), `count`
                    // datasets each.
                    let pool: &[String] = if effects.is_empty() {
                        &catalogue
                    } else {
                        effects
                    };
                    let name = &pool[k % pool.len()];
                    let h = draw(&mut rng, name, range(name))?;
                    (Class::Single, vec![h])
                }
                ContentClass::Pair { effects, sizes, .. } => {
                    let pool: &[String] = if effects.is_empty() {
                        &catalogue
                    } else {
                        effects
                    };
                    let a = rng.gen_range(0..pool.len());
                    let mut b = rng.gen_range(0..pool.len() - 1);
                    if b >= a {
                        b += 1;
                    }
                    let range = |name: &str| sizes.get(name).copied().unwrap_or(range(name));
                    let ha = draw(&mut rng, &pool[a], range(&pool[a]))?;
                    let hb = draw(&mut rng, &pool[b], range(&pool[b]))?;
                    (Class::Pair, vec![ha, hb])
                }
                ContentClass::Outside { effect, sizes, .. } => {
                    let multiple = log_uniform(&mut rng, *sizes);
                    let h = match effect {
                        OutsideEffect::Drag => Hidden::Drag {
                            multiple,
                            kd: multiple * Drag::TYPICAL,
                        },
                        OutsideEffect::AccelWarmUp => Hidden::AccelWarmUp {
                            multiple,
                            amplitude: [
                                sign(&mut rng) * multiple * AccelWarmUp::TYPICAL,
                                sign(&mut rng) * multiple * AccelWarmUp::TYPICAL,
                            ],
                            time_constant_s: 300.0 + 900.0 * rng.gen::<f64>(),
                        },
                        OutsideEffect::GpsStep => {
                            // `multiple` typical offsets per axis, in a direction drawn
                            // uniformly; somewhere in the record, for 2 to 10 minutes.
                            let size = multiple * SensorFault::TYPICAL_STEP_M * 2f64.sqrt();
                            let direction = std::f64::consts::TAU * rng.gen::<f64>();
                            let duration_s = 120.0 + 480.0 * rng.gen::<f64>();
                            let span = (trajectory_s - duration_s).max(0.0);
                            Hidden::Fault {
                                multiple,
                                fault: SensorFault::GpsStep {
                                    offset_m: [size * direction.sin(), size * direction.cos()],
                                    start_s: span * rng.gen::<f64>(),
                                    duration_s,
                                },
                            }
                        }
                        OutsideEffect::OdometerSlip => Hidden::Fault {
                            multiple,
                            fault: SensorFault::OdometerSlip {
                                gain_s2_m: multiple * SensorFault::TYPICAL_SLIP_S2_M,
                            },
                        },
                        OutsideEffect::GpsLeverArm => {
                            // Mostly ahead (a roof antenna), ahead or behind, a little aside.
                            let arm = multiple * SensorFault::TYPICAL_LEVER_ARM_M;
                            Hidden::Fault {
                                multiple,
                                fault: SensorFault::GpsLeverArm {
                                    forward_m: sign(&mut rng) * arm,
                                    right_m: arm * (rng.gen::<f64>() - 0.5) * 0.5,
                                },
                            }
                        }
                    };
                    (Class::Outside, vec![h])
                }
                ContentClass::MisstatedNoise { sizes, .. } => {
                    // One or two sources off, up or down.
                    let mut factors = vec![1.0; sources];
                    let first = rng.gen_range(0..sources);
                    factors[first] = log_uniform(&mut rng, *sizes).powf(sign(&mut rng));
                    if rng.gen::<bool>() {
                        let second = (first + rng.gen_range(1..sources)) % sources;
                        factors[second] = log_uniform(&mut rng, *sizes).powf(sign(&mut rng));
                    }
                    (
                        Class::MisstatedNoise,
                        vec![Hidden::MisstatedNoise { factors }],
                    )
                }
                ContentClass::MemsNoise { sizes, .. } => {
                    let factors =
                        vec![log_uniform(&mut rng, *sizes), log_uniform(&mut rng, *sizes)];
                    (Class::MemsNoise, vec![Hidden::MemsNoise { factors }])
                }
                ContentClass::Misaligned {
                    sizes, attitude, ..
                } => (
                    Class::Misaligned,
                    vec![Hidden::Misaligned {
                        sigma_deg: log_uniform(&mut rng, *sizes),
                        attitude: *attitude,
                    }],
                ),
                ContentClass::WrongUnits { unit, .. } => {
                    (Class::WrongUnits, vec![Hidden::WrongUnit { unit: *unit }])
                }
            };
            out.push(Planned {
                index,
                class: class_label,
                hidden,
            });
        }
    }
    Ok(out)
}

/// Simulates planned dataset `p`, with the study's family.
pub fn simulate(
    config: &DiagnosisStudyConfig,
    trajectory: &Arc<Trajectory>,
    p: &Planned,
) -> Result<Dataset, DiagnoseError> {
    match config.model.kind {
        ModelKind::Platform => simulate_platform(config, trajectory, p),
        ModelKind::Strapdown => super::strapdown::simulate(config, trajectory, p),
    }
}

/// Simulates planned dataset `p` on the platform.
fn simulate_platform(
    config: &DiagnosisStudyConfig,
    trajectory: &Arc<Trajectory>,
    p: &Planned,
) -> Result<Dataset, DiagnoseError> {
    let catalogue = config.platform_registry()?;
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
