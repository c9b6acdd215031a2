//! The strapdown model's sigma points propagated eight at a time: each block of
//! [`LANES`] points is one [`Lanes`] value per state, and the rates
//! (docs/model.md eqs. (51)-(58)) are the same source as the one-state path ([`super::rates::nav_rates`]),
//! evaluated on lanes, so the compiler turns them into SIMD instructions. The RK4 stages are
//! [`RK4`] stepped through as [`crate::integrate::propagate_one`] steps them, operation for
//! operation, noise held over the window included. Two things differ from one point alone,
//! both in the last bits only: the reciprocals a batch takes with one division
//! ([`crate::real::Real::reciprocals`]), and the latitude's sine and cosine, which come from
//! one evaluation at the first point's latitude and the series of the offset, as the
//! platform's batch takes them ([`crate::batch_propagation`]), whenever every point stays
//! within reach of it. Nothing is allocated: a block lives on the stack.
//!
//! Measured (`cargo run --release -p navkf-benches --example strapdown_step -- 2`, one run,
//! the strapdown step over the platform's, 2-core AMD EPYC): the latitude's series took the
//! standard UKF from 1.67x to 1.50x and the simplified from 1.80x to 1.63x; the rates passed
//! as a closure rather than a trait stayed a call per stage (1.72x); two or four blocks in
//! flight, as the platform's batch takes them, measured the same as one; the attitude's
//! sines by the same series from each sub-step's start cost more than they saved (1.62x
//! against 1.57x at a heading of 2 rad), as did writing out `rotate` (1.78x).

use super::attitude::angle_trig;
use super::effect_rates::rates_with_effects_at;
use super::errors::{ErrorLayout, MAX_DIM};
use super::rates::{imu_of, nav_rates_with, ImuReading};
use super::state::{BASE_DIM, HEADING, LAT, NAV_DIM, PITCH, ROLL, V_N};
use crate::batch_propagation::{latitudes_near, sin_cos_near};
use crate::dispatch;
use crate::effect::NoiseChannel;
use crate::integrate::{rk4_step, InputWindow, RK4};
use crate::real::{Lanes, Real, LANES};

/// Propagates `points` (`BASE_DIM` values each, one after another) of the base model across
/// `window`; `noise`, when given, holds one value per channel of `channels` per point.
pub fn propagate_blocks(
    points: &mut [f64],
    noise: Option<&[f64]>,
    channels: &[NoiseChannel],
    window: &InputWindow,
) {
    dispatch!({
        propagate::<BASE_DIM, NAV_DIM>(BASE_DIM, points, noise, channels, window, BaseRates)
    });
}

/// [`propagate_blocks`] for a model with effects: `dim` values per point, the rates of
/// `layout` ([`rates_with_effects_at`]), the biases and their departures among the dynamic
/// states when a triad wanders ([`ErrorLayout::dynamic_dim`]).
pub fn propagate_blocks_with(
    layout: &ErrorLayout,
    dim: usize,
    points: &mut [f64],
    noise: Option<&[f64]>,
    channels: &[NoiseChannel],
    window: &InputWindow,
) {
    const ONE_TRIAD: usize = BASE_DIM + 3;
    const BOTH_TRIADS: usize = BASE_DIM + 6;
    let rates = EffectRates(layout);
    match layout.dynamic_dim() {
        NAV_DIM => dispatch!(propagate::<MAX_DIM, NAV_DIM>(
            dim, points, noise, channels, window, rates
        )),
        ONE_TRIAD => dispatch!(propagate::<MAX_DIM, ONE_TRIAD>(
            dim, points, noise, channels, window, rates
        )),
        d => {
            debug_assert_eq!(d, BOTH_TRIADS);
            dispatch!(propagate::<MAX_DIM, BOTH_TRIADS>(
                dim, points, noise, channels, window, rates
            ))
        }
    }
}

/// The rates a block is propagated with, given the latitude's sine and cosine. A trait with
/// inlined methods rather than a closure: the closure stayed a call per stage, its arrays
/// passed through memory (a quarter of the UKF's strapdown step).
trait BlockRates {
    fn eval(&self, x: &[Lanes], imu: &ImuReading, lat: (Lanes, Lanes), dx: &mut [Lanes]);
}

/// The base model's rates ([`nav_rates_with`]).
struct BaseRates;

impl BlockRates for BaseRates {
    #[inline(always)]
    fn eval(&self, x: &[Lanes], imu: &ImuReading, lat: (Lanes, Lanes), dx: &mut [Lanes]) {
        let trig = angle_trig([x[ROLL], x[PITCH], x[HEADING]]);
        nav_rates_with(x, imu, &trig, lat, dx)
    }
}

/// The rates of a model with effects ([`rates_with_effects_at`]).
struct EffectRates<'a>(&'a ErrorLayout);

impl BlockRates for EffectRates<'_> {
    #[inline(always)]
    fn eval(&self, x: &[Lanes], imu: &ImuReading, lat: (Lanes, Lanes), dx: &mut [Lanes]) {
        let trig = angle_trig([x[ROLL], x[PITCH], x[HEADING]]);
        rates_with_effects_at(self.0, x, imu, &trig, lat, dx)
    }
}

/// Points `first..first + LANES` of `points` (`n <= N` values each) as one [`Lanes`] value per
/// state, and how many of the lanes are points: lanes past the last point repeat it (their
/// results are dropped), states past `n` are zero.
#[inline(always)]
pub(super) fn gather<const N: usize>(
    points: &[f64],
    n: usize,
    first: usize,
) -> (usize, [Lanes; N]) {
    let lanes = LANES.min(points.len() / n - first);
    let point = |l: usize| first + l.min(lanes - 1);
    let x = std::array::from_fn(|i| {
        if i < n {
            Lanes::from_fn(|l| points[point(l) * n + i])
        } else {
            Lanes::default()
        }
    });
    (lanes, x)
}

/// One block of [`LANES`] points in flight: its states (`dim <= N` used), the noise held over
/// the window on the `D` dynamic states, and the RK4 stage derivatives.
struct Block<const N: usize, const D: usize> {
    first: usize,
    lanes: usize,
    x: [Lanes; N],
    drive: [Lanes; D],
    driven: [bool; D],
    k: [[Lanes; D]; 4],
}

impl<const N: usize, const D: usize> Block<N, D> {
    /// The block of points `first..first + LANES` (lanes past the last point repeat it; their
    /// results are dropped).
    #[inline(always)]
    fn load(
        first: usize,
        points: &[f64],
        n: usize,
        noise: Option<&[f64]>,
        channels: &[NoiseChannel],
    ) -> Self {
        let (lanes, x) = gather(points, n, first);
        let point = |l: usize| first + l.min(lanes - 1);
        let nw = channels.len();
        let mut drive = [Lanes::default(); D];
        let mut driven = [false; D];
        if let Some(v) = noise {
            for (c, ch) in channels.iter().enumerate() {
                if ch.state < D {
                    drive[ch.state] += Lanes::from_fn(|l| v[point(l) * nw + c]);
                    driven[ch.state] = true;
                }
            }
        }
        Block {
            first,
            lanes,
            x,
            drive,
            driven,
            k: [[Lanes::default(); D]; 4],
        }
    }

    /// Writes the block's points back.
    #[inline(always)]
    fn store(&self, points: &mut [f64], n: usize) {
        for l in 0..self.lanes {
            for i in 0..n {
                points[(self.first + l) * n + i] = self.x[i].0[l];
            }
        }
    }
}

/// The RK4 of `rates` over blocks of [`LANES`] points of `dim <= N` states, the first `D` of
/// which have a derivative, one block at a time (two or four blocks in flight, as the
/// platform's batch takes them, measured the same here). `rates` receives the latitude's sine
/// and cosine: from the series about the first point's latitude when every point stays near
/// it over the window ([`latitudes_near`]), otherwise evaluated in full. Inlined into
/// [`crate::dispatch!`]'s copies ([`crate::instruction_set`]).
#[inline(always)]
fn propagate<const N: usize, const D: usize>(
    dim: usize,
    points: &mut [f64],
    noise: Option<&[f64]>,
    channels: &[NoiseChannel],
    window: &InputWindow,
    rates: impl BlockRates,
) {
    let n = dim;
    let count = points.len() / n;
    if count == 0 {
        return;
    }
    let lat_ref = points[LAT];
    let (s0, c0) = lat_ref.sin_cos();
    let near = latitudes_near(points, n, (LAT, V_N), window, lat_ref);
    let lat_trig = |lat: Lanes| {
        if near {
            sin_cos_near(lat, (lat_ref, s0, c0))
        } else {
            lat.sin_cos()
        }
    };
    for first in (0..count).step_by(LANES) {
        let mut block = Block::<N, D>::load(first, points, n, noise, channels);
        for j in 0..window.substeps() {
            let h = window.t[j + 1] - window.t[j];
            for (s, stage) in RK4.iter().enumerate() {
                let imu = imu_of(stage.input(window, j));
                let mut ks = [Lanes::default(); D];
                if s == 0 {
                    rates.eval(&block.x[..n], &imu, lat_trig(block.x[LAT]), &mut ks);
                } else {
                    let c = stage.offset(h);
                    let mut tmp = block.x;
                    for i in 0..D {
                        tmp[i] = block.x[i] + block.k[s - 1][i] * c;
                    }
                    rates.eval(&tmp[..n], &imu, lat_trig(tmp[LAT]), &mut ks);
                }
                for i in 0..D {
                    if block.driven[i] {
                        ks[i] += block.drive[i];
                    }
                }
                block.k[s] = ks;
            }
            let k = &block.k;
            for i in 0..D {
                block.x[i] += rk4_step(h, [k[0][i], k[1][i], k[2][i], k[3][i]]);
            }
        }
        block.store(points, n);
    }
}
