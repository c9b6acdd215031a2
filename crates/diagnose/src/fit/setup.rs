//! What one filter pass is asked to fit, besides the data: the model (effects, their
//! parameters, the noise it assumes, the priors it starts from) and the filter that runs it.
//! A diagnosis compares many of these, each a small change of the last
//! ([`FitSetup::with_effect`]), so they are plain values that compare equal when they would
//! give the same pass. The family's catalogue builds the model from it
//! ([`crate::catalogue::Catalogue::model`]).

use crate::priors::Priors;
use navkf_dynamics::NoiseConfig;
use std::collections::BTreeMap;

/// Everything that sets one filter pass besides the data.
#[derive(Debug, Clone, PartialEq)]
pub struct FitSetup {
    /// Effects in the model, in order.
    pub effects: Vec<String>,
    /// Parameters of effects that have one (the density of `gyro-bias-walk`), by effect.
    pub parameters: BTreeMap<String, f64>,
    /// Noise the filter assumes.
    pub noise: NoiseConfig,
    /// Prior sigmas of the tilt and the coefficients.
    pub priors: Priors,
    /// When set, the constant coefficients start again from their priors after the last
    /// update at or before this time (s), forgetting what the updates before it said of
    /// them while the navigation states go on: the second half of the constancy test
    /// ([`crate::stand_ins::constancy`]). No restart when no measurement comes after it.
    /// `None` in every other pass.
    pub restart_coefficients_after: Option<f64>,
    /// When set, the filter starts from these states instead of the family's start at the
    /// dataset's first fix: the second half of a noise term's constancy test
    /// ([`crate::stand_ins::density_constancy`]) resumes where the first half's fit ended.
    /// `None` in every other pass.
    pub resume: Option<ResumePoint>,
}

/// Some states of a filter at one time, with their covariance: where a later pass may
/// resume ([`FitSetup::resume`]). The navigation states always, in the family's order; after
/// them any coefficient that wanders (one driven by process noise), found again by name in
/// the later pass's model, which may not hold it. A resumed state's prior has a mean and
/// covariances; [`crate::fit::pass::Fit::profile_loglik`]'s Laplace correction assumes a
/// zero-mean diagonal one, which is why only the navigation states and the wandering ones,
/// which that correction leaves marginal, are resumed where a profile is taken.
#[derive(Debug, Clone, PartialEq)]
pub struct ResumePoint {
    /// Time of the states, s.
    pub t: f64,
    /// Their names: the navigation states first.
    pub names: Vec<String>,
    /// Their estimate.
    pub x: Vec<f64>,
    /// Their covariance, column-major (`x.len()` squared).
    pub p: Vec<f64>,
}

impl FitSetup {
    /// The model of `effects` at the noise levels `noise` from the priors `priors`: no
    /// effect parameter, no restart, the family's own start.
    pub fn new(effects: Vec<String>, noise: NoiseConfig, priors: Priors) -> FitSetup {
        FitSetup {
            effects,
            parameters: BTreeMap::new(),
            noise,
            priors,
            restart_coefficients_after: None,
            resume: None,
        }
    }

    /// The same setup at the noise levels `noise`, its coefficients' priors back where they
    /// started: a model refitted at levels a noise check found.
    pub fn at_noise(&self, noise: NoiseConfig) -> FitSetup {
        let mut s = self.clone();
        s.noise = noise;
        s.priors = s.priors.restarted();
        s
    }

    /// The same setup with `effect` added (with its parameter, if given).
    pub fn with_effect(&self, effect: &str, parameter: Option<f64>) -> FitSetup {
        let mut s = self.clone();
        s.effects.push(effect.to_string());
        if let Some(p) = parameter {
            s.parameters.insert(effect.to_string(), p);
        }
        s
    }
}
