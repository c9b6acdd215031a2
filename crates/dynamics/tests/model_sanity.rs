//! Shape of the model against docs/model.md: state names and order, dimensions, the measurement
//! (exactly `[v_x, v_y, L, lambda]` and linear for the base model, non-linear with
//! odometer-scale or gps-latency), and the process-noise channels.

use crate::common;

use common::*;
use navkf_dynamics::effects::GyroBiasWalk;
use navkf_dynamics::state::*;
use navkf_dynamics::{Effect, NoiseConfig, PlatformModel, Registry, SystemModel};

/// docs/model.md, "The state", transcribed from the table (not from `BASE_NAMES`).
const MODEL_MD_STATES: [&str; 20] = [
    "phi_x", "phi_y", "phi_z", "v_x", "v_y", "L", "lambda", "Kg0x", "Kg11x", "Kg12x", "Kg0y",
    "Kg11y", "Kg12y", "Kg0z", "Kg11z", "Kg12z", "Ka0x", "Ka1x", "Ka0y", "Ka1y",
];

fn base() -> PlatformModel {
    PlatformModel::base(&NoiseConfig::default())
}

fn with(names: &[&str]) -> PlatformModel {
    PlatformModel::new(
        Registry::catalogue().build_all(names).unwrap(),
        &NoiseConfig::default(),
    )
    .unwrap()
}

/// Catches: a reordered or renamed base state (datasets and reports go by these names), or
/// index constants that disagree with the table.
#[test]
fn base_state_names_follow_model_md_table() {
    let m = base();
    assert_eq!(m.state_names(), MODEL_MD_STATES);
    assert_eq!(m.dim(), 20);
    assert_eq!(m.dynamic_dim(), 7);
    assert_eq!(m.meas_dim(), 4);
    for (i, name) in [
        (PHI_X, "phi_x"),
        (PHI_Y, "phi_y"),
        (PHI_Z, "phi_z"),
        (V_X, "v_x"),
        (V_Y, "v_y"),
        (LAT, "L"),
        (LON, "lambda"),
        (KG0X, "Kg0x"),
        (KG11X, "Kg11x"),
        (KG12X, "Kg12x"),
        (KG0Y, "Kg0y"),
        (KG0Z, "Kg0z"),
        (KA0X, "Ka0x"),
        (KA1X, "Ka1x"),
        (KA0Y, "Ka0y"),
        (KA1Y, "Ka1y"),
    ] {
        assert_eq!(MODEL_MD_STATES[i], name, "index constant of {name}");
        assert_eq!(m.index_of(name), Some(i));
    }
    assert_eq!(MEASUREMENT_NAMES, ["v_x", "v_y", "L", "lambda"]);
}

/// Each effect adds its coefficients after the 20 base states, in assembly order.
/// Catches: wrong dimension or offsets, coefficients appended in the wrong order.
#[test]
fn effects_append_their_coefficients_in_order() {
    let reg = Registry::catalogue();
    let all = with(&reg.names().iter().map(|s| s.as_str()).collect::<Vec<_>>());
    assert_eq!(all.dim(), 20 + 3 + 2 + 2 + 3 + 1 + 1 + 1);
    let mut expected: Vec<String> = MODEL_MD_STATES.iter().map(|s| s.to_string()).collect();
    for (i, e) in all.effects().iter().enumerate() {
        assert_eq!(
            all.effect_offset(i),
            expected.len(),
            "offset of {}",
            e.name()
        );
        expected.extend(e.coefficient_names().iter().map(|s| s.to_string()));
    }
    assert_eq!(all.state_names(), expected);
    assert_eq!(all.units().len(), all.dim());
    let m = with(&["gps-latency", "gyro-fz"]);
    assert_eq!(m.index_of("tau"), Some(20));
    assert_eq!(m.index_of("Kg13x"), Some(21));
    assert_eq!(m.dim(), 24);
}

/// The base measurement is exactly `[v_x, v_y, L, lambda]` (no arithmetic on the states),
/// its Jacobian exactly `[0 I_4 0]`, and it is declared and is linear.
/// Catches: a measurement that touches other states or rescales, an inexact H, a base model
/// that claims a non-linear measurement (the simplified UKF would take the slow path).
#[test]
fn base_measurement_is_exactly_velocity_and_position_and_linear() {
    let m = base();
    assert!(m.measurement_is_linear());
    let mut rng = rng(60);
    let n = m.dim();
    let mut z = vec![0.0; 4];
    let mut h = vec![f64::NAN; 4 * n];
    let xs: Vec<Vec<f64>> = (0..6).map(|_| random_state(&m, &mut rng)).collect();
    for x in &xs {
        m.measure(x, &mut z);
        assert_eq!(z, base_measurement(x));
        m.measurement_jacobian(x, &mut h);
        assert_eq!(h, base_measurement_jacobian(n));
    }
    // Linearity: h(a x + b y) = a h(x) + b h(y).
    let (a, b) = (0.3, -1.7);
    let mix: Vec<f64> = xs[0]
        .iter()
        .zip(&xs[1])
        .map(|(p, q)| a * p + b * q)
        .collect();
    let (mut z0, mut z1, mut zm) = (vec![0.0; 4], vec![0.0; 4], vec![0.0; 4]);
    m.measure(&xs[0], &mut z0);
    m.measure(&xs[1], &mut z1);
    m.measure(&mix, &mut zm);
    for i in 0..4 {
        let want = a * z0[i] + b * z1[i];
        assert!(
            (zm[i] - want).abs() <= 1e-15 * (1.0 + want.abs()),
            "channel {i}"
        );
    }
}

/// odometer-scale and gps-latency make the measurement non-linear (and say so); the other
/// effects leave it exactly the base one. Catches: a measurement effect that declares a
/// linear measurement (a filter would use a constant H that is wrong), or a rate effect that
/// leaks into the measurement.
#[test]
fn odometer_scale_and_gps_latency_make_the_measurement_non_linear() {
    for names in [
        &["odometer-scale"][..],
        &["gps-latency"],
        &["odometer-scale", "gps-latency"],
        &["gyro-fz", "gps-latency", "torquer-scale"],
    ] {
        let m = with(names);
        assert!(!m.measurement_is_linear(), "{names:?}");
        // And it really is: h(2x) != 2 h(x) in the affected channels.
        let mut rng = rng(61);
        let x = random_state(&m, &mut rng);
        let x2: Vec<f64> = x.iter().map(|v| 2.0 * v).collect();
        let (mut z, mut z2) = (vec![0.0; 4], vec![0.0; 4]);
        m.measure(&x, &mut z);
        m.measure(&x2, &mut z2);
        assert!(
            (0..4).any(|i| (z2[i] - 2.0 * z[i]).abs() > 1e-12 * z[i].abs()),
            "{names:?}: measurement looks linear"
        );
    }
    for name in [
        "gyro-fz",
        "accel-quadratic",
        "accel-cross-axis",
        "torquer-scale",
        "gyro-bias-walk",
    ] {
        let m = with(&[name]);
        assert!(m.measurement_is_linear(), "{name}");
        let mut rng = rng(62);
        let x = random_state(&m, &mut rng);
        let mut z = vec![0.0; 4];
        m.measure(&x, &mut z);
        assert_eq!(z, base_measurement(&x), "{name} must not touch z");
        let mut h = vec![f64::NAN; 4 * m.dim()];
        m.measurement_jacobian(&x, &mut h);
        assert_eq!(
            h,
            base_measurement_jacobian(m.dim()),
            "{name} must not touch H"
        );
    }
}

/// docs/model.md eqs. (12), (44): `W = [w_gx, w_gy, w_gz, w_ax, w_ay]` on the first five
/// states with densities
/// `q_g`, `q_a`; gyro-bias-walk adds three channels on `Kg0x, Kg0y, Kg0z` with `q_b`.
/// Catches: channels on the wrong states, swapped densities, a missing walk channel.
#[test]
fn noise_channels_are_five_and_eight_with_gyro_bias_walk() {
    let cfg = NoiseConfig {
        gyro_psd: 2e-14,
        accel_psd: 3e-8,
        ..NoiseConfig::default()
    };
    let m = PlatformModel::base(&cfg);
    let ch = m.noise_channels();
    assert_eq!(ch.len(), 5);
    let want = [
        ("w_gx", PHI_X, cfg.gyro_psd),
        ("w_gy", PHI_Y, cfg.gyro_psd),
        ("w_gz", PHI_Z, cfg.gyro_psd),
        ("w_ax", V_X, cfg.accel_psd),
        ("w_ay", V_Y, cfg.accel_psd),
    ];
    for (c, (name, state, psd)) in ch.iter().zip(want) {
        assert_eq!((c.name.as_str(), c.state, c.psd), (name, state, psd));
    }

    let m = PlatformModel::new(vec![Box::new(GyroBiasWalk::default())], &cfg).unwrap();
    let ch = m.noise_channels();
    assert_eq!(ch.len(), 8);
    assert_eq!(m.dim(), 20, "gyro-bias-walk adds no coefficient");
    for (c, state) in ch[5..].iter().zip([KG0X, KG0Y, KG0Z]) {
        assert_eq!(c.state, state, "{}", c.name);
        assert_eq!(c.psd, GyroBiasWalk::DEFAULT_PSD);
    }
    // No other effect adds noise.
    for name in Registry::catalogue().names() {
        if name != "gyro-bias-walk" {
            assert_eq!(with(&[&name]).noise_channels().len(), 5, "{name}");
        }
    }
}

/// gyro-bias-walk's density is its parameter; other effects have none.
#[test]
fn gyro_bias_walk_parameter_sets_the_walk_density() {
    let mut e = GyroBiasWalk::default();
    e.set_parameter(4e-18).unwrap();
    assert!(e.process_noise().iter().all(|c| c.psd == 4e-18));
    assert!(e.set_parameter(-1.0).is_err());
    assert!(e.set_parameter(f64::NAN).is_err());
    let mut fz = Registry::catalogue().build("gyro-fz").unwrap();
    assert!(fz.set_parameter(1.0).is_err());
}
