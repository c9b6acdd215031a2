//! Cost of one filter step (predict over 1 s with 10 input sub-steps, then update) for the
//! 20-state base model and for the model with two effects that add rates
//! ([`navkf_benches::RATE_EFFECTS`], 25 states), and for the exact-attitude variant of the base model, per
//! filter; and the model evaluation on its own.
//!
//! `cargo bench --manifest-path benches/criterion/Cargo.toml` (add `-- --quick` for a short run).

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use navkf_benches::Scenario;
use navkf_dynamics::{PropagationScratch, SystemModel};
use navkf_filters::Observation;
use std::hint::black_box;

fn filter_steps(c: &mut Criterion) {
    let mut group = c.benchmark_group("predict_update");
    for (label, sc) in [
        ("base", Scenario::new()),
        (
            "with_rate_effects",
            Scenario::with_effects(&navkf_benches::RATE_EFFECTS),
        ),
        ("exact_attitude", Scenario::exact_attitude()),
    ] {
        let (window, z, sigma, avail) = sc.window_at(300.0);
        let obs = Observation {
            z: &z,
            sigma: &sigma,
            available: &avail,
        };
        for mut f in navkf_benches::all_filters(&sc.model) {
            sc.warm_up(&mut *f, 300.0);
            let x = f.state().to_vec();
            let p = f.covariance().to_vec();
            let id = format!("{}/{label}", f.name());
            group.bench_function(BenchmarkId::new(id, sc.model.dim()), |b| {
                b.iter(|| {
                    // Same prior every time, so each iteration does the same work.
                    f.reset(&x, &p).unwrap();
                    f.predict(black_box(&window)).unwrap();
                    black_box(f.update(black_box(&obs)).unwrap().nis);
                })
            });
        }
    }
    group.finish();
}

fn model_evaluation(c: &mut Criterion) {
    let sc = Scenario::new();
    let (window, ..) = sc.window_at(300.0);
    let x = sc.run.truth.states[300].clone();
    let u = window.f[0];
    let mut dx = vec![0.0; sc.model.dynamic_dim()];
    let mut group = c.benchmark_group("model");
    group.bench_function("rates", |b| {
        b.iter(|| sc.model.rates(black_box(&x), black_box(&u), &mut dx))
    });
    let mut jac = vec![0.0; sc.model.dynamic_dim() * sc.model.dim()];
    group.bench_function("rate_jacobian", |b| {
        b.iter(|| {
            sc.model
                .rate_jacobian(black_box(&x), black_box(&u), &mut jac)
        })
    });
    for count in [41usize, 51] {
        let n = sc.model.dim();
        let mut pts: Vec<f64> = (0..count).flat_map(|_| x.iter().copied()).collect();
        let base = pts.clone();
        let mut scratch = PropagationScratch::default();
        group.bench_function(BenchmarkId::new("propagate_points_1s_10sub", count), |b| {
            b.iter(|| {
                pts.copy_from_slice(&base);
                sc.model
                    .propagate_points(&mut pts[..count * n], None, &window, &mut scratch);
                black_box(pts[3]);
            })
        });
    }
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(50).measurement_time(std::time::Duration::from_secs(3)).warm_up_time(std::time::Duration::from_secs(1));
    targets = filter_steps, model_evaluation
}
criterion_main!(benches);
