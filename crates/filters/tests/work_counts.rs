//! How much model work each filter does per step, counted through a wrapper model (which
//! uses the trait's default `propagate_points`, RK4 point by point):
//!
//! - simplified UKF: `(2n + 1) * 4 * substeps` derivative calls per prediction, none in a
//!   linear update (one measurement evaluation);
//! - standard UKF (n + 5 + 4 = 29 augmented): `(1 + 2 (n + 5)) * 4 * substeps` derivative calls:
//!   the 8 points along V have the centre's state and no process noise, so they are copied,
//!   not propagated; its update measures every one of the `2 * 29 + 1` points;
//! - the W-only standard UKF (25): the same propagation, `2 * 25 + 1` measurements;
//! - EKF: `4 * substeps` derivative and Jacobian calls, one measurement and its Jacobian.
//!
//! What it catches: V points propagated (wasted work), points propagated twice or left out,
//! the wrong number of RK4 stages or sub-steps, an update that redraws or re-propagates
//! points it already has, an EKF that evaluates more Jacobians than stages.

use crate::common;

use navkf_dynamics::state::*;
use navkf_dynamics::*;
use navkf_filters::*;
use std::sync::atomic::{AtomicUsize, Ordering::Relaxed};
use std::sync::Arc;

/// The platform model with every evaluation counted.
struct Counted {
    inner: PlatformModel,
    rates: AtomicUsize,
    rate_jacobians: AtomicUsize,
    measures: AtomicUsize,
    measurement_jacobians: AtomicUsize,
}

impl Counted {
    fn new(inner: PlatformModel) -> Arc<Self> {
        Arc::new(Counted {
            inner,
            rates: AtomicUsize::new(0),
            rate_jacobians: AtomicUsize::new(0),
            measures: AtomicUsize::new(0),
            measurement_jacobians: AtomicUsize::new(0),
        })
    }
    /// (rates, rate Jacobians, measurements, measurement Jacobians) since the last call.
    fn take(&self) -> [usize; 4] {
        [
            self.rates.swap(0, Relaxed),
            self.rate_jacobians.swap(0, Relaxed),
            self.measures.swap(0, Relaxed),
            self.measurement_jacobians.swap(0, Relaxed),
        ]
    }
}

impl SystemModel for Counted {
    fn dim(&self) -> usize {
        self.inner.dim()
    }
    fn dynamic_dim(&self) -> usize {
        self.inner.dynamic_dim()
    }
    fn noise_channels(&self) -> &[NoiseChannel] {
        self.inner.noise_channels()
    }
    fn rates(&self, x: &[f64], u: &Input, dx: &mut [f64]) {
        self.rates.fetch_add(1, Relaxed);
        self.inner.rates(x, u, dx)
    }
    fn rate_jacobian(&self, x: &[f64], u: &Input, jac: &mut [f64]) {
        self.rate_jacobians.fetch_add(1, Relaxed);
        self.inner.rate_jacobian(x, u, jac)
    }
    fn meas_dim(&self) -> usize {
        self.inner.meas_dim()
    }
    fn measure(&self, x: &[f64], z: &mut [f64]) {
        self.measures.fetch_add(1, Relaxed);
        self.inner.measure(x, z)
    }
    fn measurement_jacobian(&self, x: &[f64], h: &mut [f64]) {
        self.measurement_jacobians.fetch_add(1, Relaxed);
        self.inner.measurement_jacobian(x, h)
    }
    fn measurement_is_linear(&self) -> bool {
        self.inner.measurement_is_linear()
    }
    fn state_names(&self) -> Vec<String> {
        self.inner.state_names()
    }
}

fn window(substeps: usize) -> InputWindow {
    let mut w = InputWindow::with_capacity(substeps + 1);
    for k in 0..=substeps {
        w.push_linear(k as f64 / substeps as f64, [0.1, -0.05, 9.806]);
    }
    w
}

/// Counts of one predict and of the update that follows, for `f` on `m`.
fn one_step(f: &mut dyn Filter, m: &Counted, substeps: usize) -> ([usize; 4], [usize; 4]) {
    let n = m.dim();
    let (x, p) = common::at_rest(n, |_| 1e-6);
    f.reset(&x, &p).unwrap();
    m.take();
    f.predict(&window(substeps)).unwrap();
    let predict = m.take();
    let z = [0.0, 0.0, x[LAT], x[LON]];
    let sigma = NoiseConfig::default().measurement_sigmas(0.0, x[LAT]);
    f.update(&Observation {
        z: &z,
        sigma: &sigma,
        available: &[true; 4],
    })
    .unwrap();
    (predict, m.take())
}

#[test]
fn derivative_and_measurement_calls_per_step_on_the_base_model() {
    let m = Counted::new(PlatformModel::base(&NoiseConfig::default()));
    let n = m.dim();
    let nw = m.noise_channels().len();
    assert_eq!((n, nw), (20, 5));
    for substeps in [1usize, 3, 10] {
        let s4 = 4 * substeps;
        let mut simp = Ukf::simplified(m.clone(), SigmaScaling::default()).unwrap();
        let (p, u) = one_step(&mut simp, &m, substeps);
        assert_eq!(p, [(2 * n + 1) * s4, 0, 0, 0], "simplified UKF predict");
        assert_eq!(u, [0, 0, 1, 1], "simplified UKF (linear) update");

        let mut std29 = Ukf::standard(m.clone(), SigmaScaling::default()).unwrap();
        assert_eq!(std29.sigma_dim(), n + nw + 4);
        let (p, u) = one_step(&mut std29, &m, substeps);
        assert_eq!(
            p,
            [(1 + 2 * (n + nw)) * s4, 0, 0, 0],
            "standard UKF predict"
        );
        assert_eq!(u, [0, 0, 2 * (n + nw + 4) + 1, 0], "standard UKF update");

        let mut std25 = Ukf::standard_process_only(m.clone(), SigmaScaling::default()).unwrap();
        let (p, u) = one_step(&mut std25, &m, substeps);
        assert_eq!(p, [(1 + 2 * (n + nw)) * s4, 0, 0, 0], "W-only UKF predict");
        assert_eq!(u, [0, 0, 2 * (n + nw) + 1, 0], "W-only UKF update");

        let mut ekf = Ekf::new(m.clone());
        let (p, u) = one_step(&mut ekf, &m, substeps);
        assert_eq!(p, [s4, s4, 0, 0], "EKF predict");
        assert_eq!(u, [0, 0, 1, 1], "EKF update");
    }
}

#[test]
fn simplified_ukf_redraws_points_only_for_a_nonlinear_measurement() {
    let noise = NoiseConfig::default();
    let fx = Registry::catalogue()
        .build_all(&["odometer-scale"])
        .unwrap();
    let m = Counted::new(PlatformModel::new(fx, &noise).unwrap());
    let n = m.dim();
    assert_eq!(n, 21);
    let mut simp = Ukf::simplified(m.clone(), SigmaScaling::default()).unwrap();
    assert!(!simp.uses_linear_update());
    let (p, u) = one_step(&mut simp, &m, 10);
    assert_eq!(p, [(2 * n + 1) * 40, 0, 0, 0]);
    // One redraw of 2n + 1 points through h, no propagation.
    assert_eq!(u, [0, 0, 2 * n + 1, 0]);
}
