//! The strapdown measurement of a UKF's sigma points, eight at a time: each block of
//! [`LANES`] points is one [`Lanes`] value per state, through the same source as one point
//! ([`measurement_with`], docs/model.md eqs. (59)-(61), (68), (70)), compiled for the CPU
//! ([`crate::dispatch!`]).
//!
//! Why: point by point, the three attitude angles' sines and cosines and the rotation of the
//! velocity into the body took about a tenth of the simplified UKF's strapdown step, which
//! (its update no longer linear) measures all `2 n + 1` points at every update, and the plain
//! build's scalar path took its fused multiply-adds in software. The lanes give the scalar
//! path's bits: the same operations, the sines by the same series (the GPS's lever arm and
//! latency aside, whose three reciprocals a batch takes with one division,
//! [`crate::real::Real::reciprocals`]: the last bits there).

use super::batch::gather;
use super::errors::{measurement_with, ErrorLayout, MAX_DIM};
use super::measurement::MEAS_DIM;
use crate::dispatch;
use crate::real::{Lanes, LANES};

/// Writes the measurement of `points` (`dim` values each, one after another) of a model with
/// the effects of `layout` into `z`, [`MEAS_DIM`] values each.
pub fn measure_blocks(layout: &ErrorLayout, dim: usize, points: &[f64], z: &mut [f64]) {
    dispatch!(measure_lanes(layout, dim, points, z));
}

/// [`measure_blocks`], inlined into both copies of [`crate::dispatch!`].
#[inline(always)]
fn measure_lanes(layout: &ErrorLayout, n: usize, points: &[f64], z: &mut [f64]) {
    let count = points.len() / n;
    debug_assert!(n <= MAX_DIM && z.len() >= count * MEAS_DIM);
    for first in (0..count).step_by(LANES) {
        let (lanes, x) = gather::<MAX_DIM>(points, n, first);
        let mut zl = [Lanes::default(); MEAS_DIM];
        measurement_with(layout, &x[..n], &mut zl);
        for (l, zp) in z[first * MEAS_DIM..]
            .chunks_exact_mut(MEAS_DIM)
            .take(lanes)
            .enumerate()
        {
            for (zr, lane) in zp.iter_mut().zip(&zl) {
                *zr = lane.0[l];
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::noise::NoiseConfig;
    use crate::strapdown::effect_list::StrapdownEffectList;
    use crate::strapdown::effects::StrapdownRegistry;
    use crate::strapdown::model::StrapdownModel;
    use crate::strapdown::partials_check::random_state;
    use crate::strapdown::unit_class::UnitClass;
    use crate::system::SystemModel;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    /// The batch against one point at a time, over a partial block, one block and more: the
    /// same bits without effects, within the last bits with every catalogued effect on.
    #[test]
    fn blocks_give_what_one_point_at_a_time_gives() {
        let registry = StrapdownRegistry::catalogue();
        let base = StrapdownModel::base(&NoiseConfig::default());
        let list = StrapdownEffectList::parse_entries(&registry.names(), &registry).unwrap();
        let every = base
            .clone()
            .with_effects(&list, UnitClass::Mems, 1.0)
            .unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        for (model, ulps) in [(&base, 0.0), (&every, 4.0)] {
            let (n, nz) = (model.dim(), model.meas_dim());
            for count in [1, 5, 8, 13, 27] {
                let points: Vec<f64> = (0..count)
                    .flat_map(|_| random_state(model, &mut rng))
                    .collect();
                let mut batch = vec![f64::NAN; count * nz];
                model.measure_points(&points, &mut batch);
                for (x, zb) in points.chunks_exact(n).zip(batch.chunks_exact(nz)) {
                    let mut z = vec![f64::NAN; nz];
                    model.measure(x, &mut z);
                    for (a, b) in z.iter().zip(zb) {
                        let allowed = ulps * f64::EPSILON * a.abs();
                        assert!((a - b).abs() <= allowed, "{a} against {b} ({count} points)");
                    }
                }
            }
        }
    }
}
