//! From a tally to what a reader sees: `summary.json`, CSV time series, tables.

use crate::monte_carlo::Study;
use crate::tally::{quantile, Tally};
use navkf_dynamics::state::NAV_DIM;
use navkf_report::stats::{mean_chi2_bounds, MeanChi2};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// One filter's results.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FilterSummary {
    /// RMS over runs of each coefficient's final error.
    pub final_rms: BTreeMap<String, f64>,
    /// RMS over runs of the filter's own final sigma of each coefficient.
    pub final_sigma: BTreeMap<String, f64>,
    /// The truth-linearised Riccati bound (posterior Cramer-Rao) of each coefficient.
    pub final_bound: BTreeMap<String, f64>,
    /// RMS of the navigation states' final errors.
    pub final_rms_nav: BTreeMap<String, f64>,
    /// Average NEES at the final time over runs (dof = state dimension).
    pub nees_mean: f64,
    /// 95 % bounds of `nees_mean` for a consistent filter.
    pub nees_bounds: [f64; 2],
    /// Average NIS over all updates of all runs.
    pub nis_mean: f64,
    /// 95 % bounds of `nis_mean` (independent updates assumed).
    pub nis_bounds: [f64; 2],
    /// Average measurement dimension (the NIS's expected value).
    pub nis_dof: f64,
    /// Runs excluded as diverged.
    pub diverged: u64,
    /// Those runs counted by cause (causes with none left out). Absent from summaries
    /// written before causes were typed.
    #[serde(default)]
    pub diverged_by_cause: BTreeMap<navkf_filters::DivergenceCause, u64>,
    /// Runs included.
    pub runs_ok: u64,
    /// Median cost of one predict + update, ns (measured inside the runs).
    pub step_ns_median: f64,
    /// 90th percentile of that cost, ns.
    pub step_ns_p90: f64,
    /// The first diverged runs and why (at most 20).
    pub diverged_examples: Vec<crate::tally::Divergence>,
}

impl FilterSummary {
    /// The final average NEES with its bounds (kept as two flat fields in `summary.json`,
    /// the format baselines and shards are written in).
    pub fn nees(&self) -> MeanChi2 {
        MeanChi2 {
            mean: self.nees_mean,
            bounds: self.nees_bounds,
        }
    }

    /// The average NIS over all updates with its bounds.
    pub fn nis(&self) -> MeanChi2 {
        MeanChi2 {
            mean: self.nis_mean,
            bounds: self.nis_bounds,
        }
    }
}

/// Paired comparison of two filters on one coefficient.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PairedDifference {
    /// First filter.
    pub a: String,
    /// Second filter.
    pub b: String,
    /// Coefficient.
    pub coefficient: String,
    /// Runs where both finished.
    pub n: u64,
    /// Mean of `e_a^2 - e_b^2` over runs.
    pub mean_sq_err_diff: f64,
    /// Its 95 % confidence interval.
    pub ci95: [f64; 2],
    /// The difference relative to `b`'s mean squared error.
    pub relative: f64,
    /// `b`'s mean squared error, the scale of [`EQUIVALENCE_MARGIN`] (NaN in summaries
    /// written before the margin, which then give no `equal within` verdict).
    #[serde(default = "not_known")]
    pub b_mean_sq_err: f64,
}

fn not_known() -> f64 {
    f64::NAN
}

/// Paired differences whose whole 95 % interval lies within this share of `b`'s mean
/// squared error are called equal. The filters of one study see the same draws, so their
/// paired difference is measured far more finely than either's RMS: a few hundred runs
/// resolve shares of 1e-7, the rounding of two algebraically equal filters. 1 % of a mean
/// squared error is 0.5 % of an RMS, below the RMS tables' own sampling error (about 3 % at
/// 500 runs) and below any difference a user would choose a filter by.
pub const EQUIVALENCE_MARGIN: f64 = 0.01;

/// What a paired difference says.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PairedVerdict {
    /// The interval is not finite (fewer than two runs where both finished).
    NoVerdict,
    /// The whole 95 % interval lies within [`EQUIVALENCE_MARGIN`] of `b`'s mean squared
    /// error, whether or not it holds zero.
    Equal,
    /// The 95 % interval holds zero and reaches beyond the margin.
    NoSignificantDifference,
    /// The interval is above zero and reaches beyond the margin: `a` has the larger
    /// squared error.
    AWorse,
    /// The interval is below zero and reaches beyond the margin: `b` has the larger
    /// squared error.
    BWorse,
}

impl PairedDifference {
    /// Whether one filter is worse by more than the margin could hold (a NaN interval is no
    /// verdict, so `false`).
    pub fn significant(&self) -> bool {
        matches!(
            self.verdict(),
            PairedVerdict::AWorse | PairedVerdict::BWorse
        )
    }

    /// Whether the 95 % interval excludes zero, however small the difference.
    pub fn excludes_zero(&self) -> bool {
        let [lo, hi] = self.ci95;
        lo > 0.0 || hi < 0.0
    }

    /// What the 95 % interval says.
    ///
    /// ```
    /// use navkf_study::summary::{PairedDifference, PairedVerdict};
    /// let d = |ci95: [f64; 2]| PairedDifference {
    ///     a: "ekf".into(),
    ///     b: "standard_ukf".into(),
    ///     coefficient: "Kg0x".into(),
    ///     n: 500,
    ///     mean_sq_err_diff: 0.5 * (ci95[0] + ci95[1]),
    ///     ci95,
    ///     relative: 0.5 * (ci95[0] + ci95[1]) / 4.0,
    ///     b_mean_sq_err: 4.0,
    /// };
    /// // Significant, but 1e-6 of the mean squared error: equal.
    /// assert_eq!(d([1e-6, 5e-6]).verdict(), PairedVerdict::Equal);
    /// assert_eq!(d([0.01, 0.2]).verdict(), PairedVerdict::AWorse);
    /// assert_eq!(d([-0.2, 0.01]).verdict(), PairedVerdict::NoSignificantDifference);
    /// ```
    pub fn verdict(&self) -> PairedVerdict {
        let [lo, hi] = self.ci95;
        let margin = EQUIVALENCE_MARGIN * self.b_mean_sq_err;
        if !(lo.is_finite() && hi.is_finite()) {
            PairedVerdict::NoVerdict
        } else if -margin <= lo && hi <= margin {
            PairedVerdict::Equal
        } else if lo > 0.0 {
            PairedVerdict::AWorse
        } else if hi < 0.0 {
            PairedVerdict::BWorse
        } else {
            PairedVerdict::NoSignificantDifference
        }
    }

    /// The verdict in words, naming the filter: `ekf worse`, `equal within 1 %`,
    /// `no significant difference`.
    pub fn verdict_words(&self) -> String {
        match self.verdict() {
            PairedVerdict::NoVerdict => "no verdict".into(),
            PairedVerdict::Equal => format!("equal within {} %", 100.0 * EQUIVALENCE_MARGIN),
            PairedVerdict::NoSignificantDifference => "no significant difference".into(),
            PairedVerdict::AWorse => format!("{} worse", self.a),
            PairedVerdict::BWorse => format!("{} worse", self.b),
        }
    }
}

/// The whole `summary.json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    /// Study name.
    pub study: String,
    /// Runs tallied.
    pub runs: usize,
    /// Seed.
    pub seed: u64,
    /// Per filter, by name (`ekf`, `standard_ukf`, `simplified_ukf`, ...).
    pub filters: BTreeMap<String, FilterSummary>,
    /// Paired differences, per pair and coefficient.
    pub paired: Vec<PairedDifference>,
    /// The study file's settings, as run.
    pub settings: crate::config::StudyConfig,
}

fn rms(sum: f64, n: f64) -> f64 {
    if n > 0.0 {
        (sum / n).sqrt()
    } else {
        f64::NAN
    }
}

/// Builds the summary of a complete tally.
pub fn summarize(study: &Study, tally: &Tally) -> Summary {
    let names = &study.names;
    let n = names.len();
    let last = study.times.len() - 1;
    let truth_names = study.sim.truth_model().state_names();
    let mut filters = BTreeMap::new();
    for (name, t) in study.filter_names().iter().zip(&tally.filters) {
        let ok = t.ok as f64;
        let mut s = FilterSummary {
            final_rms: BTreeMap::new(),
            final_sigma: BTreeMap::new(),
            final_bound: BTreeMap::new(),
            final_rms_nav: BTreeMap::new(),
            nees_mean: f64::NAN,
            nees_bounds: [f64::NAN; 2],
            nis_mean: f64::NAN,
            nis_bounds: [f64::NAN; 2],
            nis_dof: f64::NAN,
            diverged: t.diverged.len() as u64,
            diverged_by_cause: t.diverged_by_cause(),
            runs_ok: t.ok,
            step_ns_median: quantile(&t.step_cost, 0.5),
            step_ns_p90: quantile(&t.step_cost, 0.9),
            diverged_examples: t.diverged.iter().take(20).cloned().collect(),
        };
        if t.ok > 0 {
            for i in 0..n {
                let r = rms(t.sum_sq_err[last][i], ok);
                if i < NAV_DIM {
                    s.final_rms_nav.insert(names[i].clone(), r);
                } else {
                    s.final_rms.insert(names[i].clone(), r);
                    s.final_sigma
                        .insert(names[i].clone(), rms(t.sum_var[last][i], ok));
                }
            }
            s.nees_mean = t.sum_nees[last] / ok;
            s.nees_bounds = mean_chi2_bounds(ok * n as f64, ok);
            s.nis_mean = t.sum_nis / t.nis_count as f64;
            s.nis_dof = t.nis_dof as f64 / t.nis_count as f64;
            s.nis_bounds = mean_chi2_bounds(t.nis_dof as f64, t.nis_count as f64);
        }
        if tally.bound.count > 0 {
            for i in NAV_DIM..n {
                if let Some(j) = truth_names.iter().position(|x| *x == names[i]) {
                    s.final_bound.insert(
                        names[i].clone(),
                        rms(tally.bound.sum_var[last][j], tally.bound.count as f64),
                    );
                }
            }
        }
        filters.insert(name.clone(), s);
    }
    let mut paired = Vec::new();
    for p in &tally.pairs {
        if p.n < 2 {
            continue;
        }
        for i in NAV_DIM..n {
            paired.push(paired_difference(study, tally, p, i));
        }
    }
    Summary {
        study: study.config.study.name.clone(),
        runs: tally.runs,
        seed: study.config.study.seed,
        filters,
        paired,
        settings: study.config.clone(),
    }
}

/// The paired difference of pair `p`'s final squared errors of state `i` (a filter state
/// index): its mean over the runs both finished, 95 % confidence interval and size relative
/// to the second filter's mean squared error. `p.n` must be at least 2.
pub fn paired_difference(
    study: &Study,
    tally: &Tally,
    p: &crate::tally::PairTally,
    i: usize,
) -> PairedDifference {
    let last = study.times.len() - 1;
    let ib = study
        .filter_names()
        .iter()
        .position(|f| *f == p.b)
        .expect("a pair of the study's filters");
    let tb = &tally.filters[ib];
    let nn = p.n as f64;
    let mean = p.sum_d[i] / nn;
    let var = ((p.sum_d2[i] - nn * mean * mean) / (nn - 1.0)).max(0.0);
    let se = (var / nn).sqrt();
    let msb = tb.sum_sq_err[last][i] / tb.ok.max(1) as f64;
    PairedDifference {
        a: p.a.clone(),
        b: p.b.clone(),
        coefficient: study.names[i].clone(),
        n: p.n,
        mean_sq_err_diff: mean,
        ci95: [mean - 1.96 * se, mean + 1.96 * se],
        relative: mean / msb,
        b_mean_sq_err: msb,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn difference(ci95: [f64; 2], b_mean_sq_err: f64) -> PairedDifference {
        let mean = 0.5 * (ci95[0] + ci95[1]);
        PairedDifference {
            a: "ekf".into(),
            b: "standard_ukf".into(),
            coefficient: "Kg0x".into(),
            n: 200,
            mean_sq_err_diff: mean,
            ci95,
            relative: mean / b_mean_sq_err,
            b_mean_sq_err,
        }
    }

    #[test]
    fn the_margin_is_a_share_of_the_second_filters_mean_squared_error() {
        // 1 % of 2.0 is 0.02: an interval up to it is equal, one reaching past is not.
        assert_eq!(
            difference([0.001, 0.02], 2.0).verdict(),
            PairedVerdict::Equal
        );
        assert_eq!(
            difference([0.001, 0.021], 2.0).verdict(),
            PairedVerdict::AWorse
        );
        assert_eq!(
            difference([-0.021, -0.001], 2.0).verdict(),
            PairedVerdict::BWorse
        );
        assert_eq!(
            difference([-0.02, 0.02], 2.0).verdict_words(),
            "equal within 1 %"
        );
        assert_eq!(
            difference([-0.03, 0.01], 2.0).verdict(),
            PairedVerdict::NoSignificantDifference
        );
        assert!(difference([0.001, 0.02], 2.0).excludes_zero());
        assert!(!difference([0.001, 0.02], 2.0).significant());
        assert!(difference([0.001, 0.021], 2.0).significant());
        let none = difference([f64::NAN, f64::NAN], 2.0);
        assert_eq!(none.verdict(), PairedVerdict::NoVerdict);
        assert!(!none.excludes_zero());
    }

    #[test]
    fn a_summary_written_before_the_margin_keeps_its_verdicts() {
        // No `b_mean_sq_err`: read as NaN, so no interval is called equal.
        let json = r#"{"a":"ekf","b":"standard_ukf","coefficient":"Kg0x","n":200,
            "mean_sq_err_diff":3e-6,"ci95":[1e-6,5e-6],"relative":1.5e-6}"#;
        let d: PairedDifference = serde_json::from_str(json).unwrap();
        assert!(d.b_mean_sq_err.is_nan());
        assert_eq!(d.verdict(), PairedVerdict::AWorse);
    }
}
