//! What a noise check finds: the four noise sources, their levels scaled by a log-variance
//! each, and what the data say of each (fits, under-stated, over-stated, unresolved). The
//! search that finds them is [`super::search`].

use navkf_dynamics::NoiseConfig;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// A source is mis-stated when its fitted log-scale is this many standard errors from zero
/// (two-sided level 5e-4 per source).
pub const Z_FLAG: f64 = 3.5;
/// A source whose level the data fix only within this factor (in sigma, 95 %) is unresolved.
pub const RESOLVED_SIGMA_FACTOR: f64 = 2.0;

/// A noise source of the model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum NoiseSource {
    /// Gyro white noise, `q_g` (`gyro_psd`).
    Gyro,
    /// Accelerometer white noise, `q_a` (`accel_psd`).
    Accelerometer,
    /// Odometer velocity noise (`odometer_rel` and `odometer_floor` together).
    Odometer,
    /// GPS position noise (`gps_m`).
    Gps,
}

/// The four sources, in the order of the log-scale vector.
pub const SOURCES: [NoiseSource; 4] = [
    NoiseSource::Gyro,
    NoiseSource::Accelerometer,
    NoiseSource::Odometer,
    NoiseSource::Gps,
];

impl NoiseSource {
    /// How reports name it.
    pub fn label(self) -> &'static str {
        match self {
            NoiseSource::Gyro => "gyro noise",
            NoiseSource::Accelerometer => "accelerometer noise",
            NoiseSource::Odometer => "odometer noise",
            NoiseSource::Gps => "GPS noise",
        }
    }

    /// Its `dataset.toml` keys and values in `n`.
    pub fn values(self, n: &NoiseConfig) -> BTreeMap<String, f64> {
        let pairs: Vec<(&str, f64)> = match self {
            NoiseSource::Gyro => vec![("gyro_psd", n.gyro_psd)],
            NoiseSource::Accelerometer => vec![("accel_psd", n.accel_psd)],
            NoiseSource::Odometer => vec![
                ("odometer_rel", n.odometer_rel),
                ("odometer_floor", n.odometer_floor),
            ],
            NoiseSource::Gps => vec![("gps_m", n.gps_m)],
        };
        pairs.into_iter().map(|(k, v)| (k.to_string(), v)).collect()
    }
}

/// `stated` with each source's variance scaled by `exp(theta[j])`.
pub fn scaled(stated: &NoiseConfig, theta: [f64; 4]) -> NoiseConfig {
    let sigma = |j: usize| (0.5 * theta[j]).exp();
    NoiseConfig {
        gyro_psd: stated.gyro_psd * theta[0].exp(),
        accel_psd: stated.accel_psd * theta[1].exp(),
        odometer_rel: stated.odometer_rel * sigma(2),
        odometer_floor: stated.odometer_floor * sigma(2),
        gps_m: stated.gps_m * sigma(3),
        nhc_m_s: stated.nhc_m_s,
    }
}

/// What the data say of one source.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum NoiseVerdict {
    /// The stated level fits, within the data's resolution.
    Fits,
    /// The noise is larger than stated.
    UnderStated,
    /// The noise is smaller than stated.
    OverStated,
    /// The data cannot fix the level within [`RESOLVED_SIGMA_FACTOR`].
    Unresolved,
}

/// One source's fit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SourceFit {
    /// The source.
    pub source: NoiseSource,
    /// The verdict.
    pub verdict: NoiseVerdict,
    /// Fitted over stated, in sigma (the square root of the variance scale).
    pub sigma_ratio: f64,
    /// 95 % interval of that ratio.
    pub sigma_ratio_interval: [f64; 2],
    /// Stated values by `dataset.toml` key.
    pub stated: BTreeMap<String, f64>,
    /// Fitted values by key (the maximum-likelihood ones, used only when mis-stated).
    pub fitted: BTreeMap<String, f64>,
}

/// The noise check of one model.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NoiseFit {
    /// Effects of the model the check was made on.
    pub model: Vec<String>,
    /// The stated noise.
    pub stated: NoiseConfig,
    /// The levels the check started from (the stated ones, or ones fitted earlier).
    pub start: NoiseConfig,
    /// Whether some source's score at the start levels was significant, so that its level
    /// was fitted.
    pub refitted: bool,
    /// The levels to use: the fitted ones for mis-stated sources, the stated ones otherwise.
    pub used: NoiseConfig,
    /// Their log-variance scales over the stated levels.
    pub used_theta: [f64; 4],
    /// Log-variance scales of the maximum-likelihood levels over the stated ones.
    pub theta: [f64; 4],
    /// Their standard errors.
    pub theta_se: [f64; 4],
    /// Per source, against the stated levels.
    pub sources: Vec<SourceFit>,
    /// Log-likelihood gain of the maximum-likelihood levels over the start levels.
    pub loglik_gain: f64,
    /// Filter passes the check took.
    pub passes: usize,
}

impl NoiseFit {
    /// Whether any source is mis-stated.
    pub fn mis_stated(&self) -> bool {
        self.sources.iter().any(|s| {
            matches!(
                s.verdict,
                NoiseVerdict::UnderStated | NoiseVerdict::OverStated
            )
        })
    }
}
