//! Extended Kalman filter with the exact Jacobian of the RK4 propagation.
//!
//! The transition matrix over a filter period is the derivative of the very RK4 map the
//! UKFs and the truth use, not a single Euler step `I + F T`. It is carried through the
//! sub-steps as a tangent, differentiated stage by stage with the state:
//! `dK_1 = F(x) Phi`, `dK_2 = F(x + h/2 k1) (Phi + h/2 dK_1)`, `dK_3 = F(x + h/2 k2) (Phi +
//! h/2 dK_2)`, `dK_4 = F(x + h k3) (Phi + h dK_3)`, `Phi += h/6 (dK_1 + 2 dK_2 + 2 dK_3 +
//! dK_4)`. Only the model's dynamic rows differ from the identity (`Phi = [A B; 0 I]`, the
//! coefficients being constants), so the stage products touch the `d` dynamic rows only.
//!
//! Prediction `P = Phi P Phi^T + Q_k` with `Q_k = G Qc G^T T`; update in Joseph form
//! `P = (I - K H) P (I - K H)^T + K R K^T`, evaluated as two rank-k corrections.

use crate::error::FilterError;
use crate::filter::{add_process_noise, Estimate, Filter};
use crate::linalg::fmadd;
use crate::update::{GainWorkspace, Observation, UpdateReport};
use navkf_dynamics::{InputWindow, SystemModel};
use std::sync::Arc;

/// Lanes of a chunk: rows of the tangent are stored padded to a multiple of this, as
/// `[f64; LANES]` chunks, so that every row operation is whole SIMD vectors (four lanes is one
/// AVX2 register; n = 20 then needs no padding).
#[cfg(target_feature = "avx512f")]
const LANES: usize = 8;
#[cfg(not(target_feature = "avx512f"))]
const LANES: usize = 4;
type Chunk = [f64; LANES];

/// A buffer of chunks that starts on a cache line (64 bytes), so that no vector load or store
/// straddles two lines: a `Vec` of doubles is only 16-byte aligned, and with 8-lane chunks
/// every access then touched two lines. The heap block never moves, so neither does the
/// alignment.
struct ChunkBuf {
    buf: Vec<f64>,
    start: usize,
    len: usize,
}

impl ChunkBuf {
    /// `len` zeroed chunks.
    fn new(len: usize) -> Self {
        const LINE: usize = 64;
        let per_line = LINE / std::mem::size_of::<f64>();
        let buf = vec![0.0; len * LANES + per_line - 1];
        let misaligned = (buf.as_ptr() as usize % LINE) / std::mem::size_of::<f64>();
        ChunkBuf {
            start: (per_line - misaligned) % per_line,
            buf,
            len,
        }
    }
}

impl std::ops::Deref for ChunkBuf {
    type Target = [Chunk];
    #[inline]
    fn deref(&self) -> &[Chunk] {
        self.buf[self.start..self.start + self.len * LANES]
            .as_chunks()
            .0
    }
}

impl std::ops::DerefMut for ChunkBuf {
    #[inline]
    fn deref_mut(&mut self) -> &mut [Chunk] {
        self.buf[self.start..self.start + self.len * LANES]
            .as_chunks_mut()
            .0
    }
}

/// `acc += a * src`, lane by lane.
#[inline(always)]
fn axpy(acc: &mut Chunk, a: f64, src: &Chunk) {
    for (o, s) in acc.iter_mut().zip(src) {
        *o = fmadd(a, *s, *o);
    }
}

/// Dynamic dimension of the platform model (its seven navigation states), for which the
/// stage kernel is compiled with every size known.
const PLATFORM_D: usize = navkf_dynamics::state::NAV_DIM;

/// One RK4 stage of the tangent, fused: for every dynamic row `r`,
/// `t = [0 F_b][r] + sum_m F_a[r, m] y_in[m]` (the stage's tangent rate, never stored),
/// then `acc[r] = (first ? base[r] : acc[r]) + w t` and, for the next stage,
/// `y_out[r] = base[r] + c t`. `jac` holds the model Jacobian's `d` padded rows `[F_a F_b]`.
///
/// With the sizes known at compile time (`d = 7`, up to 8 chunks per row) each row's rate
/// `t` lives in registers. An exactly zero `F_a[r, m]` is skipped by one branch: the platform
/// model's block has 27 nonzeros of 49, always in the same places, so the branches are
/// predicted, and skipping an exact zero leaves every sum as the dense product would make it.
/// (Measured slower, on an AVX-512 Zen 5: the dense product; two partial sums per row; all
/// rows of one chunk at a time; `y_in` copied to locals first; outputs formed in registers
/// rather than copied then added to; an index list of the nonzeros rebuilt at every stage.)
struct Stage<'a> {
    d: usize,
    jac: &'a [Chunk],
    y_in: &'a [Chunk],
    base: &'a [Chunk],
    w: f64,
    first: bool,
}

impl Stage<'_> {
    fn run(&self, nc: usize, acc: &mut [Chunk], y_out: Option<(&mut [Chunk], f64)>) {
        macro_rules! fixed {
            ($($n:literal)*) => {
                match (self.d, nc) {
                    $((PLATFORM_D, $n) => self.run_n::<PLATFORM_D, $n>(acc, y_out),)*
                    _ => self.run_any(nc, acc, y_out),
                }
            };
        }
        fixed!(1 2 3 4 5 6 7 8)
    }

    /// With the sizes known, the row's rate `t` lives in registers.
    #[inline(always)]
    fn run_n<const D: usize, const NC: usize>(
        &self,
        acc: &mut [Chunk],
        mut y_out: Option<(&mut [Chunk], f64)>,
    ) {
        let y_in = &self.y_in[..D * NC];
        for r in 0..D {
            let row: &[Chunk; NC] = self.jac[r * NC..(r + 1) * NC].try_into().unwrap();
            let mut t = *row;
            // [0 F_b]: the dynamic block's columns start at zero (a constant mask).
            for (ch, tc) in t.iter_mut().enumerate() {
                for (l, v) in tc.iter_mut().enumerate() {
                    if ch * LANES + l < D {
                        *v = 0.0;
                    }
                }
            }
            for m in 0..D {
                let a = row[m / LANES][m % LANES];
                if a != 0.0 {
                    for (o, s) in t.iter_mut().zip(&y_in[m * NC..(m + 1) * NC]) {
                        axpy(o, a, s);
                    }
                }
            }
            let rows = r * NC..(r + 1) * NC;
            let base = &self.base[rows.clone()];
            let acc = &mut acc[rows.clone()];
            if self.first {
                acc.copy_from_slice(base);
            }
            for (o, s) in acc.iter_mut().zip(&t) {
                axpy(o, self.w, s);
            }
            if let Some((y, c)) = y_out.as_mut() {
                let y = &mut y[rows];
                y.copy_from_slice(base);
                for (o, s) in y.iter_mut().zip(&t) {
                    axpy(o, *c, s);
                }
            }
        }
    }

    /// Any size: the rate is accumulated one chunk at a time.
    fn run_any(&self, nc: usize, acc: &mut [Chunk], mut y_out: Option<(&mut [Chunk], f64)>) {
        let d = self.d;
        for r in 0..d {
            let row = &self.jac[r * nc..(r + 1) * nc];
            for ch in 0..nc {
                let mut t = row[ch];
                for (l, v) in t.iter_mut().enumerate() {
                    if ch * LANES + l < d {
                        *v = 0.0;
                    }
                }
                for m in 0..d {
                    let a = row[m / LANES][m % LANES];
                    axpy(&mut t, a, &self.y_in[m * nc + ch]);
                }
                let i = r * nc + ch;
                let b = &self.base[i];
                if self.first {
                    acc[i] = *b;
                }
                axpy(&mut acc[i], self.w, &t);
                if let Some((y, c)) = y_out.as_mut() {
                    y[i] = *b;
                    axpy(&mut y[i], *c, &t);
                }
            }
        }
    }
}

/// `out = rows P` for `rows` (padded rows of `nc` chunks, `n` real columns) and `P` given by
/// its `n` padded rows `p_pad` (symmetric, so row `m` is column `m`).
fn rows_times_matrix(nc: usize, rows: &[Chunk], n: usize, p_pad: &[Chunk], out: &mut [Chunk]) {
    macro_rules! fixed {
        ($($k:literal)*) => {
            match nc {
                $($k => rows_times_matrix_n::<$k>(rows, n, p_pad, out),)*
                _ => {
                    for (o, row) in out.chunks_exact_mut(nc).zip(rows.chunks_exact(nc)) {
                        o.fill([0.0; LANES]);
                        for (m, &a) in row.as_flattened()[..n].iter().enumerate() {
                            for (oc, pc) in o.iter_mut().zip(&p_pad[m * nc..(m + 1) * nc]) {
                                axpy(oc, a, pc);
                            }
                        }
                    }
                }
            }
        };
    }
    fixed!(1 2 3 4 5 6 7 8)
}

/// [`rows_times_matrix`] with the row width known: the output row accumulates in registers,
/// and the rows' exact zeros (the identity's, the padding) are skipped.
#[inline(always)]
fn rows_times_matrix_n<const NC: usize>(
    rows: &[Chunk],
    n: usize,
    p_pad: &[Chunk],
    out: &mut [Chunk],
) {
    for (o, row) in out.chunks_exact_mut(NC).zip(rows.chunks_exact(NC)) {
        let mut t = [[0.0; LANES]; NC];
        for (m, &a) in row.as_flattened()[..n].iter().enumerate() {
            if a != 0.0 {
                for (tc, pc) in t.iter_mut().zip(&p_pad[m * NC..(m + 1) * NC]) {
                    axpy(tc, a, pc);
                }
            }
        }
        o.copy_from_slice(&t);
    }
}

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
            phi: ChunkBuf::new(d * nc),
            phi_next: ChunkBuf::new(d * nc),
            y: std::array::from_fn(|_| ChunkBuf::new(d * nc)),
            jac: ChunkBuf::new(d * nc),
            tmp_rows: ChunkBuf::new(d * nc),
            k: std::array::from_fn(|_| vec![0.0; d]),
            xs: vec![0.0; n],
            p_pad: ChunkBuf::new(n * nc),
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
    /// the tangent `Phi`, differentiated through the same stages:
    /// `dK_s = F_s (Phi + c_s dK_{s-1})` (the coefficient rows of the tangent being `[0 I]`,
    /// `F_s [Y; 0 I] = F_a Y + [0 F_b]`), `Phi += h/6 (dK_1 + 2 dK_2 + 2 dK_3 + dK_4)`.
    fn rk4_substep(&mut self, window: &InputWindow, j: usize) {
        let d = self.d;
        let nc = self.nc;
        let np = nc * LANES;
        let h = window.t[j + 1] - window.t[j];
        let (f0, fm, f1) = (&window.f[j], &window.f_mid[j], &window.f[j + 1]);
        let model = &*self.model;
        let x0 = &self.est.x[..d];
        self.xs[..d].copy_from_slice(x0);
        // (input, offset of the stage state, weight in the sum, offset of the next stage).
        let stages: [(&navkf_dynamics::Input, f64, f64, f64); 4] = [
            (f0, 0.0, h / 6.0, 0.5 * h),
            (fm, 0.5 * h, h / 3.0, 0.5 * h),
            (fm, 0.5 * h, h / 3.0, h),
            (f1, h, h / 6.0, 0.0),
        ];
        for (s, &(u, c, w, c_next)) in stages.iter().enumerate() {
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
            let stage = Stage {
                d,
                jac: &self.jac,
                y_in: if s == 0 { &self.phi[..] } else { &y_in[..] },
                base: &self.phi,
                w,
                first: s == 0,
            };
            let next = (s < 3).then_some((&mut y_out[..], c_next));
            stage.run(nc, &mut self.phi_next, next);
        }
        let h6 = h / 6.0;
        let [k1, k2, k3, k4] = &self.k;
        for (i, x) in self.est.x[..d].iter_mut().enumerate() {
            *x += h6 * (k1[i] + 2.0 * (k2[i] + k3[i]) + k4[i]);
        }
        std::mem::swap(&mut self.phi, &mut self.phi_next);
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
        // The top-left block was computed both ways round; its average is what
        // `linalg::symmetrize` would make of it, and the rest of P is symmetric already.
        for c in 0..d {
            for r in c + 1..d {
                let m = 0.5 * (p[r + c * n] + p[c + r * n]);
                p[r + c * n] = m;
                p[c + r * n] = m;
            }
        }
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
        crate::update::linear_moments(
            &self.est.p,
            n,
            &self.h,
            &self.gain.report.channels,
            &mut self.pxz,
            &mut self.pzz,
        );
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The compiled-size path (the platform model's 7 dynamic states, up to 8 chunks per row)
    /// and the any-size fallback (other models) compute the same stage, to rounding.
    #[test]
    fn fixed_and_any_size_stages_agree() {
        const NC: usize = 3;
        let d = PLATFORM_D;
        let filled = |seed: f64, len: usize| -> Vec<Chunk> {
            (0..len)
                .map(|i| std::array::from_fn(|l| (seed * (i * LANES + l + 1) as f64).sin()))
                .collect()
        };
        let jac = filled(0.7, d * NC);
        let (y_in, base) = (filled(1.3, d * NC), filled(2.9, d * NC));
        for first in [true, false] {
            let stage = Stage {
                d,
                jac: &jac,
                y_in: &y_in,
                base: &base,
                w: 0.25,
                first,
            };
            let start = filled(4.1, d * NC);
            let (mut acc_n, mut acc_any) = (start.clone(), start);
            let (mut y_n, mut y_any) = (vec![[0.0; LANES]; d * NC], vec![[0.0; LANES]; d * NC]);
            stage.run_n::<PLATFORM_D, NC>(&mut acc_n, Some((&mut y_n, 0.5)));
            stage.run_any(NC, &mut acc_any, Some((&mut y_any, 0.5)));
            for (a, b) in acc_n
                .as_flattened()
                .iter()
                .zip(acc_any.as_flattened())
                .chain(y_n.as_flattened().iter().zip(y_any.as_flattened()))
            {
                assert!((a - b).abs() <= 1e-14 * (1.0 + a.abs()), "{a} vs {b}");
            }
            // And both against the product written out: t = [0 F_b] + F_a y_in.
            let (jf, yf, bf) = (jac.as_flattened(), y_in.as_flattened(), base.as_flattened());
            let np = NC * LANES;
            for r in 0..d {
                for c in 0..np {
                    let mut t = if c < d { 0.0 } else { jf[r * np + c] };
                    for m in 0..d {
                        t += jf[r * np + m] * yf[m * np + c];
                    }
                    let want = bf[r * np + c] + 0.5 * t;
                    let got = y_n.as_flattened()[r * np + c];
                    assert!(
                        (got - want).abs() <= 1e-13,
                        "row {r} col {c}: {got} vs {want}"
                    );
                }
            }
        }
    }

    #[test]
    fn chunk_buffers_start_on_a_cache_line() {
        for len in [1, 3, 7, 21, 60] {
            let mut b = ChunkBuf::new(len);
            assert_eq!(b.len(), len);
            assert_eq!(b.as_ptr() as usize % 64, 0);
            assert!(b.as_flattened().iter().all(|&v| v == 0.0));
            b[len - 1][LANES - 1] = 1.0;
            assert_eq!(b.as_flattened()[len * LANES - 1], 1.0);
        }
    }
}
