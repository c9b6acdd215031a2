//! A term's time constant by maximum likelihood: the settling rival of a noise-only term
//! ([`crate::rivals::AccelSettling`]) has one, which the filter cannot estimate as a state
//! (its rates are not linear in it). So it is fitted around the filter as a density is
//! ([`super::density`]): one pass per time constant on a grid of doublings from a
//! thirty-second of the record to twice its length, the best refined by the vertex of a
//! parabola through it and its neighbours. The grid follows the record, not a warm-up's
//! usual length: a constant much shorter than a thirty-second of the record is a step, which
//! the constant biases take after it, and one longer than twice the record is a ramp, which
//! the longest one draws as well.

use super::density::{density_loglik, max_on_grid};
use super::pass::Fit;
use crate::catalogue::Catalogue;
use crate::error::DiagnoseError;
use navkf_dynamics::dataset::Dataset;
use navkf_filters::FilterSpec;

/// Doublings of the record's length tried: from 2^-5 to 2^1 times it.
const DOUBLINGS: (i32, i32) = (-5, 1);

/// A term's time constant fitted by maximum likelihood.
#[derive(Debug, Clone)]
pub struct TimeConstantFit {
    /// The fit at the time constant.
    pub fit: Fit,
    /// The time constant, s.
    pub time_constant_s: f64,
    /// Its profile log-likelihood (the coefficients at their estimates, the noise-driven
    /// states marginal); minus infinity when every pass failed.
    pub loglik: f64,
}

/// The time constant of the term `name` of `catalogue` on `ds` (whose inputs carry the
/// time, [`crate::rivals::with_elapsed_time`]), added to `model`.
pub fn fit_time_constant(
    ds: &Dataset,
    model: &Fit,
    name: &str,
    catalogue: &dyn Catalogue,
    filter: &FilterSpec,
) -> Result<TimeConstantFit, DiagnoseError> {
    let span = match (ds.inputs.first(), ds.inputs.last()) {
        (Some(a), Some(b)) if b.t > a.t => b.t - a.t,
        _ => {
            return Err(DiagnoseError::Data(
                "no span of inputs to fit a time constant on".into(),
            ))
        }
    };
    let at = |doublings: f64| {
        density_loglik(ds, model, name, span * doublings.exp2(), catalogue, filter)
    };
    let grid: Vec<f64> = (DOUBLINGS.0..=DOUBLINGS.1).map(f64::from).collect();
    let found = max_on_grid(&grid, 1.0, at)?;
    Ok(TimeConstantFit {
        fit: found.fit,
        time_constant_s: span * found.arg.exp2(),
        loglik: found.loglik,
    })
}
