//! What a dataset of the study hides, drawn at random, and the dataset it makes.
//!
//! Each dataset's draws come from its own stream (study seed, dataset index), so dataset `i`
//! is the same bytes whatever runs beside it. Sizes are drawn log-uniformly between the
//! class's bounds, given as multiples of the effect's typical size (in sigma), by the study
//! family's draw; the family simulates the dataset (`super::family`; on the platform every
//! coefficient of an effect takes that size times its own typical sigma, with a random sign,
//! and the base coefficients and the initial tilt are drawn as a real platform's would be).

use super::hidden::{log_uniform, sign};
pub use super::hidden::{misstate, Class, Hidden, Planned, WrongUnit};
use super::{ContentClass, DiagnosisStudyConfig, OutsideEffect};
use crate::error::DiagnoseError;
use navkf_dynamics::dataset::Dataset;
use navkf_dynamics::outside::{AccelWarmUp, Drag};
use navkf_dynamics::rng::{stream, Purpose};
use navkf_dynamics::sensor_faults::SensorFault;
use navkf_dynamics::Trajectory;
use rand::Rng;
use std::sync::Arc;

/// The stream of a dataset's content draws.
const CONTENT: Purpose = Purpose::Other(40);

/// Every dataset of the study, in index order.
pub fn plan(config: &DiagnosisStudyConfig) -> Result<Vec<Planned>, DiagnoseError> {
    let catalogue = config.effect_names();
    let family = super::family::of(config.model.kind);
    let draw = family.effect_draw(config)?;
    // Noise sources a mis-stated noise may put off: the family's.
    let sources = family.noise_sources();
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
    super::family::of(config.model.kind).simulate(config, trajectory, p)
}
