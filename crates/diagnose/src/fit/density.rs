//! A noise-only term's density by maximum likelihood.
//!
//! A term that adds no coefficient, only process noise (`gyro-bias-walk`,
//! docs/model.md eq. (44)), has one parameter, its density, which the filter cannot estimate
//! as a state. So it is fitted around the filter: one pass per density on a grid of decades
//! around the typical one, the best refined by the vertex of a parabola through it and its
//! neighbours ([`parabola_vertex`]). Each pass's likelihood is
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
    let at = |decade: f64| {
        density_loglik(
            ds,
            model,
            name,
            typical * 10f64.powf(decade),
            catalogue,
            filter,
        )
    };
    let grid = density_grid();
    let found = max_on_grid(&grid, f64::from(DENSITY_STEP), at)?;
    let decade = found.arg;
    Ok(DensityFit {
        fit: found.fit,
        density: typical * 10f64.powf(decade),
        decade,
        at_lower_edge: found.best_on_grid == 0,
        profile: found.profile,
    })
}

/// The profile log-likelihood of `model` with the noise-only term `name` added at `density`
/// (the coefficients at their estimates, the noise-driven states marginal), and the fit;
/// minus infinity when the filter fails.
pub fn density_loglik(
    ds: &Dataset,
    model: &Fit,
    name: &str,
    density: f64,
    catalogue: &dyn Catalogue,
    filter: &FilterSpec,
) -> Result<(f64, Fit), DiagnoseError> {
    let setup = model.setup.with_effect(name, Some(density));
    let f = fit(ds, &setup, catalogue, filter)?;
    let v = if f.failure.is_some() {
        f64::NEG_INFINITY
    } else {
        f.profile_loglik(&marginal_states(model, &f))
    };
    Ok((v, f))
}

/// The decades, relative to a term's typical density, that [`fit_density`] tries first.
pub fn density_grid() -> Vec<f64> {
    (DENSITY_DECADES.0..=DENSITY_DECADES.1)
        .step_by(DENSITY_STEP as usize)
        .map(f64::from)
        .collect()
}

/// Index of the largest of `values` (log-likelihoods on [`density_grid`]); the last of equal
/// largest ones.
pub fn best_on_grid(values: &[f64]) -> usize {
    (0..values.len())
        .max_by(|&a, &b| values[a].total_cmp(&values[b]))
        .unwrap_or(0)
}

/// The vertex of the parabola through the grid point `best` of `values` (log-likelihoods on
/// [`density_grid`]) and its neighbours: its offset from that point and the standard error its
/// curvature gives, both in decades. `None` at the grid's edge, or where the likelihood is
/// not curved down there.
pub fn parabola_vertex(values: &[f64], best: usize) -> Option<(f64, f64)> {
    vertex_on_grid(values, best, f64::from(DENSITY_STEP))
}

/// As [`parabola_vertex`], on any grid of points `h` apart (offset and error in its units).
pub fn vertex_on_grid(values: &[f64], best: usize, h: f64) -> Option<(f64, f64)> {
    if best == 0 || best + 1 >= values.len() {
        return None;
    }
    let (l, c, r) = (values[best - 1], values[best], values[best + 1]);
    let curvature = (l - 2.0 * c + r) / (h * h);
    if curvature < 0.0 && l.is_finite() && r.is_finite() {
        let offset = ((r - l) / (2.0 * h) / -curvature).clamp(-h, h);
        Some((offset, 1.0 / (-curvature).sqrt()))
    } else {
        None
    }
}

/// The maximum over a one-parameter grid of a fit's profile log-likelihood, refined at the
/// vertex of the parabola through the grid's best point and its neighbours.
pub struct GridMax {
    /// The parameter at the maximum.
    pub arg: f64,
    /// The fit there.
    pub fit: Fit,
    /// Its profile log-likelihood.
    pub loglik: f64,
    /// Index of the best grid point (before the refinement).
    pub best_on_grid: usize,
    /// Every point tried, as (parameter, profile log-likelihood): the grid's in its order,
    /// then the refinement's, if any.
    pub profile: Vec<(f64, f64)>,
}

/// The maximum of `at` (a parameter's profile log-likelihood and its fit) over `grid`, whose
/// points are `h` apart, evaluated in parallel (the result does not depend on the thread
/// count), then refined once at the vertex of the parabola through the best point and its
/// neighbours ([`vertex_on_grid`]). Of equal maxima, the last tried is taken.
pub fn max_on_grid(
    grid: &[f64],
    h: f64,
    at: impl Fn(f64) -> Result<(f64, Fit), DiagnoseError> + Sync,
) -> Result<GridMax, DiagnoseError> {
    let mut tried = grid
        .par_iter()
        .map(|&d| at(d).map(|(v, f)| (d, v, f)))
        .collect::<Result<Vec<_>, _>>()?;
    let values: Vec<f64> = tried.iter().map(|t| t.1).collect();
    let best = best_on_grid(&values);
    if let Some((offset, _)) = vertex_on_grid(&values, best, h) {
        let d = grid[best] + offset;
        let (v, f) = at(d)?;
        tried.push((d, v, f));
    }
    let profile = tried.iter().map(|t| (t.0, t.1)).collect();
    let (arg, loglik, fit) = tried
        .into_iter()
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .ok_or_else(|| DiagnoseError::Data("empty grid of a fitted parameter".into()))?;
    Ok(GridMax {
        arg,
        fit,
        loglik,
        best_on_grid: best,
        profile,
    })
}

/// A noise-only term's density fitted by maximum likelihood.
#[derive(Debug, Clone)]
pub struct DensityFit {
    /// The fit at the density.
    pub fit: Fit,
    /// The density.
    pub density: f64,
    /// The density in decades from the typical one.
    pub decade: f64,
    /// Whether the maximum is at the grid's smallest density: the data want none of it (the
    /// density is then at most the one given).
    pub at_lower_edge: bool,
    /// Every density tried, as (decades from the typical density, profile log-likelihood):
    /// [`density_grid`]'s in its order, then the refinement's, if any.
    pub profile: Vec<(f64, f64)>,
}
