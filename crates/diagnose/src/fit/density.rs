//! A noise-only term's density by maximum likelihood.
//!
//! A term that adds no coefficient, only process noise (`gyro-bias-walk`,
//! docs/model.md eq. (44)), has one parameter, its density, which the filter cannot estimate
//! as a state. So it is fitted around the filter: one pass per density on a grid of decades
//! around the typical one, the best refined by a parabola through it and its neighbours, whose
//! curvature also gives the resolution ([`DensityFit::log10_se`]). Each pass's likelihood is
//! taken at the coefficients' estimates with the noise-driven states marginal
//! ([`super::pass::marginal_states`]), as every comparison of the diagnosis is.

use super::pass::{fit, marginal_states, Fit};
use crate::catalogue::Catalogue;
use crate::error::DiagnoseError;
use navkf_dynamics::dataset::Dataset;
use navkf_filters::FilterSpec;
use rayon::prelude::*;

/// Decades of a noise-only term's density searched below and above its typical value.
const DENSITY_DECADES: (i32, i32) = (-2, 6);
/// Spacing of that grid, decades.
const DENSITY_STEP: i32 = 2;

/// A noise-only term: its density by maximum likelihood over a grid of decades around the
/// typical one, refined by a parabola through the best point and its neighbours.
pub fn fit_density(
    ds: &Dataset,
    model: &Fit,
    name: &str,
    typical: f64,
    catalogue: &dyn Catalogue,
    filter: &FilterSpec,
) -> Result<DensityFit, DiagnoseError> {
    // (decade, profile log-likelihood, fit)
    let at = |decade: f64| -> Result<(f64, f64, Fit), DiagnoseError> {
        let setup = model
            .setup
            .with_effect(name, Some(typical * 10f64.powf(decade)));
        let f = fit(ds, &setup, catalogue, filter)?;
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
