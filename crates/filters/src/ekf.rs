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
use crate::linalg::fmadd;
use crate::update::{GainWorkspace, Observation, UpdateReport};
use navkf_dynamics::{InputWindow, SystemModel};
use std::sync::Arc;

/// Lanes of a chunk: rows of the transition matrix are stored padded to a multiple of this,
/// as `[f64; LANES]` chunks, so that every row operation is whole SIMD vectors.
const LANES: usize = 8;
type Chunk = [f64; LANES];

/// `acc += a * src`, lane by lane.
#[inline(always)]
fn axpy(acc: &mut Chunk, a: f64, src: &Chunk) {
    for (o, s) in acc.iter_mut().zip(src) {
        *o = fmadd(a, *s, *o);
    }
}

/// `out[r] = base[r] + sum_m coef[r * d + m] * rows[m]` for the `d` rows of `nc` chunks each
/// (a `d x d` matrix times `d` padded rows, plus `base`).
fn rows_product(
    d: usize,
    nc: usize,
    coef: &[f64],
    rows: &[Chunk],
    base: &[Chunk],
    out: &mut [Chunk],
) {
    match nc {
        1 => rows_product_n::<1>(d, coef, rows, base, out),
        2 => rows_product_n::<2>(d, coef, rows, base, out),
        3 => rows_product_n::<3>(d, coef, rows, base, out),
        4 => rows_product_n::<4>(d, coef, rows, base, out),
        5 => rows_product_n::<5>(d, coef, rows, base, out),
        _ => {
            for ((o_row, b_row), c_row) in out
                .chunks_exact_mut(nc)
                .zip(base.chunks_exact(nc))
                .zip(coef.chunks_exact(d))
                .take(d)
            {
                o_row.copy_from_slice(b_row);
                for (&a, src) in c_row.iter().zip(rows.chunks_exact(nc)) {
                    for (o, s) in o_row.iter_mut().zip(src) {
                        axpy(o, a, s);
                    }
                }
            }
        }
    }
}

/// [`rows_product`] with the row width known: blocks of rows keep their accumulators in
/// registers, several independent chains at once.
#[inline(always)]
fn rows_product_n<const NC: usize>(
    d: usize,
    coef: &[f64],
    rows: &[Chunk],
    base: &[Chunk],
    out: &mut [Chunk],
) {
    let mut r = 0;
    while r + 4 <= d {
        row_block::<NC, 4>(d, r, coef, rows, base, out);
        r += 4;
    }
    if r + 2 <= d {
        row_block::<NC, 2>(d, r, coef, rows, base, out);
        r += 2;
    }
    if r < d {
        row_block::<NC, 1>(d, r, coef, rows, base, out);
    }
}

/// Rows `r0..r0 + R` of [`rows_product_n`].
#[inline(always)]
fn row_block<const NC: usize, const R: usize>(
    d: usize,
    r0: usize,
    coef: &[f64],
    rows: &[Chunk],
    base: &[Chunk],
    out: &mut [Chunk],
) {
    let coef = &coef[r0 * d..(r0 + R) * d];
    let mut acc = [[[0.0; LANES]; NC]; R];
    for (a, b) in acc
        .iter_mut()
        .zip(base[r0 * NC..(r0 + R) * NC].chunks_exact(NC))
    {
        a.copy_from_slice(b);
    }
    for (m, src) in rows.chunks_exact(NC).take(d).enumerate() {
        for (i, a) in acc.iter_mut().enumerate() {
            let c = coef[i * d + m];
            for (o, s) in a.iter_mut().zip(src) {
                axpy(o, c, s);
            }
        }
    }
    for (o, a) in out[r0 * NC..(r0 + R) * NC].chunks_exact_mut(NC).zip(&acc) {
        o.copy_from_slice(a);
    }
}

/// See the module documentation.
pub struct Ekf<M: SystemModel + ?Sized> {
    model: Arc<M>,
    est: Estimate,
    d: usize,
    /// Chunks per padded row.
    nc: usize,
    /// Dynamic rows of the period's transition matrix, d padded rows (`[A B]`).
    phi: Vec<Chunk>,
    /// Dynamic rows of the sub-step's transition matrix with the first d columns zeroed
    /// (`[0 B_sub]`), and its `A_sub` block (d x d, row-major).
    phi_sub: Vec<Chunk>,
    a_sub: Vec<f64>,
    /// The model's Jacobian, d padded rows.
    jac: Vec<Chunk>,
    /// `c * F[:, :d]` of the current stage (d x d).
    cf: Vec<f64>,
    /// Stage Jacobians (chained products), d padded rows each.
    kst: [Vec<Chunk>; 4],
    tmp_rows: Vec<Chunk>,
    /// RK4 stage rates and states.
    k: [Vec<f64>; 4],
    /// Stage state (the coefficients are constant over the window).
    xs: Vec<f64>,
    /// P copied into padded rows (n x nc chunks) for the covariance propagation.
    p_pad: Vec<Chunk>,
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
        let nc = n.div_ceil(LANES);
        Ekf {
            est: Estimate::new(n),
            d,
            nc,
            phi: vec![[0.0; LANES]; d * nc],
            phi_sub: vec![[0.0; LANES]; d * nc],
            a_sub: vec![0.0; d * d],
            jac: vec![[0.0; LANES]; d * nc],
            cf: vec![0.0; d * d],
            kst: std::array::from_fn(|_| vec![[0.0; LANES]; d * nc]),
            tmp_rows: vec![[0.0; LANES]; d * nc],
            k: std::array::from_fn(|_| vec![0.0; d]),
            xs: vec![0.0; n],
            p_pad: vec![[0.0; LANES]; n * nc],
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

    /// One RK4 sub-step of the state (its dynamic rows; `xs` holds the coefficients) and of
    /// the transition matrix.
    fn rk4_substep(&mut self, window: &InputWindow, j: usize) {
        let d = self.d;
        let nc = self.nc;
        let np = nc * LANES;
        let h = window.t[j + 1] - window.t[j];
        let (f0, fm, f1) = (&window.f[j], &window.f_mid[j], &window.f[j + 1]);
        let model = &*self.model;
        let x0 = &self.est.x[..d];
        self.xs[..d].copy_from_slice(x0);
        let stages: [(f64, &navkf_dynamics::Input); 4] =
            [(0.0, f0), (0.5 * h, fm), (0.5 * h, fm), (h, f1)];
        for (s, &(c, u)) in stages.iter().enumerate() {
            let (prev, cur) = self.k.split_at_mut(s);
            if s > 0 {
                for ((xs, x), k) in self.xs.iter_mut().zip(x0).zip(&prev[s - 1]) {
                    *xs = x + c * k;
                }
            }
            if s == 0 {
                // K1 = F.
                let out = self.kst[0].as_flattened_mut();
                model.rates_and_jacobian(&self.xs, u, &mut cur[0], out, np);
            } else {
                // K_s = F (I + c K_{s-1}) = F + (c F[:, :d]) K_{s-1}.
                let jac = self.jac.as_flattened_mut();
                model.rates_and_jacobian(&self.xs, u, &mut cur[0], jac, np);
                for (cf, row) in self.cf.chunks_exact_mut(d).zip(jac.chunks_exact(np)) {
                    for (a, f) in cf.iter_mut().zip(&row[..d]) {
                        *a = c * f;
                    }
                }
                let (prev, cur) = self.kst.split_at_mut(s);
                rows_product(d, nc, &self.cf, &prev[s - 1], &self.jac, &mut cur[0]);
            }
        }
        let h6 = h / 6.0;
        let [k1, k2, k3, k4] = &self.k;
        for (i, x) in self.est.x[..d].iter_mut().enumerate() {
            *x += h6 * (k1[i] + 2.0 * (k2[i] + k3[i]) + k4[i]);
        }
        // Phi_sub rows = [I 0] + h/6 (K1 + 2 K2 + 2 K3 + K4).
        let [k1, k2, k3, k4] = &self.kst;
        for ((((o, a), b), c), e) in self
            .phi_sub
            .as_flattened_mut()
            .iter_mut()
            .zip(k1.as_flattened())
            .zip(k2.as_flattened())
            .zip(k3.as_flattened())
            .zip(k4.as_flattened())
        {
            *o = h6 * (a + 2.0 * (b + c) + e);
        }
        // Split into A_sub (+ I) and [0 B_sub].
        let ps = self.phi_sub.as_flattened_mut();
        for (r, (a_row, p_row)) in self
            .a_sub
            .chunks_exact_mut(d)
            .zip(ps.chunks_exact_mut(np))
            .enumerate()
        {
            a_row.copy_from_slice(&p_row[..d]);
            a_row[r] += 1.0;
            p_row[..d].fill(0.0);
        }
        // Phi = Phi_sub * Phi: new rows = A_sub * rows(Phi) + [0 B_sub].
        std::mem::swap(&mut self.phi, &mut self.tmp_rows);
        rows_product(
            d,
            nc,
            &self.a_sub,
            &self.tmp_rows,
            &self.phi_sub,
            &mut self.phi,
        );
    }

    /// `P = Phi P Phi^T` with `Phi = [R; 0 I]`, `R` the dynamic rows.
    fn propagate_covariance(&mut self) {
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
        let phi = self.phi.as_flattened();
        for (t_row, r_row) in self.tmp_rows.chunks_exact_mut(nc).zip(phi.chunks_exact(np)) {
            for (ch, t) in t_row.iter_mut().enumerate() {
                let mut acc = [0.0; LANES];
                for (&a, src) in r_row[..n]
                    .iter()
                    .zip(self.p_pad.iter().skip(ch).step_by(nc))
                {
                    axpy(&mut acc, a, src);
                }
                *t = acc;
            }
        }
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
        self.est.finish("state after prediction")
    }

    fn update(&mut self, obs: &Observation) -> Result<&UpdateReport, FilterError> {
        let n = self.est.n;
        let k = self.gain.select(obs, self.est.step)?;
        if k == 0 {
            return Ok(&self.gain.report);
        }
        self.model.measure(&self.est.x, &mut self.z_hat);
        self.model.measurement_jacobian(&self.est.x, &mut self.h);
        // Selected rows of H, row-major k x n.
        for (a, &ch) in self.gain.report.channels.iter().enumerate() {
            self.hsel[a * n..(a + 1) * n].copy_from_slice(&self.h[ch * n..(ch + 1) * n]);
        }
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
        // P+ = T - th K^T + K R K^T, column j: P[:, j] += K[j, a] (R_a K[:, a] - th[:, a]).
        for a in 0..k {
            let sig = obs.sigma[self.gain.report.channels[a]];
            let r = sig * sig;
            let ka = &g[a * n..(a + 1) * n];
            let th = &self.pxz[a * n..(a + 1) * n];
            for (pj, &kj) in p.chunks_exact_mut(n).zip(ka) {
                for ((pi, ki), ti) in pj.iter_mut().zip(ka).zip(th) {
                    *pi += -ti * kj + r * ki * kj;
                }
            }
        }
        self.est.finish("state after update")?;
        Ok(&self.gain.report)
    }
}
