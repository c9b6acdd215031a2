//! A candidate's evidence: what adding it to the model gains, in the one currency every
//! candidate is weighed in (effects, noise-only terms and refitted noise levels alike), and
//! what naming it would add to the model ([`Named`]).
//!
//! **Evidence.** A candidate's evidence is its BIC gain on the maximised innovation
//! likelihood, `2 dLL - k ln N`: `dLL` the gain of [`Fit::profile_loglik`] over the model
//! (the likelihood at the estimates, free of the priors' Occam factors), `k` its number of
//! free parameters, `N` the number of scalar measurements. Why BIC rather than the
//! alternatives:
//! - a Bayes factor (the filter's marginal likelihoods compared as they are) depends on the
//!   prior's width: a real effect tested with a wide prior, which the widening of
//!   [`crate::fit::widening`] gives it, would lose evidence for it;
//! - a likelihood-ratio test at a fixed level (`2 dLL` against a chi-square) is prior-free
//!   too, but over hundreds of scalar measurements per minute a fixed level names effects
//!   too small to matter, and its false-alarm rate per dataset grows with the number of
//!   candidates and rounds;
//! - BIC's `k ln N` (9.2 per parameter for a 40-minute test at 1 Hz) is stricter than any
//!   usual test level and grows with the data: under the null hypothesis `2 dLL` is
//!   chi-square with `k` degrees of freedom, so a gain above [`DECISIVE_BIC`] happens by
//!   chance with probability 1e-5 for one parameter and less for more.
//!
//! A gain above [`DECISIVE_BIC`] is "very strong" evidence on Kass & Raftery's scale.
//!
//! **Told apart.** A coefficient correlated beyond [`INDISTINGUISHABLE`] with one of the
//! model's cannot be told apart from it (the trajectory cannot say which of the two carries
//! the misfit): the candidate records the pair ([`Confusion`]) and the evidence its other
//! coefficients carry on their own ([`Candidate::separable_bic`]), which the naming rules of
//! [`crate::naming`] read.

use crate::consistency::NisStat;
use crate::fit::pass::Fit;
use crate::fit::widening::Widening;
use crate::noise::levels::NoiseFit;
use crate::physical::BeyondBound;
use crate::summary::{Coefficient, FitSummary};
use serde::{Deserialize, Serialize};

/// BIC gain beyond which evidence is decisive.
pub const DECISIVE_BIC: f64 = 10.0;
/// Correlation beyond which two coefficients cannot be told apart.
pub const INDISTINGUISHABLE: f64 = 0.9;
/// The name the refitted noise levels go by as a candidate, in the rounds' tables and in
/// `diagnosis.json` (what a round names is typed: [`Named::NoiseLevels`]).
pub const NOISE_LEVELS: &str = "noise levels";

/// Whether a candidate adds coefficients or only process noise.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum CandidateKind {
    /// It adds coefficients (random constants) and the terms they multiply.
    Structured,
    /// It only adds process noise (its one parameter is a density).
    NoiseOnly,
    /// Not an effect: the noise levels refitted (the sources whose stated level is off).
    NoiseLevels,
}

/// Why a candidate is, or is not, named.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Outcome {
    /// Named in this round.
    Named,
    /// Added by `--with`.
    Manual,
    /// Decisive, but another candidate explains more.
    Outranked,
    /// Evidence not decisive.
    NotDecisive,
    /// Its coefficients cannot be told apart from the model's on this trajectory.
    Confounded,
    /// A noise-only term that leaves the model inconsistent.
    NoiseLeavesMisfit,
    /// A noise-only term that a structured candidate explains as well.
    NoiseAsGoodAsStructure,
    /// The refitted noise levels, which explain more than any effect alone, but an effect
    /// adds to them decisively when they are refitted beside it: the effect is named first
    /// ([`crate::candidates::beside_noise`]).
    NoiseAfterStructure,
    /// A noise-only term that a drift outside the catalogue (a walk of the other sensor, or
    /// accelerometer biases settling) explains as well ([`crate::rivals`]).
    NoiseNotSpecific,
    /// The refitted noise levels, chosen only because the noise-only term that explains the
    /// misfit decisively better is [`Outcome::NoiseNotSpecific`]: a slow drift is there, and
    /// levels refitted for it would misstate the sensors' noise ([`crate::naming`]). Not
    /// named.
    NoiseLevelsBelowDrift,
    /// The refitted noise levels, but an error outside the catalogue that refitted noise can
    /// cover (on the platform a drag, [`crate::rivals`]) explains the misfit as well:
    /// levels refitted for it would misstate the sensors' noise ([`crate::naming`]). Not named.
    NoiseLevelsLikeOutside,
    /// The filter failed with it.
    Failed,
    /// Decisive, but its fitted values are no real sensor's ([`Candidate::beyond_bounds`]).
    Unphysical,
    /// Decisive, but another structured candidate explains the misfit as well: none of them
    /// is named, each is suggested ([`crate::naming`]).
    Indistinguishable,
    /// Decisive, but an explanation outside the catalogue that looks like it on this
    /// trajectory explains the misfit as well ([`crate::rivals`]): not named.
    LooksLikeOutside,
    /// Decisive, but the platform is diagnosed with the small-angle attitude equations under a
    /// tilt prior beyond their depth ([`crate::priors::beyond_small_angle`]), where a
    /// misalignment of degrees can pass for it: suggested, not named.
    BeyondSmallAngle,
}

impl std::fmt::Display for Outcome {
    /// The outcome in words, for the report and the terminal's tables.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Outcome::Named => "named",
            Outcome::Manual => "added (--with)",
            Outcome::Outranked => "decisive, outranked",
            Outcome::NotDecisive => "not decisive",
            Outcome::Confounded => "cannot be told apart",
            Outcome::NoiseLeavesMisfit => "noise term, leaves misfit",
            Outcome::NoiseAsGoodAsStructure => "noise term, no better than structure",
            Outcome::NoiseAfterStructure => "noise levels, after the effect that adds to them",
            Outcome::NoiseNotSpecific => "noise term, a drift outside the catalogue fits as well",
            Outcome::NoiseLevelsBelowDrift => "noise levels, a slow drift fits decisively better",
            Outcome::NoiseLevelsLikeOutside => {
                "noise levels, an error outside the catalogue fits as well"
            }
            Outcome::Failed => "filter failed",
            Outcome::Unphysical => "decisive, but no real sensor's: not named",
            Outcome::LooksLikeOutside => {
                "decisive, but something outside the catalogue fits as well"
            }
            Outcome::Indistinguishable => "decisive, but another explains as well: suggested",
            Outcome::BeyondSmallAngle => {
                "decisive, but the small-angle model is out of its depth: suggested"
            }
        })
    }
}

/// Two coefficients the trajectory cannot tell apart.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Confusion {
    /// The candidate's coefficient.
    pub coefficient: String,
    /// The model's coefficient.
    pub with: String,
    /// Their correlation at the end of the fit.
    pub correlation: f64,
}

/// One candidate's evidence.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Candidate {
    /// Effect name.
    pub effect: String,
    /// Structured or noise-only.
    pub kind: CandidateKind,
    /// Gain of the maximised log-likelihood over the model.
    pub delta_loglik: f64,
    /// Free parameters it adds.
    pub parameters: usize,
    /// `2 dLL - k ln N`.
    pub bic_gain: f64,
    /// Share of the model's excess NIS it removes.
    pub excess_removed: f64,
    /// Mean NIS with it added.
    pub nis: NisStat,
    /// Whether the innovations are consistent with it added.
    pub consistent: bool,
    /// Its coefficients' estimates, sigmas and the priors they were tested with.
    pub coefficients: Vec<Coefficient>,
    /// The fitted density of a noise-only term.
    pub density: Option<f64>,
    /// The noise check behind a noise-levels candidate.
    pub noise: Option<NoiseFit>,
    /// Priors widened while fitting it.
    pub widened: Vec<Widening>,
    /// Model coefficients it cannot be told apart from.
    pub confused_with: Vec<Confusion>,
    /// When some of its coefficients are confused: the evidence its other coefficients carry
    /// on their own, as a BIC gain (Wald statistic `c^T P^-1 c` of those coefficients, less
    /// their `k ln N`). The candidate can be named only if this is decisive too.
    pub separable_bic: Option<f64>,
    /// For the structured candidate the refitted noise levels lead: its BIC gain over them
    /// when the noise is refitted beside it ([`super::beside_noise`]). Decisive, it is named
    /// before the noise levels.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub beside_refitted_noise: Option<f64>,
    /// Its fitted values that no real sensor has ([`crate::physical`]): a decisive candidate
    /// with any is not named.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub beyond_bounds: Vec<BeyondBound>,
    /// Why it is or is not named.
    pub outcome: Outcome,
    /// Filter failure with it added, if any.
    pub failure: Option<navkf_filters::RunFailure>,
}

impl Candidate {
    /// Whether its evidence is decisive and usable (before the naming rules).
    pub fn decisive(&self) -> bool {
        self.failure.is_none() && self.bic_gain.is_finite() && self.bic_gain > DECISIVE_BIC
    }
}

/// What naming a candidate adds to the model: the typed result of a round's choice
/// ([`crate::naming`]), which the round loop acts on and the stand-in check tests. Its words
/// ([`Named`]'s `Display`) are the round's `named` in `diagnosis.json`.
#[derive(Debug, Clone, PartialEq)]
pub enum Named {
    /// A structured effect: its coefficients join the model as random constants
    /// (docs/model.md eq. (11)).
    Effect(String),
    /// A noise-only term: its process noise joins the model at its fitted density.
    NoiseTerm(String),
    /// The noise levels refitted: the sources found mis-stated take their fitted levels in
    /// the next rounds.
    NoiseLevels {
        /// The levels' log-variance scales over the stated ones ([`NoiseFit::used_theta`]).
        theta: crate::noise::Theta,
    },
}

impl std::fmt::Display for Named {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Named::Effect(e) | Named::NoiseTerm(e) => f.write_str(e),
            Named::NoiseLevels { .. } => f.write_str(NOISE_LEVELS),
        }
    }
}

/// A candidate with the fit behind it (the next round's model if it is named).
#[derive(Debug, Clone)]
pub struct Evaluated {
    /// The evidence.
    pub candidate: Candidate,
    /// The fit with the candidate added.
    pub fit: Fit,
    /// What naming it adds to the model.
    pub names: Named,
}

/// The model's state of a round: its fit and summary.
pub struct Model<'a> {
    /// The fit.
    pub fit: &'a Fit,
    /// Its summary.
    pub summary: &'a FitSummary,
}
