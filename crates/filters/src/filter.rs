//! The trait every filter implements, so the study and the diagnosis drive them alike.

use crate::error::FilterError;
use crate::update::{Observation, UpdateReport};
use navkf_dynamics::InputWindow;

/// A recursive estimator: predict across an input window, then update with a measurement.
///
/// Steps allocate nothing: every buffer is sized when the filter is built. The covariance is
/// column-major `dim x dim` (symmetric, so row-major reads the same).
pub trait Filter: Send {
    /// Short name used in tables and files (`ekf`, `standard_ukf`, `simplified_ukf`).
    fn name(&self) -> &str;
    /// State dimension.
    fn dim(&self) -> usize;
    /// Current estimate.
    fn state(&self) -> &[f64];
    /// Current covariance, column-major.
    fn covariance(&self) -> &[f64];
    /// Number of predictions made since the last reset.
    fn step_index(&self) -> usize;
    /// Restarts from `x0` with covariance `p0` (column-major `dim x dim`).
    fn reset(&mut self, x0: &[f64], p0: &[f64]) -> Result<(), FilterError>;
    /// Propagates the estimate across `window`.
    fn predict(&mut self, window: &InputWindow) -> Result<(), FilterError>;
    /// Corrects the estimate with `obs`; the report stays valid until the next update.
    fn update(&mut self, obs: &Observation) -> Result<&UpdateReport, FilterError>;
    /// The report of the last update.
    fn last_report(&self) -> &UpdateReport;
}

/// The [`Filter`] accessors every filter answers from its `est: Estimate` and its
/// `gain: GainWorkspace` (use inside `impl Filter for ...`).
macro_rules! estimate_accessors {
    () => {
        fn dim(&self) -> usize {
            self.est.n
        }
        fn state(&self) -> &[f64] {
            &self.est.x
        }
        fn covariance(&self) -> &[f64] {
            &self.est.p
        }
        fn step_index(&self) -> usize {
            self.est.step
        }
        fn last_report(&self) -> &$crate::update::UpdateReport {
            &self.gain.report
        }
    };
}
pub(crate) use estimate_accessors;

/// Checks an input window before a prediction: at least two knots, times finite and strictly
/// increasing, inputs finite, one midpoint per sub-step.
pub(crate) fn check_window(
    w: &navkf_dynamics::InputWindow,
    step: usize,
) -> Result<(), FilterError> {
    let bad = |what: String| {
        Err(FilterError::Invalid(format!(
            "step {step}: input window {what}"
        )))
    };
    if w.t.len() < 2 {
        return bad(format!("has {} knots: expected at least 2", w.t.len()));
    }
    if w.f.len() != w.t.len() || w.f_mid.len() + 1 != w.t.len() {
        return bad(format!(
            "has {} times, {} inputs and {} midpoints: expected n, n and n - 1",
            w.t.len(),
            w.f.len(),
            w.f_mid.len()
        ));
    }
    for k in 1..w.t.len() {
        if !(w.t[k] > w.t[k - 1]) || !w.t[k].is_finite() {
            return bad(format!(
                "times {} then {}: expected finite, strictly increasing times",
                w.t[k - 1],
                w.t[k]
            ));
        }
    }
    if !w.f.iter().chain(&w.f_mid).flatten().all(|v| v.is_finite()) {
        return bad("holds a non-finite input".into());
    }
    Ok(())
}

/// Adds the discrete process noise `Q_k = G Qc G^T T` of `channels` over `dt` to `p`
/// (docs/model.md eq. (16); the `+ Q_k` of docs/model.md eqs. (20), (28)).
pub(crate) fn add_process_noise(
    p: &mut [f64],
    n: usize,
    channels: &[navkf_dynamics::NoiseChannel],
    dt: f64,
) {
    for c in channels {
        p[c.state + c.state * n] += c.psd * dt;
    }
}

/// Normalised estimation error squared `e^T P^-1 e` with `e = x_true - x_hat`, using
/// `scratch` (at least `n * n + n` long).
pub fn nees(
    x_true: &[f64],
    x_hat: &[f64],
    p: &[f64],
    scratch: &mut [f64],
) -> Result<f64, FilterError> {
    let n = x_hat.len();
    let (l, e) = scratch.split_at_mut(n * n);
    l.copy_from_slice(&p[..n * n]);
    crate::linalg::cholesky_in_place(l, n).map_err(|(pivot, value)| {
        FilterError::NotPositiveDefinite {
            step: 0,
            matrix: "P (NEES)",
            pivot,
            dim: n,
            value,
        }
    })?;
    let e = &mut e[..n];
    for i in 0..n {
        e[i] = x_true[i] - x_hat[i];
    }
    crate::linalg::forward_substitute(l, n, e);
    Ok(e.iter().map(|v| v * v).sum())
}
