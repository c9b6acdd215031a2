//! Square-root UKF (van der Merwe & Wan, 2001), the fourth filter: the simplified UKF's
//! additive-noise transform, but carrying a Cholesky factor `S` of the covariance
//! (`P = S S^T`) instead of `P`. The covariance it implies is positive semi-definite by
//! construction, and the factor is never recomputed from a `P` that rounding may have made
//! indefinite.
//!
//! - Prediction (docs/model.md eq. (34)): sigma points `x`, `x +- gamma S_i` straight from
//!   the factor (no Cholesky); through the dynamics; `S^-` is the triangular factor
//!   (Householder QR) of `[sqrt(Wi) (X_i - x^-), sqrt(Q_k)]`, then a rank-one update (or
//!   downdate, when `Wc0 < 0`) with the centre point.
//! - Linear measurement (the base model; docs/model.md eq. (35)): the array form of the
//!   Kalman update. Triangularising `[[sqrt(R), H S], [0, S]]` gives `[[S_zz, 0], [K', S^+]]`,
//!   with `S_zz` the factor of the innovation covariance and `K = K' S_zz^-1`.
//! - Non-linear measurement (`odometer-scale`, `gps-latency`; docs/model.md eq. (36)): sigma
//!   points through `h`; `S_zz` from the QR of `[sqrt(Wi) (Z_i - z^-), sqrt(R)]` and the
//!   centre's rank-one update; `U = P_xz S_zz^-T`, `x += U S_zz^-1 nu`, and `S^+` by `k`
//!   rank-one downdates with the columns of `U`. A downdate that fails is a typed error, not a
//!   NaN.
//!
//! `covariance()` returns `S S^T`, formed after every step.

use crate::error::FilterError;
use crate::estimate::Estimate;
use crate::filter::Filter;
use crate::kernels::{
    draw_sigma_points, h_dot, innovation_statistics, solve_lower_transposed_right, weighted_mean,
};
use crate::linalg::cholesky_in_place;
use crate::sigma_points::{SigmaPoints, SigmaScaling};
use crate::triangular::{householder_r, outer_of_lower, rank_one_update};
use crate::update::{GainWorkspace, Observation, UpdateReport};
use crate::view::{ColMajor, ColMajorMut};
use navkf_dynamics::{InputWindow, PropagationScratch, SystemModel};
use std::sync::Arc;

/// See the module documentation.
///
/// ```
/// use navkf_dynamics::{NoiseConfig, PlatformModel};
/// use navkf_filters::{Filter, SigmaScaling, SquareRootUkf};
/// use std::sync::Arc;
/// let base = Arc::new(PlatformModel::base(&NoiseConfig::default()));
/// let f = SquareRootUkf::new(base, SigmaScaling::default()).unwrap();
/// assert_eq!((f.name(), f.dim()), ("square_root_ukf", 20));
/// ```
pub struct SquareRootUkf<M: SystemModel + ?Sized> {
    model: Arc<M>,
    sp: SigmaPoints,
    est: Estimate,
    linear_update: bool,
    /// Lower Cholesky factor of P, column-major n x n.
    s: Vec<f64>,
    points: Vec<f64>,
    /// Tall matrix to triangularise (column-major, `rows x cols`), sized for the largest use.
    tall: Vec<f64>,
    /// Centre deviation (rank-one update vector).
    d0: Vec<f64>,
    z_pts: Vec<f64>,
    z_hat: Vec<f64>,
    h: Vec<f64>,
    /// Innovation-covariance factor (k x k) and `U = Pxz S_zz^-T` (n x k).
    szz: Vec<f64>,
    u: Vec<f64>,
    w: Vec<f64>,
    scratch: PropagationScratch,
    gain: GainWorkspace,
}

impl<M: SystemModel + ?Sized> SquareRootUkf<M> {
    /// A square-root UKF for `model`, sized once.
    pub fn new(model: Arc<M>, scaling: SigmaScaling) -> Result<Self, FilterError> {
        let n = model.dim();
        let nz = model.meas_dim();
        let q = model.noise_channels().len();
        let sp = SigmaPoints::new(n, scaling)?;
        let npts = sp.count();
        let scratch = model.propagation_scratch(npts);
        // Largest tall matrix: the prediction's (2n + q) x n, the linear update's square
        // (nz + n), or the sigma update's (2n + nz) x nz.
        let tall = ((2 * n + q) * n)
            .max((nz + n) * (nz + n))
            .max((2 * n + nz) * nz);
        Ok(SquareRootUkf {
            sp,
            est: Estimate::new(n),
            linear_update: model.measurement_is_linear(),
            s: vec![0.0; n * n],
            points: vec![0.0; n * npts],
            tall: vec![0.0; tall],
            d0: vec![0.0; n.max(nz)],
            z_pts: vec![0.0; nz * npts],
            z_hat: vec![0.0; nz],
            h: vec![0.0; nz * n],
            szz: vec![0.0; nz * nz],
            u: vec![0.0; n * nz],
            w: vec![0.0; nz],
            scratch,
            gain: GainWorkspace::new(n, nz),
            model,
        })
    }

    /// The Cholesky factor `S` of the covariance (lower triangular, column-major).
    pub fn factor(&self) -> &[f64] {
        &self.s
    }

    /// Whether updates take the array (linear Kalman) form.
    pub fn uses_linear_update(&self) -> bool {
        self.linear_update
    }

    fn not_pd(
        &self,
        matrix: &'static str,
        dim: usize,
        (pivot, value): (usize, f64),
    ) -> FilterError {
        FilterError::NotPositiveDefinite {
            step: self.est.step,
            matrix,
            pivot,
            dim,
            value,
        }
    }

    /// Sigma points `x`, `x +- gamma S_j` into `points`.
    fn draw_points(&mut self) {
        let n = self.est.n;
        draw_sigma_points(
            &self.est.x,
            ColMajor::new(&self.s, n, n),
            self.sp.gamma,
            &mut ColMajorMut::new(&mut self.points, n, 2 * n + 1),
        );
    }

    /// Lower factor from the top of `tall` after [`householder_r`] (`rows x cols`) into `out`
    /// (`cols x cols`).
    fn lower_from_r(tall: &[f64], rows: usize, cols: usize, out: &mut [f64]) {
        for j in 0..cols {
            for i in 0..cols {
                out[i + j * cols] = if i >= j { tall[j + i * rows] } else { 0.0 };
            }
        }
    }

    /// Fills the report from the innovation factor `szz` (k x k) and the innovation; returns
    /// `w = S_zz^-1 nu` in `self.w`.
    fn report_from_factor(&mut self, k: usize) -> Result<(), FilterError> {
        let r = &mut self.gain.report;
        if !r.innovation.iter().all(|v| v.is_finite()) {
            return Err(FilterError::NonFinite {
                step: self.est.step,
                what: "innovation",
            });
        }
        let l = &self.szz[..k * k];
        r.innovation_cov.clear();
        for b in 0..k {
            for a in 0..k {
                // (L L^T)[a, b], column-major.
                let v: f64 = (0..=a.min(b)).map(|c| l[a + c * k] * l[b + c * k]).sum();
                r.innovation_cov.push(v);
            }
        }
        (r.nis, r.log_likelihood) =
            innovation_statistics(ColMajor::new(l, k, k), &r.innovation, &mut self.w);
        Ok(())
    }

    /// With `z_hat`, the innovation factor `szz` and `u` (`K S_zz`, n x k) in place: fills the
    /// report and applies `x += K nu = U S_zz^-1 nu`.
    fn apply_innovation(&mut self, obs: &Observation, k: usize) -> Result<(), FilterError> {
        let n = self.est.n;
        let r = &mut self.gain.report;
        r.innovation.clear();
        for &ca in &r.channels {
            r.innovation.push(obs.z[ca] - self.z_hat[ca]);
        }
        self.report_from_factor(k)?;
        for (b, &wb) in self.w[..k].iter().enumerate() {
            for (xi, ui) in self.est.x.iter_mut().zip(&self.u[b * n..(b + 1) * n]) {
                *xi += ui * wb;
            }
        }
        Ok(())
    }

    /// The array form of the Kalman update, docs/model.md eq. (35).
    fn update_linear(&mut self, obs: &Observation) -> Result<(), FilterError> {
        let n = self.est.n;
        let k = self.gain.report.channels.len();
        let big = k + n;
        self.model.measure(&self.est.x, &mut self.z_hat);
        self.model.measurement_jacobian(&self.est.x, &mut self.h);
        // The transposed pre-array [[sqrt R, 0], [(H S)^T, S^T]], column-major big x big.
        let t = &mut self.tall[..big * big];
        t.fill(0.0);
        for (a, &ca) in self.gain.report.channels.iter().enumerate() {
            t[a + a * big] = obs.sigma[ca];
            let ha = &self.h[ca * n..(ca + 1) * n];
            // (H S)[a, i] = sum_m H[a, m] S[m, i], S lower: m >= i.
            for i in 0..n {
                let col = &self.s[i * n..(i + 1) * n];
                t[(k + i) + a * big] = h_dot(&ha[i..], &col[i..]);
            }
        }
        for i in 0..n {
            for j in 0..=i {
                // S^T[i, j] = S[j, i] is zero for j < i; S^T is upper: row i, columns >= i.
                t[(k + j) + (k + i) * big] = self.s[i + j * n];
            }
        }
        householder_r(t, big, big);
        // Post-array R^T = [[S_zz, 0], [K', S+]]: S_zz[a, b] = R[b, a], K'[i, b] = R[b, k + i],
        // S+[i, j] = R[k + j, k + i].
        for b in 0..k {
            for a in 0..k {
                self.szz[a + b * k] = if a >= b { t[b + a * big] } else { 0.0 };
            }
            for i in 0..n {
                self.u[i + b * n] = t[b + (k + i) * big];
            }
        }
        for j in 0..n {
            for i in 0..n {
                self.s[i + j * n] = if i >= j {
                    t[(k + j) + (k + i) * big]
                } else {
                    0.0
                };
            }
        }
        self.apply_innovation(obs, k)
    }

    /// The sigma-point update, docs/model.md eq. (36).
    fn update_sigma(&mut self, obs: &Observation) -> Result<(), FilterError> {
        let n = self.est.n;
        let nz = self.model.meas_dim();
        let k = self.gain.report.channels.len();
        let sp = self.sp;
        let count = sp.count();
        self.draw_points();
        self.model
            .measure_points(&self.points[..count * n], &mut self.z_pts[..count * nz]);
        weighted_mean(
            ColMajor::new(&self.z_pts, nz, count),
            (0..count).map(|i| sp.wm(i)),
            &mut self.z_hat,
        );
        let chans = &self.gain.report.channels;
        // [sqrt(Wi) (Z_i - z^-) ; sqrt(R)] over the selected channels, (2n + k) x k.
        let rows = 2 * n + k;
        let t = &mut self.tall[..rows * k];
        t.fill(0.0);
        let sw = sp.wi.sqrt();
        for (a, &ca) in chans.iter().enumerate() {
            let col = &mut t[a * rows..(a + 1) * rows];
            for i in 1..count {
                col[i - 1] = sw * (self.z_pts[i * nz + ca] - self.z_hat[ca]);
            }
            col[2 * n + a] = obs.sigma[ca];
        }
        householder_r(t, rows, k);
        Self::lower_from_r(t, rows, k, &mut self.szz[..k * k]);
        for (a, &ca) in chans.iter().enumerate() {
            self.d0[a] = sp.wc0.abs().sqrt() * (self.z_pts[ca] - self.z_hat[ca]);
        }
        let sign = if sp.wc0 >= 0.0 { 1.0 } else { -1.0 };
        rank_one_update(&mut self.szz[..k * k], k, &mut self.d0[..k], sign)
            .map_err(|e| self.not_pd("S (innovation factor)", k, e))?;
        // Pxz (n x k) = sum_i wc_i (X_i - x)(Z_i - z^-)^T; the points are centred on x.
        let chans = &self.gain.report.channels;
        let x = &self.est.x;
        for (a, &ca) in chans.iter().enumerate() {
            let col = &mut self.u[a * n..(a + 1) * n];
            col.fill(0.0);
            for i in 0..count {
                let f = sp.wc(i) * (self.z_pts[i * nz + ca] - self.z_hat[ca]);
                for ((c, p), xs) in col.iter_mut().zip(&self.points[i * n..(i + 1) * n]).zip(x) {
                    *c += f * (p - xs);
                }
            }
        }
        // U = Pxz S_zz^-T.
        solve_lower_transposed_right(
            ColMajor::new(&self.szz, k, k),
            &mut ColMajorMut::new(&mut self.u, n, k),
        );
        self.apply_innovation(obs, k)?;
        // S+ S+^T = S S^T - U U^T: one downdate per column of U.
        for b in 0..k {
            self.d0[..n].copy_from_slice(&self.u[b * n..(b + 1) * n]);
            rank_one_update(&mut self.s, n, &mut self.d0[..n], -1.0)
                .map_err(|e| self.not_pd("S (update downdate)", n, e))?;
        }
        Ok(())
    }
}

impl<M: SystemModel + ?Sized> Filter for SquareRootUkf<M> {
    fn name(&self) -> &str {
        "square_root_ukf"
    }
    crate::filter::estimate_accessors!();

    fn reset(&mut self, x0: &[f64], p0: &[f64]) -> Result<(), FilterError> {
        self.est.reset(x0, p0)?;
        let n = self.est.n;
        self.s.copy_from_slice(&self.est.p);
        cholesky_in_place(&mut self.s, n).map_err(|e| self.not_pd("P", n, e))
    }

    /// docs/model.md eq. (34).
    fn predict(&mut self, window: &InputWindow) -> Result<(), FilterError> {
        crate::filter::check_window(window, self.est.step + 1)?;
        let n = self.est.n;
        let dt = window.duration();
        self.est.step += 1;
        let sp = self.sp;
        let count = sp.count();
        self.draw_points();
        self.model.propagate_points(
            &mut self.points[..count * n],
            None,
            window,
            &mut self.scratch,
        );
        weighted_mean(
            ColMajor::new(&self.points, n, count),
            (0..count).map(|i| sp.wm(i)),
            &mut self.est.x,
        );
        let x = &self.est.x;
        // [sqrt(Wi) (X_i - x^-) ; sqrt(Q_k)] as a (2n + q) x n column-major matrix.
        let channels = self.model.noise_channels();
        let rows = 2 * n + channels.len();
        let t = &mut self.tall[..rows * n];
        t.fill(0.0);
        let sw = sp.wi.sqrt();
        for s in 0..n {
            let col = &mut t[s * rows..(s + 1) * rows];
            for i in 1..count {
                col[i - 1] = sw * (self.points[i * n + s] - x[s]);
            }
        }
        for (c, ch) in channels.iter().enumerate() {
            t[(2 * n + c) + ch.state * rows] = (ch.psd * dt).sqrt();
        }
        householder_r(t, rows, n);
        Self::lower_from_r(t, rows, n, &mut self.s);
        for s in 0..n {
            self.d0[s] = sp.wc0.abs().sqrt() * (self.points[s] - x[s]);
        }
        let sign = if sp.wc0 >= 0.0 { 1.0 } else { -1.0 };
        rank_one_update(&mut self.s, n, &mut self.d0[..n], sign)
            .map_err(|e| self.not_pd("S (prediction)", n, e))?;
        outer_of_lower(&self.s, n, &mut self.est.p);
        self.est.finish_symmetric("state after prediction")
    }

    fn update(&mut self, obs: &Observation) -> Result<&UpdateReport, FilterError> {
        let k = self.gain.select(obs, self.est.step)?;
        if k == 0 {
            return Ok(&self.gain.report);
        }
        if self.linear_update {
            self.update_linear(obs)?;
        } else {
            self.update_sigma(obs)?;
        }
        outer_of_lower(&self.s, self.est.n, &mut self.est.p);
        self.est.finish_symmetric("state after update")?;
        Ok(&self.gain.report)
    }
}
