//! Shared set-up of the platform-model tests: the short vehicle-test path, a simulator on the
//! base model, and the filters' initial estimate matching the truth's draws.
#![allow(dead_code)]

use navkf_dynamics::prior::base_coefficient_sigma;
use navkf_dynamics::state::*;
use navkf_dynamics::*;
use std::sync::Arc;

/// The short O-A-B-C-O path (600 s) the tests use to keep their run time small.
pub fn short_config(duration_s: f64) -> TrajectoryConfig {
    TrajectoryConfig {
        duration_s,
        initial_standstill_s: 30.0,
        leg_north_m: 1500.0,
        leg_east_m: 1000.0,
        ..Default::default()
    }
}

/// A simulator of the base model on the short path of `duration_s` seconds.
pub fn base_simulator(duration_s: f64) -> Simulator {
    let noise = NoiseConfig::default();
    let model = Arc::new(PlatformModel::base(&noise));
    let traj = Arc::new(Trajectory::build(&short_config(duration_s)).unwrap());
    Simulator::new(model, traj, TruthConfig::default(), noise).unwrap()
}

/// A simulator on the short path with catalogued `effects`, whose named coefficients in
/// `fixed` take the given true values (the others are drawn from their priors).
pub fn simulator_with(effects: &[&str], fixed: &[(&str, f64)], duration_s: f64) -> Simulator {
    let noise = NoiseConfig::default();
    let fx = Registry::catalogue().build_all(effects).unwrap();
    let model = Arc::new(PlatformModel::new(fx, &noise).unwrap());
    let traj = Arc::new(Trajectory::build(&short_config(duration_s)).unwrap());
    let cfg = TruthConfig {
        coefficients: fixed
            .iter()
            .map(|&(name, v)| (name.to_string(), simulate::Prior::fixed(v)))
            .collect(),
        ..Default::default()
    };
    Simulator::new(model, traj, cfg, noise).unwrap()
}

/// One-sigma of the initial estimate, state by state, matching what the simulator draws:
/// tilt from `TruthConfig::initial_tilt`, coefficients from `base_coefficient_sigma`,
/// velocity 0 exactly at the standstill start (1e-3 m/s), position exactly the path's start
/// (1 m).
pub fn initial_sigma(sim: &Simulator, lat: f64) -> Vec<f64> {
    let tilt = sim.config().initial_tilt;
    let (s, c) = lat.sin_cos();
    let (rm, rn) = (earth::meridian_radius(s), earth::prime_vertical_radius(s));
    (0..sim.model().dim())
        .map(|i| match i {
            PHI_X | PHI_Y => tilt.level_rad,
            PHI_Z => tilt.azimuth_rad,
            V_X | V_Y => 1e-3,
            LAT => 1.0 / rm,
            LON => 1.0 / (rn * c),
            _ => base_coefficient_sigma(i),
        })
        .collect()
}

/// The filters' initial estimate for `run`: the path's start with zero tilt, zero
/// velocity and zero coefficients, and the diagonal covariance of [`initial_sigma`].
pub fn initial_estimate(sim: &Simulator, run: &SimulatedRun) -> (Vec<f64>, Vec<f64>) {
    let n = sim.model().dim();
    let truth0 = &run.truth.states[0];
    let mut x0 = vec![0.0; n];
    x0[LAT] = truth0[LAT];
    x0[LON] = truth0[LON];
    let sig = initial_sigma(sim, truth0[LAT]);
    let mut p0 = vec![0.0; n * n];
    for i in 0..n {
        p0[i + i * n] = sig[i] * sig[i];
    }
    (x0, p0)
}

/// A level platform at rest at 45.78 N, 126.63 E with a diagonal covariance: 10 arcsec level
/// and 1 arcmin azimuth tilt, 1 cm/s velocity, 3 m position, and `coefficient_sigma(i)` for
/// every state from index `NAV_DIM` on.
pub fn at_rest(n: usize, coefficient_sigma: impl Fn(usize) -> f64) -> (Vec<f64>, Vec<f64>) {
    let mut x = vec![0.0; n];
    x[LAT] = 45.78f64.to_radians();
    x[LON] = 126.63f64.to_radians();
    let mut p = vec![0.0; n * n];
    for i in 0..n {
        let s = match i {
            PHI_X | PHI_Y => 4.85e-5,
            PHI_Z => 2.91e-4,
            V_X | V_Y => 1e-2,
            LAT | LON => 5e-7,
            _ => coefficient_sigma(i),
        };
        p[i + i * n] = s * s;
    }
    (x, p)
}
