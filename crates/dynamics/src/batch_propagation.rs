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
//! The RK4 stages (docs/model.md eq. (15)) are the table [`RK4`], stepped through as
//! [`crate::system::propagate_generic`] does, operation for operation, including noise held
//! over the window and coefficients that a noise channel drives moving linearly.
//!
//! Blocks go through each stage in groups of four (`GROUP`): one RK4 stage depends on the
//! previous one, so a single block is a chain of dependent operations (the latitude series,
//! a division, the rates) that leaves the core waiting; four independent chains in flight keep
//! it busy (two in the exact-attitude variant, whose larger derivative spills registers with
//! four). The base model and the effects' declared linear terms ([`crate::linear_rates`])
//! are evaluated inline; unless an effect's own code adds rates, a block's derivative is
//! formed whole in registers, noise included, and stored once. With such code, the base and
//! linear part of every block of the group comes first, then each of those effects once for
//! the whole group ([`crate::DynEffect::add_rates_blocks`]). What they receive is each block's
//! [`LatitudeTerms`], from which they rebuild the kinematics they read ([`BlockGroup`]).
//!
//! What was measured (`cargo run --release -p navkf-benches --example prop_timing`, 51
//! points, minima of interleaved runs on a Zen 4 EPYC):
//! - Effects called per block with the whole kinematics cost 18.0 us against 11.8 us for 25
//!   states with no physics; the grouped pass with the latitude terms 15.1 us, and 13.2 us
//!   once the `Lanes` operators were plain loops ([`crate::real`]). The gain is the latitude
//!   terms in place of the kinematics (5 vectors stored per derivative instead of 23).
//! - Declared linear terms evaluated inline, in place of the two catalogued effects' vtable
//!   calls: the simplified UKF's step with `accel-cross-axis` and `torquer-scale` went from
//!   20.3 to 19.0 us (`step_timing`; base 13.2), bit for bit the same results. Their loop over
//!   the terms names every row and kinematic field statically (a run-time index would push
//!   the derivative and the kinematics to memory: 24.8 us), and the base model's loop is
//!   monomorphised without it (with an empty-list check it cost 14.2 us, against 13.2).
//! - The base model one block at a time cost 11.0 us against 9.7 for the loop before the
//!   physics was shared (`ae4115e`, which formed the drifts once per input knot and kept the
//!   block in local arrays). In groups of four it costs 9.7. With noise on every channel
//!   (`--noise`, as the standard UKF's points carry): 10.6 in groups with the noise added in
//!   registers, 12.0 when it was added to the stored derivative, 10.3 before. Groups of two:
//!   9.8 and 10.7, but 13.6 with two rate effects against 12.8 in fours. Forming the drifts
//!   once per input knot measured nothing, one block at a time or in groups.
//!
//! The arithmetic of every lane is the same whatever the grouping, so a point lands bit for
//! bit where it lands alone in its block.

use crate::attitude::{exact_rates, Attitude};
use crate::dispatch;
use crate::effect::BlockGroup;
use crate::integrate::{rk4_step, InputWindow, PropagationScratch, RK4};
use crate::kinematics::{Kinematics, LatitudeTerms};
use crate::model::PlatformModel;
use crate::real::{Lanes, LANES};
use crate::state::*;
use crate::system::SystemModel;

/// Largest latitude offset from the reference for which the series are used.
pub const MAX_OFFSET: f64 = 0.03;

/// `sin(d)` and `cos(d)` by their Taylor series in Horner form, for `|d| < MAX_OFFSET`
/// (coefficients are reciprocal factorials, multiplied rather than divided: a vector divide
/// costs ten multiplies). The first omitted terms, `d^11/11!` and `d^12/12!`, stay below
/// 3e-19 up to `|d| = 0.1`.
#[inline(always)]
pub(crate) fn small_sin_cos(d: f64) -> (f64, f64) {
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

/// Blocks of [`LANES`] points that go through a stage together: four independent dependency
/// chains in flight, and one dispatch per effect for four blocks. Their states, stage
/// derivatives and latitude terms (about 25 kB at 25 states) fit the first-level cache.
const GROUP: usize = 4;

/// The exact-attitude variant's group: its derivative holds about twice the base model's
/// values (three rotations' sines, the rotation), and four blocks of it in flight spill
/// registers; two cost 3.5 % less per UKF step (`step_timing all --exact`: simplified UKF
/// 20.4 -> 19.7 us; one block per group measured the same as two).
const EXACT_GROUP: usize = 2;

/// The latitude's functions at a block's states `x`: the one place where the batch computes
/// `sin L` and `cos L` differently from one state.
#[inline(always)]
fn block_latitude(x: &[Lanes], reference: (f64, f64, f64)) -> LatitudeTerms<Lanes> {
    let (lat_ref, s0, c0) = reference;
    let mut sin_l = Lanes::default();
    let mut cos_l = Lanes::default();
    for l in 0..LANES {
        let (sd, cd) = small_sin_cos(x[LAT].0[l] - lat_ref);
        sin_l.0[l] = s0 * cd + c0 * sd;
        cos_l.0[l] = c0 * cd - s0 * sd;
    }
    LatitudeTerms::new(sin_l, cos_l)
}

/// `(sin L, cos L)` of a block's latitudes `lat` from `reference` = `(L_ref, sin L_ref,
/// cos L_ref)` by the angle-addition formula and the series of the offset: valid while
/// every lane is within [`MAX_OFFSET`] of `L_ref` ([`latitudes_near`]). Shared by both
/// families' batches.
#[inline(always)]
pub(crate) fn sin_cos_near(lat: Lanes, reference: (f64, f64, f64)) -> (Lanes, Lanes) {
    let (lat_ref, s0, c0) = reference;
    let mut sin_l = Lanes::default();
    let mut cos_l = Lanes::default();
    for l in 0..LANES {
        let (sd, cd) = small_sin_cos(lat.0[l] - lat_ref);
        sin_l.0[l] = s0 * cd + c0 * sd;
        cos_l.0[l] = c0 * cd - s0 * sd;
    }
    (sin_l, cos_l)
}

/// Whether the batched path applies to these points over this window: every latitude within
/// reach of the reference for the whole window.
pub fn applicable(points: &[f64], n: usize, window: &InputWindow, lat_ref: f64) -> bool {
    latitudes_near(points, n, (LAT, V_Y), window, lat_ref)
}

/// Whether every latitude of `points` (`n` values each, the latitude and the North velocity
/// at the indices `(lat, v_north)`) stays within [`MAX_OFFSET`] of `lat_ref` for the whole window, so that [`sin_cos_near`]
/// holds at every stage.
pub(crate) fn latitudes_near(
    points: &[f64],
    n: usize,
    (lat, v_north): (usize, usize),
    window: &InputWindow,
    lat_ref: f64,
) -> bool {
    let mut max_d: f64 = 0.0;
    let mut max_v: f64 = 0.0;
    for x in points.chunks_exact(n) {
        max_d = max_d.max((x[lat] - lat_ref).abs());
        max_v = max_v.max(x[v_north].abs());
    }
    // Latitude cannot move faster than |v_y| / RM (RM > 6.3e6 m) plus what the velocity can
    // gain within the window; allow a factor of 2 on the distance and 50 km slack.
    let reach = (2.0 * max_v * window.duration() + 5.0e4) / 6.3e6;
    max_d.is_finite() && max_d + reach < MAX_OFFSET
}

/// Lanes of scratch [`propagate`] uses for a model of `n` states: states, stage states and
/// noise of a group.
pub fn scratch_lanes(n: usize) -> usize {
    3 * n * GROUP
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
    // Monomorphised on the attitude variant and on whether declared linear terms exist, so
    // that the base model's loop carries no trace of them; each compiled for the CPU's
    // instruction set (`crate::instruction_set`).
    let linear = model.has_linear_rates();
    match (model.attitude() == Attitude::Exact, linear) {
        (false, false) => {
            dispatch!(propagate_groups::<false, false>(
                model, points, noise, window, scratch
            ))
        }
        (false, true) => {
            dispatch!(propagate_groups::<false, true>(
                model, points, noise, window, scratch
            ))
        }
        (true, false) => {
            dispatch!(propagate_groups::<true, false>(
                model, points, noise, window, scratch
            ))
        }
        (true, true) => {
            dispatch!(propagate_groups::<true, true>(
                model, points, noise, window, scratch
            ))
        }
    }
}

/// The points, the noise and how a stage and a sub-step move a block.
struct Blocks<'a> {
    points: &'a mut [f64],
    noise: Option<&'a [f64]>,
    channels: &'a [crate::effect::NoiseChannel],
    n: usize,
    count: usize,
    /// Whether a noise channel drives a coefficient, which then moves linearly.
    drifting: bool,
}

impl Blocks<'_> {
    /// Loads the block of points from `first` into `x` (one lane each; padding lanes repeat
    /// the first point: valid numbers, discarded) and their noise into `w`.
    #[inline(always)]
    fn gather(&self, first: usize, x: &mut [Lanes], w: &mut [Lanes]) {
        let (n, nw) = (self.n, self.channels.len());
        w.fill(Lanes::default());
        for l in 0..LANES {
            let p = if first + l < self.count {
                first + l
            } else {
                first
            };
            let src = &self.points[p * n..(p + 1) * n];
            for (xs, v) in x.iter_mut().zip(src) {
                xs.0[l] = *v;
            }
            if let Some(values) = self.noise {
                for (j, c) in self.channels.iter().enumerate() {
                    w[c.state].0[l] += values[p * nw + j];
                }
            }
        }
    }
    /// Stores the block `x` back to the points from `first`: the states that moved (the
    /// coefficients stay as they were unless noise drives them).
    #[inline(always)]
    fn scatter(&mut self, first: usize, x: &[Lanes]) {
        let n = self.n;
        let moved = if self.drifting { n } else { NAV_DIM };
        for l in 0..LANES.min(self.count - first) {
            let dst = &mut self.points[(first + l) * n..(first + l) * n + moved];
            for (d, xs) in dst.iter_mut().zip(x.iter()) {
                *d = xs.0[l];
            }
        }
    }
    /// The state of a later stage, `tmp = x + c k` (and the drifting coefficients moved by
    /// `c`).
    #[inline(always)]
    fn stage(&self, tmp: &mut [Lanes], x: &[Lanes], w: &[Lanes], c: f64, k: &[Lanes; NAV_DIM]) {
        for ((t, xi), ki) in tmp.iter_mut().zip(x).zip(k) {
            *t = *xi + *ki * c;
        }
        if self.drifting {
            for s in NAV_DIM..self.n {
                tmp[s] = x[s] + w[s] * c;
            }
        }
    }
    /// Adds the noise held over the window to a stage's derivatives.
    #[inline(always)]
    fn add_noise(&self, k: &mut [Lanes; NAV_DIM], w: &[Lanes]) {
        if self.noise.is_some() {
            for (ki, wi) in k.iter_mut().zip(w) {
                *ki += *wi;
            }
        }
    }
    /// Ends a sub-step of length `h`: the RK4 sum of the stages `k` moves `x`.
    #[inline(always)]
    fn finish(
        &self,
        x: &mut [Lanes],
        tmp: &mut [Lanes],
        w: &[Lanes],
        h: f64,
        k: [&[Lanes; NAV_DIM]; 4],
    ) {
        for s in 0..NAV_DIM {
            x[s] += rk4_step(h, [k[0][s], k[1][s], k[2][s], k[3][s]]);
        }
        if self.drifting {
            for s in NAV_DIM..self.n {
                x[s] += w[s] * h;
            }
            tmp[NAV_DIM..].copy_from_slice(&x[NAV_DIM..]);
        }
    }
}

/// Sets up [`Blocks`] and the reference latitude, or `None` when there is nothing to do.
fn blocks<'a>(
    model: &'a PlatformModel,
    points: &'a mut [f64],
    noise: Option<&'a [f64]>,
    window: &InputWindow,
) -> Option<(Blocks<'a>, (f64, f64, f64))> {
    let n = model.dim();
    let count = points.len() / n;
    if count == 0 || window.substeps() == 0 {
        return None;
    }
    let lat_ref = points[LAT];
    let (s0, c0) = lat_ref.sin_cos();
    let channels = model.noise_channels();
    let drifting = noise.is_some() && channels.iter().any(|c| c.state >= NAV_DIM);
    let blocks = Blocks {
        points,
        noise,
        channels,
        n,
        count,
        drifting,
    };
    Some((blocks, (lat_ref, s0, c0)))
}

/// [`propagate`], [`GROUP`] blocks at a time. `EXACT` selects the exact-attitude variant
/// ([`crate::attitude`]); `LINEAR`, whether the model has declared linear rate terms.
/// Inlined into [`crate::dispatch!`]'s copies.
#[inline(always)]
fn propagate_groups<const EXACT: bool, const LINEAR: bool>(
    model: &PlatformModel,
    points: &mut [f64],
    noise: Option<&[f64]>,
    window: &InputWindow,
    scratch: &mut PropagationScratch,
) {
    let Some((mut blocks, reference)) = blocks(model, points, noise, window) else {
        return;
    };
    let n = blocks.n;
    let (xs, rest) = scratch.lanes(scratch_lanes(n)).split_at_mut(n * GROUP);
    let (tmps, ws) = rest.split_at_mut(n * GROUP);
    // The group's four stage derivatives, stage-major so that a stage's lie together for the
    // effects; its latitude terms; in the exact variant, the platform terms the effects add
    // to before the variant maps them.
    let mut k = [[[Lanes::default(); NAV_DIM]; GROUP]; 4];
    let mut latitude = [LatitudeTerms::<Lanes>::default(); GROUP];
    let mut terms = [[Lanes::default(); NAV_DIM]; GROUP];
    let block = |b: usize| b * n..(b + 1) * n;
    let coded = model.has_coded_rate_effects();
    let group_size = if EXACT { EXACT_GROUP } else { GROUP };
    for group_first in (0..blocks.count).step_by(LANES * group_size) {
        let count = (blocks.count - group_first).div_ceil(LANES).min(group_size);
        for b in 0..count {
            blocks.gather(
                group_first + b * LANES,
                &mut xs[block(b)],
                &mut ws[block(b)],
            );
            tmps[block(b)].copy_from_slice(&xs[block(b)]);
        }
        for j in 0..window.substeps() {
            let h = window.t[j + 1] - window.t[j];
            for (s, st) in RK4.iter().enumerate() {
                let u = st.input(window, j);
                let (earlier, rest) = k.split_at_mut(s);
                let ks = &mut rest[0];
                for b in 0..count {
                    if s > 0 {
                        let (x, w) = (&xs[block(b)], &ws[block(b)]);
                        blocks.stage(&mut tmps[block(b)], x, w, st.offset(h), &earlier[s - 1][b]);
                    }
                    let at = if s == 0 {
                        &xs[block(b)]
                    } else {
                        &tmps[block(b)]
                    };
                    let lat = block_latitude(at, reference);
                    let kb = Kinematics::from_latitude(at, u, &lat);
                    // The base model and the declared linear terms, in registers.
                    let mut r = if EXACT {
                        model.base_terms(at, &kb)
                    } else {
                        model.base_rates(at, &kb)
                    };
                    if LINEAR {
                        model.add_linear_rates(at, &kb, &mut r);
                    }
                    if coded {
                        latitude[b] = lat;
                        if EXACT {
                            terms[b] = r;
                        } else {
                            ks[b] = r;
                        }
                    } else {
                        // The whole derivative formed in registers and stored once.
                        if EXACT {
                            r = exact_rates(&kb, &r);
                        }
                        blocks.add_noise(&mut r, &ws[block(b)]);
                        ks[b] = r;
                    }
                }
                if coded {
                    let states = if s == 0 { &xs[..] } else { &tmps[..] };
                    let group = BlockGroup::new(states, n, &latitude[..count], u);
                    if EXACT {
                        model.add_effect_rates_blocks(&group, &mut terms[..count]);
                        for b in 0..count {
                            ks[b] = exact_rates(&group.kinematics(b), &terms[b]);
                        }
                    } else {
                        model.add_effect_rates_blocks(&group, &mut ks[..count]);
                    }
                    for b in 0..count {
                        blocks.add_noise(&mut ks[b], &ws[block(b)]);
                    }
                }
            }
            for b in 0..count {
                let stages = [&k[0][b], &k[1][b], &k[2][b], &k[3][b]];
                blocks.finish(
                    &mut xs[block(b)],
                    &mut tmps[block(b)],
                    &ws[block(b)],
                    h,
                    stages,
                );
            }
        }
        for b in 0..count {
            blocks.scatter(group_first + b * LANES, &xs[block(b)]);
        }
    }
}
