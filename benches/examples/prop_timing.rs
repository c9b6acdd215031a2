//! Times the batched propagation of 51 points over 1 s (10 sub-steps), for the base model,
//! `--idle` (five coefficients that enter nothing: 25 states, no physics) and
//! `--rate-effects` (`accel-cross-axis` and `torquer-scale`: 25 states); `--exact` for the
//! exact-attitude variant; `--noise` adds noise held over the window on every channel (as the
//! standard UKF's points carry). The point count is the same in every case, so the three compare
//! the cost of the rates per block.
//! `cargo run --release -p navkf-benches --example prop_timing -- [--idle | --rate-effects]
//! [--exact] [--noise]`
use navkf_benches::{IdleCoefficients, RATE_EFFECTS};
use navkf_dynamics::state::*;
use navkf_dynamics::*;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let has = |flag: &str| args.iter().any(|a| a == flag);
    let attitude = if has("--exact") {
        Attitude::Exact
    } else {
        Attitude::SmallAngle
    };
    let (effects, label): (Vec<Box<dyn DynEffect>>, &str) = if has("--rate-effects") {
        let effects = Registry::catalogue().build_all(&RATE_EFFECTS);
        (effects.expect("catalogued"), "rate effects")
    } else if has("--idle") {
        (vec![Box::new(IdleCoefficients)], "idle coefficients")
    } else {
        (Vec::new(), "base")
    };
    let model = PlatformModel::new(effects, &NoiseConfig::default())
        .expect("a valid model")
        .with_attitude(attitude);
    let n = model.dim();
    let mut w = InputWindow::with_capacity(11);
    for k in 0..=10 {
        w.push_linear(
            0.1 * k as f64,
            navkf_dynamics::kinematics::platform_input([0.3, -0.2, 9.8]),
        );
    }
    let mut x = vec![0.0; n];
    x[LAT] = 0.8;
    x[V_X] = 10.0;
    for v in &mut x[NAV_DIM..] {
        *v = 1e-5;
    }
    let base: Vec<f64> = (0..51)
        .flat_map(|i| {
            let mut y = x.clone();
            y[LAT] += 1e-7 * i as f64;
            y
        })
        .collect();
    let mut pts = base.clone();
    let mut scratch = PropagationScratch::default();
    // `--noise`: noise held over the window on every channel, as the standard UKF's points carry.
    let channels = model.noise_channels().len();
    let noise: Vec<f64> = (0..51 * channels).map(|i| 1e-9 * (i % 7) as f64).collect();
    let noise = has("--noise").then_some(&noise[..]);
    let reps = 20000;
    let mut best = f64::INFINITY;
    for _ in 0..5 {
        let t = std::time::Instant::now();
        for _ in 0..reps / 5 {
            pts.copy_from_slice(&base);
            model.propagate_points(&mut pts, noise, &w, &mut scratch);
            std::hint::black_box(&pts);
        }
        best = best.min(t.elapsed().as_secs_f64() * 1e6 / (reps / 5) as f64);
    }
    println!("{best:.2} us per propagate of 51 points, {n} states, {label} ({attitude})");
}
