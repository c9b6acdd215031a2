//! Batched RK4 propagation of many states of the base model at once: the UKF's hot path.
//!
//! A UKF step sends 41 to 59 sigma points through 10 RK4 sub-steps, 4 derivative calls each;
//! that is almost all of its cost. Here points travel in blocks of [`LANES`], each quantity of
//! a block in a fixed-size array, so that the compiler evaluates the model for all lanes in
//! SIMD registers. Two things make the evaluation cheap without changing its value beyond
//! rounding:
//!
//! - `sin L` and `cos L` come from one `sin_cos` of a reference latitude per window and the
//!   angle-addition formula with Taylor series of the offset `d = L - L_ref` (terms up to
//!   `d^9` and `d^10`; the path is taken only while `|d| < 0.03 rad`, where the first omitted
//!   term is below 1e-20);
//! - the coefficients only enter through `eps = Kg0 + Kg11 fx + Kg12 fy` and
//!   `nab = Ka0 + Ka1 f`, formed once per stage input rather than per derivative.
//!
//! Only the seven navigation states are integrated (the coefficients are constant). The
//! arithmetic mirrors [`crate::PlatformModel::nav_rates`] and
//! [`crate::integrate::propagate_generic`] operation for operation; a test checks both paths
//! agree to rounding. Models with effects that add rates, or noise on the coefficients, take
//! the generic path.

use crate::earth::{FLATTENING, RE, WIE};
use crate::integrate::InputWindow;
use crate::kinematics::Input;
use crate::state::*;

/// Points per block.
pub const LANES: usize = 8;
type Lane = [f64; LANES];

/// Largest latitude offset from the reference for which the series are used.
pub const MAX_OFFSET: f64 = 0.03;

/// Per-block constants at one stage input: gyro drifts and accelerometer errors, plus f.
struct StageInput {
    eps: [Lane; 3],
    nab: [Lane; 2],
    f: Input,
}

fn stage_input(coef: &[Lane; BASE_COEFFICIENTS], f: &Input) -> StageInput {
    let [fx, fy, _] = *f;
    let mut eps = [[0.0; LANES]; 3];
    let mut nab = [[0.0; LANES]; 2];
    for a in 0..3 {
        for l in 0..LANES {
            eps[a][l] = coef[3 * a][l] + coef[3 * a + 1][l] * fx + coef[3 * a + 2][l] * fy;
        }
    }
    let (ka0x, ka1x, ka0y, ka1y) = (
        KA0X - NAV_DIM,
        KA1X - NAV_DIM,
        KA0Y - NAV_DIM,
        KA1Y - NAV_DIM,
    );
    for l in 0..LANES {
        nab[0][l] = coef[ka0x][l] + coef[ka1x][l] * fx;
        nab[1][l] = coef[ka0y][l] + coef[ka1y][l] * fy;
    }
    StageInput { eps, nab, f: *f }
}

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

/// Navigation-state derivatives of a block at states `x`.
#[inline(always)]
fn rates(
    x: &[Lane; NAV_DIM],
    si: &StageInput,
    reference: (f64, f64, f64),
    out: &mut [Lane; NAV_DIM],
) {
    let (lat_ref, s0, c0) = reference;
    let [fx, fy, fz] = si.f;
    for l in 0..LANES {
        let (sd, cd) = small_sin_cos(x[LAT][l] - lat_ref);
        let sin_l = s0 * cd + c0 * sd;
        let cos_l = c0 * cd - s0 * sd;
        let s2 = sin_l * sin_l;
        // One division for three reciprocals.
        let rm = RE * (1.0 - 2.0 * FLATTENING + 3.0 * FLATTENING * s2);
        let rn = RE * (1.0 + FLATTENING * s2);
        let rn_cos = rn * cos_l;
        let inv = 1.0 / (rm * rn_cos);
        let inv_rm = rn_cos * inv;
        let inv_rn = rm * cos_l * inv;
        let inv_cos = rm * rn * inv;
        let tan_over_rn = sin_l * inv_cos * inv_rn;
        let (px, py, pz) = (x[PHI_X][l], x[PHI_Y][l], x[PHI_Z][l]);
        let (vx, vy) = (x[V_X][l], x[V_Y][l]);
        let w1 = -vy * inv_rm;
        let w2 = WIE * cos_l + vx * inv_rn;
        let w3 = WIE * sin_l + vx * tan_over_rn;
        let coriolis = 2.0 * WIE * sin_l + vx * tan_over_rn;
        out[PHI_X][l] = py * w3 - pz * w2 + si.eps[0][l];
        out[PHI_Y][l] = pz * w1 - px * w3 + si.eps[1][l];
        out[PHI_Z][l] = px * w2 - py * w1 + si.eps[2][l];
        out[V_X][l] = coriolis * vy + si.nab[0][l] + fx + fy * pz - fz * py;
        out[V_Y][l] = -coriolis * vx + si.nab[1][l] + fy + fz * px - fx * pz;
        out[LAT][l] = vy * inv_rm;
        out[LON][l] = vx * inv_rn * inv_cos;
    }
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

/// Propagates `points` (each `n` long: 7 navigation states, 13 base coefficients, then effect
/// coefficients that do not enter the rates) across `window`. `noise`, when given, holds
/// `channels.len()` values per point, each driving the derivative of `channels[j]` (< 7).
pub fn propagate(
    points: &mut [f64],
    n: usize,
    noise: Option<(&[f64], &[usize])>,
    window: &InputWindow,
) {
    let count = points.len() / n;
    if count == 0 || window.substeps() == 0 {
        return;
    }
    let lat_ref = points[LAT];
    let (s0, c0) = lat_ref.sin_cos();
    let reference = (lat_ref, s0, c0);
    let nw = noise.map_or(0, |(_, ch)| ch.len());
    for first in (0..count).step_by(LANES) {
        // Gather; padding lanes repeat the block's first point (valid numbers, discarded).
        let mut x = [[0.0; LANES]; NAV_DIM];
        let mut coef = [[0.0; LANES]; BASE_COEFFICIENTS];
        let mut w = [[0.0; LANES]; NAV_DIM];
        for l in 0..LANES {
            let p = if first + l < count { first + l } else { first };
            let src = &points[p * n..(p + 1) * n];
            for s in 0..NAV_DIM {
                x[s][l] = src[s];
            }
            for c in 0..BASE_COEFFICIENTS {
                coef[c][l] = src[NAV_DIM + c];
            }
            if let Some((values, channels)) = noise {
                for (j, &s) in channels.iter().enumerate() {
                    w[s][l] += values[p * nw + j];
                }
            }
        }
        let has_noise = noise.is_some();
        let mut k1 = [[0.0; LANES]; NAV_DIM];
        let mut k2 = [[0.0; LANES]; NAV_DIM];
        let mut k3 = [[0.0; LANES]; NAV_DIM];
        let mut k4 = [[0.0; LANES]; NAV_DIM];
        let mut tmp = [[0.0; LANES]; NAV_DIM];
        let add_noise = |k: &mut [Lane; NAV_DIM]| {
            if has_noise {
                for (ki, wi) in k.as_flattened_mut().iter_mut().zip(w.as_flattened()) {
                    *ki += wi;
                }
            }
        };
        // tmp = x + c k, over the flattened (contiguous) arrays so the loop runs along lanes.
        let axpy = |tmp: &mut [Lane; NAV_DIM], x: &[Lane; NAV_DIM], c: f64, k: &[Lane; NAV_DIM]| {
            for ((t, xi), ki) in tmp
                .as_flattened_mut()
                .iter_mut()
                .zip(x.as_flattened())
                .zip(k.as_flattened())
            {
                *t = xi + c * ki;
            }
        };
        let mut si_start = stage_input(&coef, &window.f[0]);
        for j in 0..window.substeps() {
            let h = window.t[j + 1] - window.t[j];
            let h6 = h / 6.0;
            let si_mid = stage_input(&coef, &window.f_mid[j]);
            let si_end = stage_input(&coef, &window.f[j + 1]);
            rates(&x, &si_start, reference, &mut k1);
            add_noise(&mut k1);
            axpy(&mut tmp, &x, 0.5 * h, &k1);
            rates(&tmp, &si_mid, reference, &mut k2);
            add_noise(&mut k2);
            axpy(&mut tmp, &x, 0.5 * h, &k2);
            rates(&tmp, &si_mid, reference, &mut k3);
            add_noise(&mut k3);
            axpy(&mut tmp, &x, h, &k3);
            rates(&tmp, &si_end, reference, &mut k4);
            add_noise(&mut k4);
            for ((((xi, a), b), c), d) in x
                .as_flattened_mut()
                .iter_mut()
                .zip(k1.as_flattened())
                .zip(k2.as_flattened())
                .zip(k3.as_flattened())
                .zip(k4.as_flattened())
            {
                *xi += h6 * (a + 2.0 * (b + c) + d);
            }
            si_start = si_end;
        }
        for l in 0..LANES.min(count - first) {
            let dst = &mut points[(first + l) * n..(first + l + 1) * n];
            for s in 0..NAV_DIM {
                dst[s] = x[s][l];
            }
        }
    }
}
