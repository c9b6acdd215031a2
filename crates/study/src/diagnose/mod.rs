//! Diagnosis: compare a model with a dataset, see where it fails, and learn which catalogued
//! effect is missing.
//!
//! 1. **Fit** the model (base plus `--with` effects) with the simplified UKF (it takes the
//!    sigma-point measurement path when an effect makes the measurement non-linear), keeping
//!    every innovation, its covariance, the NIS and the log-likelihood.
//! 2. **Where it fails**: NIS overall, in sliding windows and per motion phase; whiteness of
//!    each channel ([`consistency`]).
//! 3. **Which effect**: refit with each catalogued effect not yet in the model (in parallel).
//!    Each candidate's evidence is its BIC gain `2 dLL - k ln N` (k its coefficients, N the
//!    number of scalar measurements). A candidate is named only when the evidence is
//!    decisive (BIC gain > 10, "very strong" on Kass & Raftery's scale) *and* it makes the
//!    innovations consistent or removes at least 90 % of the model's excess NIS (a term that
//!    only adds process noise must make them consistent: it can soak up any slow misfit); otherwise the
//!    misfit is reported as unexplained by the catalogue. A candidate whose coefficients end
//!    up strongly correlated with the model's own (|rho| > 0.9) cannot be told apart from
//!    them on this trajectory, and is reported as such.

pub mod consistency;
pub mod plots;
pub mod report;

use crate::monte_carlo::typical_sigma;
use consistency::{classify, nis_windows, whiteness, NisStat, NisWindow, Whiteness};
use navkf_dynamics::dataset::Dataset;
use navkf_dynamics::state::*;
use navkf_dynamics::trajectory::Phase;
use navkf_dynamics::{PlatformModel, Registry, SystemModel};
use navkf_filters::{simplified_ukf, Filter, Runner, SigmaScaling};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::sync::Arc;

/// BIC gain beyond which evidence is decisive.
pub const DECISIVE_BIC: f64 = 10.0;
/// Share of the excess NIS a candidate must remove to be named.
pub const EXPLAINED_SHARE: f64 = 0.9;
/// Family-wise level of the whiteness tests over all channels (Bonferroni-divided).
pub const WHITENESS_ALPHA: f64 = 0.01;
/// Correlation beyond which two coefficients cannot be told apart.
pub const INDISTINGUISHABLE: f64 = 0.9;

/// Settings of a diagnosis.
#[derive(Debug, Clone)]
pub struct Options {
    /// Effects switched on in the model under test.
    pub with: Vec<String>,
    /// Width of the sliding NIS windows, s.
    pub window_s: f64,
    /// Lags of the whiteness test.
    pub lags: usize,
    /// Initial tilt sigmas (level, azimuth), rad.
    pub tilt_sigma: [f64; 2],
}

impl Default for Options {
    fn default() -> Self {
        Options {
            with: Vec::new(),
            window_s: 300.0,
            lags: 20,
            tilt_sigma: [4.85e-5, 2.91e-4],
        }
    }
}

/// One filter pass over the dataset.
#[derive(Debug, Clone)]
pub struct Fit {
    /// Effects in the model.
    pub effects: Vec<String>,
    /// State names.
    pub names: Vec<String>,
    /// Update times.
    pub t: Vec<f64>,
    /// Measured values `[v_e, v_n, L, lambda]` (NaN where absent).
    pub z: Vec<[f64; MEAS_DIM]>,
    /// Predicted measurement (NaN where absent).
    pub z_hat: Vec<[f64; MEAS_DIM]>,
    /// Predicted one-sigma of each innovation (NaN where absent).
    pub s_sigma: Vec<[f64; MEAS_DIM]>,
    /// NIS and measurement dimension per update.
    pub nis: Vec<f64>,
    /// Dimension of each update.
    pub dims: Vec<usize>,
    /// Motion phase per update.
    pub phases: Vec<Phase>,
    /// Sum of the updates' log-likelihoods.
    pub loglik: f64,
    /// Final estimate and covariance (column-major).
    pub x: Vec<f64>,
    /// Final covariance.
    pub p: Vec<f64>,
    /// Initial sigma of every state.
    pub prior_sigma: Vec<f64>,
    /// Set when the filter failed (the fit then covers the updates before it).
    pub failure: Option<String>,
}

/// Errors of a diagnosis (bad data is caught when reading the dataset).
#[derive(Debug, thiserror::Error)]
pub enum DiagnoseError {
    /// The model could not be assembled.
    #[error(transparent)]
    Dynamics(#[from] navkf_dynamics::DynamicsError),
    /// The filter refused its settings.
    #[error(transparent)]
    Filter(#[from] navkf_filters::FilterError),
    /// The dataset cannot start a filter.
    #[error("{0}")]
    Data(String),
}

/// Fits `effects` to `ds`.
pub fn fit(
    ds: &Dataset,
    effects: &[String],
    registry: &Registry,
    opts: &Options,
) -> Result<Fit, DiagnoseError> {
    let fx = registry.build_all(effects)?;
    let model = Arc::new(PlatformModel::new(fx, &ds.noise)?);
    let n = model.dim();
    let start = ds
        .measurements
        .iter()
        .position(|m| m.velocity.is_some() && m.position_deg.is_some())
        .ok_or_else(|| DiagnoseError::Data(format!(
            "dataset `{}`: no measurement row has both odometer and GPS, so the filter cannot start",
            ds.name
        )))?;
    let m0 = &ds.measurements[start];
    let v0 = m0.velocity.expect("checked");
    let p0 = m0.gps_rad().expect("checked");
    let mut x0 = vec![0.0; n];
    x0[V_X] = v0[0];
    x0[V_Y] = v0[1];
    x0[LAT] = p0[0];
    x0[LON] = p0[1];
    let sig0 = ds.noise.measurement_sigmas(v0[0].hypot(v0[1]), p0[0]);
    let prior_sigma: Vec<f64> = (0..n)
        .map(|i| match i {
            PHI_X | PHI_Y => opts.tilt_sigma[0],
            PHI_Z => opts.tilt_sigma[1],
            V_X | V_Y | LAT | LON => sig0[i - V_X],
            _ => typical_sigma(&model, i),
        })
        .collect();
    let mut pm = vec![0.0; n * n];
    for i in 0..n {
        pm[i + i * n] = prior_sigma[i] * prior_sigma[i];
    }
    let mut filter = simplified_ukf::new(model.clone(), SigmaScaling::default())?;
    filter.reset(&x0, &pm)?;
    let cap = ds.measurements.len();
    let mut fit = Fit {
        effects: effects.to_vec(),
        names: model.state_names(),
        t: Vec::with_capacity(cap),
        z: Vec::with_capacity(cap),
        z_hat: Vec::with_capacity(cap),
        s_sigma: Vec::with_capacity(cap),
        nis: Vec::with_capacity(cap),
        dims: Vec::with_capacity(cap),
        phases: Vec::with_capacity(cap),
        loglik: 0.0,
        x: x0.clone(),
        p: pm.clone(),
        prior_sigma,
        failure: None,
    };
    let inputs = &ds.inputs;
    let mut cursor = 0usize;
    let mut t_prev = m0.t;
    let result = Runner::new(64).run(
        &mut filter,
        m0.t,
        inputs,
        &ds.measurements,
        &ds.noise,
        |v| {
            let r = v.report;
            let m = &ds.measurements[v.index];
            let mut z = [f64::NAN; MEAS_DIM];
            let mut zh = [f64::NAN; MEAS_DIM];
            let mut ss = [f64::NAN; MEAS_DIM];
            let k = r.dim();
            for (a, &c) in r.channels.iter().enumerate() {
                let zc = match c {
                    0 | 1 => m.velocity.map_or(f64::NAN, |w| w[c]),
                    _ => m.gps_rad().map_or(f64::NAN, |w| w[c - 2]),
                };
                z[c] = zc;
                zh[c] = zc - r.innovation[a];
                ss[c] = r.innovation_cov[a + a * k].sqrt();
            }
            // Mean horizontal specific force over the step, for the phase.
            while cursor < inputs.len() && inputs[cursor].t < t_prev {
                cursor += 1;
            }
            let (mut fe, mut fnn, mut cnt) = (0.0, 0.0, 0.0);
            let mut c = cursor;
            while c < inputs.len() && inputs[c].t <= v.t {
                fe += inputs[c].f[0];
                fnn += inputs[c].f[1];
                cnt += 1.0;
                c += 1;
            }
            let f_mean = if cnt > 0.0 {
                [fe / cnt, fnn / cnt]
            } else {
                [0.0, 0.0]
            };
            t_prev = v.t;
            fit.t.push(v.t);
            fit.z.push(z);
            fit.z_hat.push(zh);
            fit.s_sigma.push(ss);
            fit.nis.push(r.nis);
            fit.dims.push(k);
            fit.phases.push(classify(f_mean, m.velocity));
            fit.loglik += r.log_likelihood;
        },
    );
    if let Err(e) = result {
        fit.failure = Some(e.to_string());
    }
    fit.x = filter.state().to_vec();
    fit.p = filter.covariance().to_vec();
    Ok(fit)
}

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
    /// Filter failure, if any.
    pub failure: Option<String>,
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
    /// Initial one-sigma.
    pub prior_sigma: f64,
    /// True value, when the dataset has `truth.csv`.
    pub truth: Option<f64>,
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
    let dt = if fit.t.len() > 1 {
        (fit.t[fit.t.len() - 1] - fit.t[0]) / (fit.t.len() - 1) as f64
    } else {
        1.0
    };
    let width = ((opts.window_s / dt).round() as usize).max(10);
    let windows = nis_windows(&fit.t, &fit.nis, &fit.dims, width);
    let whites: Vec<Whiteness> = MEASUREMENT_NAMES
        .iter()
        .enumerate()
        .map(|(c, name)| {
            let e: Vec<f64> = fit
                .z
                .iter()
                .zip(&fit.z_hat)
                .zip(&fit.s_sigma)
                .filter(|((z, _), _)| z[c].is_finite())
                .map(|((z, zh), s)| (z[c] - zh[c]) / s[c])
                .collect();
            whiteness(
                name,
                &e,
                opts.lags,
                WHITENESS_ALPHA / (3.0 * MEAS_DIM as f64),
            )
        })
        .collect();
    // The verdict uses the 99 % NIS bounds (the 95 % ones are shown); with the whiteness
    // tests at a family-wise 1 %, a consistent model is called inconsistent about 2 % of
    // the time.
    let nis99 = if nis.count > 0 {
        let total = nis.dof * nis.count as f64;
        [
            crate::stats::chi2_quantile(0.005, total) / nis.count as f64,
            crate::stats::chi2_quantile(0.995, total) / nis.count as f64,
        ]
    } else {
        [f64::NAN; 2]
    };
    let consistent = fit.failure.is_none()
        && nis.mean >= nis99[0]
        && nis.mean <= nis99[1]
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
    let coefficients = (NAV_DIM..n)
        .map(|i| Coefficient {
            name: fit.names[i].clone(),
            estimate: fit.x[i],
            sigma: fit.p[i + i * n].max(0.0).sqrt(),
            prior_sigma: fit.prior_sigma[i],
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
    }
}

/// Name of a phase in reports.
pub fn phase_name(p: Phase) -> &'static str {
    match p {
        Phase::Standstill => "standstill",
        Phase::Accelerating => "accelerating",
        Phase::Cruising => "cruising",
        Phase::Turning => "turning",
        Phase::Decelerating => "decelerating",
    }
}

/// One candidate effect's evidence.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Candidate {
    /// Effect name.
    pub effect: String,
    /// Log-likelihood gain over the model under test.
    pub delta_loglik: f64,
    /// `2 dLL - k ln N`.
    pub bic_gain: f64,
    /// Share of the model's excess NIS it removes.
    pub excess_removed: f64,
    /// Its coefficients' estimates and sigmas.
    pub coefficients: Vec<Coefficient>,
    /// Whether the innovations are consistent with it added.
    pub consistent: bool,
    /// Model coefficients it cannot be told apart from: `(name, correlation)`.
    pub confused_with: Vec<(String, f64)>,
    /// Whether the diagnosis names it.
    pub supported: bool,
    /// Filter failure with it added, if any.
    pub failure: Option<String>,
}

/// The whole diagnosis (`diagnosis.json`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Diagnosis {
    /// Dataset name.
    pub dataset: String,
    /// `consistent`, `explained` or `unexplained`.
    pub verdict: String,
    /// The effect the evidence supports, best first; null when none.
    pub best: Option<String>,
    /// The model under test.
    pub model: FitSummary,
    /// The base model, when `--with` added effects (before/after).
    pub before: Option<FitSummary>,
    /// Candidates, best first.
    pub candidates: Vec<Candidate>,
    /// Plain-language findings.
    pub findings: Vec<String>,
}

/// The filter passes behind a diagnosis, kept for its figures.
#[derive(Debug, Clone)]
pub struct Fits {
    /// The model under test (base plus `--with`).
    pub model: Fit,
    /// The base model, when `--with` added effects.
    pub before: Option<Fit>,
}

/// Runs the whole diagnosis. Returns the diagnosis and the fits of the model under test and,
/// with `--with`, of the base model (for the figures).
pub fn diagnose(
    ds: &Dataset,
    registry: &Registry,
    opts: &Options,
) -> Result<(Diagnosis, Fits), DiagnoseError> {
    let with = opts.with.clone();
    let mut todo: Vec<Vec<String>> = vec![with.clone()];
    if !with.is_empty() {
        todo.push(Vec::new());
    }
    let candidates: Vec<String> = registry
        .names()
        .into_iter()
        .filter(|e| !with.contains(e))
        .collect();
    for c in &candidates {
        let mut e = with.clone();
        e.push(c.clone());
        todo.push(e);
    }
    let fits: Vec<Result<Fit, DiagnoseError>> = todo
        .par_iter()
        .map(|e| fit(ds, e, registry, opts))
        .collect();
    let mut fits = fits.into_iter().collect::<Result<Vec<Fit>, _>>()?;
    let main = fits.remove(0);
    let before_fit = if with.is_empty() {
        None
    } else {
        Some(fits.remove(0))
    };
    let before = before_fit.as_ref().map(|f| summarize_fit(ds, f, opts));
    let model = summarize_fit(ds, &main, opts);
    let n_meas: usize = main.dims.iter().sum();
    let ln_n = (n_meas.max(1) as f64).ln();
    let mut cands: Vec<Candidate> = candidates
        .iter()
        .zip(&fits)
        .map(|(name, f)| {
            let s = summarize_fit(ds, f, opts);
            let k_coef = registry
                .build(name)
                .map(|e| e.coefficient_names().len())
                .unwrap_or(0);
            // A noise-only term still has one free parameter (its density).
            let k = k_coef.max(1);
            let dll = f.loglik - main.loglik;
            let bic = 2.0 * dll - k as f64 * ln_n;
            let removed = if model.excess_nis > 0.0 {
                1.0 - s.excess_nis.max(0.0) / model.excess_nis
            } else {
                0.0
            };
            let confused = confusion(f, main.names.len());
            let own: Vec<Coefficient> = s
                .coefficients
                .iter()
                .filter(|c| !main.names.contains(&c.name))
                .cloned()
                .collect();
            let valid = f.failure.is_none() && bic.is_finite();
            // Named only on decisive evidence, with coefficients of its own, and only if it
            // actually repairs the misfit (or there was none to repair).
            // A term without coefficients (extra process noise, such as `gyro-bias-walk`) can
            // soak up any slow misfit, so it is named only when it makes the model consistent.
            let noise_only = k_coef == 0;
            let repairs =
                s.consistent || (!noise_only && (model.consistent || removed >= EXPLAINED_SHARE));
            let supported = valid && bic > DECISIVE_BIC && confused.is_empty() && repairs;
            Candidate {
                effect: name.clone(),
                delta_loglik: dll,
                bic_gain: bic,
                excess_removed: removed,
                coefficients: own,
                consistent: s.consistent,
                confused_with: confused,
                supported,
                failure: f.failure.clone(),
            }
        })
        .collect();
    cands.sort_by(|a, b| {
        b.bic_gain
            .partial_cmp(&a.bic_gain)
            .unwrap_or(std::cmp::Ordering::Equal)
    });
    let best = cands.iter().find(|c| c.supported).map(|c| c.effect.clone());
    let verdict = if best.is_some() {
        "explained"
    } else if model.consistent {
        "consistent"
    } else {
        "unexplained"
    };
    let findings = report::findings(&model, &cands, best.as_deref());
    Ok((
        Diagnosis {
            dataset: ds.name.clone(),
            verdict: verdict.into(),
            best,
            model,
            before,
            candidates: cands,
            findings,
        },
        Fits {
            model: main,
            before: before_fit,
        },
    ))
}

/// Coefficients of the candidate (those after the model's own `n_model` states) strongly
/// correlated with a model coefficient at the end of the fit.
fn confusion(f: &Fit, n_model: usize) -> Vec<(String, f64)> {
    let n = f.names.len();
    let mut out = Vec::new();
    for i in n_model..n {
        for j in NAV_DIM..n_model {
            let c = f.p[i + j * n] / (f.p[i + i * n] * f.p[j + j * n]).sqrt();
            if c.abs() > INDISTINGUISHABLE {
                out.push((format!("{} ~ {}", f.names[i], f.names[j]), c));
            }
        }
    }
    out
}
