//! Bad numbers and bad calls give typed errors, never a panic or a silent NaN: an indefinite
//! covariance, an innovation covariance that is not positive definite, NaN or non-positive
//! values in an observation, wrong sizes, a NaN input.
//!
//! What it catches: a Cholesky failure that panics or is ignored (NaN sigma points), an
//! error without the step it happened at or naming the wrong matrix, an unchecked
//! observation that turns NaN into the state, an index panic on a wrong-size slice, and a
//! filter that cannot be reset after an error.

use crate::common;

use navkf_dynamics::state::*;
use navkf_dynamics::*;
use navkf_filters::*;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::Arc;

fn model() -> Arc<PlatformModel> {
    Arc::new(PlatformModel::base(&NoiseConfig::default()))
}

fn all_filters(m: &std::sync::Arc<PlatformModel>) -> Vec<Box<dyn Filter>> {
    // Every filter the harness has: a new one cannot be missed.
    navkf_filters::FilterKind::ALL
        .iter()
        .map(|k| k.build(m.clone(), SigmaScaling::default()).unwrap())
        .collect()
}

fn ukfs(m: &Arc<PlatformModel>) -> Vec<Box<dyn Filter>> {
    all_filters(m).into_iter().skip(1).collect()
}

/// A level platform at rest at 45.78 N, a good diagonal covariance.
fn start() -> (Vec<f64>, Vec<f64>) {
    common::at_rest(BASE_DIM, navkf_dynamics::prior::base_coefficient_sigma)
}

/// One second at rest, ten sub-steps.
fn rest_window() -> InputWindow {
    let mut w = InputWindow::with_capacity(11);
    for k in 0..=10 {
        w.push_linear(k as f64 * 0.1, [0.0, 0.0, 9.806]);
    }
    w
}

/// What the platform would measure at `x`, with the spec's sigmas.
fn rest_observation(x: &[f64]) -> ([f64; 4], [f64; 4], [bool; 4]) {
    let sig = NoiseConfig::default().measurement_sigmas(0.0, x[LAT]);
    ([0.0, 0.0, x[LAT], x[LON]], sig, [true; 4])
}

/// Runs `f` and fails the test with `what` if it panics.
fn no_panic<T>(what: &str, f: impl FnOnce() -> T) -> T {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(v) => v,
        Err(_) => panic!("{what} panicked"),
    }
}

/// The filter still works after an error: reset, predict, update succeed.
fn recovers(f: &mut dyn Filter) {
    let (x, p) = start();
    f.reset(&x, &p).unwrap();
    f.predict(&rest_window()).unwrap();
    let (z, s, a) = rest_observation(f.state());
    f.update(&Observation {
        z: &z,
        sigma: &s,
        available: &a,
    })
    .unwrap();
    assert!(f.state().iter().all(|v| v.is_finite()));
}

#[test]
fn indefinite_covariance_fails_the_ukf_prediction_at_step_1() {
    let m = model();
    let n = BASE_DIM;
    let (x, p) = start();
    // Two ways to be indefinite: a correlation above 1 (positive diagonal, a negative
    // eigenvalue), and a negative variance.
    let mut p_corr = p.clone();
    let c = 2.0 * (p[V_X + V_X * n] * p[V_Y + V_Y * n]).sqrt();
    p_corr[V_X + V_Y * n] = c;
    p_corr[V_Y + V_X * n] = c;
    let mut p_neg = p.clone();
    p_neg[KG0Y + KG0Y * n] = -p[KG0Y + KG0Y * n];
    for bad in [&p_corr, &p_neg] {
        for mut f in ukfs(&m) {
            let name = f.name().to_string();
            if name == "square_root_ukf" {
                // It factors P when it takes it, so the reset refuses it (step 0).
                match f.reset(&x, bad) {
                    Err(FilterError::NotPositiveDefinite {
                        step: 0,
                        matrix: "P",
                        dim,
                        value,
                        ..
                    }) => assert!(dim == n && value <= 0.0, "{name}: pivot {value}"),
                    other => panic!("{name}: expected NotPositiveDefinite at reset, got {other:?}"),
                }
                recovers(&mut *f);
                continue;
            }
            f.reset(&x, bad).unwrap();
            let r = no_panic(&name, || f.predict(&rest_window()));
            match r {
                Err(FilterError::NotPositiveDefinite {
                    step: 1,
                    matrix: "P",
                    dim,
                    value,
                    ..
                }) => {
                    assert_eq!(dim, n, "{name}");
                    assert!(value <= 0.0, "{name}: failing pivot {value}");
                }
                other => panic!("{name}: expected NotPositiveDefinite at step 1, got {other:?}"),
            }
            recovers(&mut *f);
        }
    }
}

#[test]
fn innovation_covariance_not_positive_definite_is_a_typed_error() {
    let m = model();
    let n = BASE_DIM;
    let (x, p) = start();
    let mut p_neg = p.clone();
    // A negative variance on a measured state: S = P_vx + sigma^2 < 0.
    p_neg[V_X + V_X * n] = -1.0;
    let (z, s, a) = rest_observation(&x);
    let obs = Observation {
        z: &z,
        sigma: &s,
        available: &a,
    };
    // EKF: straight after reset (step 0) and after a prediction (step 1).
    let mut ekf = Ekf::new(m.clone());
    for predict_first in [false, true] {
        ekf.reset(&x, &p_neg).unwrap();
        if predict_first {
            ekf.predict(&rest_window()).unwrap();
        }
        let step = usize::from(predict_first);
        match no_panic("ekf update", || ekf.update(&obs).cloned()) {
            Err(FilterError::NotPositiveDefinite {
                step: s,
                matrix: "S",
                pivot: 0,
                dim: 4,
                value,
            }) => {
                assert_eq!(s, step);
                assert!(value < 0.0);
            }
            other => panic!("ekf: expected S not positive definite, got {other:?}"),
        }
        assert!(ekf.state().iter().all(|v| v.is_finite()));
    }
    recovers(&mut ekf);
    // The simplified UKF's linear update meets the same S.
    let mut simp = Ukf::simplified(m.clone(), SigmaScaling::default()).unwrap();
    simp.reset(&x, &p_neg).unwrap();
    assert!(matches!(
        no_panic("simplified update", || simp.update(&obs).cloned()),
        Err(FilterError::NotPositiveDefinite {
            step: 0,
            matrix: "S",
            ..
        })
    ));
    // The standard UKF updating without a prediction draws points from P first.
    let mut std_ukf = Ukf::standard(m.clone(), SigmaScaling::default()).unwrap();
    std_ukf.reset(&x, &p_neg).unwrap();
    assert!(matches!(
        no_panic("standard update", || std_ukf.update(&obs).cloned()),
        Err(FilterError::NotPositiveDefinite {
            step: 0,
            matrix: "P",
            ..
        })
    ));
}

#[test]
fn bad_observations_are_invalid_and_change_nothing() {
    let m = model();
    let (x, p) = start();
    let (z, s, a) = rest_observation(&x);
    for mut f in all_filters(&m) {
        let name = f.name().to_string();
        f.reset(&x, &p).unwrap();
        f.predict(&rest_window()).unwrap();
        let (x1, p1) = (f.state().to_vec(), f.covariance().to_vec());
        let mut cases: Vec<(&str, [f64; 4], [f64; 4])> = Vec::new();
        for i in 0..4 {
            let mut zb = z;
            zb[i] = f64::NAN;
            cases.push(("NaN value", zb, s));
            zb[i] = f64::INFINITY;
            cases.push(("infinite value", zb, s));
            let mut sb = s;
            sb[i] = f64::NAN;
            cases.push(("NaN sigma", z, sb));
            sb[i] = 0.0;
            cases.push(("zero sigma", z, sb));
            sb[i] = -1.0;
            cases.push(("negative sigma", z, sb));
        }
        for (what, zb, sb) in &cases {
            let obs = Observation {
                z: zb,
                sigma: sb,
                available: &a,
            };
            let r = no_panic(&name, || f.update(&obs).cloned());
            assert!(
                matches!(r, Err(FilterError::Invalid(_))),
                "{name}, {what}: expected Invalid, got {r:?}"
            );
            assert_eq!(f.state(), &x1[..], "{name}, {what}: state changed");
            assert_eq!(
                f.covariance(),
                &p1[..],
                "{name}, {what}: covariance changed"
            );
        }
        // Wrong sizes of each of the three slices.
        let z3 = [0.0; 3];
        let s5 = [1.0; 5];
        let a3 = [true; 3];
        let wrong = [
            Observation {
                z: &z3,
                sigma: &s,
                available: &a,
            },
            Observation {
                z: &z,
                sigma: &s5,
                available: &a,
            },
            Observation {
                z: &z,
                sigma: &s,
                available: &a3,
            },
        ];
        for obs in &wrong {
            let r = no_panic(&name, || f.update(obs).cloned());
            assert!(
                matches!(r, Err(FilterError::Invalid(_))),
                "{name}: wrong-size observation gave {r:?}"
            );
        }
        assert_eq!(f.state(), &x1[..]);
        // NaN on an absent channel is not read.
        let mut zn = z;
        zn[2] = f64::NAN;
        let mut sn = s;
        sn[2] = f64::NAN;
        let avail = [true, true, false, true];
        let rep = f
            .update(&Observation {
                z: &zn,
                sigma: &sn,
                available: &avail,
            })
            .unwrap_or_else(|e| panic!("{name}: absent NaN channel: {e}"))
            .clone();
        assert_eq!(rep.channels, vec![0, 1, 3]);
        assert!(f.state().iter().all(|v| v.is_finite()), "{name}");
    }
}

#[test]
fn bad_resets_and_inputs_are_typed_errors() {
    let m = model();
    let n = BASE_DIM;
    let (x, p) = start();
    for mut f in all_filters(&m) {
        let name = f.name().to_string();
        assert!(
            matches!(f.reset(&x[..n - 1], &p), Err(FilterError::Invalid(_))),
            "{name}: short state"
        );
        assert!(
            matches!(f.reset(&x, &p[..n]), Err(FilterError::Invalid(_))),
            "{name}: short covariance"
        );
        let mut xn = x.clone();
        xn[3] = f64::NAN;
        assert!(
            matches!(
                f.reset(&xn, &p),
                Err(FilterError::NonFinite { step: 0, .. })
            ),
            "{name}: NaN state"
        );
        let mut pn = p.clone();
        pn[5] = f64::INFINITY;
        assert!(
            matches!(
                f.reset(&x, &pn),
                Err(FilterError::NonFinite { step: 0, .. })
            ),
            "{name}: infinite covariance"
        );
        // A NaN specific force: the window is refused before anything moves.
        f.reset(&x, &p).unwrap();
        let mut w = InputWindow::with_capacity(3);
        w.push_linear(0.0, [0.0, 0.0, 9.8]);
        w.push_linear(0.5, [f64::NAN, 0.0, 9.8]);
        w.push_linear(1.0, [0.0, 0.0, 9.8]);
        let r = no_panic(&name, || f.predict(&w));
        assert!(
            matches!(&r, Err(FilterError::Invalid(m)) if m.contains("step 1") && m.contains("non-finite")),
            "{name}: NaN input gave {r:?}"
        );
        recovers(&mut *f);
        // A window without sub-steps, or running backwards, is refused (and does not panic).
        f.reset(&x, &p).unwrap();
        let empty = InputWindow::default();
        let r = no_panic(&name, || f.predict(&empty));
        assert!(
            matches!(r, Err(FilterError::Invalid(_))),
            "{name}: empty window gave {r:?}"
        );
        let mut back = InputWindow::with_capacity(2);
        back.push_linear(1.0, [0.0, 0.0, 9.8]);
        back.push_linear(0.5, [0.0, 0.0, 9.8]);
        let r = no_panic(&name, || f.predict(&back));
        assert!(
            matches!(r, Err(FilterError::Invalid(_))),
            "{name}: backward window gave {r:?}"
        );
        for i in 0..n {
            assert!(
                (f.state()[i] - x[i]).abs() <= 1e-12 * (1.0 + x[i].abs()),
                "{name}"
            );
            let pi = f.covariance()[i + i * n];
            assert!(
                (pi - p[i + i * n]).abs() <= 1e-9 * p[i + i * n],
                "{name}: P[{i},{i}]"
            );
        }
    }
}

#[test]
fn runner_reports_where_a_filter_failed() {
    let sim = common::base_simulator(600.0);
    let run = sim.run(5, 0);
    let (x0, mut p0) = common::initial_estimate(&sim, &run);
    let n = BASE_DIM;
    p0[PHI_X + PHI_Y * n] = 2.0 * p0[PHI_X + PHI_X * n];
    p0[PHI_Y + PHI_X * n] = 2.0 * p0[PHI_X + PHI_X * n];
    let mut f = Ukf::simplified(sim.model().clone(), SigmaScaling::default()).unwrap();
    f.reset(&x0, &p0).unwrap();
    let mut seen = 0;
    let r = Runner::new(16).run(
        &mut f,
        0.0,
        sim.inputs(),
        &run.measurements,
        sim.noise(),
        |_| seen += 1,
    );
    assert_eq!(seen, 0);
    match r {
        Err(RunError {
            index: 0,
            t,
            error: FilterError::NotPositiveDefinite { step: 1, .. },
        }) => assert_eq!(t, 1.0),
        other => panic!("expected the first measurement's prediction to fail, got {other:?}"),
    }
}

/// Every filter's covariance is exactly symmetric after every prediction and update, while the
/// platform accelerates and turns (so that every block of the EKF's transition matrix is
/// filled). Catches a filter that skips the symmetrisation where its arithmetic does not
/// guarantee it (the EKF symmetrises only the block its propagation computes both ways round).
#[test]
fn covariances_stay_exactly_symmetric() {
    let m = model();
    let (x0, p0) = start();
    let n = m.dim();
    let check = |f: &dyn Filter, after: &str| {
        let p = f.covariance();
        for i in 0..n {
            for j in 0..i {
                assert_eq!(
                    p[i + j * n].to_bits(),
                    p[j + i * n].to_bits(),
                    "{} after {after}: P[{i}][{j}] {:e} vs P[{j}][{i}] {:e}",
                    f.name(),
                    p[i + j * n],
                    p[j + i * n]
                );
            }
        }
    };
    for mut f in all_filters(&m) {
        f.reset(&x0, &p0).unwrap();
        for step in 0..20 {
            let mut w = InputWindow::with_capacity(11);
            for k in 0..=10 {
                let t = step as f64 + 0.1 * k as f64;
                w.push_linear(t, [0.4 * (0.3 * t).sin(), 0.3 * (0.2 * t).cos(), 9.806]);
            }
            f.predict(&w).unwrap();
            check(&*f, "prediction");
            let (z, sigma, available) = rest_observation(f.state());
            let obs = Observation {
                z: &z,
                sigma: &sigma,
                available: &available,
            };
            f.update(&obs).unwrap();
            check(&*f, "update");
        }
    }
}
