//! A filter's estimate and covariance, with the checks every filter applies to them: sizes
//! and finiteness at a reset, symmetry and finiteness after each step.

use crate::error::FilterError;

/// Estimate and covariance with the checks every filter applies.
#[derive(Debug, Clone)]
pub(crate) struct Estimate {
    pub n: usize,
    pub x: Vec<f64>,
    pub p: Vec<f64>,
    pub step: usize,
}

impl Estimate {
    pub fn new(n: usize) -> Self {
        Estimate {
            n,
            x: vec![0.0; n],
            p: vec![0.0; n * n],
            step: 0,
        }
    }

    pub fn reset(&mut self, x0: &[f64], p0: &[f64]) -> Result<(), FilterError> {
        let n = self.n;
        if x0.len() != n || p0.len() != n * n {
            return Err(FilterError::Invalid(format!(
                "initial state has {} values and covariance {}: expected {n} and {}",
                x0.len(),
                p0.len(),
                n * n
            )));
        }
        if !crate::linalg::all_finite(x0) || !crate::linalg::all_finite(p0) {
            return Err(FilterError::NonFinite {
                step: 0,
                what: "initial state or covariance",
            });
        }
        self.x.copy_from_slice(x0);
        self.p.copy_from_slice(p0);
        crate::linalg::symmetrize(&mut self.p, n);
        self.step = 0;
        Ok(())
    }

    /// Symmetrises P and checks that nothing went non-finite.
    pub fn finish(&mut self, what: &'static str) -> Result<(), FilterError> {
        crate::linalg::symmetrize(&mut self.p, self.n);
        self.finish_symmetric(what)
    }

    /// As [`Estimate::finish`], for a covariance the caller has already made exactly
    /// symmetric.
    pub fn finish_symmetric(&mut self, what: &'static str) -> Result<(), FilterError> {
        if !crate::linalg::all_finite(&self.x) {
            return Err(FilterError::NonFinite {
                step: self.step,
                what,
            });
        }
        if !crate::linalg::all_finite(&self.p) {
            return Err(FilterError::NonFinite {
                step: self.step,
                what: "covariance",
            });
        }
        Ok(())
    }
}
