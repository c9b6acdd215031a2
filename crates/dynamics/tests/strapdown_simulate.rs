//! The strapdown truth simulator (`strapdown::simulate`): its error-free readings drive the
//! model along the path it was made from, its errors are the drawn biases plus a white
//! noise of the stated density, and its measurements carry the stated noise.

use navkf_dynamics::strapdown::model::StrapdownModel;
use navkf_dynamics::strapdown::rates::nav_rates;
use navkf_dynamics::strapdown::simulate::{ideal_reading, path_state, StrapdownSimulator};
use navkf_dynamics::strapdown::state::*;
use navkf_dynamics::strapdown::unit_class::UnitClass;
use navkf_dynamics::{NoiseConfig, Trajectory, TrajectoryConfig};
use std::collections::BTreeMap;
use std::sync::Arc;

/// RK4 of the error-free navigation equations driven by the path's ideal readings,
/// interpolated linearly between samples `h` apart, as the filters integrate them.
fn follow(traj: &Trajectory, h: f64, until: f64) -> f64 {
    let mut x = path_state(&traj.state(0.0)).to_vec();
    x.resize(BASE_DIM, 0.0);
    let rates = |x: &[f64], r: &navkf_dynamics::strapdown::rates::ImuReading| {
        let mut dx = vec![0.0; NAV_DIM];
        nav_rates(x, r, &mut dx);
        dx
    };
    let steps = (until / h).round() as usize;
    let mut worst: f64 = 0.0;
    for k in 0..steps {
        let (t0, t1) = (k as f64 * h, (k + 1) as f64 * h);
        let (r0, r1) = (
            ideal_reading(&traj.state(t0)),
            ideal_reading(&traj.state(t1)),
        );
        let mid = navkf_dynamics::strapdown::rates::ImuReading {
            w: std::array::from_fn(|i| 0.5 * (r0.w[i] + r1.w[i])),
            f: std::array::from_fn(|i| 0.5 * (r0.f[i] + r1.f[i])),
        };
        let add = |x: &[f64], d: &[f64], s: f64| -> Vec<f64> {
            let mut y = x.to_vec();
            for i in 0..NAV_DIM {
                y[i] += s * d[i];
            }
            y
        };
        let k1 = rates(&x, &r0);
        let k2 = rates(&add(&x, &k1, h / 2.0), &mid);
        let k3 = rates(&add(&x, &k2, h / 2.0), &mid);
        let k4 = rates(&add(&x, &k3, h), &r1);
        for i in 0..NAV_DIM {
            x[i] += h / 6.0 * (k1[i] + 2.0 * (k2[i] + k3[i]) + k4[i]);
        }
        let truth = path_state(&traj.state(t1));
        let rm = navkf_dynamics::earth::meridian_radius(truth[LAT].sin());
        let north_m = (x[LAT] - truth[LAT]) * rm;
        let east_m = (x[LON] - truth[LON]) * rm * truth[LAT].cos();
        worst = worst.max(north_m.hypot(east_m));
        let dpsi = (x[HEADING] - truth[HEADING]).sin().abs();
        assert!(dpsi < 1e-5, "heading off by {dpsi} rad at t = {t1}");
        assert!(
            x[ROLL].abs() < 1e-6 && x[PITCH].abs() < 1e-6,
            "t = {t1}: {x:?}"
        );
    }
    worst
}

#[test]
fn the_ideal_readings_drive_the_model_along_the_path() {
    let traj = Trajectory::build(&TrajectoryConfig::default()).unwrap();
    // The whole 2400-s test at 10 Hz (the studies' rate; 8 cm at worst when written) and its
    // first 900 s at 100 Hz: the model stays on the path to centimetres, far inside the
    // GPS's metres, so a filter's error is its own.
    let at_10 = follow(&traj, 0.1, traj.duration());
    assert!(at_10 < 0.1, "{at_10} m off the path at 10 Hz");
    let at_100 = follow(&traj, 0.01, 900.0);
    assert!(at_100 < 0.01, "{at_100} m off the path at 100 Hz");
}

#[test]
fn a_run_reads_biases_and_noise_of_the_stated_size() {
    let traj = Arc::new(Trajectory::build(&TrajectoryConfig::default()).unwrap());
    let unit = UnitClass::Tactical.errors();
    let noise = unit.noise(NoiseConfig::default());
    let model = Arc::new(StrapdownModel::base(&noise));
    let sim = StrapdownSimulator::new(
        model,
        traj.clone(),
        10.0,
        1.0,
        unit,
        &BTreeMap::new(),
        noise,
    )
    .unwrap();
    // The biases: N(0, sigma) over many runs (chi-square of 6 x 200 draws within 4 sigma).
    let mut chi2 = 0.0;
    let runs = 200;
    for run in 0..runs {
        let c = sim.coefficients(7, run);
        for a in 0..3 {
            chi2 += (c[a] / unit.gyro_bias).powi(2) + (c[3 + a] / unit.accel_bias).powi(2);
        }
    }
    let dof = 6.0 * runs as f64;
    assert!(
        (chi2 - dof).abs() < 4.0 * (2.0 * dof).sqrt(),
        "{chi2} vs {dof}"
    );
    // One run: the readings minus the ideal ones minus the biases are white with variance
    // q / h; the truth holds the run's biases; every measurement is there.
    let run = sim.run(7, 3);
    let c = sim.coefficients(7, 3);
    assert_eq!(&run.truth.states[0][NAV_DIM..], &c[..]);
    assert_eq!(run.measurements.len(), 2400);
    let (mut sw, mut sf) = (0.0, 0.0);
    for s in run.inputs.iter() {
        let ideal = ideal_reading(&traj.state(s.t));
        for a in 0..3 {
            sw += (s.f[a] - ideal.w[a] - c[a]).powi(2);
            sf += (s.f[3 + a] - ideal.f[a] - c[3 + a]).powi(2);
        }
    }
    let count = 3.0 * run.inputs.len() as f64;
    let (vw, vf) = (sw / count, sf / count);
    // 72 000 squares: the sample variance within 3 %.
    assert!((vw / (unit.gyro_psd * 10.0) - 1.0).abs() < 0.03, "{vw}");
    assert!((vf / (unit.accel_psd * 10.0) - 1.0).abs() < 0.03, "{vf}");
    // The odometer reads the signed path speed, the GPS the path, within their noise.
    let mut z2 = 0.0;
    for m in &run.measurements {
        let st = traj.state(m.t);
        let sig = noise.measurement_sigmas(st.speed.abs(), st.pos[0]);
        z2 += ((m.speed.unwrap() - st.speed) / sig[0]).powi(2);
        z2 += ((m.position_deg.unwrap()[0].to_radians() - st.pos[0]) / sig[2]).powi(2);
    }
    let dof = 2.0 * run.measurements.len() as f64;
    assert!((z2 / dof - 1.0).abs() < 0.1, "{}", z2 / dof);
    // Same seed, same bytes.
    assert_eq!(sim.run(7, 3).inputs, run.inputs);
}

#[test]
fn bad_settings_name_their_key() {
    let traj = Arc::new(Trajectory::build(&TrajectoryConfig::default()).unwrap());
    let noise = NoiseConfig::default();
    let model = Arc::new(StrapdownModel::base(&noise));
    let unit = UnitClass::Mems.errors();
    let new = |imu: f64, meas: f64, coefs: &BTreeMap<String, navkf_dynamics::Prior>| {
        StrapdownSimulator::new(model.clone(), traj.clone(), imu, meas, unit, coefs, noise)
            .unwrap_err()
            .to_string()
    };
    let none = BTreeMap::new();
    assert!(new(10.0, 3.0, &none).contains("truth.measurement_rate_hz"));
    assert!(new(f64::NAN, 1.0, &none).contains("truth.input_rate_hz"));
    let mut coefs = BTreeMap::new();
    coefs.insert("kod".to_string(), navkf_dynamics::Prior::zero_mean(1e-3));
    let e = new(10.0, 1.0, &coefs);
    assert!(
        e.contains("truth.coefficients.kod") && e.contains("bgx"),
        "{e}"
    );
}
