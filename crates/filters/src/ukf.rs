//! The unscented Kalman filter core shared by the standard (augmented) and simplified
//! (additive) variants of the paper. They differ in data, not in code:
//!
//! - [`NoiseHandling`]: the process noise `W` (and optionally the measurement noise `V`)
//!   joins the sigma points (`X^a = [X; W; V]`, n = 20 + 5 + 4 = 29 for the base model), or
//!   `Q_k` is added to the predicted covariance (n = 20).
//! - the measurement path: with additive noise and a model whose measurement is linear, the
//!   update is the Kalman filter's `Z = H X` (paper section 3.2); otherwise sigma points go
//!   through `h`.
//!
//! Augmented points are ordered centre, then `+` and `-` along each direction, state
//! directions first, then `W`, then `V`. Points along `V` have the centre's state and no
//! process noise, so their propagation equals the centre's: it is copied, not recomputed
//! (identical bits, fewer derivative calls). Sigma points for the augmented noise use the
//! block-diagonal structure of `diag(P, Qc / T, R)`, whose factor is `diag(chol P, ...)`.

use crate::error::FilterError;
use crate::filter::{add_process_noise, Estimate, Filter};
use crate::linalg::{cholesky_in_place, weighted_outer_sum};
use crate::sigma_points::{SigmaPoints, SigmaScaling};
use crate::update::{GainWorkspace, Observation, UpdateReport};
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

/// The unscented filter; see the module documentation and the constructors in
/// [`crate::standard_ukf`] and [`crate::simplified_ukf`].
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
    weights_c: Vec<f64>,
    weights_m: Vec<f64>,
    z_pts: Vec<f64>,
    z_hat: Vec<f64>,
    pzz: Vec<f64>,
    pxz: Vec<f64>,
    h: Vec<f64>,
    scratch: PropagationScratch,
    gain: GainWorkspace,
    /// Whether `points` holds the propagated points of the last prediction (augmented
    /// filters update from them).
    have_points: bool,
    last_dt: f64,
}

impl<M: SystemModel + ?Sized> Ukf<M> {
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
        let mut scratch = PropagationScratch::default();
        scratch.ensure(model.scratch_len(npts));
        let weights_c = (0..sp.count()).map(|i| sp.wc(i)).collect();
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
            weights_c,
            weights_m,
            z_pts: vec![0.0; nz * npts],
            z_hat: vec![0.0; nz],
            pzz: vec![0.0; nz * nz],
            pxz: vec![0.0; n * nz],
            h: vec![0.0; nz * n],
            scratch,
            gain: GainWorkspace::new(n, nz),
            have_points: false,
            last_dt: 0.0,
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

    /// Factors P into `chol` and writes `2 n + 1` state sigma points with spread `gamma`.
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
        let x = &self.est.x;
        self.points[..n].copy_from_slice(x);
        for j in 0..na {
            let (plus, minus) = (1 + 2 * j, 2 + 2 * j);
            let (head, tail) = self.points.split_at_mut(minus * n);
            let pp = &mut head[plus * n..(plus + 1) * n];
            let pm = &mut tail[..n];
            pp.copy_from_slice(x);
            pm.copy_from_slice(x);
            if j < n {
                let col = &self.chol[j * n..(j + 1) * n];
                for i in j..n {
                    let s = gamma * col[i];
                    pp[i] += s;
                    pm[i] -= s;
                }
            }
        }
        Ok(())
    }

    /// Weighted mean of the first `count` points into `x`, then deviations in place.
    fn mean_and_deviations(&mut self, count: usize) {
        let n = self.est.n;
        let x = &mut self.est.x;
        x.fill(0.0);
        for i in 0..count {
            let w = self.weights_m[i];
            for (xi, pi) in x.iter_mut().zip(&self.points[i * n..(i + 1) * n]) {
                *xi += w * pi;
            }
        }
    }

    fn covariance_from_points(&mut self, count: usize) {
        let n = self.est.n;
        // Deviations in place: points become chi_i - x_bar. The centre-relative form keeps
        // rounding small (the states are O(1) rad and their spread O(1e-7)).
        for i in 0..count {
            for (pi, xi) in self.points[i * n..(i + 1) * n].iter_mut().zip(&self.est.x) {
                *pi -= xi;
            }
        }
        self.est.p.fill(0.0);
        weighted_outer_sum(
            &mut self.est.p,
            n,
            &self.points[..count * n],
            &self.weights_c[..count],
        );
    }

    fn update_linear(&mut self, obs: &Observation) -> Result<(), FilterError> {
        let n = self.est.n;
        let k = self.gain.report.channels.len();
        self.model.measure(&self.est.x, &mut self.z_hat);
        self.model.measurement_jacobian(&self.est.x, &mut self.h);
        let p = &self.est.p;
        for (a, &ch) in self.gain.report.channels.iter().enumerate() {
            let ha = &self.h[ch * n..(ch + 1) * n];
            let col = &mut self.pxz[a * n..(a + 1) * n];
            col.fill(0.0);
            for (m, &hm) in ha.iter().enumerate() {
                if hm != 0.0 {
                    for (ci, pi) in col.iter_mut().zip(&p[m * n..(m + 1) * n]) {
                        *ci += hm * pi;
                    }
                }
            }
        }
        for (a, &ca) in self.gain.report.channels.iter().enumerate() {
            for b in 0..k {
                let ha = &self.h[ca * n..(ca + 1) * n];
                let col = &self.pxz[b * n..(b + 1) * n];
                self.pzz[a + b * k] = ha.iter().zip(col).map(|(x, y)| x * y).sum();
            }
        }
        self.gain.compute(
            obs,
            &self.z_hat,
            &self.pzz[..k * k],
            &self.pxz[..n * k],
            &mut self.est.x,
        )?;
        self.gain.subtract_gain_cov(&mut self.est.p);
        Ok(())
    }

    /// Sigma-point update from `count` points in `points` (full states, not deviations),
    /// with weights of `sp`; `v_aug` adds the measurement-noise points.
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
        for i in 0..count {
            self.model.measure(
                &self.points[i * n..(i + 1) * n],
                &mut self.z_pts[i * nz..(i + 1) * nz],
            );
        }
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
        self.z_hat.fill(0.0);
        for i in 0..count {
            let w = sp.wm(i);
            for (zh, zi) in self.z_hat.iter_mut().zip(&self.z_pts[i * nz..(i + 1) * nz]) {
                *zh += w * zi;
            }
        }
        self.pzz[..k * k].fill(0.0);
        self.pxz[..n * k].fill(0.0);
        let chans = &self.gain.report.channels;
        for i in 0..count {
            let w = sp.wc(i);
            let zi = &self.z_pts[i * nz..(i + 1) * nz];
            let xi = &self.points[i * n..(i + 1) * n];
            for (a, &ca) in chans.iter().enumerate() {
                let da = w * (zi[ca] - self.z_hat[ca]);
                for (b, &cb) in chans.iter().enumerate() {
                    self.pzz[a + b * k] += da * (zi[cb] - self.z_hat[cb]);
                }
                let col = &mut self.pxz[a * n..(a + 1) * n];
                for ((c, xv), xm) in col.iter_mut().zip(xi).zip(&self.est.x) {
                    *c += da * (xv - xm);
                }
            }
        }
        if v_aug {
            // R is already inside Pzz through the V points; compute() adds it, so take it out.
            for (a, &ca) in chans.iter().enumerate() {
                self.pzz[a + a * k] -= obs.sigma[ca] * obs.sigma[ca];
            }
        }
        self.gain.compute(
            obs,
            &self.z_hat,
            &self.pzz[..k * k],
            &self.pxz[..n * k],
            &mut self.est.x,
        )?;
        self.gain.subtract_gain_cov(&mut self.est.p);
        Ok(())
    }
}

impl<M: SystemModel + ?Sized> Filter for Ukf<M> {
    fn name(&self) -> &str {
        self.name
    }
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
    fn last_report(&self) -> &UpdateReport {
        &self.gain.report
    }
    fn reset(&mut self, x0: &[f64], p0: &[f64]) -> Result<(), FilterError> {
        self.have_points = false;
        self.est.reset(x0, p0)
    }

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
        self.mean_and_deviations(count);
        match self.noise {
            NoiseHandling::Additive => {
                self.covariance_from_points(count);
                add_process_noise(&mut self.est.p, n, model.noise_channels(), dt);
                self.have_points = false;
            }
            _ => {
                // Keep the propagated points for the update (classic augmented UKF): the
                // covariance is formed from deviations computed on a copy.
                self.scratch_covariance(count);
                self.have_points = true;
            }
        }
        self.last_dt = dt;
        self.est.finish("state after prediction")
    }

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
            self.update_sigma(obs, sp.count(), sp, false)?;
        }
        self.have_points = false;
        self.est.finish("state after update")?;
        Ok(&self.gain.report)
    }
}

impl<M: SystemModel + ?Sized> Ukf<M> {
    /// Covariance of the propagated points without destroying them (augmented filters).
    fn scratch_covariance(&mut self, count: usize) {
        let n = self.est.n;
        let p = &mut self.est.p;
        p.fill(0.0);
        let x = &self.est.x;
        // Row-by-row deviation into the (now unused) chol buffer, one point at a time.
        let dev = &mut self.chol[..n];
        for i in 0..count {
            for ((d, pi), xi) in dev.iter_mut().zip(&self.points[i * n..(i + 1) * n]).zip(x) {
                *d = pi - xi;
            }
            let w = self.weights_c[i];
            for j in 0..n {
                let f = w * dev[j];
                let pj = &mut p[j * n + j..(j + 1) * n];
                for (pv, dv) in pj.iter_mut().zip(&dev[j..n]) {
                    *pv += f * dv;
                }
            }
        }
        for j in 0..n {
            for i in j + 1..n {
                p[j + i * n] = p[i + j * n];
            }
        }
    }
}
