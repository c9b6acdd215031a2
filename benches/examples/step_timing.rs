//! Times one predict + update per filter on the benchmark's scenario (base model warmed up
//! for 300 s, then the 1 s window at t = 300 with 10 input sub-steps), without criterion, for
//! profiling (`perf record`):
//! `cargo run --release -p navkf-benches --example step_timing [-- FILTER [SECONDS]]`
//! with FILTER a filter's name (`ekf`, `simplified_ukf`, `standard_ukf`, `standard_ukf_25`,
//! `square_root_ukf`) or `all`. Prints the median over batches and, with `--dump`, the state
//! and covariance after one step (to compare results between versions). `--rate-effects`
//! switches on two effects that add rates (`accel-cross-axis`, `torquer-scale`: 25 states);
//! `--idle-coefficients` adds five coefficients that enter nothing (25 states, no physics);
//! `--exact` takes the base model's exact-attitude variant.

use navkf_benches::{all_filters, Scenario};
use navkf_filters::Observation;
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let dump = args.iter().any(|a| a == "--dump");
    let effects = args.iter().any(|a| a == "--rate-effects");
    let idle = args.iter().any(|a| a == "--idle-coefficients");
    let exact = args.iter().any(|a| a == "--exact");
    let args: Vec<&String> = args.iter().filter(|a| !a.starts_with("--")).collect();
    let which = args.first().map_or("all", |s| s.as_str());
    let seconds: f64 = match args.get(1).map(|s| s.parse()) {
        None => 2.0,
        Some(Ok(v)) => v,
        Some(Err(_)) => {
            eprintln!("SECONDS must be a number, got `{}`", args[1]);
            std::process::exit(2);
        }
    };
    let sc = if exact {
        Scenario::exact_attitude()
    } else if effects {
        Scenario::with_effects(&navkf_benches::RATE_EFFECTS)
    } else if idle {
        Scenario::with_effect_objects(vec![Box::new(navkf_benches::IdleCoefficients)])
    } else {
        Scenario::new()
    };
    let (window, z, sigma, avail) = sc.window_at(300.0);
    let obs = Observation {
        z: &z,
        sigma: &sigma,
        available: &avail,
    };
    for mut f in all_filters(&sc.model) {
        if which != "all" && which != f.name() {
            continue;
        }
        sc.warm_up(&mut *f, 300.0);
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
        meds.sort_by(|a, b| a.total_cmp(b));
        println!(
            "{:16} median {:.2} us  min {:.2} us  ({} batches of {batch})",
            f.name(),
            meds[meds.len() / 2],
            meds[0],
            meds.len()
        );
    }
}
