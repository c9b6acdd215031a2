//! The strapdown model's sigma points propagated eight at a time: each block of
//! [`LANES`] points is one [`Lanes`] value per state, and the rates
//! (docs/model.md eqs. (51)-(58)) are the same source as the one-state path ([`super::rates::nav_rates`]),
//! evaluated on lanes, so the compiler turns them into SIMD instructions. The RK4 stages are
//! [`RK4`] stepped through as [`crate::integrate::propagate_one`] steps them, operation for
//! operation, noise held over the window included; a lane lands where the point lands alone,
//! up to the reciprocals a batch takes with one division ([`crate::real::Real::reciprocals`]).
//! Nothing is allocated: a block lives on the stack.

use super::effect_rates::rates_with_effects;
use super::errors::{ErrorLayout, MAX_DIM};
use super::rates::{imu_of, nav_rates, ImuReading};
use super::state::{BASE_DIM, NAV_DIM};
use crate::effect::NoiseChannel;
use crate::integrate::{rk4_step, InputWindow, RK4};
use crate::real::{Lanes, LANES};

/// Propagates `points` (`BASE_DIM` values each, one after another) of the base model across
/// `window`; `noise`, when given, holds one value per channel of `channels` per point. Written
/// out for the base model's fixed width (the generic [`propagate`] with a width known only at
/// run time cost the UKFs' strapdown step about 8 %).
pub fn propagate_blocks(
    points: &mut [f64],
    noise: Option<&[f64]>,
    channels: &[NoiseChannel],
    window: &InputWindow,
) {
    let n = BASE_DIM;
    let nw = channels.len();
    let count = points.len() / n;
    for first in (0..count).step_by(LANES) {
        let lanes = LANES.min(count - first);
        // Lanes past the last point repeat it (their results are dropped).
        let point = |l: usize| first + l.min(lanes - 1);
        let mut x: [Lanes; BASE_DIM] =
            std::array::from_fn(|i| Lanes::from_fn(|l| points[point(l) * n + i]));
        let noise_of = |c: usize| -> Lanes {
            noise.map_or(Lanes::default(), |v| {
                Lanes::from_fn(|l| v[point(l) * nw + c])
            })
        };
        let mut drive = [Lanes::default(); NAV_DIM];
        let mut driven = [false; NAV_DIM];
        for (c, ch) in channels.iter().enumerate() {
            if ch.state < NAV_DIM && noise.is_some() {
                drive[ch.state] += noise_of(c);
                driven[ch.state] = true;
            }
        }
        let mut k = [[Lanes::default(); NAV_DIM]; 4];
        for j in 0..window.substeps() {
            let h = window.t[j + 1] - window.t[j];
            for (s, stage) in RK4.iter().enumerate() {
                let imu = imu_of(stage.input(window, j));
                let mut ks = [Lanes::default(); NAV_DIM];
                if s == 0 {
                    nav_rates(&x, &imu, &mut ks);
                } else {
                    let c = stage.offset(h);
                    let mut tmp = x;
                    for i in 0..NAV_DIM {
                        tmp[i] = x[i] + k[s - 1][i] * c;
                    }
                    nav_rates(&tmp, &imu, &mut ks);
                }
                for i in 0..NAV_DIM {
                    if driven[i] {
                        ks[i] += drive[i];
                    }
                }
                k[s] = ks;
            }
            for i in 0..NAV_DIM {
                x[i] += rk4_step(h, [k[0][i], k[1][i], k[2][i], k[3][i]]);
            }
        }
        for l in 0..lanes {
            for i in 0..n {
                points[(first + l) * n + i] = x[i].0[l];
            }
        }
    }
}

/// [`propagate_blocks`] for a model with effects: `dim` values per point, the rates of
/// `layout` ([`rates_with_effects`]), the biases among the dynamic states when they wander.
pub fn propagate_blocks_with(
    layout: &ErrorLayout,
    dim: usize,
    points: &mut [f64],
    noise: Option<&[f64]>,
    channels: &[NoiseChannel],
    window: &InputWindow,
) {
    let rates =
        |x: &[Lanes], imu: &ImuReading, dx: &mut [Lanes]| rates_with_effects(layout, x, imu, dx);
    if layout.biases_wander() {
        propagate::<MAX_DIM, BASE_DIM>(dim, points, noise, channels, window, rates);
    } else {
        propagate::<MAX_DIM, NAV_DIM>(dim, points, noise, channels, window, rates);
    }
}

/// The RK4 of `rates` over blocks of [`LANES`] points of `dim <= N` states, the first `D` of
/// which have a derivative.
#[inline(always)]
fn propagate<const N: usize, const D: usize>(
    dim: usize,
    points: &mut [f64],
    noise: Option<&[f64]>,
    channels: &[NoiseChannel],
    window: &InputWindow,
    rates: impl Fn(&[Lanes], &ImuReading, &mut [Lanes]),
) {
    let n = dim;
    let nw = channels.len();
    let count = points.len() / n;
    for first in (0..count).step_by(LANES) {
        let lanes = LANES.min(count - first);
        // Lanes past the last point repeat it (their results are dropped).
        let point = |l: usize| first + l.min(lanes - 1);
        let mut x: [Lanes; N] = std::array::from_fn(|i| {
            if i < n {
                Lanes::from_fn(|l| points[point(l) * n + i])
            } else {
                Lanes::default()
            }
        });
        let noise_of = |c: usize| -> Lanes {
            noise.map_or(Lanes::default(), |v| {
                Lanes::from_fn(|l| v[point(l) * nw + c])
            })
        };
        let mut drive = [Lanes::default(); D];
        let mut driven = [false; D];
        for (c, ch) in channels.iter().enumerate() {
            if ch.state < D && noise.is_some() {
                drive[ch.state] += noise_of(c);
                driven[ch.state] = true;
            }
        }
        let mut k = [[Lanes::default(); D]; 4];
        for j in 0..window.substeps() {
            let h = window.t[j + 1] - window.t[j];
            for (s, stage) in RK4.iter().enumerate() {
                let imu = imu_of(stage.input(window, j));
                let mut ks = [Lanes::default(); D];
                if s == 0 {
                    rates(&x[..n], &imu, &mut ks);
                } else {
                    let c = stage.offset(h);
                    let mut tmp = x;
                    for i in 0..D {
                        tmp[i] = x[i] + k[s - 1][i] * c;
                    }
                    rates(&tmp[..n], &imu, &mut ks);
                }
                for i in 0..D {
                    if driven[i] {
                        ks[i] += drive[i];
                    }
                }
                k[s] = ks;
            }
            for i in 0..D {
                x[i] += rk4_step(h, [k[0][i], k[1][i], k[2][i], k[3][i]]);
            }
        }
        for l in 0..lanes {
            for i in 0..n {
                points[(first + l) * n + i] = x[i].0[l];
            }
        }
    }
}
