//! One filter pass of a model over a dataset, and the likelihoods a diagnosis compares.
//!
//! The pass keeps every innovation, its predicted sigma and the NIS (for the consistency
//! tests and the figures), the path of every coefficient's estimate and variance, and the
//! total innovation log-likelihood: the sum over updates of docs/model.md eq. (18). For the
//! stand-in test, a pass may start its constant coefficients again from their priors partway
//! through ([`FitSetup::restart_coefficients_after`]); every other pass is one run.
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

use super::setup::{FitSetup, ResumePoint};
use crate::catalogue::{Catalogue, Channel, MAX_CHANNELS, PINNED_SIGMA};
use crate::error::DiagnoseError;
use navkf_dynamics::dataset::Dataset;
use navkf_dynamics::trajectory::Phase;
use navkf_dynamics::FamilyModel;
use navkf_filters::FilterSpec;
use navkf_filters::{Filter, RunError, RunFailure, Runner, StepView};

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
    /// Navigation states (the first ones); the rest are coefficients.
    pub nav_dim: usize,
    /// The measurement channels (the family's), in the order of `z`.
    pub channels: &'static [Channel],
    /// The names the tilt priors are reported by (level, then azimuth or heading).
    pub tilt_names: [&'static str; 2],
    /// Whether each state is driven by process noise (not a constant).
    pub noisy: Vec<bool>,
    /// Whether each state is a coefficient the family holds at zero
    /// ([`Catalogue::pinned`]).
    pub pinned: Vec<bool>,
    /// Update times.
    pub t: Vec<f64>,
    /// Measured values of each channel of [`Fit::channels`] (NaN where absent and beyond
    /// the family's channels).
    pub z: Vec<[f64; MAX_CHANNELS]>,
    /// Predicted measurement (NaN where absent).
    pub z_hat: Vec<[f64; MAX_CHANNELS]>,
    /// Predicted one-sigma of each innovation (NaN where absent).
    pub s_sigma: Vec<[f64; MAX_CHANNELS]>,
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
    /// The normalised innovations `(z - z_hat) / sigma` of channel `c` of
    /// [`Fit::channels`], at the updates that measured it.
    pub fn normalised_innovations(&self, c: usize) -> Vec<f64> {
        self.z
            .iter()
            .zip(&self.z_hat)
            .zip(&self.s_sigma)
            .filter(|((z, _), _)| z[c].is_finite())
            .map(|((z, zh), s)| (z[c] - zh[c]) / s[c])
            .collect()
    }

    /// Number of scalar measurements used.
    pub fn measurement_count(&self) -> usize {
        self.dims.iter().sum()
    }

    /// The log-likelihood at the coefficients' estimate (the module documentation), the
    /// Laplace correction taken over the constant coefficients not named in `keep_marginal`.
    /// Falls back to the diagonal of the covariance if its block is not positive definite.
    pub fn profile_loglik(&self, keep_marginal: &[String]) -> f64 {
        let n = self.names.len();
        let idx: Vec<usize> = (self.nav_dim..n)
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

    /// The states after the last update, with their covariance: where a pass over the rest
    /// of the record may resume ([`FitSetup::resume`]). The navigation states, and with
    /// `wandering` also the coefficients driven by process noise (the drifts under
    /// `gyro-bias-walk`, a bias instability's departures): a walk has moved those away from
    /// their prior, and a pass that starts them there again must first catch up. `None` when
    /// the pass made no update or its filter failed (its state is then not the last update's).
    pub fn resume_point(&self, wandering: bool) -> Option<ResumePoint> {
        if self.failure.is_some() {
            return None;
        }
        let t = *self.t.last()?;
        let n = self.names.len();
        let kept: Vec<usize> = (0..n)
            .filter(|&i| i < self.nav_dim || (wandering && self.noisy[i] && !self.pinned[i]))
            .collect();
        let p = kept
            .iter()
            .flat_map(|&j| kept.iter().map(move |&i| self.p[i + j * n]))
            .collect();
        Some(ResumePoint {
            t,
            names: kept.iter().map(|&i| self.names[i].clone()).collect(),
            x: kept.iter().map(|&i| self.x[i]).collect(),
            p,
        })
    }
}

/// Where a fit's filter starts: the first estimate, its covariance (column-major; diagonal
/// unless the navigation states resume a former pass) and the one-sigmas on its diagonal.
#[derive(Debug, Clone, PartialEq)]
pub struct Initial {
    /// Time of the initial state, s.
    pub t: f64,
    pub x: Vec<f64>,
    pub p: Vec<f64>,
    pub sigma: Vec<f64>,
}

/// The start of a filter on `ds` for `setup`'s `model` (built by `catalogue`): the navigation
/// states from the family's start at the first full measurement, the coefficients at zero;
/// their sigmas the start's, the pinned coefficients' [`PINNED_SIGMA`] times their typical
/// size, and the others the setup's priors or their typical size. Where [`FitSetup::resume`]
/// says, the states it holds (found by name; those the model lacks are passed over) start
/// from its estimate and covariance instead.
pub fn initial(
    ds: &Dataset,
    setup: &FitSetup,
    catalogue: &dyn Catalogue,
    model: &dyn FamilyModel,
) -> Result<Initial, DiagnoseError> {
    let n = model.dim();
    let nav = catalogue.nav_dim();
    let names = model.state_names();
    let start = match &setup.resume {
        Some(resume) => resume.clone(),
        None => {
            let tilt = [setup.priors.level_rad, setup.priors.azimuth_rad];
            let start = catalogue.start(ds, &setup.noise, tilt)?;
            let mut p = vec![0.0; nav * nav];
            for (i, s) in start.sigma.iter().enumerate().take(nav) {
                p[i + i * nav] = s * s;
            }
            ResumePoint {
                t: start.t,
                names: names[..nav].to_vec(),
                x: start.x,
                p,
            }
        }
    };
    let m = start.names.len();
    if start.x.len() != m || start.p.len() != m * m || m < nav || start.names[..nav] != names[..nav]
    {
        return Err(DiagnoseError::Data(format!(
            "a filter's start holds the states {:?} ({} estimates, a covariance of {} \
             entries); expected the family's {nav} navigation states {:?} first",
            start.names,
            start.x.len(),
            start.p.len(),
            &names[..nav]
        )));
    }
    // Where each of the start's states sits in the model.
    let placed: Vec<(usize, usize)> = start
        .names
        .iter()
        .enumerate()
        .filter_map(|(a, name)| names.iter().position(|s| s == name).map(|i| (a, i)))
        .collect();
    let mut x = vec![0.0; n];
    let mut sigma: Vec<f64> = (0..n)
        .map(|i| {
            if i < nav {
                0.0
            } else if catalogue.pinned().contains(&names[i].as_str()) {
                PINNED_SIGMA * model.typical_sigma(i)
            } else {
                setup
                    .priors
                    .coefficients
                    .get(&names[i])
                    .copied()
                    .unwrap_or_else(|| model.typical_sigma(i))
            }
        })
        .collect();
    for &(a, i) in &placed {
        x[i] = start.x[a];
        sigma[i] = start.p[a + a * m].max(0.0).sqrt();
    }
    let mut p = vec![0.0; n * n];
    for i in 0..n {
        p[i + i * n] = sigma[i] * sigma[i];
    }
    for &(a, i) in &placed {
        for &(b, j) in &placed {
            p[i + j * n] = start.p[a + b * m];
        }
    }
    Ok(Initial {
        t: start.t,
        x,
        p,
        sigma,
    })
}

/// Fits `setup` to `ds` with `filter`, the model and its sensors those of `catalogue`'s
/// family. `Err` only when the model cannot be built or the dataset cannot start a filter; a
/// filter failure during the pass is kept in [`Fit::failure`].
pub fn fit(
    ds: &Dataset,
    setup: &FitSetup,
    catalogue: &dyn Catalogue,
    filter: &FilterSpec,
) -> Result<Fit, DiagnoseError> {
    let model = catalogue.model(
        &setup.effects,
        &setup.parameters,
        &setup.noise,
        filter.attitude,
    )?;
    let n = model.dim();
    let nav = catalogue.nav_dim();
    let names = model.state_names();
    let Initial {
        t: start_t,
        x: x0,
        p: pm,
        sigma: prior_sigma,
    } = initial(ds, setup, catalogue, &*model)?;
    let typical: Vec<f64> = (0..n).map(|i| model.typical_sigma(i)).collect();
    let mut noisy = vec![false; n];
    for c in model.noise_channels() {
        noisy[c.state] = true;
    }
    let mut filt: Box<dyn Filter> = filter.build(model.clone())?;
    filt.reset(&x0, &pm)?;
    let cap = ds.measurements.len();
    let width = n - nav;
    let channels = catalogue.channels();
    let pinned = names
        .iter()
        .map(|n| catalogue.pinned().contains(&n.as_str()))
        .collect();
    let mut fit = Fit {
        setup: setup.clone(),
        effects: setup.effects.clone(),
        names,
        nav_dim: nav,
        channels,
        tilt_names: catalogue.tilt_names(),
        noisy,
        pinned,
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
    let sensors = catalogue.sensors(setup.noise);
    // The measured values, as the sensors read them (their sigmas and presence are the
    // update's business).
    let nz = channels.len();
    let mut read = [0.0; MAX_CHANNELS];
    let mut read_sigma = [0.0; MAX_CHANNELS];
    let mut read_present = [false; MAX_CHANNELS];
    let mut record = |fit: &mut Fit, v: StepView<'_, dyn Filter>, index: usize| {
        let r = v.report;
        let m = &ds.measurements[index];
        let (x, p) = (v.filter.state(), v.filter.covariance());
        sensors.observe(
            m,
            x,
            &mut read[..nz],
            &mut read_sigma[..nz],
            &mut read_present[..nz],
        );
        let mut z = [f64::NAN; MAX_CHANNELS];
        let mut zh = [f64::NAN; MAX_CHANNELS];
        let mut ss = [f64::NAN; MAX_CHANNELS];
        let k = r.dim();
        for (a, &c) in r.channels.iter().enumerate() {
            z[c] = read[c];
            zh[c] = read[c] - r.innovation[a];
            ss[c] = r.innovation_cov[a + a * k].sqrt();
        }
        fit.t.push(v.t);
        fit.z.push(z);
        fit.z_hat.push(zh);
        fit.s_sigma.push(ss);
        fit.nis.push(r.nis);
        fit.dims.push(k);
        fit.phases.push(catalogue.phase(ds, v.window, m));
        fit.loglik += r.log_likelihood;
        for i in nav..n {
            fit.track.estimate.push(x[i]);
            fit.track.variance.push(p[i + i * n]);
        }
    };
    // The measurements before the restart and after it (all of them before it when there is
    // none).
    let split = setup
        .restart_coefficients_after
        .map_or(ds.measurements.len(), |t| {
            ds.measurements.partition_point(|m| sensors.time(m) <= t)
        });
    let (before, after) = ds.measurements.split_at(split);
    let mut runner = Runner::new(64);
    let mut result = runner.run(&mut *filt, start_t, inputs, before, &*sensors, |v| {
        let index = v.index;
        record(&mut fit, v, index)
    });
    // A restart with no measurement after it would only forget: there is none.
    if result.is_ok() && !after.is_empty() {
        let resumed_t = fit.t.last().copied().unwrap_or(start_t);
        let (x, p) = restarted(&*filt, &fit.noisy, nav, &fit.prior_sigma);
        result = filt
            .reset(&x, &p)
            .map_err(|error| RunError {
                index: split,
                t: ds.measurements[split].t,
                error,
            })
            .and_then(|()| {
                runner
                    .run(&mut *filt, resumed_t, inputs, after, &*sensors, |v| {
                        let index = split + v.index;
                        record(&mut fit, v, index)
                    })
                    .map_err(|e| RunError {
                        index: split + e.index,
                        ..e
                    })
            });
    }
    if let Err(e) = result {
        fit.failure = Some(RunFailure::of_filter(&e.error, e.to_string()));
    }
    fit.x = filt.state().to_vec();
    fit.p = filt.covariance().to_vec();
    Ok(fit)
}

/// The state and covariance of `filter` with every constant coefficient (the states after
/// the first `nav`, save the `noisy` ones) back at its prior: estimate zero, variance
/// `prior_sigma^2`, no covariance with any other state. The navigation states and the
/// process-driven ones keep what the filter knows of them.
fn restarted(
    filter: &dyn Filter,
    noisy: &[bool],
    nav: usize,
    prior_sigma: &[f64],
) -> (Vec<f64>, Vec<f64>) {
    let mut x = filter.state().to_vec();
    let mut p = filter.covariance().to_vec();
    let n = x.len();
    for i in (nav..n).filter(|&i| !noisy[i]) {
        x[i] = 0.0;
        for j in 0..n {
            p[i + j * n] = 0.0;
            p[j + i * n] = 0.0;
        }
        p[i + i * n] = prior_sigma[i] * prior_sigma[i];
    }
    (x, p)
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
