//! The kernels the filters share, written once: the sigma-point draw and weighted mean (both
//! UKFs), the triangular solves of the gain (the covariance form and the square-root form),
//! the NIS and log-likelihood from a factor of the innovation covariance (every filter's
//! update), and the products with a sparse measurement Jacobian (EKF, linear-measurement
//! UKFs, square-root array form).
//!
//! They are hand loops over the filters' preallocated buffers and allocate nothing. Most of
//! them touch `n x k` values with `k <= 4` (solves, products with one row of H) or are one
//! pass over the points, where a library call has nothing to win; the two dense kernels
//! beneath them (Cholesky, the covariance's row dot products) are discussed in
//! [`crate::linalg`].

use crate::linalg::forward_substitute;
use crate::view::{ColMajor, ColMajorMut};

/// Writes the `2 d + 1` sigma points `x`, `x + gamma L_j`, `x - gamma L_j` (`j < d`) as the
/// columns of `points` (`n x (2 d + 1)`; docs/model.md eq. (24)). `factor` is a
/// lower-triangular `n x n` factor of the covariance (its zeros above the diagonal are not
/// read). Directions `j >= n` (the augmented noise directions of the standard UKF) get the
/// centre `x` itself: their spread is added to the noise inputs, not to the state.
///
/// ```
/// use navkf_filters::kernels::draw_sigma_points;
/// use navkf_filters::view::{ColMajor, ColMajorMut};
/// // P = diag(4, 9): L = diag(2, 3); gamma = 1.
/// let l = [2.0, 0.0, 0.0, 3.0];
/// let mut pts = [0.0; 10];
/// draw_sigma_points(&[1.0, 1.0], ColMajor::new(&l, 2, 2), 1.0, &mut ColMajorMut::new(&mut pts, 2, 5));
/// assert_eq!(pts, [1.0, 1.0, 3.0, 1.0, -1.0, 1.0, 1.0, 4.0, 1.0, -2.0]);
/// ```
pub fn draw_sigma_points(x: &[f64], factor: ColMajor, gamma: f64, points: &mut ColMajorMut) {
    let n = x.len();
    debug_assert_eq!(points.rows(), n);
    let directions = (points.cols() - 1) / 2;
    points.col_mut(0).copy_from_slice(x);
    for j in 0..directions {
        let (plus, minus) = (1 + 2 * j, 2 + 2 * j);
        points.col_mut(plus).copy_from_slice(x);
        points.col_mut(minus).copy_from_slice(x);
        if j < n {
            let col = &factor.col(j)[j..];
            for (p, &c) in points.col_mut(plus)[j..].iter_mut().zip(col) {
                *p += gamma * c;
            }
            for (p, &c) in points.col_mut(minus)[j..].iter_mut().zip(col) {
                *p -= gamma * c;
            }
        }
    }
}

/// `out = sum_i w_i X_i` over the columns of `points`, with the weights in column order
/// (fewer weights than columns: the rest are not read): docs/model.md eqs. (27), (29).
///
/// ```
/// use navkf_filters::kernels::weighted_mean;
/// use navkf_filters::view::ColMajor;
/// let pts = [1.0, 2.0, 3.0, 4.0];
/// let mut m = [0.0; 2];
/// weighted_mean(ColMajor::new(&pts, 2, 2), [0.25, 0.75], &mut m);
/// assert_eq!(m, [2.5, 3.5]);
/// ```
pub fn weighted_mean(points: ColMajor, weights: impl IntoIterator<Item = f64>, out: &mut [f64]) {
    out.fill(0.0);
    for (i, w) in weights.into_iter().enumerate() {
        for (o, p) in out.iter_mut().zip(points.col(i)) {
            *o += w * p;
        }
    }
}

/// `U := U L^-T` in place, for a lower-triangular `k x k` factor `L` and an `n x k` matrix
/// `U`: row `i` of the result solves `L u_i = U[i, :]`. All rows at once, column by column:
/// `U[:, a] = (U[:, a] - sum_{b<a} L[a, b] U[:, b]) / L[a, a]`. With `U = Pxz` and
/// `S = L L^T` this is the gain's half `Pxz L^-T`, whose outer product is `K S K^T`
/// (docs/model.md eqs. (17), (31)).
#[inline]
pub fn solve_lower_transposed_right(l: ColMajor, u: &mut ColMajorMut) {
    for a in 0..l.cols() {
        let (done, ua) = u.split_at_col(a);
        for b in 0..a {
            let lab = l.at(a, b);
            for (x, y) in ua.iter_mut().zip(done.col(b)) {
                *x -= lab * y;
            }
        }
        let inv = 1.0 / l.at(a, a);
        for x in ua.iter_mut() {
            *x *= inv;
        }
    }
}

/// `G := G L^-1` in place (row `i` of the result solves `L^T g_i = G[i, :]`), columns last
/// first: `G[:, a] = (G[:, a] - sum_{b>a} L[b, a] G[:, b]) / L[a, a]`. After
/// [`solve_lower_transposed_right`] this completes the gain `K = Pxz S^-1`
/// (docs/model.md eq. (17)).
#[inline]
pub fn solve_lower_right(l: ColMajor, g: &mut ColMajorMut) {
    let k = l.cols();
    for a in (0..k).rev() {
        let (ga, done) = g.split_after_col(a);
        for b in a + 1..k {
            let lba = l.at(b, a);
            for (x, y) in ga.iter_mut().zip(done.col(b - a - 1)) {
                *x -= lba * y;
            }
        }
        let inv = 1.0 / l.at(a, a);
        for x in ga.iter_mut() {
            *x *= inv;
        }
    }
}

/// What an innovation says about the prediction, from a Cholesky factor `L` of its
/// covariance (`S = L L^T`, `k x k`): `NIS = |L^-1 nu|^2` and
/// `log p = -(NIS + log det S + k log 2 pi) / 2` with `log det S = 2 sum log L_aa`
/// (docs/model.md eq. (18)).
/// `w` (at least `k` long) receives `L^-1 nu`, which the square-root update reuses.
///
/// ```
/// use navkf_filters::kernels::innovation_statistics;
/// use navkf_filters::view::ColMajor;
/// // S = diag(4, 1), nu = (2, 1): NIS = 1 + 1 = 2, log det S = ln 4.
/// let l = [2.0, 0.0, 0.0, 1.0];
/// let mut w = [0.0; 2];
/// let (nis, ll) = innovation_statistics(ColMajor::new(&l, 2, 2), &[2.0, 1.0], &mut w);
/// assert_eq!(nis, 2.0);
/// let want = -0.5 * (2.0 + 4f64.ln() + 2.0 * (2.0 * std::f64::consts::PI).ln());
/// assert!((ll - want).abs() < 1e-15);
/// ```
#[inline]
pub fn innovation_statistics(l: ColMajor, innovation: &[f64], w: &mut [f64]) -> (f64, f64) {
    let k = l.cols();
    let w = &mut w[..k];
    w.copy_from_slice(&innovation[..k]);
    forward_substitute(l.as_slice(), k, w);
    let nis: f64 = w.iter().map(|v| v * v).sum();
    let log_det: f64 = (0..k).map(|i| 2.0 * l.at(i, i).ln()).sum();
    let log_likelihood = -0.5 * (nis + log_det + k as f64 * (2.0 * std::f64::consts::PI).ln());
    (nis, log_likelihood)
}

/// `out = A h^T = sum_m h_m A[:, m]` for one row `h` of a measurement Jacobian, skipping
/// its zeros (a measurement reads a few of the states, so most columns are skipped): with
/// `A = P`, a column of `Pxz = P H^T` (docs/model.md eqs. (21), (33)).
#[inline]
pub fn sparse_row_product(a: ColMajor, h: &[f64], out: &mut [f64]) {
    out.fill(0.0);
    for (m, &hm) in h.iter().enumerate() {
        if hm != 0.0 {
            for (o, am) in out.iter_mut().zip(a.col(m)) {
                *o += hm * am;
            }
        }
    }
}

/// `h . v` for one row `h` of a measurement Jacobian. Dense, as the code it replaced was
/// (results stay bit-identical): a dot over 20-40 values vectorises, and a variant testing
/// each `h_m` for zero was not faster in `step_timing` (it skips one multiply per zero, where
/// [`sparse_row_product`] skips a whole column).
///
/// ```
/// use navkf_filters::kernels::h_dot;
/// assert_eq!(h_dot(&[0.0, 2.0, 0.0], &[5.0, 3.0, 1.0]), 6.0);
/// ```
pub fn h_dot(h: &[f64], v: &[f64]) -> f64 {
    h.iter().zip(v).map(|(hm, vm)| hm * vm).sum()
}
