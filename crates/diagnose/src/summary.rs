//! One fit summarised for the diagnosis and its report: its likelihood, its NIS overall, per
//! motion phase and in sliding windows, the whiteness of each channel, whether it is
//! consistent, and its coefficient estimates (with the truth, when the dataset has it).
//!
//! NIS is docs/model.md eq. (18); for a consistent model its mean is the measurement
//! dimension. **Consistent** means: the filter did not fail, the mean NIS lies inside its 99 %
//! chi-square bounds (the 95 % ones are shown), and every channel is white at a family-wise
//! level of [`WHITENESS_ALPHA`] (Bonferroni over channels and tests). With both at about 1 %,
//! a consistent model is called inconsistent about 2 % of the time. **Excess NIS**, the sum
//! of `NIS - dim` over the updates, is the misfit a missing effect leaves; a candidate's share
//! of it removed is one of the numbers the report gives.

use crate::consistency::{self, nis_windows, phase_name, whiteness, NisStat, NisWindow, Whiteness};
use crate::fit::pass::Fit;
use crate::options::Options;
use navkf_dynamics::dataset::Dataset;
use navkf_dynamics::NoiseConfig;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Family-wise level of the whiteness tests over all channels (Bonferroni-divided).
pub const WHITENESS_ALPHA: f64 = 0.01;

/// Consistency of one fit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FitSummary {
    /// Effects in the model.
    pub effects: Vec<String>,
    /// Total log-likelihood of the innovations.
    pub loglik: f64,
    /// NIS over all updates.
    pub nis: NisStat,
    /// NIS per motion phase.
    pub nis_by_phase: BTreeMap<String, NisStat>,
    /// NIS in sliding windows.
    pub nis_windows: Vec<NisWindow>,
    /// Whiteness of each channel.
    pub whiteness: Vec<Whiteness>,
    /// Whether NIS is inside its bounds and every channel is white.
    pub consistent: bool,
    /// Sum over updates of `NIS - dim` (the misfit a missing effect leaves).
    pub excess_nis: f64,
    /// Final coefficient estimates with their sigmas.
    pub coefficients: Vec<Coefficient>,
    /// Filter failure, if any: its cause and where.
    pub failure: Option<navkf_filters::RunFailure>,
    /// The noise the filter assumed.
    pub noise: NoiseConfig,
}

/// A coefficient estimate.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Coefficient {
    /// Name.
    pub name: String,
    /// Final estimate.
    pub estimate: f64,
    /// Final one-sigma.
    pub sigma: f64,
    /// The prior one-sigma it was tested with (after any widening).
    pub prior_sigma: f64,
    /// True value, when the dataset has `truth.csv`.
    pub truth: Option<f64>,
    /// Driven by process noise (a walking coefficient, a bias instability's departure): the
    /// estimate is its value at the end of the record, not a constant's.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub wanders: bool,
    /// Held at zero by the family ([`crate::catalogue::Catalogue::pinned`]): not estimated,
    /// so it has no error to judge.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub held: bool,
}

/// Updates per sliding window of `opts.window_s` seconds at the fit's mean update interval
/// (at least 10).
pub fn window_width(fit: &Fit, opts: &Options) -> usize {
    let dt = if fit.t.len() > 1 {
        (fit.t[fit.t.len() - 1] - fit.t[0]) / (fit.t.len() - 1) as f64
    } else {
        1.0
    };
    ((opts.window_s / dt).round() as usize).max(10)
}

/// Summarises a fit.
pub fn summarize_fit(ds: &Dataset, fit: &Fit, opts: &Options) -> FitSummary {
    let nis = NisStat::of(&fit.nis, &fit.dims);
    let mut by_phase: BTreeMap<String, (Vec<f64>, Vec<usize>)> = BTreeMap::new();
    for ((p, v), d) in fit.phases.iter().zip(&fit.nis).zip(&fit.dims) {
        let e = by_phase.entry(phase_name(*p).to_string()).or_default();
        e.0.push(*v);
        e.1.push(*d);
    }
    let nis_by_phase = by_phase
        .into_iter()
        .map(|(k, (v, d))| (k, NisStat::of(&v, &d)))
        .collect();
    let windows = nis_windows(&fit.t, &fit.nis, &fit.dims, window_width(fit, opts));
    let whites: Vec<Whiteness> = fit
        .channels
        .iter()
        .enumerate()
        .map(|(c, channel)| {
            let e = fit.normalised_innovations(c);
            whiteness(
                channel.name,
                &e,
                opts.lags,
                WHITENESS_ALPHA / (consistency::TESTS_PER_CHANNEL * fit.channels.len()) as f64,
            )
        })
        .collect();
    // The verdict uses the 99 % NIS band (the 95 % one is shown); with the whiteness tests
    // at a family-wise 1 %, a consistent model is called inconsistent about 2 % of the time.
    let consistent = fit.failure.is_none()
        && nis.within(navkf_report::stats::Band::Percent99)
        && whites.iter().filter(|w| w.count > 0).all(|w| w.white);
    let excess = fit
        .nis
        .iter()
        .zip(&fit.dims)
        .map(|(v, d)| v - *d as f64)
        .sum();
    let n = fit.names.len();
    let truth_last = ds
        .truth
        .as_ref()
        .and_then(|t| t.states.last().map(|s| (t, s)));
    let coefficients = (fit.nav_dim..n)
        .map(|i| Coefficient {
            name: fit.names[i].clone(),
            estimate: fit.x[i],
            sigma: fit.sigma(i),
            prior_sigma: fit.prior_sigma[i],
            wanders: fit.noisy[i],
            held: fit.pinned[i],
            truth: truth_last.and_then(|(t, s)| {
                t.names
                    .iter()
                    .position(|x| *x == fit.names[i])
                    .map(|j| s[j])
            }),
        })
        .collect();
    FitSummary {
        effects: fit.effects.clone(),
        loglik: fit.loglik,
        nis,
        nis_by_phase,
        nis_windows: windows,
        whiteness: whites,
        consistent,
        excess_nis: excess,
        coefficients,
        failure: fit.failure.clone(),
        noise: fit.setup.noise,
    }
}
