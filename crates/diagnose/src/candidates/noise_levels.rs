//! The refitted noise levels as a candidate. A model can fail because its noise levels are
//! wrong rather than because something physical is missing; the noise check
//! ([`crate::noise`]) fits the levels, and here they compete with the effects in the same
//! currency: the model refitted at them, weighed like an effect with one parameter per noise
//! source it changed. Noise does not go first because a missing effect inflates the fitted
//! noise: the right structural model has the larger likelihood. With two effects missing,
//! neither alone may beat the levels, which soak up a share of both; the best effect is then
//! weighed again with the noise refitted beside it ([`super::beside_noise`]).

use super::evidence::{Candidate, CandidateKind, Evaluated, Model, Named, Outcome, NOISE_LEVELS};
use crate::catalogue::Catalogue;
use crate::error::DiagnoseError;
use crate::fit::widening::fit_adaptive;
use crate::noise::levels::NoiseFit;
use crate::options::Options;
use crate::summary::summarize_fit;
use navkf_dynamics::dataset::Dataset;

/// The candidate "noise levels": `model` refitted with the levels `check` found (from the
/// starting priors), weighed like an effect with one parameter per source it changed.
pub fn noise_levels(
    ds: &Dataset,
    model: &Model<'_>,
    check: &NoiseFit,
    catalogue: &dyn Catalogue,
    opts: &Options,
) -> Result<Evaluated, DiagnoseError> {
    let setup = model.fit.setup.at_noise(check.used);
    let (fit, widened) = fit_adaptive(ds, &setup, catalogue, &opts.filter)?;
    let s = summarize_fit(ds, &fit, opts);
    let keep: Vec<String> = fit
        .names
        .iter()
        .enumerate()
        .filter(|(i, _)| fit.noisy[*i])
        .map(|(_, n)| n.clone())
        .collect();
    let dll = fit.profile_loglik(&keep) - model.fit.profile_loglik(&keep);
    let changed = check.changed_sources(&model.fit.setup.noise);
    let ln_n = (model.fit.measurement_count().max(1) as f64).ln();
    let excess = model.summary.excess_nis;
    let candidate = Candidate {
        effect: NOISE_LEVELS.into(),
        kind: CandidateKind::NoiseLevels,
        delta_loglik: dll,
        parameters: changed,
        bic_gain: 2.0 * dll - changed as f64 * ln_n,
        excess_removed: if excess > 0.0 {
            1.0 - s.excess_nis.max(0.0) / excess
        } else {
            0.0
        },
        nis: s.nis.clone(),
        consistent: s.consistent,
        coefficients: Vec::new(),
        density: None,
        noise: Some(check.clone()),
        widened,
        confused_with: Vec::new(),
        separable_bic: None,
        beside_refitted_noise: None,
        beyond_bounds: crate::physical::noise_beyond(&check.used),
        outcome: Outcome::NotDecisive,
        failure: fit.failure.clone(),
    };
    Ok(Evaluated {
        candidate,
        fit,
        names: Named::NoiseLevels {
            theta: check.used(),
        },
    })
}
