//! Name: the step of a round that decides which candidate, if any, the evidence names.
//!
//! **When a candidate is named.** Its evidence is decisive ([`DECISIVE_BIC`]), its filter
//! pass did not fail, its fitted values are a real sensor's ([`crate::physical`]), and its
//! coefficients can be told apart from the model's own: an effect with coefficients the
//! trajectory cannot separate is named only if the others carry decisive evidence on their
//! own ([`Candidate::separable_bic`]). Among those, the one with the largest gain is named.
//!
//! **Noise competes with structure rather than going first**, because a missing effect
//! inflates the fitted noise: the right structural model has the larger likelihood. A
//! noise-only term (`gyro-bias-walk`, docs/model.md eq. (44)) or the refitted noise levels can
//! soak up any slow misfit, so a noise explanation is named only when it beats the best
//! structured one by [`DECISIVE_BIC`], and a noise-only term only when it also makes the model
//! consistent; when the two compete the round says so. A noise-only term must also beat a
//! walk of the other sensor, outside the catalogue ([`crate::rivals`]): if that fits as well,
//! the data cannot say which sensor carries the drift.
//!
//! **No stand-ins.** When the misfit is explained decisively better by a candidate that
//! cannot be named (its coefficients confounded, or its values no real sensor's), nothing is
//! named in the round: a lesser candidate would only stand in for it.

use crate::candidates::evidence::{
    Candidate, CandidateKind, Evaluated, Named, Outcome, DECISIVE_BIC,
};
use crate::catalogue::Catalogue;
use crate::error::DiagnoseError;
use crate::fit::density::{fit_density, DensityFit};
use crate::fit::pass::Fit;
use navkf_dynamics::dataset::Dataset;
use navkf_filters::FilterSpec;

/// What the naming step of a round decided.
#[derive(Debug, Clone)]
pub struct Naming {
    /// Every candidate, best first, each with its outcome.
    pub candidates: Vec<Candidate>,
    /// What is named, with the fit that has it (the next round's model); `None` when nothing
    /// is.
    pub named: Option<(Named, Fit)>,
    /// Remarks for the report: competing explanations, and why a noise term was not named.
    pub notes: Vec<String>,
}

/// Names at most one of the `ranked` candidates of a round on the model `model` (module
/// documentation). A noise-only choice must beat its rival outside the catalogue; if it does
/// not, it is set aside and the choice made again.
pub fn name(
    ds: &Dataset,
    model: &Fit,
    mut ranked: Vec<Evaluated>,
    catalogue: &dyn Catalogue,
    filter: &FilterSpec,
) -> Result<Naming, DiagnoseError> {
    let mut candidates: Vec<Candidate> = ranked.iter().map(|e| e.candidate.clone()).collect();
    let mut not_specific = Vec::new();
    let mut rival_notes = Vec::new();
    let (choice, mut notes) = loop {
        let (choice, notes) = select(&mut candidates, &not_specific);
        if let Some(i) = choice.filter(|&i| candidates[i].kind == CandidateKind::NoiseOnly) {
            if let Some(note) = rival_note(ds, model, &ranked[i], catalogue, filter)? {
                not_specific.push(i);
                rival_notes.push(note);
                continue;
            }
        }
        break (choice, notes);
    };
    notes.extend(rival_notes);
    candidates.sort_by(|a, b| b.bic_gain.total_cmp(&a.bic_gain));
    let named = choice.map(|i| {
        let e = ranked.swap_remove(i);
        (e.names, e.fit)
    });
    Ok(Naming {
        candidates,
        named,
        notes,
    })
}

/// Whether a random walk of the accelerometer biases ([`AccelBiasWalk`], outside the
/// catalogue) fits the model as well as the noise-only candidate `chosen`; if so, the note
/// that says why `chosen` is not named.
fn rival_note(
    ds: &Dataset,
    model: &Fit,
    chosen: &Evaluated,
    catalogue: &dyn Catalogue,
    filter: &FilterSpec,
) -> Result<Option<String>, DiagnoseError> {
    let Some((with_rival, rival_name, rival_density)) = catalogue.with_rival() else {
        return Ok(None);
    };
    let DensityFit {
        fit: rival,
        density: q,
        ..
    } = fit_density(ds, model, rival_name, rival_density, &*with_rival, filter)?;
    // Same priors, one density each: the marginal likelihoods compare directly.
    let gain = 2.0 * (chosen.fit.loglik - rival.loglik);
    if rival.failure.is_none() && gain < DECISIVE_BIC {
        Ok(Some(format!(
            "`{}` would make the model consistent, but a random walk of the accelerometer \
             biases (density {q:.1e} (m/s^2)^2/s, not in the catalogue) fits as well (twice \
             the log-likelihood difference {gain:.1}, below {}): a slow drift is there, but the \
             data cannot say that the gyros carry it. It is not named. A drag, a warming-up \
             sensor or a walk of either sensor would all look like this; a gyro walk shows in \
             the heading too, so a longer test with turns tells them apart.",
            chosen.candidate.effect, DECISIVE_BIC
        )))
    } else {
        Ok(None)
    }
}

/// A round's choice (module documentation): sets every candidate's outcome and returns the
/// index of the one named, with notes for the report where a noise explanation competes with
/// a structured one.
pub fn select(cands: &mut [Candidate], not_specific: &[usize]) -> (Option<usize>, Vec<String>) {
    let mut notes = Vec::new();
    for (i, c) in cands.iter_mut().enumerate() {
        c.outcome = if not_specific.contains(&i) {
            Outcome::NoiseNotSpecific
        } else if c.failure.is_some() {
            Outcome::Failed
        } else if !c.decisive() {
            Outcome::NotDecisive
        } else if !c.beyond_bounds.is_empty() {
            Outcome::Unphysical
        } else if c.separable_bic.is_some_and(|b| !(b > DECISIVE_BIC)) {
            Outcome::Confounded
        } else {
            Outcome::Outranked
        };
    }
    let best = |cands: &[Candidate], noise: bool| {
        cands
            .iter()
            .enumerate()
            .filter(|(_, c)| {
                c.outcome == Outcome::Outranked && (c.kind != CandidateKind::Structured) == noise
            })
            .max_by(|a, b| a.1.bic_gain.total_cmp(&b.1.bic_gain))
            .map(|(i, c)| (i, c.bic_gain))
    };
    let structured = best(cands, false);
    // The misfit is best explained by something the trajectory cannot tell apart from the
    // model's own coefficients: naming a lesser candidate would name a stand-in.
    let confounded = cands
        .iter()
        .enumerate()
        .filter(|(_, c)| c.outcome == Outcome::Confounded)
        .max_by(|a, b| a.1.bic_gain.total_cmp(&b.1.bic_gain))
        .map(|(i, c)| (i, c.bic_gain));
    let best_named = structured
        .map(|s| s.1)
        .into_iter()
        .chain(best(cands, true).map(|n| n.1))
        .fold(f64::NEG_INFINITY, f64::max);
    // The same when the best explanation is no real sensor's.
    let unphysical = cands
        .iter()
        .enumerate()
        .filter(|(_, c)| c.outcome == Outcome::Unphysical)
        .max_by(|a, b| a.1.bic_gain.total_cmp(&b.1.bic_gain));
    if let Some((i, c)) = unphysical {
        if c.bic_gain - best_named >= DECISIVE_BIC && best_named > f64::NEG_INFINITY {
            notes.push(format!(
                "`{}` explains the misfit decisively better than any candidate that could be \
                 named (BIC gain {:.0} against {best_named:.0}), but its fitted values are no \
                 real sensor's: naming a lesser candidate would name a stand-in, so nothing is \
                 named in this round.",
                cands[i].effect, c.bic_gain
            ));
            return (None, notes);
        }
    }
    if let Some((i, bc)) = confounded {
        if bc - best_named >= DECISIVE_BIC && best_named > f64::NEG_INFINITY {
            notes.push(format!(
                "`{}` explains the misfit decisively better than any candidate that could be \
                 named (BIC gain {bc:.0} against {best_named:.0}), but the trajectory cannot tell \
                 it apart from coefficients already in the model: naming a lesser candidate would \
                 name a stand-in, so nothing is named in this round.",
                cands[i].effect
            ));
            return (None, notes);
        }
    }
    let named = loop {
        let noise = best(cands, true);
        match (structured, noise) {
            (s, Some((n, bn))) if s.is_none_or(|(_, bs)| bn - bs >= DECISIVE_BIC) => {
                if cands[n].kind == CandidateKind::NoiseOnly && !cands[n].consistent {
                    cands[n].outcome = Outcome::NoiseLeavesMisfit;
                    continue;
                }
                break Some(n);
            }
            (Some((s, bs)), noise) => {
                if let Some((n, bn)) = noise {
                    cands[n].outcome = Outcome::NoiseAsGoodAsStructure;
                    if bn > bs - DECISIVE_BIC {
                        notes.push(competition(&cands[n], bn, &cands[s], bs));
                    }
                }
                break Some(s);
            }
            (None, _) => break None,
        }
    };
    if let Some(i) = named {
        cands[i].outcome = Outcome::Named;
    }
    (named, notes)
}

/// The note when a noise explanation `n` fits about as well as a structured effect `s`.
fn competition(n: &Candidate, bn: f64, s: &Candidate, bs: f64) -> String {
    let what = match n.kind {
        CandidateKind::NoiseLevels => "Refitted noise levels".to_string(),
        _ => format!("`{}` (a noise term)", n.effect),
    };
    format!(
        "{what} fit about as well as `{}` (BIC gains {bn:.0} and {bs:.0}): more noise and a \
         structured effect can both account for a slow misfit. The structured effect is named, \
         as the more specific explanation; a structured effect recurs with the motion that \
         excites it and noise does not, so repeating the same manoeuvres (a second loop of the \
         path) or a longer record would tell them apart.",
        s.effect
    )
}
