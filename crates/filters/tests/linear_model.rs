//! On a linear time-invariant model every filter of the crate is the Kalman filter: the EKF,
//! the simplified UKF and both standard (augmented) UKFs must equal an independent Kalman
//! filter, written here with nalgebra, in state, covariance, innovation, innovation
//! covariance, NIS and log-likelihood, step by step.
//!
//! What it catches: a transition matrix that is not the exact derivative of the RK4 map (an
//! Euler `I + F T`, a wrong stage product, a wrong chaining over unequal sub-steps, a wrong
//! block of `Phi P Phi^T` where the constant coefficients feed the dynamic states), a wrong
//! `Q_k`, wrong sigma-point weights or spread, a wrong handling of the augmented noise
//! directions (W, V), a wrong gain, Joseph form, NIS or log-likelihood, and mishandled absent
//! measurement channels.
//!
//! The model: n = 6, the first 4 states dynamic (two damped oscillators with input coupling
//! `B u`), the last 2 constant coefficients feeding them; 2 noise channels on dynamic states
//! (states that feed back within the window); a linear 3-channel measurement, channel 2
//! absent every third step and every channel absent at one step.
//!
//! The process noise: the EKF and the simplified UKF add `Q_k = G Qc G^T T` (diagonal here).
//! The augmented UKFs instead hold a sigma point's noise `w` constant over the window
//! (variance `Qc / T`) and push it through the RK4 map. For a linear model that is exact,
//! and gives `Q_k = M (Qc / T) M^T`, where `M = d x_end / d w` is the RK4 response to a
//! constant unit `w` from a zero state and zero input. `M` differs from `G T` by
//! `A G T^2 / 2 + ...` because the noisy states feed back within the window, so the reference
//! for the augmented filters uses that exact `Q_k` (computed here by propagating unit `w`
//! through the reference RK4), and the reference for the additive filters uses
//! `G Qc G^T T`. Both are right: they are the two filters' own (different) noise models.

use nalgebra::{DMatrix, DVector};
use navkf_dynamics::{Input, InputWindow, NoiseChannel, SystemModel};
use navkf_filters::*;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};
use std::sync::Arc;

const N: usize = 6;
const D: usize = 4;
const NZ: usize = 3;
const TOL: f64 = 1e-9;

/// `x' = A x + B u + G w` on the first `D` states, `z = H x + v`.
struct LinearModel {
    a: [[f64; N]; D],
    b: [[f64; 3]; D],
    h: [[f64; N]; NZ],
    noise: Vec<NoiseChannel>,
}

fn model() -> LinearModel {
    LinearModel {
        a: [
            [0.0, 1.0, 0.0, 0.0, 0.0, 0.0],
            [-1.0, -0.2, 0.1, 0.0, 1.0, 0.0],
            [0.0, 0.0, 0.0, 1.0, 0.0, 0.0],
            [0.0, 0.05, -0.5, -0.1, 0.3, 1.0],
        ],
        b: [
            [0.0, 0.0, 0.1],
            [1.0, 0.0, 0.0],
            [0.0, 0.0, 0.0],
            [0.0, 1.0, 0.5],
        ],
        h: [
            [1.0, 0.0, 0.0, 0.0, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0, 0.5, 0.0],
            [0.0, 1.0, 0.0, 0.0, 0.0, -1.0],
        ],
        noise: vec![
            NoiseChannel {
                name: "w1".into(),
                state: 1,
                psd: 0.01,
            },
            NoiseChannel {
                name: "w3".into(),
                state: 3,
                psd: 0.02,
            },
        ],
    }
}

impl SystemModel for LinearModel {
    fn dim(&self) -> usize {
        N
    }
    fn dynamic_dim(&self) -> usize {
        D
    }
    fn noise_channels(&self) -> &[NoiseChannel] {
        &self.noise
    }
    fn rates(&self, x: &[f64], u: &Input, dx: &mut [f64]) {
        for ((d, a), b) in dx.iter_mut().zip(&self.a).zip(&self.b) {
            *d = a.iter().zip(x).map(|(ai, xi)| ai * xi).sum::<f64>()
                + b.iter().zip(u).map(|(bi, ui)| bi * ui).sum::<f64>();
        }
    }
    fn rate_jacobian(&self, _x: &[f64], _u: &Input, jac: &mut [f64]) {
        for r in 0..D {
            jac[r * N..(r + 1) * N].copy_from_slice(&self.a[r]);
        }
    }
    fn meas_dim(&self) -> usize {
        NZ
    }
    fn measure(&self, x: &[f64], z: &mut [f64]) {
        for (zi, h) in z.iter_mut().zip(&self.h) {
            *zi = h.iter().zip(x).map(|(hi, xi)| hi * xi).sum();
        }
    }
    fn measurement_jacobian(&self, _x: &[f64], h: &mut [f64]) {
        for i in 0..NZ {
            h[i * N..(i + 1) * N].copy_from_slice(&self.h[i]);
        }
    }
    fn measurement_is_linear(&self) -> bool {
        true
    }
    fn state_names(&self) -> Vec<String> {
        (0..N).map(|i| format!("x{i}")).collect()
    }
}

/// The reference: the model's matrices in nalgebra and a textbook Kalman filter.
struct Reference {
    a: DMatrix<f64>,
    b: DMatrix<f64>,
    g: DMatrix<f64>,
    h: DMatrix<f64>,
    psd: Vec<f64>,
    x: DVector<f64>,
    p: DMatrix<f64>,
    /// Whether `Q_k` is the augmented filters' `M (Qc/T) M^T` rather than `G Qc G^T T`.
    augmented_noise: bool,
}

/// What the reference's update gives.
struct RefReport {
    channels: Vec<usize>,
    innovation: DVector<f64>,
    s: DMatrix<f64>,
    nis: f64,
    log_likelihood: f64,
}

impl Reference {
    fn new(m: &LinearModel, x0: &[f64], p0: &[f64], augmented_noise: bool) -> Self {
        let mut a = DMatrix::zeros(N, N);
        let mut b = DMatrix::zeros(N, 3);
        for r in 0..D {
            for c in 0..N {
                a[(r, c)] = m.a[r][c];
            }
            for j in 0..3 {
                b[(r, j)] = m.b[r][j];
            }
        }
        let mut g = DMatrix::zeros(N, m.noise.len());
        for (j, c) in m.noise.iter().enumerate() {
            g[(c.state, j)] = 1.0;
        }
        let h = DMatrix::from_fn(NZ, N, |i, c| m.h[i][c]);
        Reference {
            a,
            b,
            g,
            h,
            psd: m.noise.iter().map(|c| c.psd).collect(),
            x: DVector::from_column_slice(x0),
            p: DMatrix::from_column_slice(N, N, p0),
            augmented_noise,
        }
    }

    /// `A x + B u + G w`.
    fn rate(&self, x: &DVector<f64>, u: &Input, w: &DVector<f64>) -> DVector<f64> {
        &self.a * x + &self.b * DVector::from_column_slice(&u[..3]) + &self.g * w
    }

    /// RK4 across the window, stage inputs `f_j, f_mid_j, f_mid_j, f_j+1`, `w` constant.
    fn rk4(
        &self,
        x0: &DVector<f64>,
        win: &InputWindow,
        with_input: bool,
        w: &DVector<f64>,
    ) -> DVector<f64> {
        let mut x = x0.clone();
        let z = [0.0; navkf_dynamics::kinematics::INPUT_WIDTH];
        for j in 0..win.substeps() {
            let h = win.t[j + 1] - win.t[j];
            let (u0, um, u1) = if with_input {
                (win.f[j], win.f_mid[j], win.f[j + 1])
            } else {
                (z, z, z)
            };
            let k1 = self.rate(&x, &u0, w);
            let k2 = self.rate(&(&x + &k1 * (0.5 * h)), &um, w);
            let k3 = self.rate(&(&x + &k2 * (0.5 * h)), &um, w);
            let k4 = self.rate(&(&x + &k3 * h), &u1, w);
            x += (k1 + (k2 + k3) * 2.0 + k4) * (h / 6.0);
        }
        x
    }

    /// The exact derivative of the RK4 map of a linear system: per sub-step the degree-4
    /// Taylor polynomial of `exp(A h)`, chained.
    fn transition(&self, win: &InputWindow) -> DMatrix<f64> {
        let eye = DMatrix::<f64>::identity(N, N);
        let mut phi = eye.clone();
        for j in 0..win.substeps() {
            let ah = &self.a * (win.t[j + 1] - win.t[j]);
            let ah2 = &ah * &ah;
            let ah3 = &ah2 * &ah;
            let ah4 = &ah3 * &ah;
            let sub = &eye + &ah + ah2 / 2.0 + ah3 / 6.0 + ah4 / 24.0;
            phi = sub * phi;
        }
        phi
    }

    fn process_noise(&self, win: &InputWindow) -> DMatrix<f64> {
        let t = win.duration();
        let nw = self.psd.len();
        if self.augmented_noise {
            // M = d x_end / d w: the RK4 response to a constant unit w, from zero.
            let mut m = DMatrix::zeros(N, nw);
            for j in 0..nw {
                let mut e = DVector::zeros(nw);
                e[j] = 1.0;
                let col = self.rk4(&DVector::zeros(N), win, false, &e);
                m.set_column(j, &col);
            }
            let qw =
                DMatrix::from_diagonal(&DVector::from_iterator(nw, self.psd.iter().map(|q| q / t)));
            &m * qw * m.transpose()
        } else {
            let qc = DMatrix::from_diagonal(&DVector::from_column_slice(&self.psd));
            &self.g * qc * self.g.transpose() * t
        }
    }

    fn predict(&mut self, win: &InputWindow) {
        let phi = self.transition(win);
        self.x = self.rk4(&self.x, win, true, &DVector::zeros(self.psd.len()));
        self.p = &phi * &self.p * phi.transpose() + self.process_noise(win);
    }

    fn update(&mut self, obs: &Observation) -> RefReport {
        let channels: Vec<usize> = (0..NZ).filter(|&i| obs.available[i]).collect();
        let k = channels.len();
        if k == 0 {
            return RefReport {
                channels,
                innovation: DVector::zeros(0),
                s: DMatrix::zeros(0, 0),
                nis: 0.0,
                log_likelihood: 0.0,
            };
        }
        let h = DMatrix::from_fn(k, N, |a, c| self.h[(channels[a], c)]);
        let r = DMatrix::from_fn(k, k, |a, b| {
            if a == b {
                obs.sigma[channels[a]].powi(2)
            } else {
                0.0
            }
        });
        let z = DVector::from_iterator(k, channels.iter().map(|&c| obs.z[c]));
        let nu = z - &h * &self.x;
        let s = &h * &self.p * h.transpose() + r;
        let s_inv = s.clone().try_inverse().unwrap();
        let gain = &self.p * h.transpose() * &s_inv;
        self.x += &gain * &nu;
        self.p = &self.p - &gain * &s * gain.transpose();
        self.p = (&self.p + self.p.transpose()) * 0.5;
        let nis = (nu.transpose() * &s_inv * &nu)[(0, 0)];
        let log_likelihood =
            -0.5 * (nis + s.determinant().ln() + k as f64 * (2.0 * std::f64::consts::PI).ln());
        RefReport {
            channels,
            innovation: nu,
            s,
            nis,
            log_likelihood,
        }
    }
}

fn close(what: &str, step: usize, filter: &str, got: f64, want: f64, scale: f64) {
    assert!(
        (got - want).abs() <= TOL * scale,
        "{filter}, step {step}, {what}: {got:e} vs reference {want:e} (difference {:e}, scale {scale:e})",
        (got - want).abs()
    );
}

fn compare_estimate(f: &dyn Filter, r: &Reference, step: usize, when: &str) {
    let name = f.name();
    let (x, p) = (f.state(), f.covariance());
    for i in 0..N {
        let s = r.x[i].abs() + r.p[(i, i)].sqrt();
        close(&format!("{when} x[{i}]"), step, name, x[i], r.x[i], s);
        for j in 0..N {
            let s = (r.p[(i, i)] * r.p[(j, j)]).sqrt();
            close(
                &format!("{when} P[{i},{j}]"),
                step,
                name,
                p[i + j * N],
                r.p[(i, j)],
                s,
            );
        }
    }
}

fn compare_report(f: &dyn Filter, rr: &RefReport, step: usize) {
    let name = f.name();
    let rep = f.last_report();
    assert_eq!(rep.channels, rr.channels, "{name}, step {step}: channels");
    assert_eq!(rep.step, step, "{name}: report step");
    let k = rr.channels.len();
    for a in 0..k {
        let sa = rr.s[(a, a)].sqrt();
        close(
            "innovation",
            step,
            name,
            rep.innovation[a],
            rr.innovation[a],
            sa,
        );
        for b in 0..k {
            let s = (rr.s[(a, a)] * rr.s[(b, b)]).sqrt();
            close(
                "S",
                step,
                name,
                rep.innovation_cov[a + b * k],
                rr.s[(a, b)],
                s,
            );
        }
    }
    close("NIS", step, name, rep.nis, rr.nis, rr.nis.max(1.0));
    close(
        "log-likelihood",
        step,
        name,
        rep.log_likelihood,
        rr.log_likelihood,
        rr.log_likelihood.abs().max(1.0),
    );
}

fn input_at(t: f64) -> Input {
    navkf_dynamics::kinematics::platform_input([(0.7 * t).sin(), (0.3 * t).cos(), 1.0 + 0.1 * t])
}

#[test]
fn every_filter_equals_the_kalman_filter_on_a_linear_model() {
    let m = Arc::new(model());
    // A full (non-diagonal) initial covariance: P0 = L L^T.
    let l0 = DMatrix::from_fn(N, N, |i, j| {
        if i == j {
            0.5 + 0.1 * i as f64
        } else if i > j {
            0.1 * ((i + 2 * j) as f64).sin()
        } else {
            0.0
        }
    });
    let p0m = &l0 * l0.transpose();
    let p0: Vec<f64> = p0m.as_slice().to_vec();
    let x0 = [0.5, -0.2, 0.3, 0.1, 0.4, -0.3];

    let mut filters: Vec<(Box<dyn Filter>, bool)> = vec![
        (Box::new(Ekf::new(m.clone())), false),
        (
            Box::new(Ukf::simplified(m.clone(), SigmaScaling::default()).unwrap()),
            false,
        ),
        (
            Box::new(SquareRootUkf::new(m.clone(), SigmaScaling::default()).unwrap()),
            false,
        ),
        (
            Box::new(Ukf::standard(m.clone(), SigmaScaling::default()).unwrap()),
            true,
        ),
        (
            Box::new(Ukf::standard_process_only(m.clone(), SigmaScaling::default()).unwrap()),
            true,
        ),
    ];
    let mut refs: Vec<Reference> = filters
        .iter()
        .map(|(_, aug)| Reference::new(&m, &x0, &p0, *aug))
        .collect();
    for (f, _) in filters.iter_mut() {
        f.reset(&x0, &p0).unwrap();
    }

    // The truth: a draw from the prior, driven by noise and measured with noise.
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let mut normal = || -> f64 { StandardNormal.sample(&mut rng) };
    let chol0 = p0m.clone().cholesky().unwrap().l();
    let mut truth = DVector::from_column_slice(&x0)
        + &chol0 * DVector::from_iterator(N, (0..N).map(|_| normal()));
    let truth_model = Reference::new(&m, &x0, &p0, false);
    let sigma = [0.1, 0.2, 0.15];

    // Knots at unequal spacing inside each 1 s window.
    let offsets = [0.0, 0.3, 0.5, 0.8, 1.0];
    let mut win = InputWindow::with_capacity(offsets.len());
    for step in 1..=50usize {
        let t0 = (step - 1) as f64;
        win.clear();
        for o in offsets {
            win.push_linear(t0 + o, input_at(t0 + o));
        }
        let w = DVector::from_iterator(
            m.noise.len(),
            m.noise.iter().map(|c| (c.psd / 1.0).sqrt() * normal()),
        );
        truth = truth_model.rk4(&truth, &win, true, &w);
        let mut z = [0.0; NZ];
        m.measure(truth.as_slice(), &mut z);
        for (zi, s) in z.iter_mut().zip(sigma) {
            *zi += s * normal();
        }
        let available = match step {
            25 => [false, false, false],
            s if s % 3 == 0 => [true, true, false],
            _ => [true, true, true],
        };
        if !available[2] {
            // An absent channel's value is never read.
            z[2] = f64::NAN;
        }
        let obs = Observation {
            z: &z,
            sigma: &sigma,
            available: &available,
        };
        for ((f, _), r) in filters.iter_mut().zip(refs.iter_mut()) {
            f.predict(&win).unwrap();
            r.predict(&win);
            compare_estimate(&**f, r, step, "predicted");
            let x_before = f.state().to_vec();
            let rr = r.update(&obs);
            f.update(&obs).unwrap();
            compare_report(&**f, &rr, step);
            compare_estimate(&**f, r, step, "updated");
            if rr.channels.is_empty() {
                assert_eq!(
                    f.state(),
                    &x_before[..],
                    "{}: update with no channel",
                    f.name()
                );
            }
        }
    }
}

/// The two references differ (so the augmented filters' comparison is not vacuous): the
/// noise entering states that feed back makes `M (Qc/T) M^T != G Qc G^T T` at the level the
/// test resolves.
#[test]
fn augmented_and_additive_process_noise_differ_for_this_model() {
    let m = model();
    let p0 = vec![0.0; N * N];
    let add = Reference::new(&m, &[0.0; N], &p0, false);
    let aug = Reference::new(&m, &[0.0; N], &p0, true);
    let mut win = InputWindow::with_capacity(5);
    for o in [0.0, 0.3, 0.5, 0.8, 1.0] {
        win.push_linear(o, input_at(o));
    }
    let (qa, qb) = (add.process_noise(&win), aug.process_noise(&win));
    let diff = (&qa - &qb).abs().max();
    assert!(
        diff > 1e-4 * qa.max(),
        "difference {diff:e} is too small to test anything"
    );
}
