//! Test planning: which coefficients a vehicle test identifies, predicted in seconds, without
//! Monte Carlo.
//!
//! The prediction is the truth-linearised Cramer-Rao bound the studies already compute
//! ([`Study::bound_recursion`]: the EKF's covariance recursion with the truth model, its
//! state reset to the true state before each step) along one simulated run of the study's
//! test (run 0 of its seed). On this model the information hardly depends on the particular
//! truth: the coefficients enter linearly (docs/model.md eqs. (5), (6)), and the rest of the
//! Jacobian depends on the path, which every run shares. So one recursion predicts what the
//! Monte Carlo RMS of the same study will be (README's "Plan a test" states the agreement for
//! the paper study).
//!
//! Per coefficient: the predicted final sigma and its ratio to the prior, when it first falls
//! to half the prior (identified: below half at the end), and which coefficients it stays
//! confounded with (final correlation of 0.9 or more in magnitude).

use crate::error::StudyError;
use crate::monte_carlo::Study;
use navkf_dynamics::state::NAV_DIM;
use navkf_report::markdown::{number, Number, Table};
use serde::{Deserialize, Serialize};
use std::fmt::Write;

/// A coefficient counts as identified once its sigma is below this fraction of its prior.
pub const IDENTIFIED_BELOW: f64 = 0.5;
/// Coefficients whose final correlation reaches this magnitude are reported as confounded.
pub const CONFOUNDED_FROM: f64 = 0.9;

/// A coefficient confounded with another.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Confounding {
    /// The other coefficient.
    pub with: String,
    /// Their final correlation.
    pub correlation: f64,
}

/// One coefficient's prediction.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CoefficientPlan {
    /// Its name.
    pub name: String,
    /// Its unit.
    pub unit: String,
    /// Prior one-sigma (the filters' initial sigma).
    pub prior_sigma: f64,
    /// Predicted one-sigma at the end of the test.
    pub final_sigma: f64,
    /// `final_sigma / prior_sigma`.
    pub ratio: f64,
    /// When the sigma first falls to half the prior, s (`None`: it never does).
    pub half_prior_s: Option<f64>,
    /// Whether it ends below [`IDENTIFIED_BELOW`] of its prior.
    pub identified: bool,
    /// Coefficients it ends correlated with beyond [`CONFOUNDED_FROM`].
    pub confounded: Vec<Confounding>,
}

/// `plan.json`: the whole prediction.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Plan {
    /// Study name.
    pub study: String,
    /// Test duration, s.
    pub duration_s: f64,
    /// Per coefficient, in state order.
    pub coefficients: Vec<CoefficientPlan>,
    /// Times of the series, s (every measurement).
    pub t: Vec<f64>,
    /// Per coefficient, its predicted sigma / prior at each time.
    pub sigma_over_prior: Vec<Vec<f64>>,
}

impl Plan {
    /// Names of the coefficients identified (below half their prior at the end).
    pub fn identified(&self) -> Vec<&str> {
        self.coefficients
            .iter()
            .filter(|c| c.identified)
            .map(|c| c.name.as_str())
            .collect()
    }
}

/// Predicts the identifiability of every coefficient of `study`'s truth model.
pub fn plan(study: &Study) -> Result<Plan, StudyError> {
    let model = study.sim.truth_model();
    let n = model.dim();
    let names = model.state_names();
    let units = model.state_units();
    let run = study.sim.run(study.config.study.seed, 0);
    let mut t = Vec::with_capacity(run.measurements.len());
    let mut variance: Vec<Vec<f64>> = vec![Vec::with_capacity(run.measurements.len()); n];
    let mut last = Vec::new();
    study
        .bound_recursion(&run, |time, p, nt| {
            t.push(time);
            for (i, v) in variance.iter_mut().enumerate() {
                v.push(p[i + i * nt]);
            }
            last.clear();
            last.extend_from_slice(p);
        })
        .map_err(|failure| {
            StudyError::Other(format!(
                "the bound's covariance recursion failed along the test ({}): {}",
                failure.cause, failure.reason
            ))
        })?;
    if t.is_empty() {
        return Err(StudyError::Other(
            "the test has no measurement: nothing to plan".into(),
        ));
    }
    // Prior: the recursion's own initial sigma.
    let prior = study.bound_prior_sigma();
    let mut coefficients = Vec::new();
    let mut sigma_over_prior = Vec::new();
    for i in NAV_DIM..n {
        let series: Vec<f64> = variance[i]
            .iter()
            .map(|v| v.max(0.0).sqrt() / prior[i])
            .collect();
        let final_sigma = last[i + i * n].max(0.0).sqrt();
        let ratio = final_sigma / prior[i];
        let half_prior_s = series
            .iter()
            .position(|r| *r <= IDENTIFIED_BELOW)
            .map(|k| t[k]);
        let mut confounded: Vec<Confounding> = (0..n)
            .filter(|&j| j != i && !(3..NAV_DIM).contains(&j))
            .filter_map(|j| {
                let c = last[i + j * n] / (last[i + i * n] * last[j + j * n]).sqrt();
                (c.abs() >= CONFOUNDED_FROM).then(|| Confounding {
                    with: names[j].clone(),
                    correlation: c,
                })
            })
            .collect();
        confounded.sort_by(|a, b| b.correlation.abs().total_cmp(&a.correlation.abs()));
        coefficients.push(CoefficientPlan {
            name: names[i].clone(),
            unit: units[i].clone(),
            prior_sigma: prior[i],
            final_sigma,
            ratio,
            half_prior_s,
            identified: ratio < IDENTIFIED_BELOW,
            confounded,
        });
        sigma_over_prior.push(series);
    }
    Ok(Plan {
        study: study.config.study.name.clone(),
        duration_s: study.config.trajectory.duration_s,
        coefficients,
        t,
        sigma_over_prior,
    })
}

/// The plan as a text table (what `navkf plan` prints and `plan.md` holds).
pub fn table(p: &Plan) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{:<8} {:>11} {:>11} {:>8} {:>11}  {:<10} confounded with (correlation)",
        "coef", "prior", "final", "ratio", "half at", "identified"
    );
    for c in &p.coefficients {
        let conf: Vec<String> = c
            .confounded
            .iter()
            .map(|k| format!("{} ({:+.3})", k.with, k.correlation))
            .collect();
        let _ = writeln!(
            out,
            "{:<8} {:>11.3e} {:>11.3e} {:>8.3} {:>11}  {:<10} {}",
            c.name,
            c.prior_sigma,
            c.final_sigma,
            c.ratio,
            c.half_prior_s
                .map_or("never".to_string(), |s| format!("{s:.0} s")),
            if c.identified { "yes" } else { "no" },
            conf.join(", ")
        );
    }
    let _ = writeln!(
        out,
        "identified (final sigma below {} of the prior): {} of {}",
        IDENTIFIED_BELOW,
        p.identified().len(),
        p.coefficients.len()
    );
    out
}

/// One design of a comparison: a point of a sweep or one study file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Design {
    /// How the design is named: `key = value` or the file's name.
    pub label: String,
    /// The swept value (sweeps only).
    pub value: Option<f64>,
    /// Its plan, without the time series.
    pub coefficients: Vec<CoefficientPlan>,
}

/// `designs.json`: several designs' plans side by side.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Comparison {
    /// The swept key, for a sweep.
    pub key: Option<String>,
    /// The model family of the designs (the platform unless said): a strapdown sweep's
    /// axis calls the azimuth prior the heading's.
    #[serde(
        default,
        skip_serializing_if = "navkf_dynamics::ModelKind::is_platform"
    )]
    pub model: navkf_dynamics::ModelKind,
    /// The designs, in order.
    pub designs: Vec<Design>,
}

impl Design {
    /// The design of `plan`, labelled.
    pub fn of(label: String, value: Option<f64>, plan: &Plan) -> Self {
        Design {
            label,
            value,
            coefficients: plan.coefficients.clone(),
        }
    }
}

/// The comparison as a Markdown table: per design, every coefficient's predicted sigma /
/// prior (identified ones in bold) and how many it identifies.
pub fn comparison_table(c: &Comparison) -> String {
    let mut out = String::new();
    let Some(first) = c.designs.first() else {
        return out;
    };
    let names: Vec<&str> = first.coefficients.iter().map(|k| k.name.as_str()).collect();
    let mut table = Table::new(
        ["design", "identified"]
            .into_iter()
            .chain(names.iter().copied()),
    );
    for d in &c.designs {
        let cells = names.iter().map(|n| {
            d.coefficients
                .iter()
                .find(|k| k.name == *n)
                .map_or("-".into(), |k| {
                    let ratio = number(k.ratio, Number::Fixed(3));
                    if k.identified && k.ratio.is_finite() {
                        format!("**{ratio}**")
                    } else {
                        ratio
                    }
                })
        });
        let count = d.coefficients.iter().filter(|k| k.identified).count();
        table.row(
            [
                d.label.clone(),
                format!("{count} of {}", d.coefficients.len()),
            ]
            .into_iter()
            .chain(cells),
        );
    }
    out.push_str(&table.render());
    out
}
