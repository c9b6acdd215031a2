//! `propagate_generic` is a fourth-order integrator when the window's midpoints carry the
//! exact input (`InputWindow::push_with_mid`), and drops to second order when they are the
//! average of the knots (`push_linear`), which shows that the midpoint input is really used
//! at the two middle stages.
//!
//! A non-trivial state (moving at ~15 m/s, attitude errors ~1e-3 rad, every coefficient of
//! the full catalogue at its typical size) is propagated for 100 s under a smooth turning
//! input, with steps h, h/2, h/4, and compared with a reference at h/64.

use crate::common;

use common::*;
use navkf_dynamics::state::*;
use navkf_dynamics::{InputWindow, NoiseConfig, PlatformModel, Registry};

const T: f64 = 100.0;
const H: f64 = 1.0;

/// A vehicle turning at 0.3 rad/s with 1.5 m/s^2 of centripetal force, plus a slower
/// along-track oscillation and a small vertical vibration: analytic, so the exact midpoint
/// input is known.
fn force(t: f64) -> navkf_dynamics::kinematics::SpecificForce {
    let psi = 0.3 * t;
    let along = 0.8 * (0.11 * t).sin();
    [
        -1.5 * psi.sin() + along * psi.cos(),
        1.5 * psi.cos() + along * psi.sin(),
        9.806 + 0.05 * (0.7 * t).sin(),
    ]
}

fn window(h: f64, exact_mid: bool) -> InputWindow {
    let n = (T / h).round() as usize;
    let mut w = InputWindow::with_capacity(n + 1);
    for j in 0..=n {
        let t = j as f64 * h;
        if exact_mid {
            w.push_with_mid(t, force(t), force(t - 0.5 * h));
        } else {
            w.push_linear(t, force(t));
        }
    }
    w
}

fn model() -> PlatformModel {
    let reg = Registry::catalogue();
    PlatformModel::new(
        reg.build_all(&reg.names()).unwrap(),
        &NoiseConfig::default(),
    )
    .unwrap()
}

fn initial(model: &PlatformModel) -> Vec<f64> {
    let mut rng = rng(7);
    let mut x = random_state(model, &mut rng);
    x[V_X] = 12.0;
    x[V_Y] = -9.0;
    x
}

fn run(model: &PlatformModel, x0: &[f64], h: f64, exact_mid: bool) -> Vec<f64> {
    let mut x = x0.to_vec();
    propagate(model, &mut x, None, &window(h, exact_mid));
    x
}

const NAMES: [&str; NAV_DIM] = ["phi_x", "phi_y", "phi_z", "v_x", "v_y", "L", "lambda"];

/// Error ratios `e(h)/e(h/2)` and `e(h/2)/e(h/4)` of every navigation state, with the errors.
fn ratios(exact_mid: bool) -> Vec<(usize, [f64; 3], [f64; 2])> {
    let model = model();
    let x0 = initial(&model);
    let reference = run(&model, &x0, H / 64.0, exact_mid);
    let err = |h: f64| {
        let x = run(&model, &x0, h, exact_mid);
        (0..NAV_DIM)
            .map(|i| (x[i] - reference[i]).abs())
            .collect::<Vec<_>>()
    };
    let (e1, e2, e4) = (err(H), err(H / 2.0), err(H / 4.0));
    (0..NAV_DIM)
        .map(|i| (i, [e1[i], e2[i], e4[i]], [e1[i] / e2[i], e2[i] / e4[i]]))
        .collect()
}

/// Catches: a wrong RK4 weight or stage (order drops to 1-3), stage inputs taken from the
/// wrong knot or the midpoint input replaced by the knots' average (order 2, ratio 4), noise-
/// or coefficient-drift bookkeeping that perturbs the stages, or a model whose `rates` is not
/// smooth in the state.
///
/// Observed ratios are 15.0-16.6 for all seven states. The smallest errors checked (L at h/4,
/// ~1e-14 rad) are still ~100 ulp of L, so rounding moves a ratio by a few percent at most.
#[test]
fn rk4_converges_at_fourth_order_with_exact_midpoints() {
    for (i, e, r) in ratios(true) {
        for ratio in r {
            assert!(
                (12.0..=20.0).contains(&ratio),
                "{}: errors at h, h/2, h/4 = {e:?}, ratios {r:?}: expected ~16",
                NAMES[i]
            );
        }
    }
}

/// With `push_linear` the middle stages see the average of the knots, an O(h^2) input
/// error: the method is then second order (ratio ~4). With the test above, this pins that the
/// middle stages see `f_mid` and nothing else; an integrator that held one knot's input over
/// the step would be first order (ratio ~2) in both.
#[test]
fn linear_midpoints_give_second_order() {
    for (i, e, r) in ratios(false) {
        for ratio in r {
            assert!(
                (3.5..=4.5).contains(&ratio),
                "{}: errors at h, h/2, h/4 = {e:?}, ratios {r:?}: expected ~4",
                NAMES[i]
            );
        }
    }
}
