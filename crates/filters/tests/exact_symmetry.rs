//! The UKFs and the square-root UKF do not symmetrise their covariance after a step
//! (`Estimate::finish_symmetric`): their kernels give both triangles the same products
//! (`covariance_from_deviations`, `subtract_gain_cov`, `outer_of_lower`). This checks it bit
//! for bit after every update of a simulated run and after a prediction, for every filter,
//! with a linear measurement and with a non-linear one (`odometer-scale`) behind two rate
//! effects. Catches a kernel change that leaves the triangles a last bit apart, which
//! nothing downstream would notice until a Cholesky of an almost-symmetric matrix.

use crate::common;

use navkf_dynamics::*;
use navkf_filters::*;

fn asymmetry(p: &[f64], n: usize) -> Option<(usize, usize)> {
    (0..n)
        .flat_map(|j| (0..j).map(move |i| (i, j)))
        .find(|&(i, j)| p[i + j * n].to_bits() != p[j + i * n].to_bits())
}

fn check_every_filter(sim: &Simulator, what: &str) {
    let run = sim.run(7, 0);
    let model = sim.model().clone();
    let n = model.dim();
    let (x0, mut p0) = common::initial_estimate(sim, &run);
    // The extra coefficients (zero sigma from `initial_estimate`): a loose prior.
    for i in navkf_dynamics::state::BASE_DIM..n {
        p0[i + i * n] = 1e-6;
    }
    for kind in FilterKind::ALL {
        let mut f = kind.build(model.clone(), SigmaScaling::default()).unwrap();
        f.reset(&x0, &p0).unwrap();
        let mut checked = 0;
        Runner::new(16)
            .run(
                &mut *f,
                0.0,
                sim.inputs(),
                &run.measurements,
                sim.noise(),
                |step| {
                    if kind != FilterKind::Ekf {
                        let p = step.filter.covariance();
                        if let Some((i, j)) = asymmetry(p, n) {
                            panic!("{what}: {kind:?} P[{i},{j}] != P[{j},{i}] at {} s", step.t);
                        }
                    }
                    checked += 1;
                },
            )
            .unwrap();
        assert!(checked > 100, "{what}: {kind:?}: {checked} updates");
        // A prediction on its own.
        let mut w = InputWindow::with_capacity(11);
        for k in 0..=10 {
            w.push_linear(k as f64 * 0.1, [0.0, 0.0, 9.806]);
        }
        f.predict(&w).unwrap();
        if kind != FilterKind::Ekf {
            assert_eq!(
                asymmetry(f.covariance(), n),
                None,
                "{what}: {kind:?} predict"
            );
        }
    }
}

#[test]
fn ukf_covariances_are_exactly_symmetric_on_the_base_model() {
    check_every_filter(&common::base_simulator(600.0), "base");
}

#[test]
fn ukf_covariances_are_exactly_symmetric_with_rate_effects_and_a_non_linear_measurement() {
    let sim = common::simulator_with(
        &["accel-cross-axis", "torquer-scale", "odometer-scale"],
        &[("kod", 0.003)],
        600.0,
    );
    assert!(!sim.model().measurement_is_linear());
    check_every_filter(&sim, "effects + odometer-scale");
}
