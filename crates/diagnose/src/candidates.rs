//! Which effect: every catalogued effect not yet in the model is added, fitted and weighed;
//! one round of the forward selection of [`super`].
//!
//! **Evidence.** A candidate's evidence is its BIC gain on the maximised innovation
//! likelihood, `2 dLL - k ln N`: `dLL` the gain of [`Fit::profile_loglik`] over the model
//! (the likelihood at the estimates, free of the priors' Occam factors), `k` its number of
//! free parameters, `N` the number of scalar measurements. Why BIC rather than the
//! alternatives:
//! - a Bayes factor (the filter's marginal likelihoods compared as they are) depends on the
//!   prior's width: a real effect tested with a wide prior, which the widening of
//!   [`super::priors`] gives it, would lose evidence for it;
//! - a likelihood-ratio test at a fixed level (`2 dLL` against a chi-square) is prior-free
//!   too, but over hundreds of scalar measurements per minute a fixed level names effects
//!   too small to matter, and its false-alarm rate per dataset grows with the number of
//!   candidates and rounds;
//! - BIC's `k ln N` (9.2 per parameter for a 40-minute test at 1 Hz) is stricter than any
//!   usual test level and grows with the data: under the null hypothesis `2 dLL` is
//!   chi-square with `k` degrees of freedom, so a gain above [`DECISIVE_BIC`] happens by
//!   chance with probability 1e-5 for one parameter and less for more.
//!
//! A gain above [`DECISIVE_BIC`] is "very strong" evidence on Kass & Raftery's scale.
//!
//! **When a candidate is named.** Its evidence is decisive, its filter pass did not fail, and
//! its coefficients can be told apart from the model's own: a coefficient correlated beyond
//! [`INDISTINGUISHABLE`] with one of the model's cannot (the trajectory cannot say which of
//! the two carries the misfit), and an effect with such coefficients is named only if the
//! others carry decisive evidence on their own ([`Candidate::separable_bic`]).
//! Among those, the one with the largest gain is named. A noise-only term (no coefficients:
//! `gyro-bias-walk`, its density fitted by maximum likelihood) can soak up any slow misfit, so
//! it is named only when it makes the model consistent *and* no structured candidate comes
//! within [`DECISIVE_BIC`] of it; when the two compete the round says so.
//!
//! **Is the named coefficient a constant?** A catalogued effect asserts that its coefficients
//! are random constants, so the two halves of the record should estimate the same values.
//! [`constancy`] refits the final model on each half separately (disjoint data, so the two
//! estimates are independent given the truth), takes each half's data-only estimate (the
//! prior's shrinkage undone, as in [`super::priors`]) and tests their difference,
//! `(c_a - c_b)^2 / (v_a + v_b)`, chi-square with one degree of freedom. A nearby catalogued
//! effect that only stands in for a misfit outside the catalogue is pulled one way by one
//! part of the test and another way by the other; the diagnosis withdraws a named effect
//! whose coefficients fail at level [`CONSTANCY_ALPHA`] (Bonferroni over them) in the final
//! model. (Splitting one filter pass's information by stretches would cost no refit, but
//! the states the stretches share make its estimates correlated and the test anti-
//! conservative: a true `gps-latency` failed it.)

use super::consistency::NisStat;
use super::fit::Fit;
use super::priors::{fit_adaptive, Widening};
use super::{summarize_fit, Coefficient, DiagnoseError, FitSummary, Options};
use navkf_dynamics::dataset::Dataset;
use navkf_dynamics::state::NAV_DIM;
use navkf_dynamics::Registry;
use navkf_filters::FilterSpec;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// BIC gain beyond which evidence is decisive.
pub const DECISIVE_BIC: f64 = 10.0;
/// Correlation beyond which two coefficients cannot be told apart.
pub const INDISTINGUISHABLE: f64 = 0.9;
/// Level of the constancy test (per effect, Bonferroni over its coefficients).
pub const CONSTANCY_ALPHA: f64 = 1e-3;
/// Decades of a noise-only term's density searched below and above its typical value.
const DENSITY_DECADES: (i32, i32) = (-2, 6);
/// Spacing of that grid, decades.
const DENSITY_STEP: i32 = 2;

/// Whether a candidate adds coefficients or only process noise.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum CandidateKind {
    /// It adds coefficients (random constants) and the terms they multiply.
    Structured,
    /// It only adds process noise (its one parameter is a density).
    NoiseOnly,
    /// Not an effect: the noise levels refitted (the sources whose stated level is off).
    NoiseLevels,
}

/// Why a candidate is, or is not, named.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Outcome {
    /// Named in this round.
    Named,
    /// Added by `--with`.
    Manual,
    /// Decisive, but another candidate explains more.
    Outranked,
    /// Evidence not decisive.
    NotDecisive,
    /// Its coefficients cannot be told apart from the model's on this trajectory.
    Confounded,
    /// A noise-only term that leaves the model inconsistent.
    NoiseLeavesMisfit,
    /// A noise-only term that a structured candidate explains as well.
    NoiseAsGoodAsStructure,
    /// A noise-only term that a walk of another sensor, outside the catalogue, explains as
    /// well ([`super::rivals`]).
    NoiseNotSpecific,
    /// The filter failed with it.
    Failed,
    /// Decisive, but its fitted values are no real sensor's ([`Candidate::beyond_bounds`]).
    Unphysical,
}

impl std::fmt::Display for Outcome {
    /// The outcome in words, for the report and the terminal's tables.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Outcome::Named => "named",
            Outcome::Manual => "added (--with)",
            Outcome::Outranked => "decisive, outranked",
            Outcome::NotDecisive => "not decisive",
            Outcome::Confounded => "cannot be told apart",
            Outcome::NoiseLeavesMisfit => "noise term, leaves misfit",
            Outcome::NoiseAsGoodAsStructure => "noise term, no better than structure",
            Outcome::NoiseNotSpecific => "noise term, no better than another sensor's walk",
            Outcome::Failed => "filter failed",
            Outcome::Unphysical => "decisive, but no real sensor's: not named",
        })
    }
}

/// Two coefficients the trajectory cannot tell apart.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Confusion {
    /// The candidate's coefficient.
    pub coefficient: String,
    /// The model's coefficient.
    pub with: String,
    /// Their correlation at the end of the fit.
    pub correlation: f64,
}

/// The constancy test of one effect's coefficients (module documentation).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Constancy {
    /// Per coefficient: name, statistic, degrees of freedom and p-value; coefficients a half
    /// barely informs are left out.
    pub coefficients: Vec<(String, f64, usize, f64)>,
    /// Smallest p-value times the number of coefficients tested (Bonferroni), at most 1.
    pub p_value: f64,
    /// Whether the coefficients behave as constants at [`CONSTANCY_ALPHA`].
    pub constant: bool,
}

/// One candidate's evidence.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Candidate {
    /// Effect name.
    pub effect: String,
    /// Structured or noise-only.
    pub kind: CandidateKind,
    /// Gain of the maximised log-likelihood over the model.
    pub delta_loglik: f64,
    /// Free parameters it adds.
    pub parameters: usize,
    /// `2 dLL - k ln N`.
    pub bic_gain: f64,
    /// Share of the model's excess NIS it removes.
    pub excess_removed: f64,
    /// Mean NIS with it added.
    pub nis: NisStat,
    /// Whether the innovations are consistent with it added.
    pub consistent: bool,
    /// Its coefficients' estimates, sigmas and the priors they were tested with.
    pub coefficients: Vec<Coefficient>,
    /// The fitted density of a noise-only term.
    pub density: Option<f64>,
    /// The noise check behind a noise-levels candidate.
    pub noise: Option<super::noise::NoiseFit>,
    /// Priors widened while fitting it.
    pub widened: Vec<Widening>,
    /// Model coefficients it cannot be told apart from.
    pub confused_with: Vec<Confusion>,
    /// When some of its coefficients are confused: the evidence its other coefficients carry
    /// on their own, as a BIC gain (Wald statistic `c^T P^-1 c` of those coefficients, less
    /// their `k ln N`). The candidate can be named only if this is decisive too.
    pub separable_bic: Option<f64>,
    /// Its fitted values that no real sensor has ([`super::plausible`]): a decisive candidate
    /// with any is not named.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub beyond_bounds: Vec<super::plausible::BeyondBound>,
    /// Why it is or is not named.
    pub outcome: Outcome,
    /// Filter failure with it added, if any.
    pub failure: Option<navkf_filters::RunFailure>,
}

impl Candidate {
    /// Whether its evidence is decisive and usable (before the naming rules).
    pub fn decisive(&self) -> bool {
        self.failure.is_none() && self.bic_gain.is_finite() && self.bic_gain > DECISIVE_BIC
    }
}

/// A candidate with the fit behind it (the next round's model if it is named).
#[derive(Debug, Clone)]
pub struct Evaluated {
    /// The evidence.
    pub candidate: Candidate,
    /// The fit with the candidate added.
    pub fit: Fit,
}

/// The model's state of a round: its fit and summary.
pub struct Model<'a> {
    /// The fit.
    pub fit: &'a Fit,
    /// Its summary.
    pub summary: &'a FitSummary,
}

/// Evaluates every registry effect not in `model`, in parallel, ranked by BIC gain.
pub fn evaluate_all(
    ds: &Dataset,
    model: &Model<'_>,
    registry: &Registry,
    opts: &Options,
) -> Result<Vec<Evaluated>, DiagnoseError> {
    let names: Vec<String> = registry
        .names()
        .into_iter()
        .filter(|e| !model.fit.effects.contains(e))
        .collect();
    let mut out = names
        .par_iter()
        .map(|name| evaluate(ds, model, name, registry, opts))
        .collect::<Result<Vec<Option<Evaluated>>, _>>()?
        .into_iter()
        .flatten()
        .collect::<Vec<_>>();
    out.sort_by(|a, b| b.candidate.bic_gain.total_cmp(&a.candidate.bic_gain));
    Ok(out)
}

/// Evaluates one effect; `None` for an effect with neither coefficients nor noise (nothing
/// to fit).
pub fn evaluate(
    ds: &Dataset,
    model: &Model<'_>,
    name: &str,
    registry: &Registry,
    opts: &Options,
) -> Result<Option<Evaluated>, DiagnoseError> {
    let effect = registry.build(name)?;
    let k_coef = effect.coefficient_names().len();
    let noise = effect.process_noise();
    let (fit, widened, density, kind) = if k_coef > 0 {
        // From the starting priors: a base coefficient the model had to widen to soak up the
        // misfit this candidate explains must not keep the candidate from explaining it.
        let mut setup = model.fit.setup.with_effect(name, None);
        setup.priors = setup.priors.restarted();
        setup
            .priors
            .open
            .extend(effect.coefficient_names().iter().map(|c| c.to_string()));
        let (f, w) = fit_adaptive(ds, &setup, registry, &opts.filter)?;
        (f, w, None, CandidateKind::Structured)
    } else if let Some(typical) = noise.first().map(|c| c.psd) {
        let d = fit_density(ds, model.fit, name, typical, registry, &opts.filter)?;
        (d.fit, Vec::new(), Some(d.density), CandidateKind::NoiseOnly)
    } else {
        return Ok(None);
    };
    let s = summarize_fit(ds, &fit, opts);
    let keep = marginal_states(model.fit, &fit);
    let dll = fit.profile_loglik(&keep) - model.fit.profile_loglik(&keep);
    let k = k_coef.max(1);
    let ln_n = (model.fit.measurement_count().max(1) as f64).ln();
    let bic = 2.0 * dll - k as f64 * ln_n;
    let excess = model.summary.excess_nis;
    let removed = if excess > 0.0 {
        1.0 - s.excess_nis.max(0.0) / excess
    } else {
        0.0
    };
    let confused = confusion(&fit, model.fit.names.len());
    let own: Vec<Coefficient> = s
        .coefficients
        .iter()
        .filter(|c| !model.fit.names.contains(&c.name))
        .cloned()
        .collect();
    let beyond = super::plausible::coefficients_beyond(&*effect, &own);
    let candidate = Candidate {
        effect: name.to_string(),
        kind,
        delta_loglik: dll,
        parameters: k,
        bic_gain: bic,
        excess_removed: removed,
        nis: s.nis.clone(),
        consistent: s.consistent,
        coefficients: own,
        density,
        noise: None,
        widened,
        separable_bic: separable_evidence(&fit, model.fit.names.len(), &confused, ln_n),
        confused_with: confused,
        beyond_bounds: beyond,
        outcome: Outcome::NotDecisive,
        failure: fit.failure.clone(),
    };
    Ok(Some(Evaluated { candidate, fit }))
}

/// States driven by process noise in either fit: they stay marginalised in both likelihoods.
fn marginal_states(a: &Fit, b: &Fit) -> Vec<String> {
    let mut out = Vec::new();
    for f in [a, b] {
        for (i, name) in f.names.iter().enumerate() {
            if f.noisy[i] && !out.contains(name) {
                out.push(name.clone());
            }
        }
    }
    out
}

/// A noise-only term: its density by maximum likelihood over a grid of decades around the
/// typical one, refined by a parabola through the best point and its neighbours.
pub fn fit_density(
    ds: &Dataset,
    model: &Fit,
    name: &str,
    typical: f64,
    registry: &Registry,
    filter: &FilterSpec,
) -> Result<DensityFit, DiagnoseError> {
    // (decade, profile log-likelihood, fit)
    let at = |decade: f64| -> Result<(f64, f64, Fit), DiagnoseError> {
        let setup = model
            .setup
            .with_effect(name, Some(typical * 10f64.powf(decade)));
        let f = super::fit::fit(ds, &setup, registry, filter)?;
        let v = if f.failure.is_some() {
            f64::NEG_INFINITY
        } else {
            f.profile_loglik(&marginal_states(model, &f))
        };
        Ok((decade, v, f))
    };
    let grid: Vec<f64> = (DENSITY_DECADES.0..=DENSITY_DECADES.1)
        .step_by(DENSITY_STEP as usize)
        .map(f64::from)
        .collect();
    let mut tried = grid
        .par_iter()
        .map(|&d| at(d))
        .collect::<Result<Vec<_>, _>>()?;
    let best = (0..tried.len())
        .max_by(|&a, &b| tried[a].1.total_cmp(&tried[b].1))
        .unwrap_or(0);
    let mut log10_se = None;
    if best > 0 && best + 1 < tried.len() {
        // A parabola through the best grid point and its neighbours (in decades): its
        // vertex is the next try, its curvature the resolution.
        let h = f64::from(DENSITY_STEP);
        let (l, c, r) = (tried[best - 1].1, tried[best].1, tried[best + 1].1);
        let curvature = (l - 2.0 * c + r) / (h * h);
        if curvature < 0.0 && l.is_finite() && r.is_finite() {
            log10_se = Some(1.0 / (-curvature).sqrt());
            let offset = ((r - l) / (2.0 * h) / -curvature).clamp(-h, h);
            tried.push(at(grid[best] + offset)?);
        }
    }
    let (decade, _, fit) = tried
        .into_iter()
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .ok_or_else(|| DiagnoseError::Data("empty density grid".into()))?;
    Ok(DensityFit {
        fit,
        density: typical * 10f64.powf(decade),
        log10_se,
        at_lower_edge: best == 0,
    })
}

/// A noise-only term's density fitted by maximum likelihood.
#[derive(Debug, Clone)]
pub struct DensityFit {
    /// The fit at the density.
    pub fit: Fit,
    /// The density.
    pub density: f64,
    /// Standard error of its decimal logarithm, from the likelihood's curvature; `None`
    /// when the maximum is at the edge of the grid or the likelihood is flat there.
    pub log10_se: Option<f64>,
    /// Whether the maximum is at the grid's smallest density: the data want none of it (the
    /// density is then at most the one given).
    pub at_lower_edge: bool,
}

/// Coefficients of the candidate (those after the model's own `n_model` states) that cannot
/// be told apart from one of the model's: correlated beyond [`INDISTINGUISHABLE`] in the
/// posterior the data would give from the priors the diagnosis started from.
///
/// Not the fit's own posterior: after widening, two coefficients the data see only as a sum
/// (`Kg13z fz` and `Kg0z` on a level vehicle) can carry priors a hundred times apart, and
/// their posterior correlation is then near zero although nothing but the priors separates
/// them. Nor the data alone: a drag and the g-sensitive drifts are nearly collinear on the
/// paper's test, and only the platform's priors (a drift of 500 times its typical size is not
/// this platform's) tell them apart. So the data's information `F = P_c^-1 - P0^-1` is put
/// back on the starting priors and the correlation read from `(F + P_start^-1)^-1`.
fn confusion(f: &Fit, n_model: usize) -> Vec<Confusion> {
    let n = f.names.len();
    // States driven by noise (the drifts under `gyro-bias-walk`) stay in, with their
    // posterior as it is: a walking drift still cannot be told from a constant g-sensitive one.
    let idx: Vec<usize> = (NAV_DIM..n).collect();
    let m = idx.len();
    let p = nalgebra::DMatrix::from_fn(m, m, |a, b| f.p[idx[a] + idx[b] * n]);
    let Some(p_inv) = p.clone().cholesky().map(|c| c.inverse()) else {
        return Vec::new();
    };
    let mut precision = p_inv;
    for (a, &i) in idx.iter().enumerate().filter(|(_, &i)| !f.noisy[i]) {
        let start = f
            .setup
            .priors
            .starting_sigma(&f.names[i], f.typical_sigma[i]);
        precision[(a, a)] += 1.0 / (start * start) - 1.0 / (f.prior_sigma[i] * f.prior_sigma[i]);
    }
    let Some(c) = precision.cholesky().map(|c| c.inverse()) else {
        return Vec::new();
    };
    let mut out = Vec::new();
    for (u, &i) in idx.iter().enumerate() {
        if i < n_model {
            continue;
        }
        for (v, &j) in idx.iter().enumerate() {
            if j >= n_model {
                continue;
            }
            let corr = c[(u, v)] / (c[(u, u)] * c[(v, v)]).sqrt();
            if corr.abs() > INDISTINGUISHABLE {
                out.push(Confusion {
                    coefficient: f.names[i].clone(),
                    with: f.names[j].clone(),
                    correlation: corr,
                });
            }
        }
    }
    out
}

/// The Wald evidence of the candidate's coefficients (those after `n_model`) that are not in
/// `confused`, as a BIC gain; `None` when none is confused.
fn separable_evidence(f: &Fit, n_model: usize, confused: &[Confusion], ln_n: f64) -> Option<f64> {
    if confused.is_empty() {
        return None;
    }
    let n = f.names.len();
    let free: Vec<usize> = (n_model..n)
        .filter(|&i| !confused.iter().any(|c| c.coefficient == f.names[i]))
        .collect();
    let m = free.len();
    if m == 0 {
        return Some(f64::NEG_INFINITY);
    }
    let mut block = vec![0.0; m * m];
    for (a, &i) in free.iter().enumerate() {
        for (b, &j) in free.iter().enumerate() {
            block[a + b * m] = f.p[i + j * n];
        }
    }
    if navkf_filters::linalg::cholesky_in_place(&mut block, m).is_err() {
        return Some(f64::NEG_INFINITY);
    }
    let mut c: Vec<f64> = free.iter().map(|&i| f.x[i]).collect();
    navkf_filters::linalg::forward_substitute(&block, m, &mut c);
    let wald: f64 = c.iter().map(|v| v * v).sum();
    Some(wald - m as f64 * ln_n)
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

/// The constancy test of the coefficients `names` of the model `setup` on `ds` (module
/// documentation): the model refitted on each half of the record; `None` when neither half
/// informs any of them enough to test.
pub fn constancy(
    ds: &Dataset,
    setup: &super::fit::FitSetup,
    names: &[String],
    registry: &Registry,
    filter: &FilterSpec,
) -> Result<Option<Constancy>, DiagnoseError> {
    let halves = split_in_halves(ds);
    let fits = halves
        .par_iter()
        .map(|h| fit_adaptive(h, setup, registry, filter).map(|f| f.0))
        .collect::<Result<Vec<Fit>, _>>()?;
    let mut rows = Vec::new();
    for name in names {
        // The data-only estimate of each half and its variance (module documentation of
        // `super::priors`); a half whose data barely inform the coefficient is not usable.
        let halves: Vec<(f64, f64)> = fits
            .iter()
            .filter_map(|f| {
                let i = f.names.iter().position(|n| n == name)?;
                let s2 = f.prior_sigma[i] * f.prior_sigma[i];
                let p2 = f.sigma(i).powi(2);
                let kept = 1.0 - p2 / s2;
                (f.failure.is_none() && kept > 0.5).then(|| (f.x[i] / kept, p2 / kept))
            })
            .collect();
        if let [(a, va), (b, vb)] = halves[..] {
            let stat = (a - b).powi(2) / (va + vb);
            rows.push((
                name.clone(),
                stat,
                1,
                navkf_report::stats::chi2_sf(stat, 1.0),
            ));
        }
    }
    if rows.is_empty() {
        return Ok(None);
    }
    let p_min = rows.iter().map(|r| r.3).fold(1.0, f64::min);
    let p_value = (p_min * rows.len() as f64).min(1.0);
    Ok(Some(Constancy {
        coefficients: rows,
        p_value,
        constant: p_value >= CONSTANCY_ALPHA,
    }))
}

/// The constancy test of a noise-only term `name` in the model `setup` (which holds it): is
/// its density the same in both halves of the record? A random walk's is; a term that only
/// tracks a misfit concentrated in one part of the test (a bias settling after switch-on)
/// needs a larger one there and none in the other. Each half's density is fitted by maximum
/// likelihood with the rest of the model as it is; their decimal logarithms are compared with
/// the standard errors the likelihood's curvature gives (a half that wants no walk at all
/// bounds its density by the smallest tried, and the other half is tested against that bound,
/// one-sided). `None` when neither half can fix its density.
pub fn density_constancy(
    ds: &Dataset,
    setup: &super::fit::FitSetup,
    name: &str,
    registry: &Registry,
    filter: &FilterSpec,
) -> Result<Option<Constancy>, DiagnoseError> {
    let typical = registry
        .build(name)?
        .process_noise()
        .first()
        .map_or(f64::NAN, |c| c.psd);
    let mut without = setup.clone();
    without.effects.retain(|e| e != name);
    without.parameters.remove(name);
    let halves = split_in_halves(ds);
    let fits = halves
        .par_iter()
        .map(|h| {
            let base = super::fit::fit(h, &without, registry, filter)?;
            fit_density(h, &base, name, typical, registry, filter)
        })
        .collect::<Result<Vec<DensityFit>, _>>()?;
    let [a, b] = &fits[..] else {
        return Ok(None);
    };
    let stat = match ((a.log10_se, a.at_lower_edge), (b.log10_se, b.at_lower_edge)) {
        ((Some(sa), _), (Some(sb), _)) => {
            (a.density.log10() - b.density.log10()).powi(2) / (sa * sa + sb * sb)
        }
        // One half wants no walk at all: its density is at most the grid's smallest. The
        // other half's is tested against that bound, one-sided.
        ((Some(s), false), (_, true)) | ((_, true), (Some(s), false)) => {
            let (walk, none) = if a.at_lower_edge { (b, a) } else { (a, b) };
            let excess = (walk.density.log10() - none.density.log10()).max(0.0) / s;
            excess * excess
        }
        _ => return Ok(None),
    };
    let p_value = navkf_report::stats::chi2_sf(stat, 1.0);
    Ok(Some(Constancy {
        coefficients: vec![("log10 density".into(), stat, 1, p_value)],
        p_value,
        constant: p_value >= CONSTANCY_ALPHA,
    }))
}

/// The dataset cut in two at the middle of its measurements (each half keeps every input, so
/// the filters find the inputs they need).
fn split_in_halves(ds: &Dataset) -> [Dataset; 2] {
    let mid = ds.measurements.len() / 2;
    let mut a = ds.clone();
    a.measurements.truncate(mid);
    let mut b = ds.clone();
    b.measurements.drain(..mid);
    a.truth = None;
    b.truth = None;
    [a, b]
}
