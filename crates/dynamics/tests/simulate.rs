//! The truth simulator: seeded streams give identical bytes, given values are taken, and the
//! measurements carry the noise of docs/model.md eq. (14).

use navkf_dynamics::simulate::{Prior, TruthConfig};
use navkf_dynamics::state::*;
use navkf_dynamics::{
    NoiseConfig, PlatformModel, Registry, Simulator, Trajectory, TrajectoryConfig,
};
use std::sync::Arc;

fn short_path() -> Arc<Trajectory> {
    Arc::new(
        Trajectory::build(&TrajectoryConfig {
            duration_s: 600.0,
            initial_standstill_s: 30.0,
            leg_north_m: 1500.0,
            leg_east_m: 1000.0,
            ..Default::default()
        })
        .unwrap(),
    )
}

fn sim(effects: &[&str], cfg: TruthConfig) -> Simulator {
    let noise = NoiseConfig::default();
    let fx = Registry::catalogue().build_all(effects).unwrap();
    let model = Arc::new(PlatformModel::new(fx, &noise).unwrap());
    Simulator::new(model, short_path(), cfg, noise).unwrap()
}

#[test]
fn same_seed_same_bytes_other_seed_other_bytes() {
    let s = sim(&["gyro-bias-walk"], TruthConfig::default());
    let a = s.run(11, 3);
    let b = s.run(11, 3);
    let c = s.run(11, 4);
    let bits = |r: &navkf_dynamics::SimulatedRun| -> Vec<u64> {
        r.measurements
            .iter()
            .flat_map(|m| {
                let v = m.velocity.unwrap();
                let p = m.position_deg.unwrap();
                [m.t, v[0], v[1], p[0], p[1]]
            })
            .chain(r.truth.states.iter().flatten().copied())
            .map(f64::to_bits)
            .collect()
    };
    assert_eq!(bits(&a), bits(&b));
    assert_ne!(bits(&a), bits(&c));
    // Run 3 made on another thread is the same too.
    let s2 = Arc::new(s);
    let s3 = s2.clone();
    let d = std::thread::spawn(move || s3.run(11, 3)).join().unwrap();
    assert_eq!(bits(&a), bits(&d));
}

#[test]
fn given_values_are_taken_and_others_drawn() {
    let mut cfg = TruthConfig::default();
    cfg.coefficients.insert("Ka0x".into(), Prior::fixed(1e-3));
    cfg.coefficients.insert("kod".into(), Prior::fixed(2e-3));
    let s = sim(&["odometer-scale"], cfg);
    let x0 = s.initial_state(5, 0);
    assert_eq!(x0[KA0X], 1e-3);
    assert_eq!(x0[20], 2e-3);
    assert_ne!(x0[KA0Y], 0.0);
    // Fixing one coefficient leaves the other draws unchanged.
    let free = sim(&["odometer-scale"], TruthConfig::default()).initial_state(5, 0);
    assert_eq!(free[KA0Y], x0[KA0Y]);
    assert_eq!(free[KG0Z], x0[KG0Z]);
}

#[test]
fn unknown_coefficient_is_refused_with_its_key() {
    let mut cfg = TruthConfig::default();
    cfg.coefficients.insert("Kg99".into(), Prior::fixed(1.0));
    let noise = NoiseConfig::default();
    let model = Arc::new(PlatformModel::base(&noise));
    let err = Simulator::new(model, short_path(), cfg, noise)
        .unwrap_err()
        .to_string();
    assert!(err.contains("truth.coefficients.Kg99"), "{err}");
}

#[test]
fn measurement_noise_has_the_spec_size() {
    // With every coefficient, tilt and process noise at zero the truth is the path, so the
    // measurement residuals are the measurement noise alone: check its sigma (catches a
    // wrong RM/RN or degree conversion).
    let mut cfg = TruthConfig::default();
    cfg.initial_tilt.level_rad = 0.0;
    cfg.initial_tilt.azimuth_rad = 0.0;
    let names = navkf_dynamics::state::BASE_NAMES;
    for n in &names[NAV_DIM..] {
        cfg.coefficients.insert(n.to_string(), Prior::fixed(0.0));
    }
    let noise = NoiseConfig {
        gyro_psd: 1e-30,
        accel_psd: 1e-30,
        ..Default::default()
    };
    let model = Arc::new(PlatformModel::base(&noise));
    let traj = short_path();
    let s = Simulator::new(model, traj.clone(), cfg, noise).unwrap();
    let r = s.run(1, 0);
    let (mut sn, mut se, mut sv, mut count_v) = (0.0, 0.0, 0.0, 0.0);
    for m in &r.measurements {
        let st = traj.state(m.t);
        let p = m.position_deg.unwrap();
        let s_l = st.pos[0].sin();
        let dn = (p[0].to_radians() - st.pos[0]) * navkf_dynamics::earth::meridian_radius(s_l);
        let de = (p[1].to_radians() - st.pos[1])
            * navkf_dynamics::earth::prime_vertical_radius(s_l)
            * st.pos[0].cos();
        sn += dn * dn;
        se += de * de;
        let v = m.velocity.unwrap();
        let sig = noise.odometer_sigma(st.v[0].hypot(st.v[1]));
        sv += ((v[0] - st.v[0]) / sig).powi(2) + ((v[1] - st.v[1]) / sig).powi(2);
        count_v += 2.0;
    }
    let n = r.measurements.len() as f64;
    let (rn, re) = ((sn / n).sqrt(), (se / n).sqrt());
    // 600 samples: the RMS of N(0, 3^2) lies within 3 +- 0.3 with overwhelming probability.
    assert!(
        (rn - 3.0).abs() < 0.3 && (re - 3.0).abs() < 0.3,
        "GPS rms {rn} {re}"
    );
    let rv = (sv / count_v).sqrt();
    assert!((rv - 1.0).abs() < 0.1, "normalised odometer rms {rv}");
}

#[test]
fn a_gyrocompassed_platform_starts_with_the_tilt_that_nulls_its_own_biases() {
    use navkf_dynamics::earth::WIE;
    use navkf_dynamics::simulate::{Alignment, InitialTilt};
    use navkf_dynamics::SystemModel;
    // Exact alignment (no residual), with effects that add rates at rest (gyro-fz: eps +=
    // Kg13 fz) drawn 30 times their typical size so that they matter.
    let mut cfg = TruthConfig {
        initial_tilt: InitialTilt {
            level_rad: 0.0,
            azimuth_rad: 0.0,
            alignment: Alignment::Gyrocompass,
        },
        ..Default::default()
    };
    for c in ["Kg13x", "Kg13y", "Kg13z"] {
        cfg.coefficients.insert(c.into(), Prior::zero_mean(3e-7));
    }
    let s = sim(&["gyro-fz", "accel-cross-axis"], cfg);
    let f = s.trajectory().specific_force(0.0);
    let mut independent_azimuths = Vec::new();
    for run in 0..5 {
        let x = s.initial_state(7, run);
        let mut r = vec![0.0; NAV_DIM];
        s.model()
            .rates(&x, &navkf_dynamics::kinematics::platform_input(f), &mut r);
        // Levelled and gyrocompassed: no horizontal acceleration, no drift about East.
        assert!(r[V_X].abs() < 1e-12 && r[V_Y].abs() < 1e-12, "{r:?}");
        assert!(r[PHI_X].abs() < 1e-18, "{r:?}");
        // The azimuth is the East drift over the Earth's horizontal rate (docs/model.md eq. (8)
        // at rest).
        let lat = x[LAT];
        let eps_x = x[KG0X] + x[KG11X] * f[0] + x[KG12X] * f[1] + x[20] * f[2];
        let expected = (eps_x + WIE * lat.sin() * x[PHI_Y]) / (WIE * lat.cos());
        assert!((x[PHI_Z] - expected).abs() < 1e-12 * expected.abs().max(1e-6));
        assert!((x[PHI_Y] - (x[KA0X] + x[KA1X] * f[0] + x[21] * f[1]) / f[2]).abs() < 1e-12);
        independent_azimuths.push(x[PHI_Z]);
    }
    // The draws differ from run to run (they follow the coefficients).
    assert!(independent_azimuths.windows(2).all(|w| w[0] != w[1]));
}

#[test]
fn the_independent_tilt_draw_is_unchanged_by_the_alignment_option() {
    // The default draws exactly as before the option existed: sigma times the first three
    // normals of the run's initial-state stream.
    let s = sim(&[], TruthConfig::default());
    let x = s.initial_state(3, 1);
    let t = TruthConfig::default().initial_tilt;
    use rand::Rng;
    let mut rng = navkf_dynamics::rng::stream(3, 1, navkf_dynamics::rng::Purpose::InitialState);
    let z: Vec<f64> = (0..3)
        .map(|_| rng.sample::<f64, _>(rand_distr::StandardNormal))
        .collect();
    assert_eq!(x[PHI_X], t.level_rad * z[0]);
    assert_eq!(x[PHI_Y], t.level_rad * z[1]);
    assert_eq!(x[PHI_Z], t.azimuth_rad * z[2]);
}
