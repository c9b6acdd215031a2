//! Sigma-point scaling (Julier & Uhlmann's scaled unscented transform), built and validated
//! once from `(n, alpha, beta, kappa)`: docs/model.md eqs. (23)-(25).
//!
//! `lambda = alpha^2 (n + kappa) - n`; points `x`, `x +- sqrt(n + lambda) S_i`; weights
//! `Wm0 = lambda / (n + lambda)`, `Wc0 = Wm0 + 1 - alpha^2 + beta`, `Wi = 1 / (2 (n + lambda))`.
//! The paper's choice (alpha = 1, kappa = 1, beta = 2) gives `n + lambda = n + 1`.

use crate::error::FilterError;

/// The scaling parameters a user chooses.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SigmaScaling {
    /// Spread, `0 < alpha <= 1` usually.
    pub alpha: f64,
    /// Prior-knowledge weight on the centre point's covariance (2 is optimal for Gaussians).
    pub beta: f64,
    /// Secondary scaling.
    pub kappa: f64,
}

impl Default for SigmaScaling {
    /// The paper's: alpha = 1, kappa = 1, beta = 2.
    fn default() -> Self {
        SigmaScaling {
            alpha: 1.0,
            beta: 2.0,
            kappa: 1.0,
        }
    }
}

/// Validated weights for dimension `n`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SigmaPoints {
    /// Dimension the points span.
    pub n: usize,
    /// The scaling it was built from.
    pub scaling: SigmaScaling,
    /// `sqrt(n + lambda)`.
    pub gamma: f64,
    /// Mean weight of the centre point.
    pub wm0: f64,
    /// Covariance weight of the centre point.
    pub wc0: f64,
    /// Weight of every other point (mean and covariance).
    pub wi: f64,
}

impl SigmaPoints {
    /// Builds the weights; refuses settings that make `n + lambda <= 0` or non-finite.
    ///
    /// ```
    /// use navkf_filters::{SigmaPoints, SigmaScaling};
    /// let sp = SigmaPoints::new(20, SigmaScaling::default()).unwrap();
    /// assert_eq!(sp.count(), 41);
    /// assert!((sp.wm0 - 1.0 / 21.0).abs() < 1e-15);
    /// assert!((sp.wc0 - (1.0 / 21.0 + 2.0)).abs() < 1e-15);
    /// ```
    pub fn new(n: usize, scaling: SigmaScaling) -> Result<Self, FilterError> {
        let SigmaScaling { alpha, beta, kappa } = scaling;
        if !(alpha.is_finite() && alpha > 0.0 && beta.is_finite() && kappa.is_finite()) || n == 0 {
            return Err(FilterError::Invalid(format!(
                "sigma-point scaling alpha = {alpha}, beta = {beta}, kappa = {kappa} for n = {n}: expected finite values, alpha > 0, n > 0"
            )));
        }
        let nf = n as f64;
        let lambda = alpha * alpha * (nf + kappa) - nf;
        let c = nf + lambda;
        if !(c > 0.0) {
            return Err(FilterError::Invalid(format!(
                "sigma-point scaling gives n + lambda = {c} <= 0 for n = {n} (alpha = {alpha}, kappa = {kappa}): expected kappa > -n"
            )));
        }
        let wm0 = lambda / c;
        Ok(SigmaPoints {
            n,
            scaling,
            gamma: c.sqrt(),
            wm0,
            wc0: wm0 + 1.0 - alpha * alpha + beta,
            wi: 0.5 / c,
        })
    }

    /// Number of points, `2 n + 1`.
    pub fn count(&self) -> usize {
        2 * self.n + 1
    }

    /// Mean weight of point `i`.
    #[inline]
    pub fn wm(&self, i: usize) -> f64 {
        if i == 0 {
            self.wm0
        } else {
            self.wi
        }
    }

    /// Covariance weight of point `i`.
    #[inline]
    pub fn wc(&self, i: usize) -> f64 {
        if i == 0 {
            self.wc0
        } else {
            self.wi
        }
    }
}
