//! What a dataset of a diagnosis study hides, as the plan records it, and the draws both
//! families make it from. Its own module so that the family that simulates a dataset
//! (`content` for the platform, `strapdown`) and the plan that dispatches to it import it
//! and not each other.

use navkf_dynamics::sensor_faults::SensorFault;
use navkf_dynamics::NoiseConfig;
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
        }
    }
    /// Its size as a multiple of its typical size (1 for mis-stated noise).
    pub fn multiple(&self) -> f64 {
        match self {
            Hidden::Effect { multiple, .. }
            | Hidden::Drag { multiple, .. }
            | Hidden::AccelWarmUp { multiple, .. }
            | Hidden::Fault { multiple, .. } => *multiple,
            Hidden::MisstatedNoise { .. } => 1.0,
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
/// stated): gyro, accelerometer, odometer, GPS and, when given, the constraints' tolerance
/// (both the non-holonomic and the zero-velocity one).
pub fn misstate(truth: &NoiseConfig, factors: &[f64]) -> NoiseConfig {
    let f = |i: usize| factors.get(i).copied().unwrap_or(1.0);
    NoiseConfig {
        gyro_psd: truth.gyro_psd / (f(0) * f(0)),
        accel_psd: truth.accel_psd / (f(1) * f(1)),
        odometer_rel: truth.odometer_rel / f(2),
        odometer_floor: truth.odometer_floor / f(2),
        gps_m: truth.gps_m / f(3),
        nhc_m_s: truth.nhc_m_s.map(|v| v / f(4)),
        zupt_m_s: truth.zupt_m_s.map(|v| v / f(4)),
    }
}
