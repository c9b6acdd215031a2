//! The diagnosis of data that cannot be what they claim.
//!
//! **Before anything is fitted**, the dataset's own checks
//! ([`navkf_dynamics::dataset::Dataset::implausibilities`]: input gaps, GPS jumps beyond what
//! the speed allows, flips across the pole or of a sign, free fall, an odometer faster than
//! any road vehicle, stated noise beyond any real sensor, a latitude too close to a pole for
//! the model). When any holds, the diagnosis names nothing and fits no noise:
//! [`implausible_diagnosis`] returns the verdict [`Verdict::ImplausibleData`] with the
//! findings first, and one pass of the model under test at the stated noise for the figures.
//! Any effect named on such data would stand in for the defect (a 10 km GPS step "is" a
//! latency of 207 s), and a noise level fitted across a 1000 s input gap "is" a gyro 28,000
//! times noisier than stated. This is an answer about the data, not a failure: the command
//! succeeds (exit 0) and prints the verdict; only data that cannot start a filter at all (no
//! row with both sensors, too few updates) are an error.

use crate::catalogue::first_full_measurement;
use crate::catalogue::Catalogue;
use crate::diagnosis::{Diagnosis, Fits};
use crate::error::DiagnoseError;
use crate::fit::pass::fit;
use crate::fit::setup::FitSetup;
use crate::options::Options;
use crate::priors;
use crate::summary::summarize_fit;
use crate::verdict::Verdict;
use navkf_dynamics::dataset::{Dataset, Implausibility};

/// The diagnosis of data that cannot be what they claim (module documentation): verdict
/// [`Verdict::ImplausibleData`], nothing named, no noise fitted, and one pass of the model
/// under test (base plus `--with`) at the stated noise for the figures and the final-model
/// table.
pub fn implausible_diagnosis(
    ds: &Dataset,
    catalogue: &dyn Catalogue,
    opts: &Options,
    found: Vec<Implausibility>,
) -> Result<(Diagnosis, Fits), DiagnoseError> {
    let (_, start) = first_full_measurement(ds)?;
    let (mut start_priors, prior_entries) = priors::resolve(ds, &opts.prior, start[0], catalogue);
    for e in &opts.with {
        start_priors.open.extend(catalogue.effect(e)?.coefficients);
    }
    let setup = FitSetup::new(opts.with.clone(), ds.noise, start_priors);
    let model = fit(ds, &setup, catalogue, &opts.filter)?;
    let mut d = Diagnosis {
        dataset: ds.name.clone(),
        family: catalogue.kind(),
        pinned: catalogue.pinned().iter().map(|p| p.to_string()).collect(),
        start_attitude: catalogue.start_attitude(ds),
        attitude: opts.filter.attitude,
        verdict: Verdict::ImplausibleData,
        best: None,
        effects: Vec::new(),
        suggested: Vec::new(),
        misfit: None,
        model: summarize_fit(ds, &model, opts),
        before: None,
        rounds: Vec::new(),
        noise: None,
        noise_checks: Vec::new(),
        priors: prior_entries,
        widened: Vec::new(),
        withdrawn: Vec::new(),
        constancy: Vec::new(),
        findings: Vec::new(),
        data_warnings: ds.warnings(),
        implausible: found,
        noise_stated: ds.noise_stated,
    };
    d.findings = crate::report::findings::findings(&d);
    Ok((
        d,
        Fits {
            model,
            before: None,
        },
    ))
}
