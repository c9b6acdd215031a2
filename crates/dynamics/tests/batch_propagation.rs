//! The batched propagation (the UKF's hot path) agrees with the generic RK4 to rounding, with
//! and without process noise, across several blocks with padding lanes, and steps aside when
//! the latitudes are too far apart for its series.

use crate::common;

use common::{one_by_one, window};
use navkf_dynamics::prior::base_coefficient_sigma;
use navkf_dynamics::state::*;
use navkf_dynamics::{NoiseConfig, PlatformModel, PropagationScratch, SystemModel};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn points(count: usize, lat_spread: f64, rng: &mut ChaCha8Rng) -> Vec<f64> {
    let mut out = Vec::new();
    for _ in 0..count {
        let mut x = vec![0.0; BASE_DIM];
        x[PHI_X] = rng.gen_range(-1e-3..1e-3);
        x[PHI_Y] = rng.gen_range(-1e-3..1e-3);
        x[PHI_Z] = rng.gen_range(-3e-3..3e-3);
        x[V_X] = rng.gen_range(-20.0..20.0);
        x[V_Y] = rng.gen_range(-20.0..20.0);
        x[LAT] = 0.8 + rng.gen_range(-lat_spread..lat_spread);
        x[LON] = 2.2 + rng.gen_range(-1e-4..1e-4);
        for (i, xi) in x.iter_mut().enumerate().skip(NAV_DIM) {
            *xi = 3.0 * base_coefficient_sigma(i) * rng.gen_range(-1.0..1.0);
        }
        out.extend(x);
    }
    out
}

/// Largest difference relative to each state's own scale.
fn max_scaled_difference(a: &[f64], b: &[f64]) -> f64 {
    let scale = [1e-3, 1e-3, 1e-3, 20.0, 20.0, 1.0, 1.0];
    a.chunks_exact(BASE_DIM)
        .zip(b.chunks_exact(BASE_DIM))
        .flat_map(|(x, y)| (0..BASE_DIM).map(move |i| (i, x[i], y[i])))
        .map(|(i, x, y)| {
            let s = if i < NAV_DIM {
                scale[i]
            } else {
                base_coefficient_sigma(i)
            };
            (x - y).abs() / s
        })
        .fold(0.0, f64::max)
}

#[test]
fn batched_equals_generic_to_rounding() {
    let model = PlatformModel::base(&NoiseConfig::default());
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let w = window();
    // 19 points: two full blocks of 8 and one padded block of 3.
    for with_noise in [false, true] {
        let start = points(19, 1e-5, &mut rng);
        let nw = model.noise_channels().len();
        let noise: Vec<f64> = (0..19 * nw).map(|_| rng.gen_range(-1e-4..1e-4)).collect();
        let noise = with_noise.then_some(&noise[..]);
        let mut batched = start.clone();
        model.propagate_points(&mut batched, noise, &w, &mut PropagationScratch::default());
        let generic = one_by_one(&model, &start, noise, &w);
        // The states moved (the test is not comparing two no-ops)...
        assert!(max_scaled_difference(&batched, &start) > 1e-3);
        // ...and both paths agree to a few ulps of each state's scale.
        let d = max_scaled_difference(&batched, &generic);
        assert!(
            d < 1e-13,
            "batched and generic differ by {d:e} (noise: {with_noise})"
        );
        // Coefficients are untouched.
        for (a, b) in batched
            .chunks_exact(BASE_DIM)
            .zip(start.chunks_exact(BASE_DIM))
        {
            assert_eq!(a[NAV_DIM..], b[NAV_DIM..]);
        }
    }
}

#[test]
fn far_apart_latitudes_take_the_generic_path_and_stay_exact() {
    // Points 0.1 rad apart are beyond the series' range: the batched path must not be used,
    // and the result must equal the generic one bit for bit.
    let model = PlatformModel::base(&NoiseConfig::default());
    let mut rng = ChaCha8Rng::seed_from_u64(4);
    let w = window();
    let start = points(5, 0.1, &mut rng);
    let mut batched = start.clone();
    model.propagate_points(&mut batched, None, &w, &mut PropagationScratch::default());
    assert_eq!(batched, one_by_one(&model, &start, None, &w));
}

/// An effect written outside the crate, with rates, as a user would write it.
#[derive(Debug)]
struct Damping;
impl navkf_dynamics::Effect for Damping {
    fn name(&self) -> &str {
        "damping"
    }
    fn description(&self) -> &str {
        "v' -= kd v_x v_y / 10, phi_z' += kd (tan L / cos L + phi_x fz + 1e6 tan L / RN) / 1000"
    }
    fn coefficient_names(&self) -> &[&str] {
        &["kd"]
    }
    fn coefficient_units(&self) -> &[&str] {
        &["1/s"]
    }
    fn coefficient_sigma(&self) -> &[f64] {
        &[1e-3]
    }
    fn terms(&self) -> navkf_dynamics::Terms {
        navkf_dynamics::Terms::RATES
    }
    fn add_rates<T: navkf_dynamics::Real>(
        &self,
        k: &navkf_dynamics::Kinematics<T>,
        c: &[T],
        rates: &mut [T; NAV_DIM],
    ) {
        // A product of states, so that a lane mix-up could not cancel out.
        rates[V_X] -= c[0] * k.v_x * k.v_y * 0.1;
        rates[V_Y] -= c[0] * k.v_y * k.v_x * 0.1;
        // Kinematics no catalogued effect reads: the batch hands effects the latitude's
        // functions and each rebuilds the rest, so every field must come out as the one-state
        // path's.
        rates[PHI_Z] +=
            c[0] * (k.tan_l * k.inv_cos + k.phi[0] * k.f[2] + k.tan_over_rn * 1e6) * 1e-3;
    }
}

#[test]
fn every_effect_and_a_users_own_run_batched_and_agree_with_the_generic_path() {
    // Every catalogued effect (rates, measurement terms, noise on the drifts) plus one from
    // outside the crate; the batch is called directly, so it cannot step aside.
    let registry = navkf_dynamics::Registry::catalogue();
    let mut effects = registry.build_all(&registry.names()).unwrap();
    effects.push(Box::new(Damping));
    let model = PlatformModel::new(effects, &NoiseConfig::default()).unwrap();
    let n = model.dim();
    let sigmas = model.effect_coefficient_sigmas();
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let w = window();
    // Six blocks: a whole group of four and a part-group, the last block one point and seven
    // padding lanes.
    let count = 41;
    let mut start = Vec::new();
    for base in points(count, 1e-5, &mut rng).chunks_exact(BASE_DIM) {
        start.extend_from_slice(base);
        for (i, s) in &sigmas {
            assert!(*i >= BASE_DIM);
            start.push(30.0 * s * rng.gen_range(-1.0..1.0));
        }
    }
    assert_eq!(start.len(), count * n);
    let nw = model.noise_channels().len();
    assert!(model.noise_channels().iter().any(|c| c.state >= NAV_DIM));
    let noise: Vec<f64> = (0..count * nw)
        .map(|_| rng.gen_range(-1e-4..1e-4))
        .collect();
    for noise in [None, Some(&noise[..])] {
        let mut batched = start.clone();
        navkf_dynamics::batch_propagation::propagate(
            &model,
            &mut batched,
            noise,
            &w,
            &mut PropagationScratch::default(),
        );
        let generic = one_by_one(&model, &start, noise, &w);
        for (p, (a, b)) in batched
            .chunks_exact(n)
            .zip(generic.chunks_exact(n))
            .enumerate()
        {
            for s in 0..n {
                let scale = if s < NAV_DIM {
                    [1e-3, 1e-3, 1e-3, 20.0, 20.0, 1.0, 1.0][s]
                } else {
                    start[p * n + s].abs().max(1e-12)
                };
                let d = (a[s] - b[s]).abs() / scale;
                assert!(d < 1e-12, "point {p}, state {s}: {} vs {}", a[s], b[s]);
            }
        }
        // The effects moved the states: without them the result differs.
        let base = PlatformModel::base(&NoiseConfig::default());
        let mut plain: Vec<f64> = start
            .chunks_exact(n)
            .flat_map(|x| x[..BASE_DIM].to_vec())
            .collect();
        base.propagate_points(&mut plain, None, &w, &mut PropagationScratch::default());
        let moved = plain
            .chunks_exact(BASE_DIM)
            .zip(batched.chunks_exact(n))
            .map(|(p, b)| (p[V_X] - b[V_X]).abs())
            .fold(0.0, f64::max);
        assert!(moved > 1e-6, "effects changed v_x by only {moved:e}");
    }
}
