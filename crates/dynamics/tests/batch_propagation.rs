//! The batched propagation (the UKF's hot path) agrees with the generic RK4 to rounding, with
//! and without process noise, across several blocks with padding lanes, and steps aside when
//! the latitudes are too far apart for its series.

use navkf_dynamics::integrate::propagate_generic;
use navkf_dynamics::simulate::base_coefficient_sigma;
use navkf_dynamics::state::*;
use navkf_dynamics::{InputWindow, NoiseConfig, PlatformModel, PropagationScratch, SystemModel};
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

fn window() -> InputWindow {
    let mut w = InputWindow::with_capacity(11);
    for k in 0..=10 {
        let t = 0.1 * k as f64;
        w.push_linear(t, [0.8 * (t * 2.0).sin(), -0.5 + 0.3 * t, 9.806]);
    }
    w
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
        let mut generic = start.clone();
        let mut scratch = vec![0.0; model.scratch_len(1)];
        for (i, x) in generic.chunks_exact_mut(BASE_DIM).enumerate() {
            propagate_generic(
                &model,
                x,
                noise.map(|n| &n[i * nw..(i + 1) * nw]),
                &w,
                &mut scratch,
            );
        }
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
    let mut generic = start.clone();
    let mut scratch = vec![0.0; model.scratch_len(1)];
    for x in generic.chunks_exact_mut(BASE_DIM) {
        propagate_generic(&model, x, None, &w, &mut scratch);
    }
    assert_eq!(batched, generic);
}
