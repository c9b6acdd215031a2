//! The square-root UKF is the simplified UKF's algebra carried in a Cholesky factor: on the
//! platform model the two must agree to rounding, both where the measurement is linear (the
//! array-form update) and where an effect makes it non-linear (`odometer-scale`: sigma points
//! through `h`, the innovation factor by QR, rank-one downdates). Catches a wrong block of the
//! pre-array, a lost sign of a reflection, a wrong centre-point update or downdate.

use crate::common;

use navkf_dynamics::state::*;
use navkf_dynamics::*;
use navkf_filters::*;

/// Largest disagreement, in posterior sigmas, of state and sigma over one run.
fn disagreement(sim: &Simulator, seed: u64, extra_sigma: &[f64]) -> (f64, f64) {
    let run = sim.run(seed, 0);
    let (x0b, p0b) = common::initial_estimate(sim, &run);
    let model = sim.model().clone();
    let n = model.dim();
    let nb = x0b.len().min(BASE_DIM);
    // The base states' estimate, then the extra coefficients at zero with their sigmas.
    let mut x0 = vec![0.0; n];
    x0[..nb].copy_from_slice(&x0b[..nb]);
    let mut p0 = vec![0.0; n * n];
    for i in 0..n {
        p0[i + i * n] = if i < BASE_DIM {
            p0b[i + i * x0b.len()]
        } else {
            extra_sigma[i - BASE_DIM].powi(2)
        };
    }
    let scaling = SigmaScaling::default();
    let mut simp = Ukf::simplified(model.clone(), scaling).unwrap();
    let mut sr = SquareRootUkf::new(model.clone(), scaling).unwrap();
    assert_eq!(simp.uses_linear_update(), sr.uses_linear_update());
    let mut out = Vec::new();
    for f in [&mut simp as &mut dyn Filter, &mut sr] {
        f.reset(&x0, &p0).unwrap();
        Runner::new(16)
            .run(f, 0.0, sim.inputs(), &run.measurements, sim.noise(), |_| {})
            .unwrap();
        out.push((f.state().to_vec(), f.covariance().to_vec()));
    }
    let ((xa, pa), (xb, pb)) = (&out[0], &out[1]);
    let (mut dx, mut ds) = (0.0f64, 0.0f64);
    for i in 0..n {
        let sig = pa[i + i * n].sqrt();
        dx = dx.max((xa[i] - xb[i]).abs() / sig);
        ds = ds.max((pb[i + i * n].sqrt() - sig).abs() / sig);
    }
    (dx, ds)
}

#[test]
fn square_root_and_simplified_ukf_agree_on_the_base_model() {
    let sim = common::base_simulator(600.0);
    let (dx, ds) = disagreement(&sim, 2024, &[]);
    eprintln!("base model: state {dx:.2e} sigma, sigma ratio {ds:.2e}");
    assert!(dx < 1e-6 && ds < 1e-6, "state {dx:e}, sigma {ds:e}");
}

#[test]
fn square_root_and_simplified_ukf_agree_with_a_non_linear_measurement() {
    let sim = common::simulator_with(&["odometer-scale"], &[("kod", 0.003)], 600.0);
    assert!(!sim.model().measurement_is_linear());
    let extra: Vec<f64> = sim.model().effects()[0].coefficient_sigma().to_vec();
    let (dx, ds) = disagreement(&sim, 2025, &extra);
    eprintln!("odometer-scale: state {dx:.2e} sigma, sigma ratio {ds:.2e}");
    assert!(dx < 1e-6 && ds < 1e-6, "state {dx:e}, sigma {ds:e}");
}
