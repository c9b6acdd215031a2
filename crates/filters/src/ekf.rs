//! Extended Kalman filter with the exact Jacobian of the RK4 propagation
//! (docs/model.md eqs. (19)-(22)).
//!
//! The transition matrix over a filter period is the derivative of the very RK4 map the
//! UKFs and the truth use, not a single Euler step `I + F T`. It is carried through the
//! sub-steps as a tangent, differentiated stage by stage with the state:
//! `dK_1 = F(x) Phi`, `dK_2 = F(x + h/2 k1) (Phi + h/2 dK_1)`, `dK_3 = F(x + h/2 k2) (Phi +
//! h/2 dK_2)`, `dK_4 = F(x + h k3) (Phi + h dK_3)`, `Phi += h/6 (dK_1 + 2 dK_2 + 2 dK_3 +
//! dK_4)`. Only the model's dynamic rows differ from the identity (`Phi = [A B; 0 I]`, the
//! coefficients being constants), so the stage products touch the `d` dynamic rows only.
//!
//! Prediction `P = Phi P Phi^T + Q_k` with `Q_k = G Qc G^T T` (docs/model.md eqs. (16), (20));
//! update in Joseph form `P = (I - K H) P (I - K H)^T + K R K^T`
//! (docs/model.md eqs. (21), (22)), evaluated as two rank-k corrections.

use crate::error::FilterError;
use crate::estimate::Estimate;
use crate::filter::{add_process_noise, Filter};
use crate::kernels::sparse_row_product;
use crate::tangent::{rows_times_matrix, ChunkBuf, Stage, LANES};
use crate::update::{GainWorkspace, MeasurementMoments, Observation, UpdateReport};
use crate::view::{ColMajor, RowMajor};
use navkf_dynamics::integrate::{rk4_step, RK4};
use navkf_dynamics::{InputWindow, SystemModel};
use std::sync::Arc;

/// See the module documentation.
pub struct Ekf<M: SystemModel + ?Sized> {
    model: Arc<M>,
    est: Estimate,
    d: usize,
    /// Chunks per padded row.
    nc: usize,
    /// Dynamic rows of the period's transition matrix so far, d padded rows (`[A B]`).
    phi: ChunkBuf,
    /// The same after the current sub-step, accumulated stage by stage.
    phi_next: ChunkBuf,
    /// The tangent at the current and the next stage's state, `Phi + c dK` (d padded rows).
    y: [ChunkBuf; 2],
    /// The model's Jacobian at the current stage, d padded rows.
    jac: ChunkBuf,
    /// RK4 stage rates.
    k: [Vec<f64>; 4],
    /// Stage state (the coefficients are constant over the window).
    xs: Vec<f64>,
    /// P copied into padded rows (n x nc chunks) for the covariance propagation.
    p_pad: ChunkBuf,
    /// `Phi P`'s dynamic rows.
    tmp_rows: ChunkBuf,
    mom: MeasurementMoments,
    gain: GainWorkspace,
}

impl<M: SystemModel + ?Sized> Ekf<M> {
    /// An EKF for `model`, sized once.
    pub fn new(model: Arc<M>) -> Self {
        let n = model.dim();
        let d = model.dynamic_dim();
        let nz = model.meas_dim();
        let nc = n.div_ceil(LANES);
        Ekf {
            est: Estimate::new(n),
            d,
            nc,
            phi: ChunkBuf::new(d * nc),
            phi_next: ChunkBuf::new(d * nc),
            y: std::array::from_fn(|_| ChunkBuf::new(d * nc)),
            jac: ChunkBuf::new(d * nc),
            tmp_rows: ChunkBuf::new(d * nc),
            k: std::array::from_fn(|_| vec![0.0; d]),
            xs: vec![0.0; n],
            p_pad: ChunkBuf::new(n * nc),
            mom: MeasurementMoments::new(n, nz),
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

    /// One RK4 sub-step of the state (its dynamic rows; `xs` holds the coefficients) and of
    /// the tangent `Phi`, differentiated through the same stages
    /// (docs/model.md eqs. (15), (19)): `dK_s = F_s (Phi + c_s dK_{s-1})` (the coefficient
    /// rows of the tangent being `[0 I]`, `F_s [Y; 0 I] = F_a Y + [0 F_b]`),
    /// `Phi += h/6 (dK_1 + 2 dK_2 + 2 dK_3 + dK_4)`.
    fn rk4_substep(&mut self, window: &InputWindow, j: usize) {
        let d = self.d;
        let nc = self.nc;
        let np = nc * LANES;
        let h = window.t[j + 1] - window.t[j];
        let model = &*self.model;
        let x0 = &self.est.x[..d];
        self.xs[..d].copy_from_slice(x0);
        for (s, stage) in RK4.iter().enumerate() {
            let (u, c, w) = (stage.input(window, j), stage.offset(h), stage.weight(h));
            let c_next = RK4.get(s + 1).map_or(0.0, |next| next.offset(h));
            let (prev, cur) = self.k.split_at_mut(s);
            if s > 0 {
                for ((xs, x), k) in self.xs.iter_mut().zip(x0).zip(&prev[s - 1]) {
                    *xs = x + c * k;
                }
            }
            let jac = self.jac.as_flattened_mut();
            model.rates_and_jacobian(&self.xs, u, &mut cur[0], jac, np);
            let [y0, y1] = &mut self.y;
            let (y_in, y_out) = if s % 2 == 0 { (y0, y1) } else { (y1, y0) };
            let kernel = Stage {
                d,
                jac: &self.jac,
                y_in: if s == 0 { &self.phi[..] } else { &y_in[..] },
                base: &self.phi,
                w,
                first: s == 0,
            };
            let next = (s + 1 < RK4.len()).then_some((&mut y_out[..], c_next));
            kernel.run(nc, &mut self.phi_next, next);
        }
        let [k1, k2, k3, k4] = &self.k;
        for (i, x) in self.est.x[..d].iter_mut().enumerate() {
            *x += rk4_step(h, [k1[i], k2[i], k3[i], k4[i]]);
        }
        std::mem::swap(&mut self.phi, &mut self.phi_next);
    }

    /// `P = Phi P Phi^T` with `Phi = [R; 0 I]`, `R` the dynamic rows (docs/model.md eq. (20)
    /// without `Q_k`).
    fn propagate_covariance(&mut self) {
        navkf_dynamics::dispatch!(self.propagate_covariance_inline())
    }

    /// [`Ekf::propagate_covariance`], inlined into both copies of
    /// [`navkf_dynamics::dispatch!`].
    #[inline(always)]
    fn propagate_covariance_inline(&mut self) {
        let n = self.est.n;
        let d = self.d;
        let nc = self.nc;
        let np = nc * LANES;
        let p = &mut self.est.p;
        // P in padded rows (row m of P is column m: P is symmetric).
        for (dst, src) in self
            .p_pad
            .as_flattened_mut()
            .chunks_exact_mut(np)
            .zip(p.chunks_exact(n))
        {
            dst[..n].copy_from_slice(src);
        }
        // T = R P (d padded rows in tmp_rows).
        rows_times_matrix(nc, &self.phi, n, &self.p_pad, &mut self.tmp_rows);
        let phi = self.phi.as_flattened();
        // Top-left block T R^T, top-right T[:, d..], bottom-right unchanged.
        let t = self.tmp_rows.as_flattened();
        for r in 0..d {
            let tr = &t[r * np..(r + 1) * np];
            for c in 0..d {
                let rc = &phi[c * np..(c + 1) * np];
                let mut acc = [0.0; LANES];
                for (x, y) in tr.chunks_exact(LANES).zip(rc.chunks_exact(LANES)) {
                    for l in 0..LANES {
                        acc[l] += x[l] * y[l];
                    }
                }
                p[r + c * n] = acc.iter().sum();
            }
            for c in d..n {
                let v = tr[c];
                p[r + c * n] = v;
                p[c + r * n] = v;
            }
        }
        // Only the top-left block was computed both ways round; the rest is symmetric already.
        crate::linalg::symmetrize_leading(p, n, d);
    }
}

impl<M: SystemModel + ?Sized> Filter for Ekf<M> {
    fn name(&self) -> &str {
        "ekf"
    }
    crate::filter::estimate_accessors!();
    fn reset(&mut self, x0: &[f64], p0: &[f64]) -> Result<(), FilterError> {
        self.est.reset(x0, p0)
    }

    /// docs/model.md eqs. (15), (19), (20).
    fn predict(&mut self, window: &InputWindow) -> Result<(), FilterError> {
        crate::filter::check_window(window, self.est.step + 1)?;
        let n = self.est.n;
        let d = self.d;
        self.est.step += 1;
        let np = self.nc * LANES;
        let phi = self.phi.as_flattened_mut();
        phi.fill(0.0);
        for r in 0..d {
            phi[r * np + r] = 1.0;
        }
        self.xs.copy_from_slice(&self.est.x);
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
        // P went in symmetric (every finish and reset leaves it so), and the propagation
        // and the diagonal process noise keep it so.
        self.est.finish_symmetric("state after prediction")
    }

    /// docs/model.md eqs. (17), (21), (22).
    fn update(&mut self, obs: &Observation) -> Result<&UpdateReport, FilterError> {
        let n = self.est.n;
        let k = self.gain.select(obs, self.est.step)?;
        if k == 0 {
            return Ok(&self.gain.report);
        }
        self.mom
            .linear_gain(&*self.model, &mut self.est, &mut self.gain, obs)?;
        // Joseph form as two rank-k corrections:
        // T = (I - K H) P = P - K Pxz^T;  P+ = T - (T H^T) K^T + K R K^T.
        let g = &self.gain.gain;
        let p = &mut self.est.p;
        for j in 0..n {
            for a in 0..k {
                let f = self.mom.pxz[j + a * n];
                if f != 0.0 {
                    let ka = &g[a * n..(a + 1) * n];
                    let pj = &mut p[j * n..(j + 1) * n];
                    for (pi, ki) in pj.iter_mut().zip(ka) {
                        *pi -= ki * f;
                    }
                }
            }
        }
        // th = T H^T (n x k), reusing pxz; H's rows are those of the selected channels.
        let h = RowMajor::new(&self.mom.h, self.model.meas_dim(), n);
        for (a, &ch) in self.gain.report.channels.iter().enumerate() {
            sparse_row_product(
                ColMajor::new(p, n, n),
                h.row(ch),
                &mut self.mom.pxz[a * n..(a + 1) * n],
            );
        }
        // P+ = T - th K^T + K R K^T, column j: P[:, j] += K[j, a] (R_a K[:, a] - th[:, a]),
        // with R_a K[:, a] formed once per channel (the same products as inside the loop).
        let r_k = &mut self.gain.tmp[..n];
        for a in 0..k {
            let sig = obs.sigma[self.gain.report.channels[a]];
            let r = sig * sig;
            let ka = &g[a * n..(a + 1) * n];
            for (rk, ki) in r_k.iter_mut().zip(ka) {
                *rk = r * ki;
            }
            let th = &self.mom.pxz[a * n..(a + 1) * n];
            for (pj, &kj) in p.chunks_exact_mut(n).zip(ka) {
                for ((pi, rk), ti) in pj.iter_mut().zip(&*r_k).zip(th) {
                    *pi += -ti * kj + rk * kj;
                }
            }
        }
        self.est.finish("state after update")?;
        Ok(&self.gain.report)
    }
}
