//! What a diagnosis study needs of its model family: the effects it may hide, what of the
//! study file the family does not read, the content classes it has no use for, whether two
//! effects fit one model, their typical sizes, how an effect's size is drawn, and the
//! datasets themselves.
//!
//! Why a trait: the plan, the tallies, the rates and the report are the same for every
//! family, so a new family's error-rate study is one implementation of [`StudyFamily`] here
//! and one arm of [`of`], its registration.

mod platform;
mod strapdown;

use super::hidden::{Hidden, Planned};
use super::rates::EffectScale;
use super::{ContentClass, DiagnosisStudyConfig};
use crate::error::DiagnoseError;
use navkf_dynamics::dataset::Dataset;
use navkf_dynamics::{ModelKind, Trajectory};
use rand_chacha::ChaCha8Rng;
use std::sync::Arc;

/// Whether one model holds both effects of a pair (the study's family, registry built once).
pub(super) type PairFits = Box<dyn Fn([&str; 2]) -> Result<(), DiagnoseError>>;

/// Draws a hidden effect of a catalogue built once: `(rng, name, size range)`, the range in
/// multiples of the effect's typical size.
pub(super) type EffectDraw<'a> =
    Box<dyn Fn(&mut ChaCha8Rng, &str, [f64; 2]) -> Result<Hidden, DiagnoseError> + 'a>;

/// A model family as a diagnosis study runs it (module documentation).
pub(super) trait StudyFamily: Sync {
    /// The family's effects: its catalogue's, then those the study file declares.
    fn effect_names(&self, config: &DiagnosisStudyConfig) -> Result<Vec<String>, DiagnoseError>;

    /// Refuses, by key, what of the study file the family does not read.
    fn validate(&self, config: &DiagnosisStudyConfig) -> Result<(), String>;

    /// Why a content class is not the family's (the refusal after `content[i]: `); `None`:
    /// it is.
    fn refuses_class(&self, class: &ContentClass) -> Option<&'static str>;

    /// Whether one model of the family holds both effects of a pair.
    fn pair_fits(&self, config: &DiagnosisStudyConfig) -> Result<PairFits, DiagnoseError>;

    /// The family's effects with their typical sizes (the detection curves' scale).
    fn effect_scales(&self, config: &DiagnosisStudyConfig) -> Vec<EffectScale>;

    /// How a hidden effect's size is drawn.
    fn effect_draw<'a>(
        &self,
        config: &'a DiagnosisStudyConfig,
    ) -> Result<EffectDraw<'a>, DiagnoseError>;

    /// The noise sources a mis-stated noise may put off (the first of
    /// [`super::hidden::misstate`]'s factors).
    fn noise_sources(&self) -> usize;

    /// Simulates planned dataset `p`.
    fn simulate(
        &self,
        config: &DiagnosisStudyConfig,
        trajectory: &Arc<Trajectory>,
        p: &Planned,
    ) -> Result<Dataset, DiagnoseError>;

    /// What the report says the tests are of, after "vehicle tests" (empty, or ` of a
    /// strapdown mems unit`).
    fn unit_words(&self, config: &DiagnosisStudyConfig) -> String;
}

/// The family `kind` as a diagnosis study runs it: the families' registration.
pub(super) fn of(kind: ModelKind) -> &'static dyn StudyFamily {
    match kind {
        ModelKind::Platform => &platform::Platform,
        ModelKind::Strapdown => &strapdown::Strapdown,
    }
}

/// A declaration's error as its key and message (`effect[0].places[1].place: ...`).
fn declaration_message(e: DiagnoseError) -> String {
    match e {
        DiagnoseError::Dynamics(navkf_dynamics::DynamicsError::Config { key, message }) => {
            format!("{key}: {message}")
        }
        other => other.to_string(),
    }
}
