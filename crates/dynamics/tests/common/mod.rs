//! Helpers shared by the integration tests: realistic random states, finite-difference
//! Jacobians and their comparison with the analytic ones, and small propagation wrappers.
//!
//! Each test file uses only some of them.
#![allow(dead_code)]

pub mod datasets;

use navkf_dynamics::kinematics::{platform_input, IntoInput};
use navkf_dynamics::state::*;
use navkf_dynamics::system::propagate_generic;
use navkf_dynamics::{Input, InputWindow, PlatformModel, SystemModel};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// A seeded generator, so that a failure is reproducible.
pub fn rng(seed: u64) -> ChaCha8Rng {
    ChaCha8Rng::seed_from_u64(seed)
}

/// A value of magnitude `scale * [0.5, 1.5)` with a random sign: never near zero, so that
/// every term it multiplies contributes to the derivatives being checked.
pub fn signed(rng: &mut ChaCha8Rng, scale: f64) -> f64 {
    let m = scale * rng.gen_range(0.5..1.5);
    if rng.gen::<bool>() {
        m
    } else {
        -m
    }
}

/// Typical size of a base coefficient of a navigation-grade platform
/// (docs/model.md, "The state"): gyro drifts 1e-7 rad/s, g-sensitive drifts 1e-8 rad/s per
/// m/s^2, accelerometer bias 5e-4 m/s^2, accelerometer scale factor 5e-5.
pub fn base_coefficient_scale(i: usize) -> f64 {
    match i {
        KG0X | KG0Y | KG0Z => 1e-7,
        7..=15 => 1e-8,
        KA0X | KA0Y => 5e-4,
        KA1X | KA1Y => 5e-5,
        _ => panic!("state {i} is not a base coefficient"),
    }
}

/// Typical size of every coefficient of `model` (base table, then the effects' sigmas);
/// zero for the navigation states.
pub fn coefficient_scales(model: &PlatformModel) -> Vec<f64> {
    let mut s = vec![0.0; model.dim()];
    for (i, v) in s.iter_mut().enumerate().take(BASE_DIM).skip(NAV_DIM) {
        *v = base_coefficient_scale(i);
    }
    for (i, sigma) in model.effect_coefficient_sigmas() {
        s[i] = sigma;
    }
    s
}

/// A realistic random state: latitude 45 +- 5 deg, longitude 100-130 deg, speeds 2-20 m/s
/// of either sign, attitude errors ~1e-3 rad, every coefficient at its typical size.
pub fn random_state(model: &PlatformModel, rng: &mut ChaCha8Rng) -> Vec<f64> {
    let scales = coefficient_scales(model);
    let mut x = vec![0.0; model.dim()];
    for v in x.iter_mut().take(3) {
        *v = signed(rng, 1e-3);
    }
    x[V_X] = signed(rng, 11.0);
    x[V_Y] = signed(rng, 11.0);
    x[LAT] = (45.0 + rng.gen_range(-5.0..5.0f64)).to_radians();
    x[LON] = rng.gen_range(100.0..130.0f64).to_radians();
    for i in NAV_DIM..model.dim() {
        x[i] = signed(rng, scales[i]);
    }
    x
}

/// A realistic specific force: up to 2 m/s^2 horizontally, ~9.8 vertically.
pub fn random_input(rng: &mut ChaCha8Rng) -> Input {
    platform_input([
        rng.gen_range(-2.0..2.0),
        rng.gen_range(-2.0..2.0),
        9.8 + rng.gen_range(-0.1..0.1),
    ])
}

/// Finite-difference steps, one per state, relative to each state's scale.
#[derive(Debug, Clone, Copy)]
pub struct Steps {
    /// Attitude errors, rad.
    pub phi: f64,
    /// Velocities, m/s.
    pub v: f64,
    /// Latitude and longitude, rad.
    pub pos: f64,
    /// Coefficients, as a fraction of their typical size.
    pub coeff_rel: f64,
}

/// Steps for the state equations. Everything there varies on scales of ~1 rad (attitude,
/// latitude through sin/cos/tan), ~1e7 m/s (velocity through v/R) or is linear (coefficients),
/// so the central-difference truncation error `h^2 f'''/6` is below 1e-11 relative with
/// these steps, and the steps are as large as that allows to keep rounding small.
pub const RATE_STEPS: Steps = Steps {
    phi: 1e-6,
    v: 1e-4,
    pos: 1e-6,
    coeff_rel: 1e-3,
};

/// Steps for the measurement. `z_L = L + (effect terms)` carries the whole latitude, ~0.8 rad,
/// so one rounding of `z_L` is ~1e-16 rad and only larger steps resolve the small latitude and
/// velocity partials the effects add there (e.g. `-tau v_y d(1/RM)/dL ~ 3e-9`, resolved to
/// ~1 % by the 1e-4 rad step). The latitude step is capped by truncation: `sec L / RN` has
/// `f'''/f' ~ tan^2 L + 5 sec^2 L`, ~50 at 70 deg, so `h^2/6 * 50 ~ 1e-7` relative.
pub const MEAS_STEPS: Steps = Steps {
    phi: 1e-4,
    v: 1e-2,
    pos: 1e-4,
    coeff_rel: 1e-1,
};

/// The step of every state of `model`.
pub fn steps(model: &PlatformModel, s: Steps) -> Vec<f64> {
    let scales = coefficient_scales(model);
    (0..model.dim())
        .map(|i| match i {
            PHI_X..=PHI_Z => s.phi,
            V_X | V_Y => s.v,
            LAT | LON => s.pos,
            _ => s.coeff_rel * scales[i],
        })
        .collect()
}

/// Unit roundoff of f64.
pub const EPS: f64 = f64::EPSILON;

/// The central-difference Jacobian of `f: R^n -> R^rows` at `x`, row-major, and for each
/// entry the rounding floor of that difference.
///
/// The floor: each evaluation of `f_r` is a sum of terms whose magnitudes add up to at most
/// `m_r`, so it is off by a few ulp of `m_r`; the difference quotient divides that by the
/// step `2 h_c`. `floor(r, c) = ROUNDING_ULPS * eps * m_r / (2 h_c)`. The step used is the one
/// actually taken, `(x + h) - (x - h)`, which is exact in floating point.
pub const ROUNDING_ULPS: f64 = 16.0;

/// Result of a finite-difference evaluation.
pub struct FiniteDiff {
    /// Numerical Jacobian, row-major `rows x n`.
    pub jac: Vec<f64>,
    /// Step actually taken per column, `(x + h) - (x - h)`.
    pub span: Vec<f64>,
}

/// Central differences of `f` at `x` with per-state steps `h`.
pub fn central_difference<F>(x: &[f64], h: &[f64], rows: usize, mut f: F) -> FiniteDiff
where
    F: FnMut(&[f64], &mut [f64]),
{
    let n = x.len();
    let mut jac = vec![0.0; rows * n];
    let mut span = vec![0.0; n];
    let mut xp = x.to_vec();
    let mut fp = vec![0.0; rows];
    let mut fm = vec![0.0; rows];
    for c in 0..n {
        xp[c] = x[c] + h[c];
        let hi = xp[c];
        f(&xp, &mut fp);
        xp[c] = x[c] - h[c];
        let lo = xp[c];
        f(&xp, &mut fm);
        xp[c] = x[c];
        span[c] = hi - lo;
        for r in 0..rows {
            jac[r * n + c] = (fp[r] - fm[r]) / span[c];
        }
    }
    FiniteDiff { jac, span }
}

/// One entry where the analytic and numerical Jacobians disagree.
#[derive(Debug)]
pub struct Mismatch {
    pub row: usize,
    pub col: usize,
    pub analytic: f64,
    pub numeric: f64,
    pub tolerance: f64,
}

/// Compares `analytic` with `fd` entry by entry.
///
/// Tolerance of entry `(r, c)`: `rtol * |J(r, c)| + floor(r, c)`, where `|J(r, c)|` is the
/// magnitude of the entry being checked (units differ from row to row, so each entry is
/// judged against its own size, not against the largest in its column) and `floor` is the
/// rounding floor above, computed from the row's term magnitudes `m[r]`. `rtol` covers the
/// truncation error `h^2 f'''/6`. Any analytic error larger than what finite differences can
/// resolve is reported, including a missing small term. A NaN (an entry the analytic code
/// did not write) is always reported.
pub fn compare(
    analytic: &[f64],
    fd: &FiniteDiff,
    m: &[f64],
    rtol: f64,
    names: &[String],
) -> Result<f64, String> {
    let n = fd.span.len();
    let rows = m.len();
    assert_eq!(analytic.len(), rows * n, "analytic Jacobian size");
    let mut bad = Vec::new();
    let mut worst: f64 = 0.0;
    for r in 0..rows {
        for c in 0..n {
            let a = analytic[r * n + c];
            let d = fd.jac[r * n + c];
            let floor = ROUNDING_ULPS * EPS * m[r] / fd.span[c];
            let tol = rtol * a.abs().max(d.abs()) + floor;
            let err = (a - d).abs();
            // `is_nan` first: a NaN (unwritten entry) must fail, not slip past a comparison.
            if err.is_nan() || err > tol {
                bad.push(Mismatch {
                    row: r,
                    col: c,
                    analytic: a,
                    numeric: d,
                    tolerance: tol,
                });
            } else if tol > 0.0 {
                worst = worst.max(err / tol);
            }
        }
    }
    if bad.is_empty() {
        Ok(worst)
    } else {
        let lines: Vec<String> = bad
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
}

/// Relative tolerance of the rate Jacobian check: truncation with [`RATE_STEPS`] is below
/// 1e-11 relative; 1e-9 leaves room without hiding any real error.
pub const RATE_RTOL: f64 = 1e-9;
/// Relative tolerance of the measurement Jacobian check: truncation with [`MEAS_STEPS`] is
/// below ~1e-7 relative up to 70 deg of latitude.
pub const MEAS_RTOL: f64 = 1e-6;

/// Checks `rate_jacobian` against central differences of `rates` at `(x, u)`.
/// Returns the worst `|error| / tolerance` seen.
pub fn check_rate_jacobian(model: &PlatformModel, x: &[f64], u: &Input) -> Result<f64, String> {
    let n = model.dim();
    let d = model.dynamic_dim();
    // Filled with NaN: an entry the analytic code leaves unwritten fails the comparison.
    let mut jac = vec![f64::NAN; d * n];
    model.rate_jacobian(x, u, &mut jac);
    let fd = central_difference(x, &steps(model, RATE_STEPS), d, |xx, out| {
        model.rates(xx, u, out)
    });
    // Term magnitudes of each row: the rate itself, every linear term J(r, c) x_c, the
    // specific force, which enters v_x' and v_y' directly (a term the Jacobian does not see),
    // and in the attitude rows the Earth's and the transport rates, which enter through the
    // attitude's rotation and may cancel to a rate far smaller than either (the exact
    // variant at large angles).
    let mut r0 = vec![0.0; d];
    model.rates(x, u, &mut r0);
    let transport = (x[V_X].abs() + x[V_Y].abs()) / 6.3e6 * (1.0 + x[LAT].tan().abs());
    let m: Vec<f64> = (0..d)
        .map(|r| {
            let lin: f64 = (0..n).map(|c| (jac[r * n + c] * x[c]).abs()).sum();
            let force = if r == V_X || r == V_Y {
                u.iter().map(|f| f.abs()).sum()
            } else {
                0.0
            };
            let turning = if r < 3 {
                navkf_dynamics::earth::WIE + transport
            } else {
                0.0
            };
            r0[r].abs() + lin + force + turning
        })
        .collect();
    compare(&jac, &fd, &m, RATE_RTOL, &model.state_names())
}

/// `[v_x, v_y, L, lambda]`: the base measurement, written independently of the model.
pub fn base_measurement(x: &[f64]) -> [f64; MEAS_DIM] {
    [x[V_X], x[V_Y], x[LAT], x[LON]]
}

/// The base measurement Jacobian `H = [0 I_4 0]`.
pub fn base_measurement_jacobian(n: usize) -> Vec<f64> {
    let mut h = vec![0.0; MEAS_DIM * n];
    for (r, c) in [V_X, V_Y, LAT, LON].into_iter().enumerate() {
        h[r * n + c] = 1.0;
    }
    h
}

/// Checks `measurement_jacobian` against central differences of `measure` at `x`.
///
/// The base part `[v_x, v_y, L, lambda]` is subtracted from both sides before comparing (it is
/// checked exactly elsewhere): the effects' partials there are ~1e-9 next to the identity's 1,
/// and a tolerance relative to the whole entry would hide them. The difference of two nearby
/// floats is exact, so the subtraction adds no error; the rounding of `z` itself is in the
/// floor through `|z_r|`.
pub fn check_measurement_jacobian(model: &PlatformModel, x: &[f64]) -> Result<f64, String> {
    let n = model.dim();
    let rows = model.meas_dim();
    let mut h = vec![f64::NAN; rows * n];
    model.measurement_jacobian(x, &mut h);
    let base = base_measurement_jacobian(n);
    let h_eff: Vec<f64> = h.iter().zip(&base).map(|(a, b)| a - b).collect();
    let fd = central_difference(x, &steps(model, MEAS_STEPS), rows, |xx, out| {
        model.measure(xx, out);
        let b = base_measurement(xx);
        for (o, bi) in out.iter_mut().zip(b) {
            *o -= bi;
        }
    });
    let mut z0 = vec![0.0; rows];
    model.measure(x, &mut z0);
    let m: Vec<f64> = (0..rows)
        .map(|r| {
            let lin: f64 = (0..n).map(|c| (h[r * n + c] * x[c]).abs()).sum();
            z0[r].abs() + lin
        })
        .collect();
    compare(&h_eff, &fd, &m, MEAS_RTOL, &model.state_names())
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
