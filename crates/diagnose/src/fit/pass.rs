//! One filter pass of a model over a dataset, and the likelihoods a diagnosis compares.
//!
//! The pass keeps every innovation, its predicted sigma and the NIS (for the consistency
//! tests and the figures), the path of every coefficient's estimate and variance, and the
//! total innovation log-likelihood: the sum over updates of docs/model.md eq. (18).
//!
//! That log-likelihood is the *marginal* likelihood of the data: the coefficients are
//! integrated over their prior. It therefore carries the prior's Occam factor, which punishes
//! a wide prior even when the data determine the coefficient well. [`Fit::profile_loglik`]
//! removes it with the Laplace identity, exact for a linear Gaussian model:
//!
//! ```text
//! ln p(y | c = c_hat) = ln p(y) + 1/2 c_hat^T P0^-1 c_hat + 1/2 ln |P0| - 1/2 ln |P_c|
//! ```
//!
//! with `c_hat` and `P_c` the coefficients' final estimate and covariance (their marginal
//! posterior) and `P0` their prior. The result is the likelihood at the estimate, whatever
//! prior the coefficients were fitted with, so that comparisons between models do not depend
//! on how wide a prior was chosen or widened. States driven by process noise (the drifts under
//! `gyro-bias-walk`) are not constants; they stay marginalised.

use super::setup::FitSetup;
use crate::consistency::classify;
use crate::error::DiagnoseError;
use navkf_dynamics::dataset::Dataset;
use navkf_dynamics::prior::typical_sigma;
use navkf_dynamics::state::*;
use navkf_dynamics::trajectory::Phase;
use navkf_dynamics::{Registry, SystemModel};
use navkf_filters::FilterSpec;
use navkf_filters::{Filter, RunFailure, Runner};
use std::sync::Arc;

/// Estimates and variances of the coefficients after every update, for the constancy test.
#[derive(Debug, Clone, Default)]
pub struct CoefficientTrack {
    /// Number of coefficients (states after the navigation ones).
    pub width: usize,
    /// Estimates, `width` per update.
    pub estimate: Vec<f64>,
    /// Variances, `width` per update.
    pub variance: Vec<f64>,
}

impl CoefficientTrack {
    /// Number of updates recorded.
    pub fn len(&self) -> usize {
        self.estimate.len() / self.width.max(1)
    }
    /// Whether nothing was recorded.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// Estimate and variance of coefficient `j` (0 = the first after the navigation states)
    /// after update `k`.
    pub fn at(&self, k: usize, j: usize) -> (f64, f64) {
        (
            self.estimate[k * self.width + j],
            self.variance[k * self.width + j],
        )
    }
}

/// One filter pass over the dataset.
#[derive(Debug, Clone)]
pub struct Fit {
    /// What was fitted.
    pub setup: FitSetup,
    /// Effects in the model.
    pub effects: Vec<String>,
    /// State names.
    pub names: Vec<String>,
    /// Whether each state is driven by process noise (not a constant).
    pub noisy: Vec<bool>,
    /// Update times.
    pub t: Vec<f64>,
    /// Measured values `[v_e, v_n, L, lambda]` (NaN where absent).
    pub z: Vec<[f64; MEAS_DIM]>,
    /// Predicted measurement (NaN where absent).
    pub z_hat: Vec<[f64; MEAS_DIM]>,
    /// Predicted one-sigma of each innovation (NaN where absent).
    pub s_sigma: Vec<[f64; MEAS_DIM]>,
    /// NIS per update.
    pub nis: Vec<f64>,
    /// Dimension of each update.
    pub dims: Vec<usize>,
    /// Motion phase per update.
    pub phases: Vec<Phase>,
    /// Sum of the updates' log-likelihoods (the marginal likelihood).
    pub loglik: f64,
    /// Final estimate.
    pub x: Vec<f64>,
    /// Final covariance, column-major.
    pub p: Vec<f64>,
    /// Initial sigma of every state.
    pub prior_sigma: Vec<f64>,
    /// Typical sigma of every coefficient (0 for the navigation states), the unit the
    /// widening of [`super::widening`] counts in.
    pub typical_sigma: Vec<f64>,
    /// The coefficients' path.
    pub track: CoefficientTrack,
    /// Set when the filter failed (the fit then covers the updates before it).
    pub failure: Option<RunFailure>,
}

impl Fit {
    /// Number of scalar measurements used.
    pub fn measurement_count(&self) -> usize {
        self.dims.iter().sum()
    }

    /// The log-likelihood at the coefficients' estimate (the module documentation), the
    /// Laplace correction taken over the constant coefficients not named in `keep_marginal`.
    /// Falls back to the diagonal of the covariance if its block is not positive definite.
    pub fn profile_loglik(&self, keep_marginal: &[String]) -> f64 {
        let n = self.names.len();
        let idx: Vec<usize> = (NAV_DIM..n)
            .filter(|&i| !self.noisy[i] && !keep_marginal.contains(&self.names[i]))
            .collect();
        let m = idx.len();
        let mut block = vec![0.0; m * m];
        for (a, &i) in idx.iter().enumerate() {
            for (b, &j) in idx.iter().enumerate() {
                block[a + b * m] = self.p[i + j * n];
            }
        }
        let log_det_post = match navkf_filters::linalg::cholesky_in_place(&mut block, m) {
            Ok(()) => (0..m).map(|a| 2.0 * block[a + a * m].ln()).sum::<f64>(),
            Err(_) => idx
                .iter()
                .map(|&i| self.p[i + i * n].max(1e-300).ln())
                .sum(),
        };
        let mut correction = -0.5 * log_det_post;
        for &i in &idx {
            let s2 = self.prior_sigma[i] * self.prior_sigma[i];
            correction += 0.5 * (self.x[i] * self.x[i] / s2 + s2.ln());
        }
        self.loglik + correction
    }

    /// Final one-sigma of state `i`.
    pub fn sigma(&self, i: usize) -> f64 {
        let n = self.names.len();
        self.p[i + i * n].max(0.0).sqrt()
    }
}

/// Fits `setup` to `ds` with `filter`. `Err` only when the model cannot be built or the
/// dataset cannot start a filter; a filter failure during the pass is kept in
/// [`Fit::failure`].
pub fn fit(
    ds: &Dataset,
    setup: &FitSetup,
    registry: &Registry,
    filter: &FilterSpec,
) -> Result<Fit, DiagnoseError> {
    let model = Arc::new(setup.model(registry)?.with_attitude(filter.attitude));
    let n = model.dim();
    let (m0, v0, p0) = first_full_measurement(ds)?;
    let mut x0 = vec![0.0; n];
    x0[V_X] = v0[0];
    x0[V_Y] = v0[1];
    x0[LAT] = p0[0];
    x0[LON] = p0[1];
    let sig0 = setup.noise.measurement_sigmas(v0[0].hypot(v0[1]), p0[0]);
    let names = model.state_names();
    let prior_sigma: Vec<f64> = (0..n)
        .map(|i| match i {
            PHI_X | PHI_Y => setup.priors.level_rad,
            PHI_Z => setup.priors.azimuth_rad,
            V_X | V_Y | LAT | LON => sig0[i - V_X],
            _ => setup
                .priors
                .coefficients
                .get(&names[i])
                .copied()
                .unwrap_or_else(|| typical_sigma(&model, i)),
        })
        .collect();
    let typical: Vec<f64> = (0..n).map(|i| typical_sigma(&model, i)).collect();
    let mut pm = vec![0.0; n * n];
    for i in 0..n {
        pm[i + i * n] = prior_sigma[i] * prior_sigma[i];
    }
    let mut noisy = vec![false; n];
    for c in model.noise_channels() {
        noisy[c.state] = true;
    }
    let mut filt: Box<dyn Filter> = filter.build(model.clone())?;
    filt.reset(&x0, &pm)?;
    let cap = ds.measurements.len();
    let width = n - NAV_DIM;
    let mut fit = Fit {
        setup: setup.clone(),
        effects: setup.effects.clone(),
        names,
        noisy,
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
        typical_sigma: typical,
        track: CoefficientTrack {
            width,
            estimate: Vec::with_capacity(cap * width),
            variance: Vec::with_capacity(cap * width),
        },
        failure: None,
    };
    let inputs = &ds.inputs;
    let result = Runner::new(64).run(
        &mut *filt,
        m0.t,
        inputs,
        &ds.measurements,
        &setup.noise,
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
            // Mean horizontal specific force over the step's input knots, for the phase.
            let knots = v.window.f.len().max(1) as f64;
            let (fe, fnn) = v
                .window
                .f
                .iter()
                .fold((0.0, 0.0), |(e, n), f| (e + f[0], n + f[1]));
            let f_mean = [fe / knots, fnn / knots];
            fit.t.push(v.t);
            fit.z.push(z);
            fit.z_hat.push(zh);
            fit.s_sigma.push(ss);
            fit.nis.push(r.nis);
            fit.dims.push(k);
            fit.phases.push(classify(f_mean, m.velocity));
            fit.loglik += r.log_likelihood;
            let (x, p) = (v.filter.state(), v.filter.covariance());
            for i in NAV_DIM..n {
                fit.track.estimate.push(x[i]);
                fit.track.variance.push(p[i + i * n]);
            }
        },
    );
    if let Err(e) = result {
        fit.failure = Some(RunFailure::of_filter(&e.error, e.to_string()));
    }
    fit.x = filt.state().to_vec();
    fit.p = filt.covariance().to_vec();
    Ok(fit)
}

/// The first measurement with both odometer and GPS (where a filter can start), with its
/// velocity and its position in radians.
pub fn first_full_measurement(
    ds: &Dataset,
) -> Result<(&navkf_dynamics::dataset::Measurement, [f64; 2], [f64; 2]), DiagnoseError> {
    ds.measurements
        .iter()
        .find_map(|m| match (m.velocity, m.gps_rad()) {
            (Some(v), Some(p)) => Some((m, v, p)),
            _ => None,
        })
        .ok_or_else(|| {
            DiagnoseError::Data(format!(
                "dataset `{}`: no measurement row has both odometer and GPS, so the filter \
                 cannot start",
                ds.name
            ))
        })
}

/// States driven by process noise in either fit: they stay marginalised in both likelihoods
/// ([`Fit::profile_loglik`]) when the two are compared.
pub fn marginal_states(a: &Fit, b: &Fit) -> Vec<String> {
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
