//! `gyro-bias-instability`: the gyro biases wander about their turn-on values `bgx, bgy, bgz`:
//! each reading carries `b + d`, the departure `d` a first-order Gauss-Markov process,
//! `d' = -d / T_g + w`, of steady one-sigma `sigma_bg` (docs/model.md eq. (69)). It adds no
//! coefficient; it adds the three departures `dbgx, dbgy, dbgz` as noise-driven states, and
//! its two parameters are set by name in an effect list (`T_g=1800, sigma_bg=5e-5`).
//!
//! Defaults: `T_g` one hour, as KF-GINS models its MEMS units' biases; `sigma_bg` the
//! in-run bias stability of each class (0.003 deg/h navigation, 0.3 deg/h tactical, 10 deg/h
//! MEMS; Groves, 2013, section 4.4.1, cited from memory; gnss-ins-sim's built-in models give
//! 0.1, 3.5 and 10 deg/h for its high, mid and low accuracy units, with a 100 s correlation
//! time: only the MEMS value agrees).

use super::{Instability, StrapdownEffect, Triad, DEG_PER_H};

/// See the module documentation.
pub const GYRO_BIAS_INSTABILITY: StrapdownEffect = StrapdownEffect {
    name: "gyro-bias-instability",
    description: "b_g + d_g, d_g' = -d_g / T_g + w, steady sigma sigma_bg (gyro bias instability)",
    coefficients: &[],
    instability: Some(Instability {
        triad: Triad::Gyro,
        time_s: 3600.0,
        sigma: [0.003 * DEG_PER_H, 0.3 * DEG_PER_H, 10.0 * DEG_PER_H],
        parameter_names: ["T_g", "sigma_bg"],
    }),
    declaration: None,
};
