//! What a dataset of a diagnosis study hides, as the plan records it, and the draws both
//! families make it from. Its own module so that the family that simulates a dataset
//! (`content` for the platform, `strapdown`) and the plan that dispatches to it import it
//! and not each other.

use navkf_dynamics::dataset::{Dataset, Doubt};
use navkf_dynamics::sensor_faults::SensorFault;
use navkf_dynamics::{Attitude, NoiseConfig};
use rand::Rng;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// One thing hidden in a dataset's truth.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum Hidden {
    /// A catalogued effect with fixed coefficients.
    Effect {
        /// Its name.
        name: String,
        /// Size as a multiple of its typical size (sigma).
        multiple: f64,
        /// The true coefficients (or, for a noise-only effect, its density), by name.
        values: BTreeMap<String, f64>,
    },
    /// The velocity-proportional drag (outside the catalogue).
    Drag {
        /// Size as a multiple of [`navkf_dynamics::outside::Drag::TYPICAL`].
        multiple: f64,
        /// `kd`, 1/s.
        kd: f64,
    },
    /// Accelerometer biases settling after switch-on (outside the catalogue).
    AccelWarmUp {
        /// Size as a multiple of [`navkf_dynamics::outside::AccelWarmUp::TYPICAL`].
        multiple: f64,
        /// The settled change, m/s^2, East and North.
        amplitude: [f64; 2],
        /// Time constant, s.
        time_constant_s: f64,
    },
    /// A fault of the recorded measurements (outside the catalogue): GPS multipath, wheel
    /// slip, a GPS lever arm.
    Fault {
        /// Size as a multiple of the fault's typical size.
        multiple: f64,
        /// The fault.
        fault: SensorFault,
    },
    /// The stated noise is not the truth's: each source's stated sigma is the true one
    /// divided by its factor.
    MisstatedNoise {
        /// Per source (gyro, accelerometer, odometer, GPS, and a strapdown study's constraint
        /// tolerance): true sigma over stated sigma.
        factors: Vec<f64>,
    },
    /// Nothing hidden, but the gyro and accelerometer are a MEMS unit's while the dataset
    /// states the navigation-grade defaults: their true sigma over the stated one.
    MemsNoise {
        /// Gyro, then accelerometer: true sigma over stated sigma.
        factors: Vec<f64>,
    },
    /// Nothing hidden, but the platform starts misaligned in azimuth by degrees (drawn with
    /// this sigma, the truth's attitude equations exact), the dataset states that sigma as
    /// its azimuth prior, and the diagnosis uses `attitude`.
    Misaligned {
        /// Azimuth sigma, deg.
        sigma_deg: f64,
        /// The attitude equations the dataset is diagnosed with.
        attitude: Attitude,
    },
    /// Nothing hidden, but one column is written in another unit than data-format.md's.
    WrongUnit {
        /// Which.
        unit: WrongUnit,
    },
}

/// The label of [`Hidden::MemsNoise`] (its report row).
pub const MEMS_NOISE_LABEL: &str = "MEMS noise stated at navigation grade";

/// A column written in another unit, as users do.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum WrongUnit {
    /// Every time column in milliseconds.
    Milliseconds,
    /// GPS latitude in radians (longitude in degrees: both in radians, the reader refuses
    /// the file with the line of the first fix).
    Radians,
    /// The specific force in g.
    G,
    /// The odometer's velocities in km/h.
    KmH,
}

impl WrongUnit {
    /// Rewrites `ds` as a user writing this unit would have.
    pub fn apply(self, ds: &mut Dataset) {
        match self {
            WrongUnit::Milliseconds => {
                ds.inputs.iter_mut().for_each(|i| i.t *= 1e3);
                ds.measurements.iter_mut().for_each(|m| m.t *= 1e3);
                if let Some(t) = ds.truth.as_mut() {
                    t.t.iter_mut().for_each(|t| *t *= 1e3);
                }
            }
            // Latitude only: with both columns in radians the reader refuses the file
            // (dataset/read/units.rs), so the warnings meet the case it cannot see.
            WrongUnit::Radians => ds
                .measurements
                .iter_mut()
                .filter_map(|m| m.position_deg.as_mut())
                .for_each(|p| p[0] = p[0].to_radians()),
            WrongUnit::G => ds.inputs.iter_mut().for_each(|i| {
                i.f.iter_mut()
                    .for_each(|f| *f /= navkf_dynamics::earth::STANDARD_GRAVITY)
            }),
            WrongUnit::KmH => ds
                .measurements
                .iter_mut()
                .filter_map(|m| m.velocity.as_mut())
                .for_each(|v| *v = [3.6 * v[0], 3.6 * v[1]]),
        }
    }
    /// The warnings that name this unit (radians may show on either GPS column).
    pub fn doubts(self) -> &'static [Doubt] {
        match self {
            WrongUnit::Milliseconds => &[Doubt::TimesInMilliseconds],
            WrongUnit::Radians => &[Doubt::LatitudeInRadians, Doubt::LongitudeInRadians],
            WrongUnit::G => &[Doubt::SpecificForceNotGravity],
            WrongUnit::KmH => &[Doubt::OdometerNotMetresPerSecond],
        }
    }
    /// Short label.
    pub fn label(self) -> &'static str {
        match self {
            WrongUnit::Milliseconds => "times in ms",
            WrongUnit::Radians => "GPS latitude in radians",
            WrongUnit::G => "specific force in g",
            WrongUnit::KmH => "odometer in km/h",
        }
    }
}

impl Hidden {
    /// The catalogued effect's name, if it is one.
    pub fn effect(&self) -> Option<&str> {
        match self {
            Hidden::Effect { name, .. } => Some(name),
            _ => None,
        }
    }
    /// Short label for tables.
    pub fn label(&self) -> String {
        match self {
            Hidden::Effect { name, .. } => name.clone(),
            Hidden::Drag { .. } => "drag (outside)".into(),
            Hidden::AccelWarmUp { .. } => "accel warm-up (outside)".into(),
            Hidden::Fault { fault, .. } => format!("{} (outside)", fault.label()),
            Hidden::MisstatedNoise { .. } => "mis-stated noise".into(),
            Hidden::MemsNoise { .. } => MEMS_NOISE_LABEL.into(),
            Hidden::Misaligned { attitude, .. } => format!(
                "misaligned by degrees, diagnosed {}",
                match attitude {
                    Attitude::SmallAngle => "small-angle",
                    Attitude::Exact => "exact",
                }
            ),
            Hidden::WrongUnit { unit } => format!("{} (wrong unit)", unit.label()),
        }
    }
    /// Its size as a multiple of its typical size (1 for noise and units; degrees of azimuth
    /// sigma for a misalignment).
    pub fn multiple(&self) -> f64 {
        match self {
            Hidden::Effect { multiple, .. }
            | Hidden::Drag { multiple, .. }
            | Hidden::AccelWarmUp { multiple, .. }
            | Hidden::Fault { multiple, .. } => *multiple,
            Hidden::Misaligned { sigma_deg, .. } => *sigma_deg,
            Hidden::MisstatedNoise { .. } | Hidden::MemsNoise { .. } | Hidden::WrongUnit { .. } => {
                1.0
            }
        }
    }
}

/// The content classes of the study's datasets, as the report groups them.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Class {
    /// Nothing hidden.
    Nothing,
    /// One catalogued effect.
    Single,
    /// Two catalogued effects.
    Pair,
    /// An effect outside the catalogue.
    Outside,
    /// Nothing hidden, but the stated noise is wrong.
    MisstatedNoise,
    /// Nothing hidden, but the unit is MEMS-class and stated at navigation grade.
    MemsNoise,
    /// Nothing hidden, but the platform is misaligned by degrees.
    Misaligned,
    /// Nothing hidden, but a column is in another unit.
    WrongUnits,
}

/// A dataset of the study before it is simulated.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Planned {
    /// Index (the run of its simulation).
    pub index: usize,
    /// Its class.
    pub class: Class,
    /// What its truth hides.
    pub hidden: Vec<Hidden>,
}

/// A draw log-uniform between `lo` and `hi`.
pub(super) fn log_uniform<R: Rng>(rng: &mut R, [lo, hi]: [f64; 2]) -> f64 {
    (lo.ln() + rng.gen::<f64>() * (hi.ln() - lo.ln())).exp()
}

/// +1 or -1, evenly.
pub(super) fn sign<R: Rng>(rng: &mut R) -> f64 {
    if rng.gen::<bool>() {
        1.0
    } else {
        -1.0
    }
}

/// `truth` as a user would state it who has each source's sigma off by `factors` (true over
/// stated): gyro, accelerometer, odometer, GPS and, when given, the non-holonomic constraint's
/// tolerance and the zero-velocity update's.
pub fn misstate(truth: &NoiseConfig, factors: &[f64]) -> NoiseConfig {
    let f = |i: usize| factors.get(i).copied().unwrap_or(1.0);
    NoiseConfig {
        gyro_psd: truth.gyro_psd / (f(0) * f(0)),
        accel_psd: truth.accel_psd / (f(1) * f(1)),
        odometer_rel: truth.odometer_rel / f(2),
        odometer_floor: truth.odometer_floor / f(2),
        gps_m: truth.gps_m / f(3),
        nhc_m_s: truth.nhc_m_s.map(|v| v / f(4)),
        // A family with the standstill's own source states it whether or not the truth leaves
        // it to default to the odometer's floor, so that an odometer stated off is not a
        // standstill stated off too.
        zupt_m_s: if factors.len() > 5 {
            Some(truth.zupt_sigma() / f(5))
        } else {
            truth.zupt_m_s
        },
    }
}
