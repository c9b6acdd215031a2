//! Times one predict + update per filter on the benchmark's scenario (base model warmed up
//! for 300 s, then the 1 s window at t = 300 with 10 input sub-steps), for profiling:
//! `cargo run --release -p navkf-filters --example step_timing [-- FILTER [SECONDS]]`
//! with FILTER one of `ekf`, `simplified_ukf`, `standard_ukf`, `standard_ukf_25`, `square_root_ukf` or `all`.
//! Prints the median over batches and, with `--dump`, the state and covariance after one
//! step (to compare results between versions).
use navkf_dynamics::simulate::base_coefficient_sigma;
use navkf_dynamics::state::*;
use navkf_dynamics::*;
use navkf_filters::runner::observation_of;
use navkf_filters::*;
use std::sync::Arc;
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let dump = args.iter().any(|a| a == "--dump");
    let args: Vec<&String> = args.iter().filter(|a| *a != "--dump").collect();
    let which = args.first().map_or("all", |s| s.as_str());
    let seconds: f64 = args.get(1).map_or(2.0, |s| s.parse().unwrap());

    let noise = NoiseConfig::default();
    let model = Arc::new(PlatformModel::base(&noise));
    let traj = Arc::new(Trajectory::build(&TrajectoryConfig::default()).unwrap());
    let sim = Simulator::new(model.clone(), traj, TruthConfig::default(), noise).unwrap();
    let run = sim.run(1, 0);
    let n = model.dim();
    let mut x0 = vec![0.0; n];
    x0[LAT] = run.truth.states[0][LAT];
    x0[LON] = run.truth.states[0][LON];
    let mut p0 = vec![0.0; n * n];
    for i in 0..n {
        let s = match i {
            PHI_X | PHI_Y => 4.85e-5,
            PHI_Z => 2.91e-4,
            V_X | V_Y => 0.01,
            LAT | LON => 5e-7,
            _ => base_coefficient_sigma(i),
        };
        p0[i + i * n] = s * s;
    }
    let t = 300.0;
    let mut window = InputWindow::with_capacity(11);
    for s in sim
        .inputs()
        .iter()
        .filter(|s| s.t >= t - 1e-9 && s.t <= t + 1.0 + 1e-9)
    {
        window.push_linear(s.t, s.f);
    }
    let m = run
        .measurements
        .iter()
        .find(|m| (m.t - (t + 1.0)).abs() < 1e-9)
        .unwrap();
    let (z, sigma, avail) = observation_of(m, sim.noise(), 0.8);
    let obs = Observation {
        z: &z,
        sigma: &sigma,
        available: &avail,
    };
    let meas: Vec<_> = run
        .measurements
        .iter()
        .filter(|m| m.t <= t)
        .copied()
        .collect();

    let filters: Vec<Box<dyn Filter>> = vec![
        Box::new(Ekf::new(model.clone())),
        Box::new(simplified_ukf::new(model.clone(), SigmaScaling::default()).unwrap()),
        Box::new(standard_ukf::new(model.clone(), SigmaScaling::default()).unwrap()),
        Box::new(standard_ukf::process_only(model.clone(), SigmaScaling::default()).unwrap()),
        Box::new(SquareRootUkf::new(model.clone(), SigmaScaling::default()).unwrap()),
    ];
    for mut f in filters {
        if which != "all" && which != f.name() {
            continue;
        }
        f.reset(&x0, &p0).unwrap();
        Runner::new(16)
            .run(&mut *f, 0.0, sim.inputs(), &meas, sim.noise(), |_| {})
            .unwrap();
        let x = f.state().to_vec();
        let p = f.covariance().to_vec();
        if dump {
            f.predict(&window).unwrap();
            f.update(&obs).unwrap();
            println!("{}", f.name());
            for v in f.state().iter().chain(f.covariance()) {
                println!("{v:.17e}");
            }
            continue;
        }
        let batch = 1000;
        let mut meds = Vec::new();
        let start = Instant::now();
        while start.elapsed().as_secs_f64() < seconds {
            let t0 = Instant::now();
            for _ in 0..batch {
                f.reset(&x, &p).unwrap();
                f.predict(std::hint::black_box(&window)).unwrap();
                std::hint::black_box(f.update(std::hint::black_box(&obs)).unwrap().nis);
            }
            meds.push(t0.elapsed().as_secs_f64() * 1e6 / batch as f64);
        }
        meds.sort_by(|a, b| a.partial_cmp(b).unwrap());
        println!(
            "{:16} median {:.2} us  min {:.2} us  ({} batches of {batch})",
            f.name(),
            meds[meds.len() / 2],
            meds[0],
            meds.len()
        );
    }
}
