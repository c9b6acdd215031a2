//! What every filter's measurement update shares: the measurement a caller passes in, the
//! report it gets back, and the gain computation from the predicted measurement moments.
//!
//! Given the predicted measurement `z_hat`, its covariance `Pzz` (without `R`) and the
//! state-measurement cross-covariance `Pxz`, over the channels that are present
//! (docs/model.md eqs. (17), (18)):
//! `S = Pzz + R`, `nu = z - z_hat`, `NIS = nu^T S^-1 nu`,
//! `log p(z) = -(NIS + log det S + k log 2 pi) / 2`, `K = Pxz S^-1`, `x += K nu`.

use crate::error::FilterError;
use crate::estimate::Estimate;
use crate::kernels::{
    h_dot, innovation_statistics, solve_lower_right, solve_lower_transposed_right,
    sparse_row_product,
};
use crate::linalg::cholesky_in_place;
use crate::view::{ColMajor, ColMajorMut, RowMajor};
use navkf_dynamics::SystemModel;

/// One measurement: values, one-sigma of each channel (diagonal `R`), and which channels are
/// present (an empty cell in `measurements.csv` is an absent channel). All three are
/// `meas_dim` long.
#[derive(Debug, Clone, Copy)]
pub struct Observation<'a> {
    /// Measured values.
    pub z: &'a [f64],
    /// One-sigma of each channel.
    pub sigma: &'a [f64],
    /// Which channels are present.
    pub available: &'a [bool],
}

/// What an update reports: enough for NIS tallies, the likelihood ranking of the diagnosis
/// and innovation plots. Reused between steps (no allocation after construction).
#[derive(Debug, Clone, PartialEq)]
pub struct UpdateReport {
    /// Filter step (number of predictions so far).
    pub step: usize,
    /// Indices of the measurement channels used, in order.
    pub channels: Vec<usize>,
    /// Innovation `z - z_hat` on those channels.
    pub innovation: Vec<f64>,
    /// Innovation covariance `S`, column-major `k x k`.
    pub innovation_cov: Vec<f64>,
    /// Normalised innovation squared.
    pub nis: f64,
    /// Log-likelihood of the measurement under the prediction.
    pub log_likelihood: f64,
}

impl UpdateReport {
    pub(crate) fn with_capacity(nz: usize) -> Self {
        UpdateReport {
            step: 0,
            channels: Vec::with_capacity(nz),
            innovation: Vec::with_capacity(nz),
            innovation_cov: Vec::with_capacity(nz * nz),
            nis: 0.0,
            log_likelihood: 0.0,
        }
    }
    /// Number of channels used.
    pub fn dim(&self) -> usize {
        self.channels.len()
    }
}

/// Scratch and results of the gain computation, sized once for state `n`, measurement `nz`.
#[derive(Debug, Clone)]
pub(crate) struct GainWorkspace {
    pub n: usize,
    pub nz: usize,
    /// Cholesky factor of S (k x k).
    pub s_chol: Vec<f64>,
    /// `U = Pxz L^-T` (n x k, column-major): `K = U L^-1`, `K S K^T = U U^T`.
    pub u: Vec<f64>,
    /// The gain K (n x k, column-major).
    pub gain: Vec<f64>,
    pub tmp: Vec<f64>,
    pub report: UpdateReport,
}

impl GainWorkspace {
    pub fn new(n: usize, nz: usize) -> Self {
        GainWorkspace {
            n,
            nz,
            s_chol: vec![0.0; nz * nz],
            u: vec![0.0; n * nz],
            gain: vec![0.0; n * nz],
            tmp: vec![0.0; n.max(nz)],
            report: UpdateReport::with_capacity(nz),
        }
    }

    /// Checks an observation's sizes and values; selects the present channels.
    pub fn select(&mut self, obs: &Observation, step: usize) -> Result<usize, FilterError> {
        if obs.z.len() != self.nz || obs.sigma.len() != self.nz || obs.available.len() != self.nz {
            return Err(FilterError::Invalid(format!(
                "observation has {} values, {} sigmas and {} flags: expected {} of each",
                obs.z.len(),
                obs.sigma.len(),
                obs.available.len(),
                self.nz
            )));
        }
        let r = &mut self.report;
        r.step = step;
        r.channels.clear();
        // With no channel present the report must not keep the previous update's values.
        r.innovation.clear();
        r.innovation_cov.clear();
        r.nis = 0.0;
        r.log_likelihood = 0.0;
        for i in 0..self.nz {
            if obs.available[i] {
                if !(obs.z[i].is_finite() && obs.sigma[i].is_finite() && obs.sigma[i] > 0.0) {
                    return Err(FilterError::Invalid(format!(
                        "step {step}: measurement channel {i} is {} with sigma {}: expected finite values and sigma > 0",
                        obs.z[i], obs.sigma[i]
                    )));
                }
                r.channels.push(i);
            }
        }
        Ok(r.channels.len())
    }

    /// From `z_hat` (full length), `pzz` (k x k over the selected channels, without R) and
    /// `pxz` (n x k): fills the report, the gain and `U`, and applies `x += K nu`.
    pub fn compute(
        &mut self,
        obs: &Observation,
        z_hat: &[f64],
        pzz: &[f64],
        pxz: &[f64],
        x: &mut [f64],
    ) -> Result<(), FilterError> {
        let n = self.n;
        let k = self.report.channels.len();
        let step = self.report.step;
        let r = &mut self.report;
        r.innovation.clear();
        r.innovation_cov.clear();
        for (a, &ca) in r.channels.iter().enumerate() {
            r.innovation.push(obs.z[ca] - z_hat[ca]);
            for b in 0..k {
                let mut v = pzz[b + a * k];
                if a == b {
                    v += obs.sigma[ca] * obs.sigma[ca];
                }
                r.innovation_cov.push(v);
            }
        }
        if !r.innovation.iter().all(|v| v.is_finite()) {
            return Err(FilterError::NonFinite {
                step,
                what: "innovation",
            });
        }
        let l = &mut self.s_chol[..k * k];
        l.copy_from_slice(&r.innovation_cov);
        cholesky_in_place(l, k).map_err(|(pivot, value)| FilterError::NotPositiveDefinite {
            step,
            matrix: "S",
            pivot,
            dim: k,
            value,
        })?;
        (r.nis, r.log_likelihood) =
            innovation_statistics(ColMajor::new(l, k, k), &r.innovation, &mut self.tmp);
        // U = Pxz L^-T, then K = U L^-1 = Pxz S^-1.
        let u = &mut self.u[..n * k];
        u.copy_from_slice(&pxz[..n * k]);
        solve_lower_transposed_right(ColMajor::new(l, k, k), &mut ColMajorMut::new(u, n, k));
        let g = &mut self.gain[..n * k];
        g.copy_from_slice(u);
        solve_lower_right(ColMajor::new(l, k, k), &mut ColMajorMut::new(g, n, k));
        for a in 0..k {
            let nu = r.innovation[a];
            for (xi, gi) in x.iter_mut().zip(&g[a * n..(a + 1) * n]) {
                *xi += gi * nu;
            }
        }
        Ok(())
    }

    /// `P -= K S K^T = U U^T` (the UKF's covariance update, docs/model.md eq. (31)), on a `P`
    /// that is exactly symmetric (the UKFs' is between steps: `reset` symmetrises it, and
    /// their prediction and this update give both triangles the same values;
    /// `tests/exact_symmetry.rs`). Whole columns at a time: entry `(r, c)` loses
    /// `U[r, a] U[c, a]` for each channel `a` in order, the same products in the same order as
    /// entry `(c, r)`, so `P` stays exactly symmetric without a mirroring pass.
    pub fn subtract_gain_cov(&self, p: &mut [f64]) {
        let n = self.n;
        let k = self.report.channels.len();
        // (A NaN left by a failed step is not an asymmetry.)
        debug_assert!((0..n).all(|j| (0..j).all(|i| {
            let (a, b) = (p[i + j * n], p[j + i * n]);
            a == b || (a.is_nan() && b.is_nan())
        })));
        for col in self.u[..k * n].chunks_exact(n) {
            for (pj, &f) in p[..n * n].chunks_exact_mut(n).zip(col) {
                for (pi, ci) in pj.iter_mut().zip(col) {
                    *pi -= ci * f;
                }
            }
        }
    }
}

/// The predicted measurement and its moments, what a filter hands to
/// [`GainWorkspace::compute`]: `z_hat` (all `nz` channels), `Pzz` (k x k) and `Pxz` (n x k,
/// column-major) over the selected channels, and the measurement Jacobian `h` (row-major
/// `nz x n`) when the measurement is linearised. Sized once.
#[derive(Debug, Clone)]
pub(crate) struct MeasurementMoments {
    pub z_hat: Vec<f64>,
    pub h: Vec<f64>,
    pub pzz: Vec<f64>,
    pub pxz: Vec<f64>,
}

impl MeasurementMoments {
    pub fn new(n: usize, nz: usize) -> Self {
        MeasurementMoments {
            z_hat: vec![0.0; nz],
            h: vec![0.0; nz * n],
            pzz: vec![0.0; nz * nz],
            pxz: vec![0.0; n * nz],
        }
    }

    /// The update's first half for a measurement linearised at the estimate (exact when it
    /// is linear): `z_hat = h(x)`, `H`, the moments by [`linear_moments`], then the gain,
    /// which corrects `est.x`. The covariance is the caller's to correct.
    pub fn linear_gain<M: SystemModel + ?Sized>(
        &mut self,
        model: &M,
        est: &mut Estimate,
        gain: &mut GainWorkspace,
        obs: &Observation,
    ) -> Result<(), FilterError> {
        model.measure(&est.x, &mut self.z_hat);
        model.measurement_jacobian(&est.x, &mut self.h);
        let nz = self.z_hat.len();
        linear_moments(
            ColMajor::new(&est.p, est.n, est.n),
            RowMajor::new(&self.h, nz, est.n),
            &gain.report.channels,
            &mut self.pxz,
            &mut self.pzz,
        );
        self.gain(gain, obs, &mut est.x)
    }

    /// [`GainWorkspace::compute`] with these moments: the gain, the report, `x` corrected.
    pub fn gain(
        &self,
        gain: &mut GainWorkspace,
        obs: &Observation,
        x: &mut [f64],
    ) -> Result<(), FilterError> {
        let (n, k) = (gain.n, gain.report.channels.len());
        gain.compute(obs, &self.z_hat, &self.pzz[..k * k], &self.pxz[..n * k], x)
    }
}

/// The moments of a linear measurement `z = H x` (docs/model.md eqs. (21), (33)):
/// `Pxz = P H^T` (n x k, column-major) and `Pzz = H P H^T` (k x k), for the rows `channels` of
/// `H`, skipping the zeros of `H` (a measurement reads few states).
fn linear_moments(p: ColMajor, h: RowMajor, channels: &[usize], pxz: &mut [f64], pzz: &mut [f64]) {
    let (n, k) = (p.rows(), channels.len());
    for (a, &ch) in channels.iter().enumerate() {
        sparse_row_product(p, h.row(ch), &mut pxz[a * n..(a + 1) * n]);
    }
    for (a, &ca) in channels.iter().enumerate() {
        for b in 0..k {
            pzz[a + b * k] = h_dot(h.row(ca), &pxz[b * n..(b + 1) * n]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn subtract_gain_cov_keeps_p_exactly_symmetric_with_the_lower_triangles_bits() {
        let (n, k) = (7, 3);
        let mut gain = GainWorkspace::new(n, k);
        gain.report.channels.extend(0..k);
        for (i, u) in gain.u.iter_mut().enumerate() {
            *u = ((i * 37 % 23) as f64 - 11.0) / 7.0;
        }
        let mut p = vec![0.0; n * n];
        for j in 0..n {
            for i in j..n {
                let v = ((i * 13 + j * 5) % 17) as f64 / 3.0 + if i == j { 40.0 } else { 0.0 };
                p[i + j * n] = v;
                p[j + i * n] = v;
            }
        }
        // The lower triangle, one product at a time, then mirrored.
        let mut want = p.clone();
        for a in 0..k {
            let u = &gain.u[a * n..(a + 1) * n];
            for j in 0..n {
                for i in j..n {
                    want[i + j * n] -= u[i] * u[j];
                }
            }
        }
        gain.subtract_gain_cov(&mut p);
        for j in 0..n {
            for i in j..n {
                let w = want[i + j * n].to_bits();
                assert_eq!(p[i + j * n].to_bits(), w, "P[{i},{j}]");
                assert_eq!(p[j + i * n].to_bits(), w, "P[{j},{i}]");
            }
        }
    }
}
