//! Can an answer be physical at all? A candidate's fitted values against what any real sensor
//! has.
//!
//! When a candidate is weighed, its fitted coefficients are compared with the bounds its
//! effect declares ([`navkf_dynamics::Effect::coefficient_bounds`], reasons in
//! [`navkf_dynamics::sensor_classes`]), and a refitted noise level with the sensor classes'
//! ([`navkf_dynamics::sensor_classes::NOISE_BOUNDS`]). A decisive candidate beyond them is not
//! named ([`crate::candidates::Outcome::Unphysical`], with [`BeyondBound`] saying which value
//! and why). If it explains the misfit decisively better than anything nameable, nothing is
//! named in that round ([`crate::naming`]): a lesser candidate would be a stand-in.
//!
//! The data themselves are checked before anything is fitted: [`crate::implausible_data`].

use crate::catalogue::EffectInfo;
use crate::summary::Coefficient;
use navkf_dynamics::sensor_classes::noise_out_of_bounds;
use navkf_dynamics::NoiseConfig;
use serde::{Deserialize, Serialize};

/// A fitted value beyond what any real sensor has: why a candidate was not named.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BeyondBound {
    /// The coefficient, or the `[noise]` key of a refitted level.
    pub name: String,
    /// The fitted value.
    pub value: f64,
    /// The smallest value a real sensor has (`-limit` for a coefficient).
    pub min: f64,
    /// The largest.
    pub max: f64,
    /// Why.
    pub reason: String,
}

impl std::fmt::Display for BeyondBound {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.min == -self.max {
            write!(
                f,
                "{} = {:.3e} is beyond +-{:.3e} ({})",
                self.name, self.value, self.max, self.reason
            )
        } else {
            write!(
                f,
                "{} = {:.3e} is outside {:.3e}-{:.3e} ({})",
                self.name, self.value, self.min, self.max, self.reason
            )
        }
    }
}

/// The candidate's own `coefficients` that lie beyond the bounds `effect` declares.
pub fn coefficients_beyond(effect: &EffectInfo, coefficients: &[Coefficient]) -> Vec<BeyondBound> {
    effect
        .coefficients
        .iter()
        .zip(&effect.bounds)
        .filter_map(|(name, bound)| {
            let c = coefficients.iter().find(|c| c.name == *name)?;
            (!bound.contains(c.estimate)).then(|| BeyondBound {
                name: c.name.clone(),
                value: c.estimate,
                min: -bound.limit,
                max: bound.limit,
                reason: bound.reason.to_owned(),
            })
        })
        .collect()
}

/// The levels of a refitted `noise` that no real sensor has.
pub fn noise_beyond(noise: &NoiseConfig) -> Vec<BeyondBound> {
    noise_out_of_bounds(noise)
        .map(|(b, value)| BeyondBound {
            name: format!("noise.{}", b.key),
            value,
            min: b.min(),
            max: b.max(),
            reason: format!("real sensors span {}", b.classes),
        })
        .collect()
}
