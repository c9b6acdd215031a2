//! Sensor faults outside the catalogue do what they say to the measurements, and nothing
//! else: measured against the clean run they were applied to, in metres and per cent.

use crate::common;

use common::datasets::short;
use navkf_dynamics::dataset::Dataset;
use navkf_dynamics::earth::{meridian_radius, prime_vertical_radius};
use navkf_dynamics::sensor_faults::SensorFault;
use navkf_dynamics::state::{LAT, V_X, V_Y};
use navkf_dynamics::{NoiseConfig, PlatformModel, Simulator, Trajectory, TruthConfig};
use std::sync::Arc;

/// A clean 600 s run of the paper's test, with its truth.
fn clean() -> Dataset {
    let noise = NoiseConfig::default();
    let model = Arc::new(PlatformModel::base(&noise));
    let traj = Arc::new(Trajectory::build(&short()).unwrap());
    let sim = Simulator::new(model, traj, TruthConfig::default(), noise).unwrap();
    sim.dataset("clean", 3, &sim.run(3, 0))
}

/// East and North metres from fix `a` to fix `b` at latitude `lat`.
fn metres(a: [f64; 2], b: [f64; 2], lat: f64) -> [f64; 2] {
    let s = lat.sin();
    [
        (b[1] - a[1]).to_radians() * prime_vertical_radius(s) * lat.cos(),
        (b[0] - a[0]).to_radians() * meridian_radius(s),
    ]
}

/// The true state at measurement `k` (the simulator stores one at 0 and one per measurement).
fn truth(ds: &Dataset, k: usize) -> &[f64] {
    &ds.truth.as_ref().unwrap().states[k + 1]
}

#[test]
fn a_lever_arm_moves_every_fix_by_the_arm_turned_with_the_heading() {
    let clean = clean();
    let mut ds = clean.clone();
    let fault = SensorFault::GpsLeverArm {
        forward_m: 1.5,
        right_m: -0.4,
    };
    fault.apply(&mut ds).unwrap();
    let mut heading = 0.0;
    let (mut at_stops, mut moving) = (0, 0);
    for (k, (a, b)) in clean.measurements.iter().zip(&ds.measurements).enumerate() {
        assert_eq!(a.velocity, b.velocity, "the odometer is untouched");
        let x = truth(&clean, k);
        let speed = x[V_X].hypot(x[V_Y]);
        if speed > 0.1 {
            heading = x[V_X].atan2(x[V_Y]);
            moving += 1;
        } else {
            at_stops += 1;
        }
        let d = metres(a.position_deg.unwrap(), b.position_deg.unwrap(), x[LAT]);
        let (s, c) = f64::sin_cos(heading);
        let expected = [1.5 * s - 0.4 * c, 1.5 * c + 0.4 * s];
        for i in 0..2 {
            assert!(
                (d[i] - expected[i]).abs() < 1e-6,
                "t = {}: {d:?} vs {expected:?}",
                a.t
            );
        }
        // The arm's length, whatever the heading: it does not vanish at a stop.
        assert!((d[0].hypot(d[1]) - 1.5f64.hypot(0.4)).abs() < 1e-6);
    }
    assert!(
        at_stops > 10 && moving > 100,
        "{at_stops} at stops, {moving} moving"
    );
}

#[test]
fn a_gps_step_moves_the_fixes_of_its_window_only() {
    let clean = clean();
    let mut ds = clean.clone();
    SensorFault::GpsStep {
        offset_m: [4.0, -2.5],
        start_s: 200.0,
        duration_s: 120.0,
    }
    .apply(&mut ds)
    .unwrap();
    let mut inside = 0;
    for (k, (a, b)) in clean.measurements.iter().zip(&ds.measurements).enumerate() {
        let d = metres(
            a.position_deg.unwrap(),
            b.position_deg.unwrap(),
            truth(&clean, k)[LAT],
        );
        if (200.0..320.0).contains(&a.t) {
            inside += 1;
            assert!(
                (d[0] - 4.0).abs() < 1e-6 && (d[1] + 2.5).abs() < 1e-6,
                "{d:?}"
            );
        } else {
            assert_eq!(a.position_deg, b.position_deg, "t = {}", a.t);
        }
        assert_eq!(a.velocity, b.velocity);
    }
    assert_eq!(inside, 120);
}

#[test]
fn slip_raises_the_odometer_while_accelerating_and_only_then() {
    let clean = clean();
    let mut ds = clean.clone();
    SensorFault::OdometerSlip { gain_s2_m: 0.05 }
        .apply(&mut ds)
        .unwrap();
    let (mut raised, mut kept) = (0, 0);
    let mut previous: Option<(f64, f64)> = None;
    for (k, (a, b)) in clean.measurements.iter().zip(&ds.measurements).enumerate() {
        let x = truth(&clean, k);
        let speed = x[V_X].hypot(x[V_Y]);
        let accel = previous.map_or(0.0, |(t, s)| (speed - s) / (a.t - t));
        previous = Some((a.t, speed));
        let (va, vb) = (a.velocity.unwrap(), b.velocity.unwrap());
        if accel > 1e-3 {
            raised += 1;
            let ratio = vb[0].hypot(vb[1]) / va[0].hypot(va[1]);
            assert!((ratio - (1.0 + 0.05 * accel)).abs() < 1e-12, "t = {}", a.t);
        } else if accel <= 0.0 {
            kept += 1;
            assert_eq!(va, vb, "t = {}: no slip when not accelerating", a.t);
        }
        assert_eq!(a.position_deg, b.position_deg);
    }
    assert!(raised > 10 && kept > 100, "{raised} raised, {kept} kept");
}

#[test]
fn a_fault_needs_the_truth_and_finite_sizes() {
    let mut ds = clean();
    let before = ds.clone();
    let bad = SensorFault::GpsLeverArm {
        forward_m: f64::NAN,
        right_m: 0.0,
    };
    assert!(bad.apply(&mut ds).unwrap_err().contains("finite"));
    ds.truth = None;
    let e = SensorFault::OdometerSlip { gain_s2_m: 0.02 }.apply(&mut ds);
    assert_eq!(e.unwrap_err(), "the dataset has no truth");
    ds.truth = before.truth.clone();
    assert_eq!(ds, before, "a refused fault changes nothing");
}
