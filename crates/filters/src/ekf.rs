//! Extended Kalman filter with the exact Jacobian of the RK4 propagation.
//!
//! The transition matrix over a filter period is the derivative of the very RK4 map the
//! UKFs and the truth use, not a single Euler step `I + F T`: for each sub-step,
//! `K1 = F(x)`, `K2 = F(x + h/2 k1) (I + h/2 K1)`, `K3 = F(x + h/2 k2) (I + h/2 K2)`,
//! `K4 = F(x + h k3) (I + h K3)`, `Phi_sub = I + h/6 (K1 + 2 K2 + 2 K3 + K4)`, chained over the
//! sub-steps. Only the model's dynamic rows differ from the identity (`Phi = [A B; 0 I]`, the
//! coefficients being constants), which the products exploit.
//!
//! Prediction `P = Phi P Phi^T + Q_k` with `Q_k = G Qc G^T T`; update in Joseph form
//! `P = (I - K H) P (I - K H)^T + K R K^T`, evaluated as two rank-k corrections.

use crate::error::FilterError;
use crate::filter::{add_process_noise, Estimate, Filter};
use crate::update::{GainWorkspace, Observation, UpdateReport};
use navkf_dynamics::{InputWindow, SystemModel};
use std::sync::Arc;

/// See the module documentation.
pub struct Ekf<M: SystemModel + ?Sized> {
    model: Arc<M>,
    est: Estimate,
    d: usize,
    /// Dynamic rows of the period's transition matrix, row-major d x n.
    phi: Vec<f64>,
    /// Dynamic rows of the sub-step's transition matrix.
    phi_sub: Vec<f64>,
    /// Stage Jacobians and their chained products, row-major d x n.
    jac: Vec<f64>,
    kst: [Vec<f64>; 4],
    tmp_rows: Vec<f64>,
    /// RK4 stage rates and states.
    k: [Vec<f64>; 4],
    xs: Vec<f64>,
    x0: Vec<f64>,
    /// Update scratch.
    h: Vec<f64>,
    hsel: Vec<f64>,
    pzz: Vec<f64>,
    pxz: Vec<f64>,
    z_hat: Vec<f64>,
    gain: GainWorkspace,
}

impl<M: SystemModel + ?Sized> Ekf<M> {
    /// An EKF for `model`, sized once.
    pub fn new(model: Arc<M>) -> Self {
        let n = model.dim();
        let d = model.dynamic_dim();
        let nz = model.meas_dim();
        Ekf {
            est: Estimate::new(n),
            d,
            phi: vec![0.0; d * n],
            phi_sub: vec![0.0; d * n],
            jac: vec![0.0; d * n],
            kst: std::array::from_fn(|_| vec![0.0; d * n]),
            tmp_rows: vec![0.0; d * n],
            k: std::array::from_fn(|_| vec![0.0; d]),
            xs: vec![0.0; n],
            x0: vec![0.0; n],
            h: vec![0.0; nz * n],
            hsel: vec![0.0; nz * n],
            pzz: vec![0.0; nz * nz],
            pxz: vec![0.0; n * nz],
            z_hat: vec![0.0; nz],
            gain: GainWorkspace::new(n, nz),
            model,
        }
    }

    /// Overwrites the estimate (keeping the covariance). Running the covariance recursion with
    /// the state reset to the truth before every step gives the Riccati bound linearised
    /// along the true path, which the study reports next to each filter's error.
    pub fn set_state(&mut self, x: &[f64]) {
        self.est.x.copy_from_slice(x);
    }

    /// `out = F[:, :d] * rows + F` where `F` is `self.jac` (d x n) and `rows` is d x n:
    /// the stage product `F (I + c K)` with `c` folded into `rows` by the caller.
    fn stage_product(d: usize, n: usize, f: &[f64], rows: &[f64], c: f64, out: &mut [f64]) {
        out.copy_from_slice(f);
        for r in 0..d {
            let o = &mut out[r * n..(r + 1) * n];
            for m in 0..d {
                let a = c * f[r * n + m];
                if a != 0.0 {
                    let src = &rows[m * n..(m + 1) * n];
                    for (oi, si) in o.iter_mut().zip(src) {
                        *oi += a * si;
                    }
                }
            }
        }
    }

    fn rk4_substep(&mut self, window: &InputWindow, j: usize) {
        let n = self.est.n;
        let d = self.d;
        let h = window.t[j + 1] - window.t[j];
        let (f0, fm, f1) = (&window.f[j], &window.f_mid[j], &window.f[j + 1]);
        let model = &*self.model;
        self.x0.copy_from_slice(&self.est.x);
        self.xs.copy_from_slice(&self.est.x);
        let stages: [(f64, &navkf_dynamics::Input); 4] =
            [(0.0, f0), (0.5 * h, fm), (0.5 * h, fm), (h, f1)];
        for (s, &(c, u)) in stages.iter().enumerate() {
            if s > 0 {
                for i in 0..d {
                    self.xs[i] = self.x0[i] + c * self.k[s - 1][i];
                }
            }
            model.rates(&self.xs, u, &mut self.k[s]);
            model.rate_jacobian(&self.xs, u, &mut self.jac);
            if s == 0 {
                self.kst[0].copy_from_slice(&self.jac);
            } else {
                let (prev, cur) = self.kst.split_at_mut(s);
                Self::stage_product(d, n, &self.jac, &prev[s - 1], c, &mut cur[0]);
            }
        }
        for i in 0..d {
            self.est.x[i] = self.x0[i]
                + h / 6.0 * (self.k[0][i] + 2.0 * (self.k[1][i] + self.k[2][i]) + self.k[3][i]);
        }
        // Phi_sub rows = [I 0] + h/6 (K1 + 2 K2 + 2 K3 + K4).
        for (idx, v) in self.phi_sub.iter_mut().enumerate() {
            let (r, c) = (idx / n, idx % n);
            let eye = if r == c { 1.0 } else { 0.0 };
            *v = eye
                + h / 6.0
                    * (self.kst[0][idx]
                        + 2.0 * (self.kst[1][idx] + self.kst[2][idx])
                        + self.kst[3][idx]);
        }
        // Phi = Phi_sub * Phi: new rows = A_sub * rows(Phi) + [0 B_sub].
        self.tmp_rows.copy_from_slice(&self.phi);
        for r in 0..d {
            let o = &mut self.phi[r * n..(r + 1) * n];
            o[..d].fill(0.0);
            o[d..].copy_from_slice(&self.phi_sub[r * n + d..(r + 1) * n]);
            for m in 0..d {
                let a = self.phi_sub[r * n + m];
                if a != 0.0 {
                    let src = &self.tmp_rows[m * n..(m + 1) * n];
                    for (oi, si) in o.iter_mut().zip(src) {
                        *oi += a * si;
                    }
                }
            }
        }
    }

    /// `P = Phi P Phi^T` with `Phi = [R; 0 I]`, `R` the dynamic rows.
    fn propagate_covariance(&mut self) {
        let n = self.est.n;
        let d = self.d;
        let p = &mut self.est.p;
        // T = R P (d x n, row-major in tmp_rows).
        let t = &mut self.tmp_rows;
        t.fill(0.0);
        for r in 0..d {
            let tr = &mut t[r * n..(r + 1) * n];
            for m in 0..n {
                let a = self.phi[r * n + m];
                if a != 0.0 {
                    // Row m of P equals column m (symmetric); column-major column is contiguous.
                    let pm = &p[m * n..(m + 1) * n];
                    for (ti, pi) in tr.iter_mut().zip(pm) {
                        *ti += a * pi;
                    }
                }
            }
        }
        // Top-left block T R^T, top-right T[:, d..], bottom-right unchanged.
        for r in 0..d {
            for c in 0..d {
                let tr = &t[r * n..(r + 1) * n];
                let rc = &self.phi[c * n..(c + 1) * n];
                let v: f64 = tr.iter().zip(rc).map(|(a, b)| a * b).sum();
                p[r + c * n] = v;
            }
            for c in d..n {
                let v = t[r * n + c];
                p[r + c * n] = v;
                p[c + r * n] = v;
            }
        }
    }
}

impl<M: SystemModel + ?Sized> Filter for Ekf<M> {
    fn name(&self) -> &str {
        "ekf"
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
        self.est.reset(x0, p0)
    }

    fn predict(&mut self, window: &InputWindow) -> Result<(), FilterError> {
        crate::filter::check_window(window, self.est.step + 1)?;
        let n = self.est.n;
        let d = self.d;
        self.est.step += 1;
        self.phi.fill(0.0);
        for r in 0..d {
            self.phi[r * n + r] = 1.0;
        }
        for j in 0..window.substeps() {
            self.rk4_substep(window, j);
        }
        self.propagate_covariance();
        add_process_noise(
            &mut self.est.p,
            n,
            self.model.noise_channels(),
            window.duration(),
        );
        self.est.finish("state after prediction")
    }

    fn update(&mut self, obs: &Observation) -> Result<&UpdateReport, FilterError> {
        let n = self.est.n;
        let k = self.gain.select(obs, self.est.step)?;
        if k == 0 {
            return Ok(&self.gain.report);
        }
        let nz = self.model.meas_dim();
        self.model.measure(&self.est.x, &mut self.z_hat);
        self.model.measurement_jacobian(&self.est.x, &mut self.h);
        // Selected rows of H, row-major k x n.
        for (a, &ch) in self.gain.report.channels.iter().enumerate() {
            self.hsel[a * n..(a + 1) * n].copy_from_slice(&self.h[ch * n..(ch + 1) * n]);
        }
        let _ = nz;
        let p = &self.est.p;
        // Pxz = P H^T (n x k, column-major): column a = P * h_a.
        for a in 0..k {
            let ha = &self.hsel[a * n..(a + 1) * n];
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
        for a in 0..k {
            for b in 0..k {
                let ha = &self.hsel[a * n..(a + 1) * n];
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
        // Joseph form as two rank-k corrections:
        // T = (I - K H) P = P - K Pxz^T;  P+ = T - (T H^T) K^T + K R K^T.
        let g = &self.gain.gain;
        let p = &mut self.est.p;
        for j in 0..n {
            for a in 0..k {
                let f = self.pxz[j + a * n];
                if f != 0.0 {
                    let ka = &g[a * n..(a + 1) * n];
                    let pj = &mut p[j * n..(j + 1) * n];
                    for (pi, ki) in pj.iter_mut().zip(ka) {
                        *pi -= ki * f;
                    }
                }
            }
        }
        // th = T H^T (n x k), reusing pxz.
        for a in 0..k {
            let ha = &self.hsel[a * n..(a + 1) * n];
            let col = &mut self.pxz[a * n..(a + 1) * n];
            col.fill(0.0);
            for (m, &hm) in ha.iter().enumerate() {
                if hm != 0.0 {
                    // Column m of T (T is column-major like P).
                    for (ci, ti) in col.iter_mut().zip(&p[m * n..(m + 1) * n]) {
                        *ci += hm * ti;
                    }
                }
            }
        }
        // T H^T is (T H^T)[i, a] = sum_m T[i, m] H[a, m]: column m of T gives T[:, m].
        for a in 0..k {
            let sig = obs.sigma[self.gain.report.channels[a]];
            let r = sig * sig;
            let ka = &g[a * n..(a + 1) * n];
            for j in 0..n {
                let th_j = self.pxz[j + a * n];
                let kj = ka[j];
                let pj = &mut p[j * n..(j + 1) * n];
                for i in 0..n {
                    pj[i] += -self.pxz[i + a * n] * kj + r * ka[i] * kj;
                }
                let _ = th_j;
            }
        }
        self.est.finish("state after update")?;
        Ok(&self.gain.report)
    }
}
