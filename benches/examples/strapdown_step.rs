//! One predict + update of each filter on the strapdown base model against the same filter on
//! the platform base model, timed in one run, interleaved, so that the ratio holds whatever the
//! CPU (the strapdown issue's bound: at most 1.5x). Both windows are 1 s with 10 input
//! sub-steps; the strapdown update has the five rows of a moving vehicle (speed, GPS, two NHC;
//! the two zero-velocity rows are a standstill's), the platform's four.
//! `cargo run --release -p navkf-benches --example strapdown_step [-- SECONDS [FILTER]]`
//! (a FILTER name times that filter alone, for a profiler).

use navkf_benches::{all_filters, Scenario};
use navkf_dynamics::strapdown::model::{measurement, StrapdownModel, MEAS_DIM};
use navkf_dynamics::strapdown::rates::input_of;
use navkf_dynamics::strapdown::rates::ImuReading;
use navkf_dynamics::strapdown::state::*;
use navkf_dynamics::{InputWindow, NoiseConfig};
use navkf_filters::{Filter, FilterKind, Observation, SigmaScaling};
use std::sync::Arc;
use std::time::Instant;

/// Median microseconds of one reset + predict + update over batches for `seconds`.
fn time(
    f: &mut dyn Filter,
    x: &[f64],
    p: &[f64],
    w: &InputWindow,
    obs: &Observation,
    seconds: f64,
) -> f64 {
    let batch = 500;
    let mut meds = Vec::new();
    let start = Instant::now();
    while start.elapsed().as_secs_f64() < seconds {
        let t0 = Instant::now();
        for _ in 0..batch {
            f.reset(x, p).unwrap();
            f.predict(std::hint::black_box(w)).unwrap();
            std::hint::black_box(f.update(std::hint::black_box(obs)).unwrap().nis);
        }
        meds.push(t0.elapsed().as_secs_f64() * 1e6 / batch as f64);
    }
    meds.sort_by(|a, b| a.total_cmp(b));
    meds[meds.len() / 2]
}

fn main() {
    let seconds: f64 = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(1.0);
    let only = std::env::args().nth(2);
    // The platform: the benchmarks' scenario, warmed up.
    let sc = Scenario::new();
    let (pw, pz, ps, pa) = sc.window_at(300.0);
    let pobs = Observation {
        z: &pz,
        sigma: &ps,
        available: &pa,
    };
    // The strapdown: cruising level at 15 m/s, heading 30 deg, 48 deg of latitude.
    let model = Arc::new(StrapdownModel::base(&NoiseConfig {
        gyro_psd: 1e-10,
        accel_psd: 1e-6,
        ..NoiseConfig::default()
    }));
    let mut x = vec![0.0; BASE_DIM];
    x[HEADING] = 0.5;
    x[V_E] = 15.0 * 0.5f64.sin();
    x[V_N] = 15.0 * 0.5f64.cos();
    x[LAT] = 0.84;
    let sd = [
        1e-3, 1e-3, 2e-2, 0.1, 0.1, 1e-6, 1e-6, 5e-5, 5e-5, 5e-5, 1e-2, 1e-2, 1e-2,
    ];
    let mut p = vec![0.0; BASE_DIM * BASE_DIM];
    for i in 0..BASE_DIM {
        p[i + i * BASE_DIM] = sd[i] * sd[i];
    }
    let mut w = InputWindow::with_capacity(11);
    let imu = ImuReading {
        w: [1e-5, 2e-5, 5e-5],
        f: [0.01, -0.02, 9.81],
    };
    for k in 0..=10 {
        w.push_linear(0.1 * k as f64, input_of(&imu));
    }
    let mut z = [0.0; MEAS_DIM];
    measurement(&x, &mut z);
    let sigma = [0.03, 5e-7, 7e-7, 0.05, 0.05, 0.01, 0.01];
    // Moving: speed, GPS and the constraint; the zero-velocity rows are a standstill's.
    let obs = Observation {
        z: &z,
        sigma: &sigma,
        available: &[true, true, true, true, true, false, false],
    };
    println!(
        "{:16} {:>10} {:>10} {:>6}",
        "filter", "platform", "strapdown", "ratio"
    );
    for mut pf in all_filters(&sc.model) {
        if only.as_deref().is_some_and(|name| name != pf.name()) {
            continue;
        }
        sc.warm_up(&mut *pf, 300.0);
        let (px, pp) = (pf.state().to_vec(), pf.covariance().to_vec());
        let kind: FilterKind = pf.name().parse().unwrap();
        let mut sf = kind.build(model.clone(), SigmaScaling::default()).unwrap();
        let (mut tp, mut ts) = (f64::INFINITY, f64::INFINITY);
        for _ in 0..3 {
            tp = tp.min(time(&mut *pf, &px, &pp, &pw, &pobs, seconds / 6.0));
            ts = ts.min(time(&mut *sf, &x, &p, &w, &obs, seconds / 6.0));
        }
        println!(
            "{:16} {:>8.2} us {:>8.2} us {:>6.2}",
            pf.name(),
            tp,
            ts,
            ts / tp
        );
    }
}
