//! The example run's traces, for the estimate-versus-truth figures.

use super::run::RunRecord;
use super::Study;
use serde::{Deserialize, Serialize};

/// The example run's traces, for the estimate-versus-truth figures.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct ExampleRun {
    /// Run index.
    pub run: usize,
    /// State names (filter model).
    pub names: Vec<String>,
    /// Times, s.
    pub t: Vec<f64>,
    /// True value of each filter state at each time (NaN where the truth lacks the state).
    #[serde(with = "navkf_report::json_nan")]
    pub truth: Vec<Vec<f64>>,
    /// Per filter: estimates and sigmas at each time.
    pub filters: Vec<ExampleFilter>,
}

/// One filter's trace in the example run.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct ExampleFilter {
    /// Filter name.
    pub name: String,
    /// Times of the estimates (may stop early if the filter diverged).
    pub t: Vec<f64>,
    /// Estimates.
    #[serde(with = "navkf_report::json_nan")]
    pub estimate: Vec<Vec<f64>>,
    /// One-sigma.
    #[serde(with = "navkf_report::json_nan")]
    pub sigma: Vec<Vec<f64>>,
}

impl Study {
    /// The example run's traces from its record.
    pub fn example_of(&self, rec: &RunRecord) -> ExampleRun {
        let truth = rec.truth.as_ref();
        let mut ex = ExampleRun {
            run: rec.run,
            names: self.names.clone(),
            ..Default::default()
        };
        if let Some(tr) = truth {
            for (t, s) in tr.t.iter().zip(&tr.states).skip(1) {
                ex.t.push(*t);
                ex.truth.push(
                    self.to_truth
                        .iter()
                        .map(|j| j.map_or(f64::NAN, |j| s[j]))
                        .collect(),
                );
            }
        }
        for (name, fr) in self.filter_names().iter().zip(&rec.filters) {
            let mut ef = ExampleFilter {
                name: name.clone(),
                ..Default::default()
            };
            if let Some(trace) = &fr.trace {
                for point in trace {
                    ef.t.push(point.t);
                    ef.estimate.push(point.estimate.clone());
                    ef.sigma.push(point.sigma.clone());
                }
            }
            ex.filters.push(ef);
        }
        ex
    }
}
