//! `accel-bias-instability`: the accelerometer biases wander about their turn-on values
//! `bax, bay, baz`, the departures `dbax, dbay, dbaz` first-order Gauss-Markov processes,
//! `d' = -d / T_a + w`, of steady one-sigma `sigma_ba` (docs/model.md eq. (69)), as
//! `gyro-bias-instability` does for the gyros.
//!
//! Defaults: `T_a` one hour; `sigma_ba` 10 ug navigation, 50 ug tactical, 250 ug MEMS
//! (Groves, 2013, section 4.4.1, cited from memory). gnss-ins-sim's built-in models give far
//! smaller ones, 0.37, 5 and 20 ug for its high, mid and low accuracy units (correlation time
//! 100 s): read a detection
//! limit stated in multiples of these sizes with that in mind, and state a data sheet's
//! figure (`sigma_ba=...`) when there is one.

use super::{Instability, StrapdownEffect, Triad, G0};

const UG: f64 = 1e-6 * G0;

/// See the module documentation.
pub const ACCEL_BIAS_INSTABILITY: StrapdownEffect = StrapdownEffect {
    name: "accel-bias-instability",
    description:
        "b_a + d_a, d_a' = -d_a / T_a + w, steady sigma sigma_ba (accelerometer bias instability)",
    coefficients: &[],
    instability: Some(Instability {
        triad: Triad::Accel,
        time_s: 3600.0,
        sigma: [10.0 * UG, 50.0 * UG, 250.0 * UG],
        parameter_names: ["T_a", "sigma_ba"],
    }),
    declaration: None,
};
