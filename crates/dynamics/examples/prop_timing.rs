//! Times the batched propagation of 41 points over 1 s (10 sub-steps); `--exact` for the
//! exact-attitude variant.
use navkf_dynamics::state::*;
use navkf_dynamics::*;
fn main() {
    let attitude = if std::env::args().any(|a| a == "--exact") {
        Attitude::Exact
    } else {
        Attitude::SmallAngle
    };
    let model = PlatformModel::base(&NoiseConfig::default()).with_attitude(attitude);
    let mut w = InputWindow::with_capacity(11);
    for k in 0..=10 {
        w.push_linear(0.1 * k as f64, [0.3, -0.2, 9.8]);
    }
    let mut x = vec![0.0; BASE_DIM];
    x[LAT] = 0.8;
    x[V_X] = 10.0;
    let base: Vec<f64> = (0..41)
        .flat_map(|i| {
            let mut y = x.clone();
            y[LAT] += 1e-7 * i as f64;
            y
        })
        .collect();
    let mut pts = base.clone();
    let mut scratch = PropagationScratch::default();
    let reps = 20000;
    let t = std::time::Instant::now();
    for _ in 0..reps {
        pts.copy_from_slice(&base);
        model.propagate_points(&mut pts, None, &w, &mut scratch);
        std::hint::black_box(&pts);
    }
    println!(
        "{:.2} us per propagate of 41 points ({attitude})",
        t.elapsed().as_secs_f64() * 1e6 / reps as f64
    );
}
