//! The step of the diagnosis that asks whether an answer can be physical at all.
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
//!
//! **When a candidate is weighed**, its fitted coefficients are compared with the bounds its
//! effect declares ([`navkf_dynamics::Effect::coefficient_bounds`], reasons in
//! [`navkf_dynamics::sensor_classes`]), and a refitted noise level with the sensor classes'
//! ([`navkf_dynamics::sensor_classes::NOISE_BOUNDS`]). A decisive candidate beyond them is not
//! named ([`super::candidates::Outcome::Unphysical`], with [`BeyondBound`] saying which value
//! and why). If it explains the misfit decisively better than anything nameable, nothing is
//! named in that round ([`super::candidates::select`]): a lesser candidate would be a stand-in.

use super::candidates::{Candidate, Outcome};
use super::fit::{self, FitSetup};
use super::{priors, summarize_fit, Coefficient, DiagnoseError, Diagnosis, Fits, Options, Verdict};
use navkf_dynamics::dataset::{Dataset, Implausibility};
use navkf_dynamics::sensor_classes::noise_out_of_bounds;
use navkf_dynamics::{DynEffect, NoiseConfig, Registry};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

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
pub fn coefficients_beyond(
    effect: &dyn DynEffect,
    coefficients: &[Coefficient],
) -> Vec<BeyondBound> {
    effect
        .coefficient_names()
        .iter()
        .zip(effect.coefficient_bounds())
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

/// The diagnosis of data that cannot be what they claim (module documentation): verdict
/// [`Verdict::ImplausibleData`], nothing named, no noise fitted, and one pass of the model
/// under test (base plus `--with`) at the stated noise for the figures and the final-model
/// table.
pub fn implausible_diagnosis(
    ds: &Dataset,
    registry: &Registry,
    opts: &Options,
    found: Vec<Implausibility>,
) -> Result<(Diagnosis, Fits), DiagnoseError> {
    let (_, _, start) = fit::first_full_measurement(ds)?;
    let (mut start_priors, prior_entries) = priors::resolve(ds, &opts.prior, start[0]);
    for e in &opts.with {
        let effect = registry.build(e)?;
        start_priors
            .open
            .extend(effect.coefficient_names().iter().map(|c| c.to_string()));
    }
    let setup = FitSetup {
        effects: opts.with.clone(),
        parameters: BTreeMap::new(),
        noise: ds.noise,
        priors: start_priors,
    };
    let model = fit::fit(ds, &setup, registry, &opts.filter)?;
    let mut d = Diagnosis {
        dataset: ds.name.clone(),
        attitude: opts.filter.attitude,
        verdict: Verdict::ImplausibleData,
        best: None,
        effects: Vec::new(),
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
    d.findings = super::report::findings(&d);
    Ok((
        d,
        Fits {
            model,
            before: None,
        },
    ))
}

/// The findings of an implausible-data diagnosis: each implausibility, where it is, then what
/// follows.
pub fn implausible_findings(d: &Diagnosis) -> Vec<String> {
    let mut out: Vec<String> = d.implausible.iter().map(|i| format!("{i}.")).collect();
    out.push(format!(
        "The data are not what they claim ({}, found in the data themselves): no effect is \
         named and no noise level is fitted, because any answer would stand in for the defect. \
         Correct or cut the data and diagnose again.",
        match d.implausible.len() {
            1 => "the finding above".to_string(),
            n => format!("the {n} findings above"),
        }
    ));
    if let Some(f) = &d.model.failure {
        out.push(format!(
            "The model under test could not even be run over them at the stated noise: {f}."
        ));
    }
    out
}

/// Sentences for the candidates of `rounds` that were decisive but not named because their
/// fitted values are no real sensor's.
pub fn refusal_findings(rounds: &[super::Round]) -> Vec<String> {
    let mut out = Vec::new();
    for (k, r) in rounds.iter().enumerate() {
        for c in r
            .candidates
            .iter()
            .filter(|c| c.outcome == Outcome::Unphysical)
        {
            out.push(refusal(k + 1, c));
        }
    }
    out
}

fn refusal(round: usize, c: &Candidate) -> String {
    let values: Vec<String> = c.beyond_bounds.iter().map(|b| b.to_string()).collect();
    format!(
        "Round {round}: `{}` has decisive evidence (BIC gain {:.1}) but is not named: fitted, \
         {}. No real sensor has that value; the data, or what is stated about them, are more \
         likely at fault than the instrument.",
        c.effect,
        c.bic_gain,
        values.join("; ")
    )
}

/// When the last round refused decisive candidates as no real sensor's: why no catalogued
/// effect is named (instead of "none has decisive evidence").
pub fn unphysical_instead(last: &[Candidate]) -> Option<String> {
    let refused: Vec<String> = last
        .iter()
        .filter(|c| c.outcome == Outcome::Unphysical)
        .map(|c| format!("`{}`", c.effect))
        .collect();
    (!refused.is_empty()).then(|| {
        format!(
            "No catalogued effect can be named: {} explain the misfit decisively, but only \
             with values no real sensor has (above), and nothing else explains it as well. The \
             cause is outside the catalogue, or the data are not what they claim.",
            refused.join(", ")
        )
    })
}
