//! Helpers shared by the integration tests: realistic random states, finite-difference
//! Jacobians and their comparison with the analytic ones, and small propagation wrappers.
//!
//! Each test file uses only some of them.
#![allow(dead_code)]

pub mod datasets;
pub mod markdown;
pub mod scratch;

use navkf_dynamics::kinematics::IntoInput;
use navkf_dynamics::state::*;
use navkf_dynamics::system::propagate_generic;
use navkf_dynamics::{Input, InputWindow, PlatformModel, SystemModel};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// A seeded generator, so that a failure is reproducible.
pub fn rng(seed: u64) -> ChaCha8Rng {
    ChaCha8Rng::seed_from_u64(seed)
}

// Each test file uses some of these.
#[allow(unused_imports)]
pub use navkf_dynamics::partials_check::{
    base_coefficient_scale, base_measurement, central_difference, coefficient_scales, random_input,
    random_state, signed, steps, Comparison, FiniteDiff, Steps, MEAS_RTOL, MEAS_STEPS, RATE_RTOL,
    RATE_STEPS,
};

/// The base measurement Jacobian `H = [0 I_4 0]`.
pub fn base_measurement_jacobian(n: usize) -> Vec<f64> {
    let mut h = vec![0.0; MEAS_DIM * n];
    for (r, c) in [V_X, V_Y, LAT, LON].into_iter().enumerate() {
        h[r * n + c] = 1.0;
    }
    h
}

/// A comparison as the tests read it: the worst `|error| / tolerance` when every entry
/// passes, else every failing entry, one a line.
pub fn verdict(c: Comparison, names: &[String]) -> Result<f64, String> {
    if c.failures.is_empty() {
        return Ok(c.worst.map_or(0.0, |w| w.ratio()));
    }
    let lines: Vec<String> = c
        .failures
        .iter()
        .map(|b| {
            format!(
                "  d(row {})/d({}): analytic {:e}, numeric {:e}, |diff| {:e} > tol {:e}",
                b.row,
                names[b.col],
                b.analytic,
                b.numeric,
                (b.analytic - b.numeric).abs(),
                b.tolerance
            )
        })
        .collect();
    Err(lines.join("\n"))
}

/// Checks `rate_jacobian` against central differences of `rates` at `(x, u)`
/// ([`navkf_dynamics::partials_check::check_rate_jacobian`]).
pub fn check_rate_jacobian(model: &PlatformModel, x: &[f64], u: &Input) -> Result<f64, String> {
    verdict(
        navkf_dynamics::partials_check::check_rate_jacobian(model, x, u),
        &model.state_names(),
    )
}

/// Checks `measurement_jacobian` against central differences of `measure` at `x`
/// ([`navkf_dynamics::partials_check::check_measurement_jacobian`]).
pub fn check_measurement_jacobian(model: &PlatformModel, x: &[f64]) -> Result<f64, String> {
    verdict(
        navkf_dynamics::partials_check::check_measurement_jacobian(model, x),
        &model.state_names(),
    )
}

/// A window of knots `0, h, 2h, ..., T` with a constant input (midpoints by `push_linear`).
pub fn constant_window(f: impl IntoInput + Copy, h: f64, duration: f64) -> InputWindow {
    let steps = (duration / h).round() as usize;
    let mut w = InputWindow::with_capacity(steps + 1);
    for j in 0..=steps {
        w.push_linear(j as f64 * h, f);
    }
    w
}

/// Propagates `x` across `window` with `propagate_generic`.
pub fn propagate(
    model: &PlatformModel,
    x: &mut [f64],
    noise: Option<&[f64]>,
    window: &InputWindow,
) {
    let mut scratch = navkf_dynamics::PropagationScratch::new(model.scratch_len(1));
    navkf_dynamics::system::propagate_generic(model, x, noise, window, scratch.as_mut_slice());
}

/// A base-model state with every entry zero except latitude and longitude.
pub fn rest_state(dim: usize, lat: f64, lon: f64) -> Vec<f64> {
    let mut x = vec![0.0; dim];
    x[LAT] = lat;
    x[LON] = lon;
    x
}

/// One second of input in 10 sub-steps, varying in every component.
pub fn window() -> InputWindow {
    let mut w = InputWindow::with_capacity(11);
    for k in 0..=10 {
        let t = 0.1 * k as f64;
        w.push_linear(t, [0.8 * (t * 2.0).sin(), -0.5 + 0.3 * t, 9.806]);
    }
    w
}

/// `start`'s points propagated one at a time by the generic RK4.
pub fn one_by_one(
    model: &PlatformModel,
    start: &[f64],
    noise: Option<&[f64]>,
    w: &InputWindow,
) -> Vec<f64> {
    let (n, nw) = (model.dim(), model.noise_channels().len());
    let mut out = start.to_vec();
    let mut scratch = vec![0.0; model.scratch_len(1)];
    for (i, x) in out.chunks_exact_mut(n).enumerate() {
        propagate_generic(
            model,
            x,
            noise.map(|v| &v[i * nw..(i + 1) * nw]),
            w,
            &mut scratch,
        );
    }
    out
}

/// Propagates `points` of `model` (one after another) across `window` in one batch
/// ([`SystemModel::propagate_points`]) and each alone (`propagate_generic`), with `noise`
/// (one value per channel per point) held over the window; asserts that every state of every
/// point lands within `1e-13` of its size (floor 1e-6) of itself, and returns the points
/// propagated alone.
pub fn batch_matches_one_point(
    model: &dyn SystemModel,
    points: &[f64],
    noise: &[f64],
    window: &InputWindow,
) -> Vec<f64> {
    let n = model.dim();
    let nw = model.noise_channels().len();
    let count = points.len() / n;
    let mut batch = points.to_vec();
    let mut scratch = model.propagation_scratch(count);
    model.propagate_points(&mut batch, Some(noise), window, &mut scratch);
    let mut one = vec![0.0; 4 * model.dynamic_dim() + n];
    let mut alone = points.to_vec();
    for p in 0..count {
        let x = &mut alone[p * n..(p + 1) * n];
        propagate_generic(
            model,
            x,
            Some(&noise[p * nw..(p + 1) * nw]),
            window,
            &mut one,
        );
        for i in 0..n {
            let b = batch[p * n + i];
            assert!(
                (b - x[i]).abs() <= 1e-13 * x[i].abs().max(1e-6),
                "point {p}, state {i}: batch {b:e}, alone {:e}",
                x[i]
            );
        }
    }
    alone
}
