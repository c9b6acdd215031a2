//! What a noise check finds: the noise sources (four for the platform; the strapdown family
//! adds its pseudo-measurements' two tolerances), their levels scaled by a log-variance each, and
//! what the data say of each (fits, under-stated, over-stated, unresolved). The search that
//! finds them is [`super::search`].

use navkf_dynamics::NoiseConfig;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// A source is mis-stated when its fitted log-scale is this many standard errors from zero
/// (two-sided level 5e-4 per source).
pub const Z_FLAG: f64 = 3.5;
/// A source whose level the data fix only within this factor (in sigma, 95 %) is unresolved.
pub const RESOLVED_SIGMA_FACTOR: f64 = 2.0;
/// A fitted level is *fixed* when its 95 % interval lies within this share of the truth
/// whichever point of it the truth is: the interval within `[r / (1 + s), r / (1 - s)]` of the
/// fitted ratio `r`. A fitted level that is not is reported as coarse ([`SourceFit::fixed`]).
pub const FIXED_WITHIN: f64 = 0.2;

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
    /// The tolerance of the non-holonomic constraint (`nhc_m_s`; the strapdown family): how
    /// far from zero the moving vehicle's sideways and vertical velocities really are.
    Constraint,
    /// The tolerance of the zero-velocity update (`zupt_m_s`; the strapdown family): how far
    /// from zero a standing vehicle's velocity really is. A source of its own, since nothing
    /// ties a car's idle shake to its sideslip: fitted as one with the constraint's, a
    /// standstill tolerance stated 10x off alone moved the other levels to absorb it (an
    /// accelerometer noise fitted at 0.7x of the truth) or left the verdict `unexplained`.
    Standstill,
}

/// The most sources a family has.
pub const MAX_SOURCES: usize = 6;

/// Log-variance scales, one per source (those a family lacks stay zero).
pub type Theta = [f64; MAX_SOURCES];

/// The sources, in the order of the log-scale vector; a family has the first few
/// ([`crate::catalogue::Catalogue::noise_sources`]).
pub const SOURCES: [NoiseSource; MAX_SOURCES] = [
    NoiseSource::Gyro,
    NoiseSource::Accelerometer,
    NoiseSource::Odometer,
    NoiseSource::Gps,
    NoiseSource::Constraint,
    NoiseSource::Standstill,
];

impl NoiseSource {
    /// How reports name it.
    pub fn label(self) -> &'static str {
        match self {
            NoiseSource::Gyro => "gyro noise",
            NoiseSource::Accelerometer => "accelerometer noise",
            NoiseSource::Odometer => "odometer noise",
            NoiseSource::Gps => "GPS noise",
            NoiseSource::Constraint => "constraint tolerance",
            NoiseSource::Standstill => "standstill tolerance",
        }
    }

    /// Whether it is the tolerance of a pseudo-measurement that reads zero (the constraint's,
    /// the standstill's): one whose truth may be met exactly, so that its likelihood can go
    /// flat towards zero, which no sensor's noise does.
    pub fn is_tolerance(self) -> bool {
        matches!(self, NoiseSource::Constraint | NoiseSource::Standstill)
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
            NoiseSource::Constraint => n.nhc_m_s.map(|v| ("nhc_m_s", v)).into_iter().collect(),
            NoiseSource::Standstill => vec![("zupt_m_s", n.zupt_sigma())],
        };
        pairs.into_iter().map(|(k, v)| (k.to_string(), v)).collect()
    }
}

/// `stated` with each source's variance scaled by `exp(theta[j])` (a tolerance left
/// unscaled keeps its stated key as it is: absent stays absent).
pub fn scaled(stated: &NoiseConfig, theta: Theta) -> NoiseConfig {
    let sigma = |j: usize| (0.5 * theta[j]).exp();
    let (constraint, standstill) = (theta[4] != 0.0, theta[5] != 0.0);
    NoiseConfig {
        gyro_psd: stated.gyro_psd * theta[0].exp(),
        accel_psd: stated.accel_psd * theta[1].exp(),
        odometer_rel: stated.odometer_rel * sigma(2),
        odometer_floor: stated.odometer_floor * sigma(2),
        gps_m: stated.gps_m * sigma(3),
        nhc_m_s: stated
            .nhc_m_s
            .map(|v| if constraint { v * sigma(4) } else { v }),
        zupt_m_s: if standstill {
            Some(stated.zupt_sigma() * sigma(5))
        } else {
            stated.zupt_m_s
        },
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

/// Why the data cannot fix a source's level ([`NoiseVerdict::Unresolved`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum WhyUnresolved {
    /// Its channel has this few updates (fewer than [`FEW_UPDATES`]).
    FewUpdates {
        /// Updates of the channel.
        updates: usize,
    },
    /// It trades off against another source's level: the data fix a combination of the two
    /// (their log-scales' correlation at the optimum is at least [`TRADE_OFF`] in size).
    TradesOff {
        /// The other source.
        with: NoiseSource,
        /// The correlation of the two log-scales.
        correlation: f64,
    },
    /// The likelihood is flat in it: no measurement resolves its noise on this record.
    Flat,
    /// None of these: the record resolves it, but only coarsely.
    Weak,
}

/// A measurement source with fewer updates than this is unresolved for that reason.
pub const FEW_UPDATES: usize = 30;
/// Log-scales correlated at least this much (in size) trade off.
pub const TRADE_OFF: f64 = 0.7;

/// One source's fit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SourceFit {
    /// The source.
    pub source: NoiseSource,
    /// The verdict.
    pub verdict: NoiseVerdict,
    /// Fitted over stated, in sigma (the square root of the variance scale).
    pub sigma_ratio: f64,
    /// 95 % interval of that ratio: the likelihood ratio's for a mis-stated source
    /// ([`super::likelihood_interval`]; 0 below, or 10^4 times the fit above, where the
    /// likelihood never falls far enough), the curvature's otherwise.
    pub sigma_ratio_interval: [f64; 2],
    /// Stated values by `dataset.toml` key.
    pub stated: BTreeMap<String, f64>,
    /// Fitted values by key (the maximum-likelihood ones, used only when mis-stated).
    pub fitted: BTreeMap<String, f64>,
    /// Why the level is unresolved, when it is; or why a fitted level is not fixed
    /// ([`SourceFit::fixed`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub unresolved_because: Option<WhyUnresolved>,
}

impl SourceFit {
    /// Whether the level is fixed ([`is_fixed`]).
    pub fn fixed(&self) -> bool {
        is_fixed(self.sigma_ratio, self.sigma_ratio_interval)
    }
}

/// Whether a fitted ratio `r` with 95 % interval `[lo, hi]` is fixed within [`FIXED_WITHIN`]
/// of the truth, if the truth is inside the interval: the interval within `[r / 1.2, r / 0.8]`.
pub fn is_fixed(r: f64, [lo, hi]: [f64; 2]) -> bool {
    lo >= r / (1.0 + FIXED_WITHIN) && hi <= r / (1.0 - FIXED_WITHIN)
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
    /// Their log-variance scales over the stated levels, one per source of the family.
    pub used_theta: Vec<f64>,
    /// Log-variance scales of the maximum-likelihood levels over the stated ones.
    pub theta: Vec<f64>,
    /// Their standard errors.
    pub theta_se: Vec<f64>,
    /// Per source, against the stated levels.
    pub sources: Vec<SourceFit>,
    /// Log-likelihood gain of the maximum-likelihood levels over the start levels.
    pub loglik_gain: f64,
    /// Filter passes the check took.
    pub passes: usize,
}

impl NoiseFit {
    /// [`NoiseFit::used_theta`] as the search takes it back.
    pub fn used(&self) -> Theta {
        std::array::from_fn(|j| self.used_theta.get(j).copied().unwrap_or(0.0))
    }

    /// How many of the check's sources take levels other than `from`'s: the parameters the
    /// refitted levels cost when they are weighed like an effect (at least one).
    pub fn changed_sources(&self, from: &NoiseConfig) -> usize {
        SOURCES[..self.sources.len()]
            .iter()
            .filter(|src| src.values(&self.used) != src.values(from))
            .count()
            .max(1)
    }

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
