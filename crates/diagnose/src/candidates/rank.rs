//! The ranking of a round: every catalogued effect not yet in the model that can join it
//! ([`Catalogue::cannot_join`]) weighed against it,
//! in parallel, best first, and the refitted noise levels after them when the noise check
//! found the stated levels off. What the trajectory could not tell apart in an earlier round
//! stays so ([`Confounded`]).

use super::effect::evaluate;
use super::evidence::{Candidate, Confusion, Evaluated, Model, DECISIVE_BIC};
use super::noise_levels::noise_levels;
use crate::catalogue::Catalogue;
use crate::error::DiagnoseError;
use crate::noise::levels::NoiseFit;
use crate::options::Options;
use navkf_dynamics::dataset::Dataset;
use rayon::prelude::*;

/// Every candidate of a round weighed against `model`: each catalogue effect not in it, ranked
/// by BIC gain, with those found confounded earlier marked so again; then, when the noise
/// `check` refitted levels other than the model's, the candidate "noise levels".
pub fn rank(
    ds: &Dataset,
    model: &Model<'_>,
    check: Option<&NoiseFit>,
    confounded: &Confounded,
    catalogue: &dyn Catalogue,
    opts: &Options,
) -> Result<Vec<Evaluated>, DiagnoseError> {
    let mut ranked = evaluate_all(ds, model, catalogue, opts)?;
    confounded.mark(&mut ranked);
    if let Some(c) = check.filter(|c| c.refitted && c.used != model.fit.setup.noise) {
        ranked.push(noise_levels(ds, model, c, catalogue, opts)?);
    }
    Ok(ranked)
}

/// Evaluates every catalogue effect not in `model` that can join it
/// ([`Catalogue::cannot_join`]), in parallel, ranked by BIC gain.
pub fn evaluate_all(
    ds: &Dataset,
    model: &Model<'_>,
    catalogue: &dyn Catalogue,
    opts: &Options,
) -> Result<Vec<Evaluated>, DiagnoseError> {
    let names: Vec<String> = catalogue
        .effect_names()
        .into_iter()
        .filter(|e| !model.fit.effects.contains(e))
        .filter(|e| catalogue.cannot_join(&model.fit.effects, e).is_none())
        .collect();
    let mut out = names
        .par_iter()
        .map(|name| {
            // A stop on request (Ctrl-C) skips the candidates not yet started.
            crate::error::stop_if_requested()?;
            evaluate(ds, model, name, catalogue, opts)
        })
        .collect::<Result<Vec<Option<Evaluated>>, _>>()?
        .into_iter()
        .flatten()
        .collect::<Vec<_>>();
    out.sort_by(|a, b| b.candidate.bic_gain.total_cmp(&a.candidate.bic_gain));
    Ok(out)
}

/// Effects the trajectory could not tell from the model's coefficients in an earlier round,
/// with the pairs: they stay so in later rounds. A noise term named meanwhile (a walk of the
/// drifts) makes the base coefficients wander, which hides the confusion without removing it.
#[derive(Debug, Clone, Default)]
pub struct Confounded(Vec<(String, Vec<Confusion>)>);

impl Confounded {
    /// Remembers the candidates of a round whose coefficients could not be told apart and
    /// whose other coefficients carry no decisive evidence on their own.
    pub fn remember(&mut self, candidates: &[Candidate]) {
        for c in candidates {
            let inseparable =
                !c.confused_with.is_empty() && !c.separable_bic.is_some_and(|b| b > DECISIVE_BIC);
            if inseparable && !self.0.iter().any(|k| k.0 == c.effect) {
                self.0.push((c.effect.clone(), c.confused_with.clone()));
            }
        }
    }

    /// Marks the remembered effects among `ranked` that this round's fit no longer finds
    /// confused: their earlier pairs, and no separable evidence.
    fn mark(&self, ranked: &mut [Evaluated]) {
        for e in ranked {
            if let Some((_, confusion)) = self.0.iter().find(|k| k.0 == e.candidate.effect) {
                if e.candidate.confused_with.is_empty() {
                    e.candidate.confused_with = confusion.clone();
                    e.candidate.separable_bic = Some(f64::NEG_INFINITY);
                }
            }
        }
    }
}
