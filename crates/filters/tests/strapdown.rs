//! Every filter on the strapdown family (docs/model.md, "The strapdown family"): a simulated
//! five-minute drive with turns, read by a unit with gyro and accelerometer biases and white
//! noise, measured by an odometer, a GPS and the non-holonomic constraint. Over seeded runs
//! each filter's final errors must be what its covariance claims (mean NEES within a 99 %
//! chi-square band), and the filters must agree with one another.

use navkf_dynamics::earth::{normal_gravity, WIE};
use navkf_dynamics::strapdown::attitude::{body_to_nav, rotate_back};
use navkf_dynamics::strapdown::model::{measurement, StrapdownModel, MEAS_DIM};
use navkf_dynamics::strapdown::rates::input_of;
use navkf_dynamics::strapdown::rates::{nav_rates, ImuReading};
use navkf_dynamics::strapdown::state::*;
use navkf_dynamics::{InputWindow, NoiseConfig};
use navkf_filters::{FilterKind, Observation, SigmaScaling};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;
use std::sync::Arc;

const IMU_HZ: f64 = 100.0;
const DURATION_S: usize = 300;
const SPEED: f64 = 15.0;

/// The heading rate of the drive at `t`: straight, then S-bends.
fn turn_rate(t: f64) -> f64 {
    if t < 30.0 {
        0.0
    } else {
        0.15 * (2.0 * std::f64::consts::PI * t / 60.0).sin()
    }
}

/// The error-free reading that makes the level vehicle at `x` turn at `turn_rate(t)` at
/// constant speed along its heading.
fn ideal_reading(t: f64, x: &[f64]) -> ImuReading {
    let c = body_to_nav([x[ROLL], x[PITCH], x[HEADING]]);
    let (sl, cl) = x[LAT].sin_cos();
    let rm = navkf_dynamics::earth::meridian_radius(sl);
    let rn = navkf_dynamics::earth::prime_vertical_radius(sl);
    let (ve, vn) = (x[V_E], x[V_N]);
    let w_in = [-vn / rm, WIE * cl + ve / rn, WIE * sl + ve * sl / cl / rn];
    let w_in_b = rotate_back(&c, w_in);
    // Heading counts clockwise: a turn to the right is a negative rate about up.
    let r = turn_rate(t);
    let w = [w_in_b[0], w_in_b[1], w_in_b[2] - r];
    // v' along the turn: the velocity turns at r; plus the Coriolis and transport terms.
    let turn = 2.0 * WIE * sl + ve * sl / cl / rn;
    let f_n = [vn * r - turn * vn, -ve * r + turn * ve, normal_gravity(sl)];
    ImuReading {
        w,
        f: rotate_back(&c, f_n),
    }
}

struct Run {
    truth: Vec<[f64; BASE_DIM]>,
    imu: Vec<(f64, ImuReading)>,
    z: Vec<[f64; MEAS_DIM]>,
}

fn simulate(seed: u64, noise: &NoiseConfig, bias_g: f64, bias_a: f64) -> Run {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut x = [0.0f64; BASE_DIM];
    x[HEADING] = 0.5;
    x[LAT] = 0.7;
    x[LON] = 0.2;
    x[V_E] = SPEED * x[HEADING].sin();
    x[V_N] = SPEED * x[HEADING].cos();
    for i in 0..3 {
        x[BG_X + i] = bias_g * rng.sample::<f64, _>(StandardNormal);
        x[BA_X + i] = bias_a * rng.sample::<f64, _>(StandardNormal);
    }
    let h = 1.0 / IMU_HZ;
    let steps = DURATION_S * IMU_HZ as usize;
    let mut truth = vec![x];
    let mut imu = Vec::with_capacity(steps + 1);
    let mut z = Vec::new();
    let sg = (noise.gyro_psd / h).sqrt();
    let sa = (noise.accel_psd / h).sqrt();
    let read = |t: f64, x: &[f64; BASE_DIM], rng: &mut ChaCha8Rng| {
        let ideal = ideal_reading(t, x);
        ImuReading {
            w: std::array::from_fn(|i| {
                ideal.w[i] + x[BG_X + i] + sg * rng.sample::<f64, _>(StandardNormal)
            }),
            f: std::array::from_fn(|i| {
                ideal.f[i] + x[BA_X + i] + sa * rng.sample::<f64, _>(StandardNormal)
            }),
        }
    };
    imu.push((0.0, read(0.0, &x, &mut rng)));
    for k in 0..steps {
        let t = k as f64 * h;
        // The truth follows the ideal reading (RK4 on the error-free rates).
        let f = |t: f64, x: &[f64; BASE_DIM]| {
            let mut dx = [0.0; BASE_DIM];
            let mut clean = *x;
            for i in 0..3 {
                clean[BG_X + i] = 0.0;
                clean[BA_X + i] = 0.0;
            }
            nav_rates(&clean, &ideal_reading(t, x), &mut dx[..NAV_DIM]);
            dx
        };
        let add = |x: &[f64; BASE_DIM], k: &[f64; BASE_DIM], s: f64| {
            std::array::from_fn::<f64, BASE_DIM, _>(|i| x[i] + s * k[i])
        };
        let k1 = f(t, &x);
        let k2 = f(t + h / 2.0, &add(&x, &k1, h / 2.0));
        let k3 = f(t + h / 2.0, &add(&x, &k2, h / 2.0));
        let k4 = f(t + h, &add(&x, &k3, h));
        for i in 0..BASE_DIM {
            x[i] += h / 6.0 * (k1[i] + 2.0 * (k2[i] + k3[i]) + k4[i]);
        }
        let t1 = (k + 1) as f64 * h;
        imu.push((t1, read(t1, &x, &mut rng)));
        if (k + 1) % IMU_HZ as usize == 0 {
            truth.push(x);
            let mut m = [0.0; MEAS_DIM];
            measurement(&x, &mut m);
            z.push(m);
        }
    }
    Run { truth, imu, z }
}

fn sigmas(x: &[f64; BASE_DIM], noise: &NoiseConfig, nhc: f64) -> [f64; MEAS_DIM] {
    let (sl, cl) = x[LAT].sin_cos();
    let rm = navkf_dynamics::earth::meridian_radius(sl);
    let rn = navkf_dynamics::earth::prime_vertical_radius(sl);
    [
        (noise.odometer_rel * SPEED).max(noise.odometer_floor),
        noise.gps_m / rm,
        noise.gps_m / (rn * cl),
        nhc,
        nhc,
        noise.odometer_floor,
        noise.odometer_floor,
    ]
}

/// NEES of the final estimate of one run with `kind`, and the final estimate.
fn run_filter(
    kind: FilterKind,
    run: &Run,
    noise: &NoiseConfig,
    p0: &[f64],
    seed: u64,
) -> (f64, Vec<f64>) {
    let model = Arc::new(StrapdownModel::base(noise));
    let mut f = kind.build(model, SigmaScaling::default()).unwrap();
    let n = BASE_DIM;
    // The initial estimate: the truth off by a draw from the initial covariance.
    let mut rng = ChaCha8Rng::seed_from_u64(1000 + seed);
    let x0: Vec<f64> = (0..n)
        .map(|i| run.truth[0][i] + p0[i + i * n].sqrt() * rng.sample::<f64, _>(StandardNormal))
        .collect();
    f.reset(&x0, p0).unwrap();
    let per_second = IMU_HZ as usize;
    let mut w = InputWindow::with_capacity(per_second + 1);
    let nhc = 0.05;
    for (s, z) in run.z.iter().enumerate() {
        w.clear();
        for (t, r) in &run.imu[s * per_second..=(s + 1) * per_second] {
            w.push_linear(*t, input_of(r));
        }
        f.predict(&w).unwrap();
        // The measurement noise: drawn here, on top of the error-free values.
        let sig = sigmas(&run.truth[s + 1], noise, nhc);
        let zn: Vec<f64> = (0..MEAS_DIM)
            .map(|i| z[i] + sig[i] * rng.sample::<f64, _>(StandardNormal))
            .collect();
        f.update(&Observation {
            z: &zn,
            sigma: &sig,
            // Never at rest: the odometer and the constraint, not the zero-velocity update.
            available: &[true, true, true, true, true, false, false],
        })
        .unwrap();
    }
    let truth = run.truth.last().unwrap();
    let mut scratch = vec![0.0; n * n + n];
    let nees = navkf_filters::nees(truth, f.state(), f.covariance(), &mut scratch).unwrap();
    (nees, f.state().to_vec())
}

#[test]
fn every_filter_is_consistent_on_a_strapdown_drive_and_they_agree() {
    // A tactical-grade unit: 10 deg/h gyro biases, 1 mg accelerometer biases.
    let noise = NoiseConfig {
        gyro_psd: 1e-10,
        accel_psd: 1e-6,
        ..NoiseConfig::default()
    };
    let (bias_g, bias_a) = (10f64.to_radians() / 3600.0, 1e-3 * 9.81);
    let n = BASE_DIM;
    let mut p0 = vec![0.0; n * n];
    let sd = [
        1e-3, 1e-3, 2e-2, 0.1, 0.1, 1e-6, 1e-6, bias_g, bias_g, bias_g, bias_a, bias_a, bias_a,
    ];
    for i in 0..n {
        p0[i + i * n] = sd[i] * sd[i];
    }
    let runs = 20;
    let kinds = [
        FilterKind::Ekf,
        FilterKind::StandardUkf,
        FilterKind::SimplifiedUkf,
        FilterKind::SquareRootUkf,
    ];
    let mut nees = vec![0.0; kinds.len()];
    for seed in 0..runs {
        let run = simulate(seed, &noise, bias_g, bias_a);
        let results: Vec<(f64, Vec<f64>)> = kinds
            .iter()
            .map(|&k| run_filter(k, &run, &noise, &p0, seed))
            .collect();
        for (i, (e, _)) in results.iter().enumerate() {
            nees[i] += e / runs as f64;
        }
        // The filters agree: every final estimate within half the state's initial sigma of
        // the EKF's.
        let ekf = &results[0].1;
        for (k, (_, x)) in results.iter().enumerate().skip(1) {
            for i in 0..n {
                let diff = (x[i] - ekf[i]).abs();
                assert!(
                    diff <= 0.5 * sd[i],
                    "{:?} and the EKF disagree on {} by {diff:e} (seed {seed})",
                    kinds[k],
                    STATE_NAMES[i]
                );
            }
        }
    }
    // Mean NEES of `runs` runs of 13 states: chi-square with 13 runs dof, divided by runs.
    let total = (n * runs as usize) as f64;
    let lo = navkf_report_free_chi2_quantile(0.005, total) / runs as f64;
    let hi = navkf_report_free_chi2_quantile(0.995, total) / runs as f64;
    for (k, m) in kinds.iter().zip(&nees) {
        assert!(
            *m >= lo && *m <= hi,
            "{k:?}: mean NEES {m:.2} outside {lo:.2}-{hi:.2}"
        );
    }
}

/// The chi-square quantile by the Wilson-Hilferty approximation (ample for hundreds of
/// degrees of freedom; the filters crate does not depend on navkf-report).
fn navkf_report_free_chi2_quantile(p: f64, k: f64) -> f64 {
    // Normal quantile by Acklam's rational approximation is overkill here: the two tails used
    // are fixed.
    let z = if p < 0.5 {
        -2.575_829_303_548_901
    } else {
        2.575_829_303_548_901
    };
    let a = 2.0 / (9.0 * k);
    k * (1.0 - a + z * a.sqrt()).powi(3)
}
