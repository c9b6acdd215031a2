//! The unscented Kalman filter core shared by the standard (augmented) and simplified
//! (additive) variants of the paper (docs/model.md eqs. (26)-(33)). They differ in data, not
//! in code:
//!
//! - [`NoiseHandling`]: the process noise `W` (and optionally the measurement noise `V`)
//!   joins the sigma points (`X^a = [X; W; V]`, n = 20 + 5 + 4 = 29 for the base model;
//!   docs/model.md eq. (32)), or `Q_k` is added to the predicted covariance (n = 20;
//!   docs/model.md eq. (28)).
//! - the measurement path: with additive noise and a model whose measurement is linear, the
//!   update is the Kalman filter's `Z = H X` (paper section 3.2; docs/model.md eq. (33));
//!   otherwise sigma points go through `h` (docs/model.md eqs. (29)-(31)).
//!
//! Augmented points are ordered centre, then `+` and `-` along each direction, state
//! directions first, then `W`, then `V`. Points along `V` have the centre's state and no
//! process noise, so their propagation equals the centre's: it is copied, not recomputed
//! (identical bits, fewer derivative calls). Sigma points for the augmented noise use the
//! block-diagonal structure of `diag(P, Qc / T, R)`, whose factor is `diag(chol P, ...)`.

use crate::error::FilterError;
use crate::estimate::Estimate;
use crate::filter::{add_process_noise, Filter};
use crate::kernels::{draw_sigma_points, weighted_mean};
use crate::linalg::{cholesky_in_place, row_dots, DOT_BLOCK};
use crate::sigma_points::{SigmaPoints, SigmaScaling};
use crate::update::{GainWorkspace, MeasurementMoments, Observation, UpdateReport};
use crate::view::{ColMajor, ColMajorMut, RowMajor};
use navkf_dynamics::{InputWindow, PropagationScratch, SystemModel};
use std::sync::Arc;

/// How process and measurement noise enter the unscented transform.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NoiseHandling {
    /// `Q_k` added to the predicted covariance, `R` to the innovation covariance.
    Additive,
    /// Process noise augments the sigma points; `R` is added (paper's text: n = 25).
    AugmentProcess,
    /// Process and measurement noise augment the sigma points (paper's Step 1: n = 29).
    AugmentProcessAndMeasurement,
}

/// The unscented filter; see the module documentation and the paper's constructors
/// [`Ukf::standard`], [`Ukf::standard_process_only`] and [`Ukf::simplified`].
pub struct Ukf<M: SystemModel + ?Sized> {
    model: Arc<M>,
    name: &'static str,
    noise: NoiseHandling,
    linear_update: bool,
    sp: SigmaPoints,
    /// Sigma points for the measurement-path redraw of the additive filter (dimension n).
    sp_state: SigmaPoints,
    est: Estimate,
    nw: usize,
    nv: usize,
    npts: usize,
    /// Points that need propagating (the `V` ones are copies of the centre).
    nprop: usize,
    chol: Vec<f64>,
    points: Vec<f64>,
    noise_pts: Vec<f64>,
    noise_sd: Vec<f64>,
    weights_m: Vec<f64>,
    z_pts: Vec<f64>,
    mom: MeasurementMoments,
    /// Deviations of the points from the mean, state-major: row `s` holds state `s` of every
    /// point (`dev_len` long, zero-padded), rows padded to a multiple of [`DOT_BLOCK`].
    dev: Vec<f64>,
    /// Measurement deviations of the selected channels, laid out like `dev`.
    dz: Vec<f64>,
    dev_len: usize,
    scratch: PropagationScratch,
    gain: GainWorkspace,
    /// Whether `points` holds the propagated points of the last prediction (augmented
    /// filters update from them).
    have_points: bool,
}

impl<M: SystemModel + ?Sized> Ukf<M> {
    /// The standard UKF of the paper (section 3.1): the state augmented with the process noise
    /// and the measurement noise, `X^a = [X; W; V]` (n = 29 for the base model); every sigma
    /// point goes through the dynamics and the measurement function (docs/model.md eq. (32)).
    ///
    /// ```
    /// use navkf_dynamics::{NoiseConfig, PlatformModel};
    /// use navkf_filters::{NoiseHandling, SigmaScaling, Ukf};
    /// use std::sync::Arc;
    /// let model = Arc::new(PlatformModel::base(&NoiseConfig::default()));
    /// let ukf = Ukf::standard(model, SigmaScaling::default()).unwrap();
    /// assert_eq!(ukf.noise_handling(), NoiseHandling::AugmentProcessAndMeasurement);
    /// assert_eq!(ukf.sigma_dim(), 29);
    /// // The 8 measurement-noise points share the centre's propagation.
    /// assert_eq!(ukf.propagated_points(), 2 * 25 + 1);
    /// ```
    pub fn standard(model: Arc<M>, scaling: SigmaScaling) -> Result<Self, FilterError> {
        Self::new(
            model,
            "standard_ukf",
            NoiseHandling::AugmentProcessAndMeasurement,
            false,
            scaling,
        )
    }

    /// The standard UKF augmented with the process noise only, `X^a = [X; W]` (n = 25 for
    /// the base model, as the paper's text counts), with additive `R`.
    pub fn standard_process_only(
        model: Arc<M>,
        scaling: SigmaScaling,
    ) -> Result<Self, FilterError> {
        Self::new(
            model,
            "standard_ukf_25",
            NoiseHandling::AugmentProcess,
            false,
            scaling,
        )
    }

    /// The simplified UKF of the paper (section 3.2; docs/model.md eq. (33)): no augmentation,
    /// additive `Q_k` on the predicted covariance, and the Kalman filter's linear update
    /// `Z = H X` while the model's measurement is linear. When an effect makes the measurement
    /// non-linear (`odometer-scale`, `gps-latency`), the update falls back to sigma points
    /// drawn from the prediction.
    ///
    /// ```
    /// use navkf_dynamics::{NoiseConfig, PlatformModel, Registry};
    /// use navkf_filters::{SigmaScaling, Ukf};
    /// use std::sync::Arc;
    /// let noise = NoiseConfig::default();
    /// let base = Arc::new(PlatformModel::base(&noise));
    /// let ukf = Ukf::simplified(base, SigmaScaling::default()).unwrap();
    /// assert_eq!(ukf.sigma_dim(), 20);
    /// assert!(ukf.uses_linear_update());
    /// let odo = Registry::catalogue().build_all(&["odometer-scale"]).unwrap();
    /// let model = Arc::new(PlatformModel::new(odo, &noise).unwrap());
    /// assert!(!Ukf::simplified(model, SigmaScaling::default()).unwrap().uses_linear_update());
    /// ```
    pub fn simplified(model: Arc<M>, scaling: SigmaScaling) -> Result<Self, FilterError> {
        Self::new(
            model,
            "simplified_ukf",
            NoiseHandling::Additive,
            true,
            scaling,
        )
    }

    /// Builds a UKF for `model`. `linear_update` takes the Kalman update when the model's
    /// measurement is linear (only with [`NoiseHandling::Additive`]).
    pub fn new(
        model: Arc<M>,
        name: &'static str,
        noise: NoiseHandling,
        linear_update: bool,
        scaling: SigmaScaling,
    ) -> Result<Self, FilterError> {
        let n = model.dim();
        let nz = model.meas_dim();
        let nw = match noise {
            NoiseHandling::Additive => 0,
            _ => model.noise_channels().len(),
        };
        let nv = match noise {
            NoiseHandling::AugmentProcessAndMeasurement => nz,
            _ => 0,
        };
        let na = n + nw + nv;
        let sp = SigmaPoints::new(na, scaling)?;
        let sp_state = SigmaPoints::new(n, scaling)?;
        let npts = sp.count().max(sp_state.count());
        let nprop = 1 + 2 * (n + nw);
        let scratch = model.propagation_scratch(npts);
        let dev_len = npts.div_ceil(8) * 8;
        let pad = |rows: usize| rows.div_ceil(DOT_BLOCK) * DOT_BLOCK;
        let weights_m = (0..sp.count()).map(|i| sp.wm(i)).collect();
        Ok(Ukf {
            name,
            noise,
            linear_update: linear_update
                && noise == NoiseHandling::Additive
                && model.measurement_is_linear(),
            sp,
            sp_state,
            est: Estimate::new(n),
            nw,
            nv,
            npts: sp.count(),
            nprop,
            chol: vec![0.0; n * n],
            points: vec![0.0; n * npts],
            noise_pts: vec![0.0; nw.max(1) * npts],
            noise_sd: vec![0.0; nw],
            weights_m,
            z_pts: vec![0.0; nz * npts],
            mom: MeasurementMoments::new(n, nz),
            dev: vec![0.0; pad(n) * dev_len],
            dz: vec![0.0; pad(nz) * dev_len],
            dev_len,
            scratch,
            gain: GainWorkspace::new(n, nz),
            have_points: false,
            model,
        })
    }

    /// Augmented dimension `n` of the sigma points (29 for the standard UKF on the base model).
    pub fn sigma_dim(&self) -> usize {
        self.sp.n
    }

    /// Number of sigma points propagated per prediction (derivative calls per prediction are
    /// this times 4 per sub-step).
    pub fn propagated_points(&self) -> usize {
        self.nprop
    }

    /// The noise handling.
    pub fn noise_handling(&self) -> NoiseHandling {
        self.noise
    }

    /// Whether updates take the linear Kalman path.
    pub fn uses_linear_update(&self) -> bool {
        self.linear_update
    }

    /// Factors P into `chol` and writes `2 n + 1` state sigma points with spread `gamma`
    /// (docs/model.md eq. (24)).
    fn draw_state_points(&mut self, gamma: f64, na: usize) -> Result<(), FilterError> {
        let n = self.est.n;
        self.chol.copy_from_slice(&self.est.p);
        cholesky_in_place(&mut self.chol, n).map_err(|(pivot, value)| {
            FilterError::NotPositiveDefinite {
                step: self.est.step,
                matrix: "P",
                pivot,
                dim: n,
                value,
            }
        })?;
        draw_sigma_points(
            &self.est.x,
            ColMajor::new(&self.chol, n, n),
            gamma,
            &mut ColMajorMut::new(&mut self.points, n, 2 * na + 1),
        );
        Ok(())
    }

    /// Weighted mean of the first `count` points into `x`.
    fn weighted_mean(&mut self, count: usize) {
        let n = self.est.n;
        weighted_mean(
            ColMajor::new(&self.points, n, count),
            self.weights_m[..count].iter().copied(),
            &mut self.est.x,
        );
    }

    /// Deviations `chi_i - x_bar` of the first `count` points into `dev` (state-major). The
    /// centre-relative form keeps rounding small (the states are O(1) rad and their spread
    /// O(1e-7)).
    fn build_deviations(&mut self, count: usize) {
        let n = self.est.n;
        let len = self.dev_len;
        for (s, (row, &xs)) in self.dev.chunks_exact_mut(len).zip(&self.est.x).enumerate() {
            for (d, p) in row[..count]
                .iter_mut()
                .zip(self.points.iter().skip(s).step_by(n))
            {
                *d = p - xs;
            }
            row[count..].fill(0.0);
        }
    }

    /// `P = sum_i wc_i d_i d_i^T` (docs/model.md eq. (28)) from `dev`, the weights being `wc0`
    /// for the centre and `wi` for every other point: `wi * D D^T + (wc0 - wi) d_0 d_0^T`.
    fn covariance_from_deviations(&mut self, wc0: f64, wi: f64) {
        let n = self.est.n;
        let len = self.dev_len;
        let rows = n.div_ceil(DOT_BLOCK) * DOT_BLOCK;
        let dev = &self.dev;
        let rows_of = RowMajor::new(dev, rows, len);
        let p = &mut self.est.p;
        let dc = wc0 - wi;
        for a0 in (0..rows).step_by(DOT_BLOCK) {
            for b0 in (a0..rows).step_by(DOT_BLOCK) {
                let g = row_dots(rows_of, a0, rows_of, b0);
                for (i, gi) in g.iter().enumerate() {
                    let a = a0 + i;
                    if a >= n {
                        break;
                    }
                    for (j, gij) in gi.iter().enumerate() {
                        let b = b0 + j;
                        if b >= n {
                            break;
                        }
                        let v = wi * gij + dc * dev[a * len] * dev[b * len];
                        p[a + b * n] = v;
                        p[b + a * n] = v;
                    }
                }
            }
        }
    }

    /// The linear update: docs/model.md eqs. (33), (17), (31).
    fn update_linear(&mut self, obs: &Observation) -> Result<(), FilterError> {
        self.mom
            .linear_gain(&*self.model, &mut self.est, &mut self.gain, obs)?;
        self.gain.subtract_gain_cov(&mut self.est.p);
        Ok(())
    }

    /// Sigma-point update (docs/model.md eqs. (29)-(31)) from `count` points in `points` (full
    /// states, not deviations), with weights of `sp`; `v_aug` adds the measurement-noise
    /// points. `dev` must hold the points' deviations from the state.
    fn update_sigma(
        &mut self,
        obs: &Observation,
        count: usize,
        sp: SigmaPoints,
        v_aug: bool,
    ) -> Result<(), FilterError> {
        let n = self.est.n;
        let nz = self.model.meas_dim();
        let k = self.gain.report.channels.len();
        self.model
            .measure_points(&self.points[..count * n], &mut self.z_pts[..count * nz]);
        if v_aug {
            // V directions are the last nv of the augmented directions.
            let first = n + self.nw;
            for j in 0..self.nv {
                let s = if obs.available[j] {
                    sp.gamma * obs.sigma[j]
                } else {
                    0.0
                };
                self.z_pts[(1 + 2 * (first + j)) * nz + j] += s;
                self.z_pts[(2 + 2 * (first + j)) * nz + j] -= s;
            }
        }
        weighted_mean(
            ColMajor::new(&self.z_pts, nz, count),
            (0..count).map(|i| sp.wm(i)),
            &mut self.mom.z_hat,
        );
        // Measurement deviations of the selected channels, state-major like `dev`.
        let len = self.dev_len;
        let chans = &self.gain.report.channels;
        for (row, &ca) in self.dz.chunks_exact_mut(len).zip(chans) {
            let zh = self.mom.z_hat[ca];
            for (d, z) in row[..count]
                .iter_mut()
                .zip(self.z_pts.iter().skip(ca).step_by(nz))
            {
                *d = z - zh;
            }
            row[count..].fill(0.0);
        }
        // Rows k.. of dz stay zero (blocks of DOT_BLOCK rows read them).
        for row in self.dz.chunks_exact_mut(len).skip(k) {
            row.fill(0.0);
        }
        // Pzz = sum_i wc_i dz_i dz_i^T and Pxz = sum_i wc_i dx_i dz_i^T, with wc = wc0 for the
        // centre and wi elsewhere.
        let (wi, dc) = (sp.wi, sp.wc0 - sp.wi);
        let rows_x = n.div_ceil(DOT_BLOCK) * DOT_BLOCK;
        let rows_z = k.div_ceil(DOT_BLOCK) * DOT_BLOCK;
        let (dev, dz) = (&self.dev, &self.dz);
        let dev_rows = RowMajor::new(dev, rows_x, len);
        let dz_rows = RowMajor::new(dz, rows_z, len);
        for b0 in (0..rows_z).step_by(DOT_BLOCK) {
            for a0 in (0..rows_z).step_by(DOT_BLOCK) {
                let g = row_dots(dz_rows, a0, dz_rows, b0);
                for (i, gi) in g.iter().enumerate().take(k.saturating_sub(a0)) {
                    for (j, gij) in gi.iter().enumerate().take(k.saturating_sub(b0)) {
                        let (a, b) = (a0 + i, b0 + j);
                        self.mom.pzz[a + b * k] = wi * gij + dc * dz[a * len] * dz[b * len];
                    }
                }
            }
            for s0 in (0..rows_x).step_by(DOT_BLOCK) {
                let g = row_dots(dev_rows, s0, dz_rows, b0);
                for (i, gi) in g.iter().enumerate().take(n.saturating_sub(s0)) {
                    for (j, gij) in gi.iter().enumerate().take(k.saturating_sub(b0)) {
                        let (s, b) = (s0 + i, b0 + j);
                        self.mom.pxz[s + b * n] = wi * gij + dc * dev[s * len] * dz[b * len];
                    }
                }
            }
        }
        if v_aug {
            // R is already inside Pzz through the V points; compute() adds it, so take it out.
            for (a, &ca) in chans.iter().enumerate() {
                self.mom.pzz[a + a * k] -= obs.sigma[ca] * obs.sigma[ca];
            }
        }
        self.mom.gain(&mut self.gain, obs, &mut self.est.x)?;
        self.gain.subtract_gain_cov(&mut self.est.p);
        Ok(())
    }
}

impl<M: SystemModel + ?Sized> Filter for Ukf<M> {
    fn name(&self) -> &str {
        self.name
    }
    crate::filter::estimate_accessors!();
    fn reset(&mut self, x0: &[f64], p0: &[f64]) -> Result<(), FilterError> {
        self.have_points = false;
        self.est.reset(x0, p0)
    }

    /// docs/model.md eqs. (26)-(28), the noise as in docs/model.md eqs. (16), (32).
    fn predict(&mut self, window: &InputWindow) -> Result<(), FilterError> {
        crate::filter::check_window(window, self.est.step + 1)?;
        let n = self.est.n;
        let dt = window.duration();
        self.est.step += 1;
        let sp = self.sp;
        self.draw_state_points(sp.gamma, sp.n)?;
        let model = self.model.clone();
        if self.nw > 0 {
            // Noise held constant over the window with variance Qc / T (integrated: Qc T).
            for (sd, c) in self.noise_sd.iter_mut().zip(model.noise_channels()) {
                *sd = sp.gamma * (c.psd / dt).sqrt();
            }
            let nw = self.nw;
            self.noise_pts[..nw * self.nprop].fill(0.0);
            for j in 0..nw {
                let dir = n + j;
                self.noise_pts[(1 + 2 * dir) * nw + j] = self.noise_sd[j];
                self.noise_pts[(2 + 2 * dir) * nw + j] = -self.noise_sd[j];
            }
            model.propagate_points(
                &mut self.points[..self.nprop * n],
                Some(&self.noise_pts[..self.nprop * nw]),
                window,
                &mut self.scratch,
            );
        } else {
            model.propagate_points(
                &mut self.points[..self.nprop * n],
                None,
                window,
                &mut self.scratch,
            );
        }
        // V points: same state as the centre, no process noise.
        for i in self.nprop..self.npts {
            self.points.copy_within(0..n, i * n);
        }
        let count = self.npts;
        self.weighted_mean(count);
        self.build_deviations(count);
        self.covariance_from_deviations(sp.wc0, sp.wi);
        match self.noise {
            NoiseHandling::Additive => {
                add_process_noise(&mut self.est.p, n, model.noise_channels(), dt);
                self.have_points = false;
            }
            _ => {
                // Keep the propagated points and their deviations for the update (classic
                // augmented UKF).
                self.have_points = true;
            }
        }
        // Exactly symmetric already: both triangles get each value, and the noise is diagonal.
        self.est.finish_symmetric("state after prediction")
    }

    /// The linear path (docs/model.md eq. (33)) or sigma points (docs/model.md eqs. (29)-(31)).
    fn update(&mut self, obs: &Observation) -> Result<&UpdateReport, FilterError> {
        let k = self.gain.select(obs, self.est.step)?;
        if k == 0 {
            return Ok(&self.gain.report);
        }
        if self.linear_update {
            self.update_linear(obs)?;
        } else if self.have_points {
            let sp = self.sp;
            let v_aug = self.nv > 0;
            self.update_sigma(obs, self.npts, sp, v_aug)?;
        } else {
            // Additive filter, non-linear measurement: redraw points from the prediction.
            let sp = self.sp_state;
            self.draw_state_points(sp.gamma, sp.n)?;
            self.build_deviations(sp.count());
            self.update_sigma(obs, sp.count(), sp, false)?;
        }
        self.have_points = false;
        // Exactly symmetric already (`subtract_gain_cov` keeps it so).
        self.est.finish_symmetric("state after update")?;
        Ok(&self.gain.report)
    }
}
