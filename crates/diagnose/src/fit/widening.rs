//! How a fit keeps a prior from capping what it finds: the priors it is fitted with are
//! widened where the data ask for it, and kept wider only if the evidence says so.
//!
//! A Kalman filter shrinks each coefficient towards its prior: with prior sigma
//! `s` and data information `F`, the estimate is `c_hat = c_ml (1 - p^2 / s^2)`, where `p` is
//! the posterior sigma and `c_ml` the estimate the data alone would give. A true value several
//! `s` away is then found only in part: it stalls at a few prior sigmas and leaves a misfit
//! that looks like something else. After each fit, every constant coefficient's `c_ml` is
//! recovered from that relation (`F = 1/p^2 - 1/s^2`, `c_ml = c_hat s^2 / (s^2 - p^2)`).
//! Where the data pull it beyond [`WIDEN_BEYOND`] prior sigmas and disagree with the prior
//! (`|c_ml|` beyond [`WIDEN_Z`] standard deviations of its prior predictive distribution
//! `N(0, s^2 + 1/F)`), its prior is proposed `3 |c_ml|` wide. A posterior sigma close to the
//! prior's is no reason to leave a coefficient alone: a torquer scale error of 3 % tested
//! with a prior of 300 ppm ends at its prior sigma although the data put it 15 of their own
//! standard errors from zero.
//!
//! The relation is exact for one coefficient on its own; among correlated ones it can
//! propose a widening the data do not want. So the proposal is a hypothesis about the prior's
//! width, tested like one: the model is refitted with the wider priors, and they are kept only
//! if the marginal likelihood (the filter's own, with the priors' Occam factors) rises by at
//! least [`WIDEN_EVIDENCE`], which a wider prior does only when the data put the coefficient
//! out there. Refits go on until nothing more is proposed (at most [`MAX_WIDENINGS`]). An
//! effect's coefficient may grow to [`WIDEST_EFFECT`] times its starting prior or its typical
//! size, whichever is larger: how large it is, is the question, and a tight prior a user
//! states is a starting point, not a cap. A base coefficient only to [`WIDEST_BASE`] times:
//! beyond that the platform belongs to another class than the stated (or default) priors
//! describe, its user should state priors for it, and a base coefficient let free that far
//! would soak up what a missing effect does (a drag on the paper's test is matched, to the
//! last unit of log-likelihood, by g-sensitive drifts 500 times their typical size). The
//! likelihoods compared afterwards do not depend on the prior's width
//! ([`Fit::profile_loglik`]), so a real effect found with a wide prior is not punished for it.

use super::pass::{fit, Fit};
use super::setup::FitSetup;
use crate::catalogue::Catalogue;
use crate::error::DiagnoseError;
use crate::priors::Priors;
use navkf_dynamics::dataset::Dataset;
use navkf_filters::FilterSpec;
use serde::{Deserialize, Serialize};

/// A coefficient pulled beyond this many prior sigmas gets a wider prior.
pub const WIDEN_BEYOND: f64 = 3.0;
/// ... and the data disagree with the prior by this many standard deviations of the
/// estimate's prior predictive distribution.
pub const WIDEN_Z: f64 = 3.5;
/// Most refits with widened priors per fit.
pub const MAX_WIDENINGS: usize = 4;
/// A base coefficient's prior is not widened beyond this many times the one the diagnosis
/// started from: far beyond it the platform is of another class than the priors describe,
/// and a base coefficient that free would soak up what a missing effect does (a drag is
/// matched by g-sensitive drifts 500 times their typical size).
pub const WIDEST_BASE: f64 = 30.0;
/// An effect's coefficient's prior is not widened beyond this many times its starting one:
/// its size is what the diagnosis is asked for.
pub const WIDEST_EFFECT: f64 = 1000.0;
/// A widening is kept only if the marginal log-likelihood rises by at least this ("strong"
/// evidence for the wider prior: a Bayes factor of e^3, about 20).
pub const WIDEN_EVIDENCE: f64 = 3.0;
/// A coefficient whose variance fell by less than this share is not informed by the data at
/// all (and the data-only estimate cannot be recovered from the rounding).
const UNINFORMED: f64 = 1e-6;

/// One prior widened during a fit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Widening {
    /// Coefficient.
    pub name: String,
    /// Prior sigma before.
    pub from: f64,
    /// Prior sigma after.
    pub to: f64,
    /// The estimate the data alone gave, which asked for it.
    pub implied_estimate: f64,
    /// Whether `to` is the widest prior allowed (the data asked for more).
    pub at_cap: bool,
}

/// How many times its starting prior coefficient `name` may widen to.
fn widest_factor(priors: &Priors, name: &str) -> f64 {
    if priors.open.iter().any(|o| o == name) {
        WIDEST_EFFECT
    } else {
        WIDEST_BASE
    }
}

/// The widest prior sigma coefficient `name` may reach, from its starting sigma `start` and
/// its typical one. An effect's coefficient widens from the larger of the two, so a user's
/// tight prior (`--prior kod=1e-9`) is where the search starts, never a cap on what it finds.
/// A base coefficient's cap stays relative to the stated prior: stating it is saying which
/// class the platform belongs to.
pub fn widest_sigma(priors: &Priors, name: &str, start: f64, typical: f64) -> f64 {
    let factor = widest_factor(priors, name);
    if factor == WIDEST_EFFECT {
        start.max(typical) * factor
    } else {
        start * factor
    }
}

/// The widenings `f` asks for (module documentation), in state order, leaving out the
/// coefficients in `refused`.
pub fn widenings(f: &Fit, refused: &[String]) -> Vec<Widening> {
    let mut out = Vec::new();
    for i in f.nav_dim..f.names.len() {
        // A coefficient held at zero keeps its pinned prior whatever the setup says.
        if f.noisy[i] || f.pinned[i] || refused.contains(&f.names[i]) {
            continue;
        }
        let s = f.prior_sigma[i];
        let p2 = f.sigma(i).powi(2);
        let shrink = p2 / (s * s);
        if !(shrink < 1.0 - UNINFORMED) {
            // A prior so tight that the data cannot move the estimate says nothing of what
            // they hold: an effect's coefficient stated below its typical size is tried at
            // that size (kept, like any widening, only if the evidence rises).
            let typical = f.typical_sigma[i];
            if widest_factor(&f.setup.priors, &f.names[i]) == WIDEST_EFFECT && s < typical {
                out.push(Widening {
                    name: f.names[i].clone(),
                    from: s,
                    to: typical,
                    implied_estimate: f.x[i],
                    at_cap: false,
                });
            }
            continue;
        }
        let c_ml = f.x[i] / (1.0 - shrink);
        let var_ml = p2 / (1.0 - shrink);
        let start = f
            .setup
            .priors
            .starting_sigma(&f.names[i], f.typical_sigma[i]);
        let widest = widest_sigma(&f.setup.priors, &f.names[i], start, f.typical_sigma[i]);
        // Under the prior, c_ml ~ N(0, s^2 + var_ml): beyond WIDEN_Z of that, data and prior
        // disagree.
        let disagree = c_ml * c_ml > WIDEN_Z * WIDEN_Z * (s * s + var_ml);
        if c_ml.abs() > WIDEN_BEYOND * s && disagree && s < widest {
            out.push(Widening {
                name: f.names[i].clone(),
                from: s,
                to: (3.0 * c_ml.abs()).min(widest),
                implied_estimate: c_ml,
                at_cap: 3.0 * c_ml.abs() >= widest,
            });
        }
    }
    out
}

/// Fits `setup`, widening priors until none caps its coefficient (module documentation).
/// Returns the last fit (its setup holds the priors it was fitted with) and the widenings
/// kept.
pub fn fit_adaptive(
    ds: &Dataset,
    setup: &FitSetup,
    catalogue: &dyn Catalogue,
    filter: &FilterSpec,
) -> Result<(Fit, Vec<Widening>), DiagnoseError> {
    let mut f = fit(ds, setup, catalogue, filter)?;
    let mut log = Vec::new();
    let mut refused: Vec<String> = Vec::new();
    for _ in 0..MAX_WIDENINGS {
        if f.failure.is_some() {
            break;
        }
        let w = widenings(&f, &refused);
        if w.is_empty() {
            break;
        }
        let mut trial = f.setup.clone();
        for wi in &w {
            trial.priors.coefficients.insert(wi.name.clone(), wi.to);
        }
        let g = fit(ds, &trial, catalogue, filter)?;
        if g.failure.is_none() && g.loglik >= f.loglik + WIDEN_EVIDENCE {
            f = g;
            log.extend(w);
        } else {
            refused.extend(w.into_iter().map(|wi| wi.name));
        }
    }
    Ok((f, log))
}

/// Factors by which the initial tilt's priors are tried wider ([`widen_tilt`]).
pub const TILT_FACTORS: [f64; 2] = [10.0, 100.0];

/// The initial tilt's priors (level, azimuth) tried [`TILT_FACTORS`] times wider, one at a
/// time; the best is kept if it raises the marginal likelihood by at least
/// [`WIDEN_EVIDENCE`] (a gyrocompassed platform whose drift is far beyond the default starts
/// degrees off in azimuth, and a filter held to arcminutes then blames the misfit on
/// something else). Returns the fit to go on from and the widenings kept (named by the
/// family's tilt names: `level_rad`, and `azimuth_rad` or `heading_rad`).
pub fn widen_tilt(
    ds: &Dataset,
    f: Fit,
    catalogue: &dyn Catalogue,
    filter: &FilterSpec,
) -> Result<(Fit, Vec<Widening>), DiagnoseError> {
    use rayon::prelude::*;
    let start = [f.setup.priors.level_rad, f.setup.priors.azimuth_rad];
    let widest = catalogue.widest_tilt();
    let trials: Vec<(usize, f64)> = (0..2)
        .flat_map(|k| TILT_FACTORS.iter().map(move |&m| (k, m)))
        .filter(|&(k, m)| start[k] * m <= widest[k])
        .collect();
    let fits = trials
        .par_iter()
        .map(|&(k, m)| {
            let mut setup = f.setup.clone();
            if k == 0 {
                setup.priors.level_rad *= m;
            } else {
                setup.priors.azimuth_rad *= m;
            }
            fit(ds, &setup, catalogue, filter)
        })
        .collect::<Result<Vec<Fit>, _>>()?;
    let best = fits
        .into_iter()
        .zip(&trials)
        .filter(|(g, _)| g.failure.is_none())
        .max_by(|a, b| a.0.loglik.total_cmp(&b.0.loglik));
    match best {
        Some((g, &(k, m))) if g.loglik >= f.loglik + WIDEN_EVIDENCE => {
            let (name, from) = if k == 0 {
                (f.tilt_names[0], f.setup.priors.level_rad)
            } else {
                (f.tilt_names[1], f.setup.priors.azimuth_rad)
            };
            let w = Widening {
                name: name.into(),
                from,
                to: from * m,
                implied_estimate: f64::NAN,
                at_cap: m == TILT_FACTORS[TILT_FACTORS.len() - 1]
                    || from * m * TILT_FACTORS[0] > widest[k],
            };
            // The coefficients' priors may now want other widths.
            let (g, _) = fit_adaptive(ds, &g.setup, catalogue, filter)?;
            Ok((g, vec![w]))
        }
        _ => Ok((f, Vec::new())),
    }
}

/// The coefficient priors of `fit` wider than the ones the diagnosis started from (`start`);
/// the `implied_estimate` is the final estimate.
pub fn widened_since(start: &Priors, fit: &Fit) -> Vec<Widening> {
    (fit.nav_dim..fit.names.len())
        .filter_map(|i| {
            let name = &fit.names[i];
            let from = start
                .coefficients
                .get(name)
                .copied()
                .unwrap_or(fit.typical_sigma[i]);
            let cap = widest_sigma(&fit.setup.priors, name, from, fit.typical_sigma[i]);
            (fit.prior_sigma[i] > from).then(|| Widening {
                name: name.clone(),
                from,
                to: fit.prior_sigma[i],
                implied_estimate: fit.x[i],
                at_cap: fit.prior_sigma[i] >= cap * (1.0 - 1e-12),
            })
        })
        .collect()
}

/// `fit` again from the priors the diagnosis started from, if any was widened: a prior the
/// data pulled wide only because an effect was missing (or the noise mis-stated) must not
/// stay wide once the model has it.
pub fn refit_from_starting_priors(
    ds: &Dataset,
    fit: Fit,
    catalogue: &dyn Catalogue,
    filter: &FilterSpec,
) -> Result<Fit, DiagnoseError> {
    if fit.setup.priors == fit.setup.priors.restarted() {
        return Ok(fit);
    }
    let mut setup = fit.setup.clone();
    setup.priors = setup.priors.restarted();
    Ok(fit_adaptive(ds, &setup, catalogue, filter)?.0)
}
