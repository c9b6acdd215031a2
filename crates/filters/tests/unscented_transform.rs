//! The unscented transform of the UKF core against what theory guarantees for a quadratic
//! map `g(s) = s^T A s + b^T s + d` of a Gaussian `s ~ N(mu, P)`.
//!
//! Theory (symmetric sigma points `mu`, `mu +- gamma L e_i`, `P = L L^T`, `gamma^2 = n +
//! lambda = alpha^2 (n + kappa)`, weights `Wm0 = lambda / gamma^2`, `Wc0 = Wm0 + 1 - alpha^2 +
//! beta`, `Wi = 1 / (2 gamma^2)`). In whitened coordinates `s = mu + L z`, `g = z^T B z + c^T z
//! + g(mu)` with `B = L^T A L`, `c = L^T (2 A mu + b)` (A symmetric). Then, because the weights
//! sum to 1, `2 Wi gamma^2 = 1` and the points are symmetric:
//!
//! - mean: `g(mu) + tr B`, exact for every quadratic and every scaling (alpha, beta, kappa);
//!   in particular `E[x^T x] = tr P` for a zero-mean `x`;
//! - cross-covariance `Cov(s, g) = L c`, exact for every scaling (odd moments vanish);
//! - variance: the transform gives `c^T c + gamma^2 sum_i B_ii^2 + (beta - alpha^2) (tr B)^2`,
//!   the truth is `c^T c + 2 sum_ij B_ij^2`. It is exact only when `B` is diagonal (in the
//!   Cholesky directions) and the scaling matches the fourth moment, e.g. for a scalar
//!   `x ~ N(m, s^2)` and `y = a x^2` (n = 1) exactly when `beta = 2 - alpha^2 kappa`: kappa = 2
//!   (n + kappa = 3, Julier's choice) needs beta = 0, kappa = 0 needs beta = 2. The paper's
//!   scaling (alpha = 1, kappa = 1, beta = 2) overestimates that variance:
//!   `a^2 (4 m^2 s^2 + 3 s^4)` against the true `a^2 (4 m^2 s^2 + 2 s^4)`.
//!
//! So "alpha = 1, beta = 2, n + kappa = 3" does not make the covariance exact: with n + kappa =
//! 3 the exact choice is beta = 0. These tests check exactly the statements above, through
//! the filter (a model whose propagation over one window is a quadratic map) and through the
//! weights directly. What they catch: wrong weights or spread, points along the wrong
//! factor (rows of L, or L^T), a mean or covariance accumulated with the wrong weights (Wm
//! for Wc), a covariance taken about the centre point instead of the mean.

use nalgebra::{DMatrix, DVector};
use navkf_dynamics::{Input, InputWindow, NoiseChannel, SystemModel};
use navkf_filters::linalg::cholesky_in_place;
use navkf_filters::*;
use std::sync::Arc;

/// State `s = [y, x_1..x_m]`, `y' = q(x) = x^T A x + b^T x + d0`, `x' = 0`. One RK4 sub-step
/// of a constant rate is exact, so one prediction over `T` maps `y -> y + T q(x)`: a
/// quadratic map of the state.
struct QuadraticModel {
    m: usize,
    a: DMatrix<f64>,
    b: DVector<f64>,
    d0: f64,
}

impl QuadraticModel {
    fn q(&self, x: &[f64]) -> f64 {
        let x = DVector::from_column_slice(x);
        (x.transpose() * &self.a * &x)[(0, 0)] + self.b.dot(&x) + self.d0
    }
}

impl SystemModel for QuadraticModel {
    fn dim(&self) -> usize {
        1 + self.m
    }
    fn dynamic_dim(&self) -> usize {
        1
    }
    fn noise_channels(&self) -> &[NoiseChannel] {
        &[]
    }
    fn rates(&self, x: &[f64], _u: &Input, dx: &mut [f64]) {
        dx[0] = self.q(&x[1..]);
    }
    fn rate_jacobian(&self, x: &[f64], _u: &Input, jac: &mut [f64]) {
        let xv = DVector::from_column_slice(&x[1..]);
        let grad = (&self.a + self.a.transpose()) * xv + &self.b;
        jac[0] = 0.0;
        jac[1..1 + self.m].copy_from_slice(grad.as_slice());
    }
    fn meas_dim(&self) -> usize {
        1
    }
    fn measure(&self, x: &[f64], z: &mut [f64]) {
        z[0] = x[0];
    }
    fn measurement_jacobian(&self, _x: &[f64], h: &mut [f64]) {
        h.fill(0.0);
        h[0] = 1.0;
    }
    fn measurement_is_linear(&self) -> bool {
        true
    }
    fn state_names(&self) -> Vec<String> {
        (0..=self.m).map(|i| format!("s{i}")).collect()
    }
}

const T: f64 = 0.8;

fn window() -> InputWindow {
    let mut w = InputWindow::with_capacity(2);
    w.push_linear(0.0, [0.0; 3]);
    w.push_linear(T, [0.0; 3]);
    w
}

/// Moments of `y_end = y + T q(x)`: (mean, variance, cross-covariance with s).
struct Moments {
    mean: f64,
    var: f64,
    cross: DVector<f64>,
}

/// The whitened form `(B, c, g(mu))` of `g(s) = y + T q(x)` with the Cholesky factor of `p`.
fn whitened(
    model: &QuadraticModel,
    mu: &DVector<f64>,
    p: &DMatrix<f64>,
) -> (DMatrix<f64>, DVector<f64>, f64, DMatrix<f64>) {
    let n = 1 + model.m;
    let mut a_full = DMatrix::zeros(n, n);
    let a_sym = (&model.a + model.a.transpose()) * 0.5;
    a_full
        .view_mut((1, 1), (model.m, model.m))
        .copy_from(&(a_sym * T));
    let mut b_full = DVector::zeros(n);
    b_full[0] = 1.0;
    b_full.rows_mut(1, model.m).copy_from(&(&model.b * T));
    let g_mu = mu[0] + T * model.q(&mu.as_slice()[1..]);
    let l = p.clone().cholesky().unwrap().l();
    let bw = l.transpose() * &a_full * &l;
    let cw = l.transpose() * (&a_full * mu * 2.0 + b_full);
    (bw, cw, g_mu, l)
}

/// The true moments of a Gaussian through the quadratic.
fn exact(model: &QuadraticModel, mu: &DVector<f64>, p: &DMatrix<f64>) -> Moments {
    let (bw, cw, g_mu, l) = whitened(model, mu, p);
    Moments {
        mean: g_mu + bw.trace(),
        var: cw.dot(&cw) + 2.0 * bw.norm_squared(),
        cross: l * cw,
    }
}

/// What the unscented transform must give (module documentation).
fn unscented(
    model: &QuadraticModel,
    mu: &DVector<f64>,
    p: &DMatrix<f64>,
    s: SigmaScaling,
) -> Moments {
    let n = (1 + model.m) as f64;
    let (bw, cw, g_mu, l) = whitened(model, mu, p);
    let gamma2 = s.alpha * s.alpha * (n + s.kappa);
    let diag2: f64 = bw.diagonal().iter().map(|v| v * v).sum();
    Moments {
        mean: g_mu + bw.trace(),
        var: cw.dot(&cw) + gamma2 * diag2 + (s.beta - s.alpha * s.alpha) * bw.trace().powi(2),
        cross: l * cw,
    }
}

/// The simplified UKF's predicted moments of `y_end` (no process noise in this model).
fn through_filter(
    model: Arc<QuadraticModel>,
    mu: &DVector<f64>,
    p: &DMatrix<f64>,
    s: SigmaScaling,
) -> Moments {
    let n = 1 + model.m;
    let mut f = Ukf::simplified(model, s).unwrap();
    f.reset(mu.as_slice(), p.as_slice()).unwrap();
    f.predict(&window()).unwrap();
    // x is unchanged by the map: its mean and covariance must come back exactly.
    for i in 1..n {
        assert!(
            (f.state()[i] - mu[i]).abs() <= 1e-12 * (1.0 + mu[i].abs()),
            "x mean moved"
        );
        for j in 1..n {
            let (got, want) = (f.covariance()[i + j * n], p[(i, j)]);
            assert!(
                (got - want).abs() <= 1e-11 * (p[(i, i)] * p[(j, j)]).sqrt(),
                "x covariance changed"
            );
        }
    }
    Moments {
        mean: f.state()[0],
        var: f.covariance()[0],
        cross: DVector::from_iterator(n, (0..n).map(|i| f.covariance()[i])),
    }
}

fn assert_close(what: &str, got: f64, want: f64, scale: f64, tol: f64) {
    assert!(
        (got - want).abs() <= tol * scale,
        "{what}: {got:.15e} vs {want:.15e} (difference {:e}, scale {scale:e})",
        (got - want).abs()
    );
}

/// A random-looking but fixed quadratic in `m` variables and a full Gaussian over `[y, x]`.
fn problem(m: usize) -> (QuadraticModel, DVector<f64>, DMatrix<f64>) {
    let a = DMatrix::from_fn(m, m, |i, j| 0.3 * ((1 + i + 3 * j) as f64).sin());
    let b = DVector::from_fn(m, |i, _| 0.5 * ((2 + i) as f64).cos());
    let n = 1 + m;
    let l = DMatrix::from_fn(n, n, |i, j| match i.cmp(&j) {
        std::cmp::Ordering::Equal => 0.6 + 0.1 * i as f64,
        std::cmp::Ordering::Greater => 0.2 * ((i * 7 + j) as f64).cos(),
        std::cmp::Ordering::Less => 0.0,
    });
    let mu = DVector::from_fn(n, |i, _| 0.4 * ((3 * i + 1) as f64).sin());
    (QuadraticModel { m, a, b, d0: 0.25 }, mu, &l * l.transpose())
}

fn scalings(n: usize) -> Vec<SigmaScaling> {
    let n = n as f64;
    vec![
        SigmaScaling::default(), // the paper's: alpha 1, beta 2, kappa 1
        SigmaScaling {
            alpha: 1.0,
            beta: 0.0,
            kappa: 3.0 - n,
        },
        SigmaScaling {
            alpha: 1.0,
            beta: 2.0,
            kappa: 3.0 - n,
        },
        SigmaScaling {
            alpha: 0.5,
            beta: 2.0,
            kappa: 0.0,
        },
        SigmaScaling {
            alpha: 0.1,
            beta: 2.0,
            kappa: 0.0,
        },
    ]
}

#[test]
fn weights_are_the_scaled_unscented_transforms() {
    for n in [1usize, 2, 5, 20, 29] {
        for s in scalings(n) {
            if s.kappa + n as f64 <= 0.0 {
                continue;
            }
            let sp = SigmaPoints::new(n, s).unwrap();
            let nf = n as f64;
            let lambda = s.alpha * s.alpha * (nf + s.kappa) - nf;
            assert_close(
                "gamma^2",
                sp.gamma * sp.gamma,
                nf + lambda,
                nf + lambda,
                1e-14,
            );
            assert_close(
                "sum Wm",
                sp.wm0 + 2.0 * nf * sp.wi,
                1.0,
                1.0 + sp.wm0.abs(),
                1e-14,
            );
            assert_close(
                "2 Wi gamma^2",
                2.0 * sp.wi * sp.gamma * sp.gamma,
                1.0,
                1.0,
                1e-14,
            );
            assert_close(
                "Wc0 - Wm0",
                sp.wc0 - sp.wm0,
                1.0 - s.alpha * s.alpha + s.beta,
                1.0 + s.beta,
                1e-14,
            );
            assert_eq!(sp.count(), 2 * n + 1);
            for i in 1..sp.count() {
                assert_eq!((sp.wm(i), sp.wc(i)), (sp.wi, sp.wi));
            }
            assert_eq!((sp.wm(0), sp.wc(0)), (sp.wm0, sp.wc0));
        }
    }
    // n + lambda <= 0 is refused, not turned into NaN weights.
    let bad = SigmaScaling {
        alpha: 1.0,
        beta: 2.0,
        kappa: -3.0,
    };
    assert!(matches!(
        SigmaPoints::new(3, bad),
        Err(FilterError::Invalid(_))
    ));
}

/// `y = a x^2`, `x ~ N(m, s^2)`, through the three points built from `SigmaPoints` and the
/// crate's Cholesky, with the weights' mean and covariance sums.
fn scalar_square(scaling: SigmaScaling, m: f64, s: f64, a: f64) -> (f64, f64) {
    let sp = SigmaPoints::new(1, scaling).unwrap();
    let mut l = [s * s];
    cholesky_in_place(&mut l, 1).unwrap();
    let pts = [m, m + sp.gamma * l[0], m - sp.gamma * l[0]];
    let ys: Vec<f64> = pts.iter().map(|x| a * x * x).collect();
    let mean: f64 = (0..3).map(|i| sp.wm(i) * ys[i]).sum();
    let var: f64 = (0..3).map(|i| sp.wc(i) * (ys[i] - mean).powi(2)).sum();
    (mean, var)
}

#[test]
fn scalar_square_is_exact_exactly_when_beta_is_two_minus_alpha_squared_kappa() {
    let (m, s, a): (f64, f64, f64) = (0.7, 0.3, 1.3);
    let true_mean = a * (m * m + s * s);
    let true_var = a * a * (4.0 * m * m * s * s + 2.0 * s.powi(4));
    for (alpha, kappa) in [(1.0, 2.0), (1.0, 0.0), (0.5, 0.0), (0.5, 2.0), (1.0, 1.0)] {
        let beta = 2.0 - alpha * alpha * kappa;
        let (mean, var) = scalar_square(SigmaScaling { alpha, beta, kappa }, m, s, a);
        assert_close("scalar mean", mean, true_mean, true_mean, 1e-13);
        assert_close(
            "scalar variance (exact scaling)",
            var,
            true_var,
            true_var,
            1e-12,
        );
    }
    // Any scaling: mean exact; variance off by (gamma^2 - 2 + beta - alpha^2) a^2 s^4.
    for sc in scalings(1) {
        let (mean, var) = scalar_square(sc, m, s, a);
        assert_close("scalar mean", mean, true_mean, true_mean, 1e-12);
        let g2 = sc.alpha * sc.alpha * (1.0 + sc.kappa);
        let want = true_var + (g2 - 2.0 + sc.beta - sc.alpha * sc.alpha) * a * a * s.powi(4);
        assert_close("scalar variance (formula)", var, want, true_var, 1e-10);
    }
    // The paper's scaling: a^2 (4 m^2 s^2 + 3 s^4).
    let (_, var) = scalar_square(SigmaScaling::default(), m, s, a);
    let want = a * a * (4.0 * m * m * s * s + 3.0 * s.powi(4));
    assert_close("paper's scaling", var, want, want, 1e-13);
}

#[test]
fn mean_and_cross_covariance_are_exact_for_any_quadratic_and_scaling() {
    for m in [1usize, 2, 4] {
        let (model, mu, p) = problem(m);
        let model = Arc::new(model);
        let truth = exact(&model, &mu, &p);
        for s in scalings(1 + m) {
            let got = through_filter(model.clone(), &mu, &p, s);
            let scale = truth.var.sqrt() + truth.mean.abs();
            assert_close(
                &format!("m {m} {s:?} mean"),
                got.mean,
                truth.mean,
                scale,
                1e-12,
            );
            // Cov(x_i, y_end) for the unchanged x (index 0 is y_end itself).
            for i in 1..=m {
                let sc = (truth.var * p[(i, i)]).sqrt();
                assert_close(
                    &format!("m {m} {s:?} Cov(s{i}, y)"),
                    got.cross[i],
                    truth.cross[i],
                    sc,
                    1e-11,
                );
            }
        }
    }
}

#[test]
fn mean_of_squared_norm_is_trace_of_p() {
    // y' = x^T x from y = 0 with zero-mean x: E[y_end] = T tr(P_x), for the paper's scaling too.
    let m = 4;
    let (mut model, _, p) = problem(m);
    model.a = DMatrix::identity(m, m);
    model.b = DVector::zeros(m);
    model.d0 = 0.0;
    let mu = DVector::zeros(1 + m);
    let tr = p.view((1, 1), (m, m)).trace();
    let model = Arc::new(model);
    for s in scalings(1 + m) {
        let got = through_filter(model.clone(), &mu, &p, s);
        assert_close(&format!("{s:?} E[x^T x]"), got.mean, T * tr, T * tr, 1e-12);
    }
}

#[test]
fn variance_is_the_unscented_formula_and_exact_where_theory_says() {
    for m in [1usize, 2, 4] {
        let (model, mu, p) = problem(m);
        let model = Arc::new(model);
        for s in scalings(1 + m) {
            let got = through_filter(model.clone(), &mu, &p, s);
            let want = unscented(&model, &mu, &p, s);
            assert_close(
                &format!("m {m} {s:?} Var(y)"),
                got.var,
                want.var,
                want.var,
                1e-11,
            );
        }
    }
    // A quadratic along one Cholesky direction: q = a x1^2 with x1 independent of y. Exact
    // when gamma^2 + beta - alpha^2 = 2: alpha = 1, n + kappa = 3, beta = 0 (n = 2 here).
    let (mut model, mu, _) = problem(1);
    model.a = DMatrix::from_element(1, 1, 1.3);
    let p = DMatrix::from_diagonal(&DVector::from_vec(vec![0.2, 0.09]));
    let model = Arc::new(model);
    let truth = exact(&model, &mu, &p);
    let julier = SigmaScaling {
        alpha: 1.0,
        beta: 0.0,
        kappa: 1.0,
    };
    let got = through_filter(model.clone(), &mu, &p, julier);
    assert_close(
        "Var(y), n + kappa = 3, beta = 0",
        got.var,
        truth.var,
        truth.var,
        1e-12,
    );
    // With beta = 2 the same transform overestimates by 2 B^2 (so the formula is not vacuous).
    let paper = through_filter(model.clone(), &mu, &p, SigmaScaling::default());
    let b = T * 1.3 * 0.09;
    assert_close(
        "Var(y), paper's scaling",
        paper.var,
        truth.var + 2.0 * b * b,
        truth.var,
        1e-12,
    );
}
