//! The model under test: the first step of a diagnosis, before any round.
//!
//! The base model plus the `--with` effects, fitted from the starting priors ([`crate::priors`])
//! with the priors widened where the data pull beyond them ([`crate::fit::widening`]); the
//! initial tilt's priors are also tried wider, because a platform gyrocompassed with drifts
//! far beyond its priors starts degrees off in azimuth, and a filter held to arcminutes then
//! blames the misfit on something else. When `--with` added effects, a manual round records
//! what they gain over the base model, weighed like a candidate.

use crate::candidates::evidence::{Candidate, CandidateKind, Outcome};
use crate::catalogue::Catalogue;
use crate::diagnosis::{Round, RoundKind};
use crate::error::DiagnoseError;
use crate::fit::pass::Fit;
use crate::fit::setup::FitSetup;
use crate::fit::widening::{fit_adaptive, widen_tilt, Widening};
use crate::options::Options;
use crate::priors::{self, PriorEntry, Priors};
use crate::summary::summarize_fit;
use navkf_dynamics::dataset::Dataset;

/// The model under test, fitted, and where the diagnosis started.
#[derive(Debug, Clone)]
pub struct UnderTest {
    /// The priors the diagnosis started from.
    pub start: Priors,
    /// The same as the report shows them, with their sources.
    pub prior_entries: Vec<PriorEntry>,
    /// The base model (no effects) with the tilt priors the model under test ended with: the
    /// "before" of the report.
    pub base: FitSetup,
    /// The model under test, fitted.
    pub fit: Fit,
    /// The tilt priors widened.
    pub tilt_widened: Vec<Widening>,
    /// The manual round, when `--with` added effects.
    pub manual_round: Option<Round>,
}

/// Fits the model under test (module documentation) on `ds`, whose first full measurement
/// is at latitude `start_lat` (rad).
pub fn fit_under_test(
    ds: &Dataset,
    catalogue: &dyn Catalogue,
    opts: &Options,
    start_lat: f64,
) -> Result<UnderTest, DiagnoseError> {
    let (start, prior_entries) = priors::resolve(ds, &opts.prior, start_lat, catalogue);
    let base = FitSetup::new(Vec::new(), ds.noise, start.clone());
    let mut under_test = FitSetup {
        effects: opts.with.clone(),
        ..base.clone()
    };
    for e in &opts.with {
        under_test
            .priors
            .open
            .extend(catalogue.effect(e)?.coefficients);
    }
    let (fit, _) = fit_adaptive(ds, &under_test, catalogue, &opts.filter)?;
    let (fit, tilt_widened) = widen_tilt(ds, fit, catalogue, &opts.filter)?;
    let base = FitSetup {
        priors: Priors {
            coefficients: base.priors.coefficients.clone(),
            ..fit.setup.priors.clone()
        },
        ..base
    };
    let manual_round = if opts.with.is_empty() {
        None
    } else {
        let (b, _) = fit_adaptive(ds, &base, catalogue, &opts.filter)?;
        Some(manual_round(ds, &b, &fit, opts))
    };
    Ok(UnderTest {
        start,
        prior_entries,
        base,
        fit,
        tilt_widened,
        manual_round,
    })
}

/// The `--with` round: the effects added together to the base model `before`, giving `after`.
fn manual_round(ds: &Dataset, before: &Fit, after: &Fit, opts: &Options) -> Round {
    let b = summarize_fit(ds, before, opts);
    let a = summarize_fit(ds, after, opts);
    let keep: Vec<String> = after
        .names
        .iter()
        .enumerate()
        .filter(|(i, _)| after.noisy[*i])
        .map(|(_, n)| n.clone())
        .collect();
    let dll = after.profile_loglik(&keep) - before.profile_loglik(&keep);
    // The coefficients added; a bias instability's departures are driven by noise and
    // count as its one parameter (the density), as a candidate's do, and a coefficient the
    // family holds at zero is none.
    let added = (after.nav_dim..after.names.len())
        .filter(|&i| !after.noisy[i] && !after.pinned[i] && !before.names.contains(&after.names[i]))
        .count();
    let k = added.max(opts.with.len());
    let ln_n = (before.measurement_count().max(1) as f64).ln();
    let removed = if b.excess_nis > 0.0 {
        1.0 - a.excess_nis.max(0.0) / b.excess_nis
    } else {
        0.0
    };
    Round {
        kind: RoundKind::Manual,
        model: Vec::new(),
        nis: b.nis.clone(),
        consistent: b.consistent,
        candidates: vec![Candidate {
            effect: opts.with.join(","),
            kind: CandidateKind::Structured,
            delta_loglik: dll,
            parameters: k,
            bic_gain: 2.0 * dll - k as f64 * ln_n,
            excess_removed: removed,
            nis: a.nis.clone(),
            consistent: a.consistent,
            coefficients: a
                .coefficients
                .iter()
                .filter(|c| !before.names.contains(&c.name) && !c.wanders && !c.held)
                .cloned()
                .collect(),
            density: None,
            noise: None,
            widened: Vec::new(),
            confused_with: Vec::new(),
            separable_bic: None,
            beside_refitted_noise: None,
            beyond_bounds: Vec::new(),
            outcome: Outcome::Manual,
            failure: after.failure.clone(),
        }],
        named: opts.with.clone(),
        notes: Vec::new(),
    }
}
