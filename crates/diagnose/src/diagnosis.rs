//! What a diagnosis found, as `diagnosis.json` holds it and the report renders it: the
//! verdict, the named effects, the final model and the base model before them, every round
//! with its full ranking, the noise checks, the priors and what became of them, and the
//! findings in words. The steps of [`crate::rounds`] fill it; [`crate::report`] and
//! [`crate::plots`] read it.

use crate::candidates::evidence::{Candidate, CandidateKind};
use crate::consistency::NisStat;
use crate::fit::pass::Fit;
use crate::fit::widening::Widening;
use crate::misfit::Misfit;
use crate::noise::levels::NoiseFit;
use crate::priors::PriorEntry;
use crate::stand_ins::{Constancy, Withdrawn};
use crate::summary::FitSummary;
use crate::verdict::Verdict;
use serde::{Deserialize, Serialize};

/// Whether a round was asked for (`--with`) or chosen by the evidence.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum RoundKind {
    /// `--with`: the effects were added as given.
    Manual,
    /// Forward selection.
    Automatic,
}

/// One round of the forward selection.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Round {
    /// Manual or automatic.
    pub kind: RoundKind,
    /// Effects of the model the candidates were added to.
    pub model: Vec<String>,
    /// That model's NIS.
    pub nis: NisStat,
    /// Whether that model is consistent.
    pub consistent: bool,
    /// The candidates, best first (for a manual round, the `--with` effects together).
    pub candidates: Vec<Candidate>,
    /// What this round named, in words ([`crate::candidates::Named`]'s): the effect, or
    /// `noise levels`; for a manual round, the `--with` effects.
    pub named: Vec<String>,
    /// Remarks (competing explanations).
    pub notes: Vec<String>,
}

impl Round {
    /// Whether this round named the refitted noise levels (a candidate of kind
    /// [`CandidateKind::NoiseLevels`]), whatever its label.
    pub fn named_noise_levels(&self) -> bool {
        self.candidates
            .iter()
            .any(|c| c.kind == CandidateKind::NoiseLevels && self.named.contains(&c.effect))
    }
}

/// The whole diagnosis (`diagnosis.json`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Diagnosis {
    /// Dataset name.
    pub dataset: String,
    /// The model family judged (the platform unless said).
    #[serde(
        default,
        skip_serializing_if = "navkf_dynamics::ModelKind::is_platform"
    )]
    pub family: navkf_dynamics::ModelKind,
    /// Coefficients the family's measurements cannot inform, held at zero in every fit
    /// ([`crate::catalogue::Catalogue::pinned`]).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub pinned: Vec<String>,
    /// The attitude the filters start from and where it came from (the strapdown family:
    /// `[initial]` or the alignment from the data); absent for the platform.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub start_attitude: Option<crate::start_attitude::StartAttitude>,
    /// The attitude equations of every fit's model.
    #[serde(default)]
    pub attitude: navkf_dynamics::Attitude,
    /// The verdict.
    pub verdict: Verdict,
    /// The first named effect; null when none.
    pub best: Option<String>,
    /// The named effects, in the order named (the `--with` ones are not repeated here).
    pub effects: Vec<String>,
    /// Effects that fit decisively better but leave the model inconsistent (verdict
    /// `partly explained`): suggested, not named, in the order found.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub suggested: Vec<String>,
    /// The final model: the model under test plus the named effects.
    pub model: FitSummary,
    /// Where the final model fails (channels, phases, spans of time), when it is
    /// inconsistent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub misfit: Option<Misfit>,
    /// The base model, when the final model has effects (before/after).
    pub before: Option<FitSummary>,
    /// The rounds, with their full rankings.
    pub rounds: Vec<Round>,
    /// The last noise check (stated and fitted levels); null with `--noise stated`.
    pub noise: Option<NoiseFit>,
    /// Every noise check made, in order.
    pub noise_checks: Vec<NoiseFit>,
    /// The priors the diagnosis started from, with their source.
    pub priors: Vec<PriorEntry>,
    /// Priors widened in the final model's fit.
    pub widened: Vec<Widening>,
    /// Named effects withdrawn by the constancy test.
    pub withdrawn: Vec<Withdrawn>,
    /// Constancy of each named structured effect in the final model.
    pub constancy: Vec<(String, Option<Constancy>)>,
    /// Plain-language findings.
    pub findings: Vec<String>,
    /// The dataset's values that look written in the wrong unit
    /// ([`navkf_dynamics::dataset::Dataset::warnings`]): the verdict stands on data that may
    /// be wrong, and the report says so first.
    #[serde(default)]
    pub data_warnings: Vec<navkf_dynamics::dataset::DataWarning>,
    /// What the data cannot be ([`navkf_dynamics::dataset::Dataset::implausibilities`]); when
    /// any, the verdict is [`Verdict::ImplausibleData`] and nothing is fitted beyond one pass
    /// ([`crate::implausible_data`]).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub implausible: Vec<navkf_dynamics::dataset::Implausibility>,
    /// Whether the dataset states its noise (a `[noise]` table in dataset.toml); without it
    /// the "stated" noise is navkf's default, and the findings say so first.
    #[serde(default = "stated_by_default")]
    pub noise_stated: bool,
}

/// Diagnoses written before `noise_stated` existed read datasets that stated their noise.
fn stated_by_default() -> bool {
    true
}

/// The filter passes behind a diagnosis, kept for its figures.
#[derive(Debug, Clone)]
pub struct Fits {
    /// The final model.
    pub model: Fit,
    /// The base model, when the final model has effects.
    pub before: Option<Fit>,
}
