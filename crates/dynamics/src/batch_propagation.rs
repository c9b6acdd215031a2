//! Batched RK4 propagation of many states at once: the UKF's hot path.
//!
//! A UKF step sends 41 to 59 sigma points through 10 RK4 sub-steps, 4 derivative calls each;
//! that is almost all of its cost. Here points travel in blocks of [`LANES`], each state of a
//! block one [`Lanes`] value, and the model's own rates ([`PlatformModel::nav_rates`], with
//! every switched-on effect's) are evaluated on them: the compiler turns the element-wise
//! arithmetic into SIMD instructions. Only `sin L` and `cos L` are computed differently from
//! the one-state path: from one `sin_cos` of a reference latitude per window and the
//! angle-addition formula with Taylor series of the offset `d = L - L_ref` (terms up to `d^9`
//! and `d^10`; the path is taken only while `|d| < 0.03 rad`, where the first omitted term is
//! below 1e-20). The two paths agree to rounding; a test checks it.
//!
//! The RK4 stages are the table [`RK4`], stepped through as
//! [`crate::integrate::propagate_generic`] does, operation for operation, including noise held over the window and coefficients that a noise channel
//! drives moving linearly.

use crate::attitude::{exact_rates, Attitude};
use crate::integrate::{rk4_step, InputWindow, PropagationScratch, RK4};
use crate::kinematics::Kinematics;
use crate::model::PlatformModel;
use crate::real::{Lanes, LANES};
use crate::state::*;
use crate::system::SystemModel;

/// Largest latitude offset from the reference for which the series are used.
pub const MAX_OFFSET: f64 = 0.03;

/// `sin(d)` and `cos(d)` by their Taylor series in Horner form, for `|d| < MAX_OFFSET`
/// (coefficients are reciprocal factorials, multiplied rather than divided: a vector divide
/// costs ten multiplies).
#[inline(always)]
fn small_sin_cos(d: f64) -> (f64, f64) {
    const S3: f64 = -1.0 / 6.0;
    const S5: f64 = 1.0 / 120.0;
    const S7: f64 = -1.0 / 5040.0;
    const S9: f64 = 1.0 / 362_880.0;
    const C2: f64 = -1.0 / 2.0;
    const C4: f64 = 1.0 / 24.0;
    const C6: f64 = -1.0 / 720.0;
    const C8: f64 = 1.0 / 40_320.0;
    const C10: f64 = -1.0 / 3_628_800.0;
    let d2 = d * d;
    let s = d + d * d2 * (S3 + d2 * (S5 + d2 * (S7 + d2 * S9)));
    let c = 1.0 + d2 * (C2 + d2 * (C4 + d2 * (C6 + d2 * (C8 + d2 * C10))));
    (s, c)
}

/// Navigation-state derivatives of a block at states `x` (all `n` states, as lanes).
/// `EFFECTS` says whether the model has effects with rates: without, nothing takes the
/// kinematics' address, and they stay in registers. `EXACT` selects the exact-attitude
/// variant ([`crate::attitude`]).
#[inline(always)]
fn rates<const EFFECTS: bool, const EXACT: bool>(
    model: &PlatformModel,
    x: &[Lanes],
    f: &crate::kinematics::Input,
    reference: (f64, f64, f64),
) -> [Lanes; NAV_DIM] {
    let (lat_ref, s0, c0) = reference;
    let mut sin_l = Lanes::default();
    let mut cos_l = Lanes::default();
    for l in 0..LANES {
        let (sd, cd) = small_sin_cos(x[LAT].0[l] - lat_ref);
        sin_l.0[l] = s0 * cd + c0 * sd;
        cos_l.0[l] = c0 * cd - s0 * sd;
    }
    let k = Kinematics::values(x, f, sin_l, cos_l);
    if EXACT {
        let mut terms = model.base_terms(x, &k);
        if EFFECTS {
            model.add_effect_rates(x, &k, &mut terms);
        }
        return exact_rates(&k, &terms);
    }
    let mut r = model.base_rates(x, &k);
    if EFFECTS {
        model.add_effect_rates(x, &k, &mut r);
    }
    r
}

/// Whether the batched path applies to these points over this window: every latitude within
/// reach of the reference for the whole window.
pub fn applicable(points: &[f64], n: usize, window: &InputWindow, lat_ref: f64) -> bool {
    let mut max_d: f64 = 0.0;
    let mut max_v: f64 = 0.0;
    for x in points.chunks_exact(n) {
        max_d = max_d.max((x[LAT] - lat_ref).abs());
        max_v = max_v.max(x[V_Y].abs());
    }
    // Latitude cannot move faster than |v_y| / RM (RM > 6.3e6 m) plus what the velocity can
    // gain within the window; allow a factor of 2 on the distance and 50 km slack.
    let reach = (2.0 * max_v * window.duration() + 5.0e4) / 6.3e6;
    max_d.is_finite() && max_d + reach < MAX_OFFSET
}

/// Lanes of scratch [`propagate`] uses for a model of `n` states.
pub fn scratch_lanes(n: usize) -> usize {
    3 * n
}

/// Propagates `points` (each `model.dim()` long, one after another) across `window`.
/// `noise`, when given, holds one value per noise channel per point, held over the window.
pub fn propagate(
    model: &PlatformModel,
    points: &mut [f64],
    noise: Option<&[f64]>,
    window: &InputWindow,
    scratch: &mut PropagationScratch,
) {
    let exact = model.attitude() == Attitude::Exact;
    match (model.has_rate_effects(), exact) {
        (true, false) => propagate_blocks::<true, false>(model, points, noise, window, scratch),
        (false, false) => propagate_blocks::<false, false>(model, points, noise, window, scratch),
        (true, true) => propagate_blocks::<true, true>(model, points, noise, window, scratch),
        (false, true) => propagate_blocks::<false, true>(model, points, noise, window, scratch),
    }
}

/// [`propagate`], compiled with and without effects' rates, for each attitude variant.
fn propagate_blocks<const EFFECTS: bool, const EXACT: bool>(
    model: &PlatformModel,
    points: &mut [f64],
    noise: Option<&[f64]>,
    window: &InputWindow,
    scratch: &mut PropagationScratch,
) {
    let n = model.dim();
    let count = points.len() / n;
    if count == 0 || window.substeps() == 0 {
        return;
    }
    let lat_ref = points[LAT];
    let (s0, c0) = lat_ref.sin_cos();
    let reference = (lat_ref, s0, c0);
    let channels = model.noise_channels();
    let nw = channels.len();
    // Coefficients a noise channel drives move linearly over the window.
    let drifting = noise.is_some() && channels.iter().any(|c| c.state >= NAV_DIM);
    let (x, rest) = scratch.lanes(scratch_lanes(n)).split_at_mut(n);
    let (tmp, w) = rest.split_at_mut(n);
    for first in (0..count).step_by(LANES) {
        // Gather; padding lanes repeat the block's first point (valid numbers, discarded).
        w.fill(Lanes::default());
        for l in 0..LANES {
            let p = if first + l < count { first + l } else { first };
            let src = &points[p * n..(p + 1) * n];
            for (xs, v) in x.iter_mut().zip(src) {
                xs.0[l] = *v;
            }
            if let Some(values) = noise {
                for (j, c) in channels.iter().enumerate() {
                    w[c.state].0[l] += values[p * nw + j];
                }
            }
        }
        let add_noise = |k: &mut [Lanes; NAV_DIM], w: &[Lanes]| {
            if noise.is_some() {
                for (ki, wi) in k.iter_mut().zip(w) {
                    *ki += *wi;
                }
            }
        };
        // tmp = x + c k on the navigation states.
        let stage = |tmp: &mut [Lanes], x: &[Lanes], c: f64, k: &[Lanes; NAV_DIM]| {
            for ((t, xi), ki) in tmp.iter_mut().zip(x).zip(k) {
                *t = *xi + *ki * c;
            }
        };
        let drift = |tmp: &mut [Lanes], x: &[Lanes], w: &[Lanes], tau: f64| {
            for s in NAV_DIM..n {
                tmp[s] = x[s] + w[s] * tau;
            }
        };
        tmp.copy_from_slice(x);
        let mut k = [[Lanes::default(); NAV_DIM]; 4];
        for j in 0..window.substeps() {
            let h = window.t[j + 1] - window.t[j];
            for (s, st) in RK4.iter().enumerate() {
                let u = st.input(window, j);
                k[s] = if s == 0 {
                    rates::<EFFECTS, EXACT>(model, x, u, reference)
                } else {
                    let c = st.offset(h);
                    stage(tmp, x, c, &k[s - 1]);
                    if drifting {
                        drift(tmp, x, w, c);
                    }
                    rates::<EFFECTS, EXACT>(model, tmp, u, reference)
                };
                add_noise(&mut k[s], w);
            }
            for s in 0..NAV_DIM {
                x[s] += rk4_step(h, [k[0][s], k[1][s], k[2][s], k[3][s]]);
            }
            if drifting {
                for s in NAV_DIM..n {
                    x[s] += w[s] * h;
                }
                tmp[NAV_DIM..].copy_from_slice(&x[NAV_DIM..]);
            }
        }
        for l in 0..LANES.min(count - first) {
            let dst = &mut points[(first + l) * n..(first + l + 1) * n];
            for (d, xs) in dst.iter_mut().zip(x.iter()) {
                *d = xs.0[l];
            }
        }
    }
}
