//! The strapdown truth simulator (`strapdown::simulate`): its error-free readings drive the
//! model along the path it was made from, its errors are the drawn biases plus a white
//! noise of the stated density, and its measurements carry the stated noise.

use navkf_dynamics::strapdown::body_motion::{BodyMotion, BodyOffsets};
use navkf_dynamics::strapdown::model::StrapdownModel;
use navkf_dynamics::strapdown::rates::nav_rates;
use navkf_dynamics::strapdown::simulate::{
    body_reading, body_state, ideal_reading, StrapdownSimulator,
};
use navkf_dynamics::strapdown::state::*;
use navkf_dynamics::strapdown::unit_class::UnitClass;
use navkf_dynamics::{NoiseConfig, Trajectory, TrajectoryConfig};
use std::collections::BTreeMap;
use std::sync::Arc;

/// RK4 of the error-free navigation equations driven by the ideal readings of the body
/// (a rigid vehicle without `motion`), interpolated linearly between samples `h` apart, as
/// the filters integrate them; the worst horizontal distance from the path, m, and the worst
/// attitude error, rad.
fn follow(traj: &Trajectory, motion: Option<&BodyMotion>, h: f64, until: f64) -> (f64, f64) {
    let offsets = |t: f64| {
        let st = traj.state(t);
        let off = motion.map_or(BodyOffsets::default(), |m| m.offsets(t, &st));
        (st, off)
    };
    let truth_at = |t: f64| {
        let (st, off) = offsets(t);
        body_state(&st, &off)
    };
    let reading_at = |t: f64| {
        let (st, off) = offsets(t);
        body_reading(&st, &off)
    };
    let mut x = truth_at(0.0).to_vec();
    x.resize(BASE_DIM, 0.0);
    let rates = |x: &[f64], r: &navkf_dynamics::strapdown::rates::ImuReading| {
        let mut dx = vec![0.0; NAV_DIM];
        nav_rates(x, r, &mut dx);
        dx
    };
    let steps = (until / h).round() as usize;
    let (mut worst, mut worst_angle): (f64, f64) = (0.0, 0.0);
    for k in 0..steps {
        let (t0, t1) = (k as f64 * h, (k + 1) as f64 * h);
        let (r0, r1) = (reading_at(t0), reading_at(t1));
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
        let truth = truth_at(t1);
        let rm = navkf_dynamics::earth::meridian_radius(truth[LAT].sin());
        let north_m = (x[LAT] - truth[LAT]) * rm;
        let east_m = (x[LON] - truth[LON]) * rm * truth[LAT].cos();
        worst = worst.max(north_m.hypot(east_m));
        let dpsi = (x[HEADING] - truth[HEADING]).sin().abs();
        worst_angle = worst_angle
            .max(dpsi)
            .max((x[ROLL] - truth[ROLL]).abs())
            .max((x[PITCH] - truth[PITCH]).abs());
    }
    (worst, worst_angle)
}

#[test]
fn the_ideal_readings_drive_the_model_along_the_path() {
    let traj = Trajectory::build(&TrajectoryConfig::default()).unwrap();
    // The whole 2400-s test at 10 Hz (the studies' rate; 8 cm at worst when written) and its
    // first 900 s at 100 Hz: the model stays on the path to centimetres, far inside the
    // GPS's metres, so a filter's error is its own.
    let (at_10, angle_10) = follow(&traj, None, 0.1, traj.duration());
    assert!(at_10 < 0.1, "{at_10} m off the path at 10 Hz");
    assert!(angle_10 < 1e-5, "attitude off by {angle_10} rad at 10 Hz");
    let (at_100, angle_100) = follow(&traj, None, 0.01, 900.0);
    assert!(at_100 < 0.01, "{at_100} m off the path at 100 Hz");
    assert!(
        angle_100 < 1e-6,
        "attitude off by {angle_100} rad at 100 Hz"
    );
}

#[test]
fn a_sliding_bouncing_body_is_followed_by_its_readings() {
    // The body's sideslip and bounce (0.1 m/s rms, the default) turn it by tenths of a
    // degree at a degree or two a second. (3.2 m and 1.4e-5 rad at 100 Hz over 900 s, when
    // written: an acceleration error of 1e-5 m/s^2, far below any unit's bias.) Its readings integrate to its attitude, not the rigid
    // vehicle's, to within the integration's own error, which falls as the step squared: a
    // rate that were not the attitude's derivative would leave an error no step removes.
    let traj = Trajectory::build(&TrajectoryConfig::default()).unwrap();
    let mut rng = navkf_dynamics::rng::stream(3, 0, navkf_dynamics::rng::Purpose::Other(7));
    let motion = BodyMotion::draw(0.1, traj.duration(), &mut rng);
    let (at_100, angle_100) = follow(&traj, Some(&motion), 0.01, 900.0);
    assert!(at_100 < 5.0, "{at_100} m off the path at 100 Hz");
    assert!(
        angle_100 < 3e-5,
        "attitude off by {angle_100} rad at 100 Hz"
    );
    let (_, angle_200) = follow(&traj, Some(&motion), 0.005, 900.0);
    assert!(
        angle_200 < angle_100 / 3.0,
        "attitude off by {angle_200} rad at 200 Hz, {angle_100} rad at 100 Hz"
    );
    let (at_1000, angle_1000) = follow(&traj, Some(&motion), 0.001, 200.0);
    assert!(at_1000 < 5e-4, "{at_1000} m off the path at 1 kHz");
    assert!(
        angle_1000 < 3e-7,
        "attitude off by {angle_1000} rad at 1 kHz"
    );
}

/// A simulator of the base model at 10 Hz, odometer and GPS at 1 Hz, no effects.
fn simulator(
    traj: &Arc<Trajectory>,
    unit: navkf_dynamics::strapdown::unit_class::UnitErrors,
    noise: NoiseConfig,
) -> StrapdownSimulator {
    let model = Arc::new(StrapdownModel::base(&noise));
    StrapdownSimulator::new(
        model,
        traj.clone(),
        10.0,
        1.0,
        unit,
        &BTreeMap::new(),
        noise,
    )
    .unwrap()
}

#[test]
fn a_run_reads_biases_and_noise_of_the_stated_size() {
    let traj = Arc::new(Trajectory::build(&TrajectoryConfig::default()).unwrap());
    let unit = UnitClass::Tactical.errors();
    let noise = unit.noise(NoiseConfig::default());
    let sim = simulator(&traj, unit, noise);
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
fn a_moving_body_carries_the_constraint_s_sigma_and_stands_still() {
    let traj = Arc::new(Trajectory::build(&TrajectoryConfig::default()).unwrap());
    let unit = UnitClass::Mems.errors();
    let noise = unit.noise(NoiseConfig {
        nhc_m_s: Some(0.1),
        ..NoiseConfig::default()
    });
    let new = || simulator(&traj, unit, noise);
    let rigid = new().run(2, 0);
    let sim = new().with_body_motion(0.1).unwrap();
    for refused in [f64::NAN, 0.0, -0.1, 1.5, f64::INFINITY] {
        let e = new().with_body_motion(refused).unwrap_err().to_string();
        assert!(e.contains("truth.body_motion_m_s"), "{e}");
    }
    let run = sim.run(2, 0);
    // The same biases and noise as the rigid vehicle's run: the motion has its own stream.
    assert_eq!(
        run.truth.states[0][NAV_DIM..],
        rigid.truth.states[0][NAV_DIM..]
    );
    // The body velocity the truth holds: the path's velocity in the turned body's axes.
    let (mut cruise, mut standing_angle, mut largest_pitch) = (Vec::new(), 0.0f64, 0.0f64);
    for (t, x) in run.truth.t.iter().zip(&run.truth.states) {
        let c = navkf_dynamics::strapdown::attitude::body_to_nav([x[ROLL], x[PITCH], x[HEADING]]);
        let vb = navkf_dynamics::strapdown::attitude::rotate_back(&c, [x[V_E], x[V_N], 0.0]);
        let speed = traj.state(*t).speed;
        if speed == 0.0 {
            // A standing car neither slides nor pitches.
            assert!(vb[1] == 0.0 && vb[2] == 0.0, "t = {t}: {vb:?}");
            let slip = (x[HEADING] - traj.state(*t).heading).abs();
            standing_angle = standing_angle.max(x[PITCH].abs()).max(slip);
        } else if speed > 14.0 {
            cruise.push([vb[1], vb[2]]);
        }
        largest_pitch = largest_pitch.max(x[PITCH].abs());
    }
    assert_eq!(standing_angle, 0.0);
    // An angle's rms is at most sigma / (2 v_c), 0.01 rad; its largest a few times that.
    assert!(
        largest_pitch < 0.05 && largest_pitch > 1e-3,
        "{largest_pitch}"
    );
    let n = cruise.len() as f64;
    assert!(n > 1000.0, "{n}");
    for axis in 0..2 {
        let rms = (cruise.iter().map(|v| v[axis] * v[axis]).sum::<f64>() / n).sqrt();
        // 0.9 of sigma at 15 m/s (v^2 / (v^2 + v_c^2)), within the sampling error of
        // ~1800 independent samples (2 %).
        assert!((rms / 0.09 - 1.0).abs() < 0.1, "axis {axis}: rms {rms}");
        // Samples a second apart are independent: their lag-one correlation is within a
        // few of its sampling sigma, 1/sqrt(n).
        let lag: f64 = cruise
            .windows(2)
            .map(|w| w[0][axis] * w[1][axis])
            .sum::<f64>()
            / (n - 1.0)
            / rms.powi(2);
        assert!(
            lag.abs() < 4.0 / n.sqrt(),
            "axis {axis}: lag-one correlation {lag}"
        );
    }
    // The truth carries the motion: no drawn constraint or zero-velocity reading.
    assert!(run
        .measurements
        .iter()
        .all(|m| m.nhc.is_none() && m.zupt.is_none()));
    assert!(rigid.measurements.iter().any(|m| m.nhc.is_some()));
    // The odometer reads the body's forward speed; the readings differ from the rigid
    // vehicle's; the same seed gives the same bytes.
    assert_ne!(run.inputs, rigid.inputs);
    assert_eq!(sim.run(2, 0).inputs, run.inputs);
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
