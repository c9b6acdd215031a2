//! What the dataset tests share: fresh temporary folders (removed when the test ends), a
//! sample dataset with awkward values, and the reading of a folder expected to fail.
//!
//! Each test file uses only some of them.
#![allow(dead_code)]

use navkf_dynamics::dataset::{Dataset, InputSample, Measurement, Provenance, Truth};
use navkf_dynamics::{NoiseConfig, PlatformPrior};
use std::sync::atomic::{AtomicUsize, Ordering};

use crate::common::scratch;

pub use scratch::Scratch;

static COUNTER: AtomicUsize = AtomicUsize::new(0);

/// A fresh, empty folder under the system temp dir, unique to this process and call, removed
/// when the test ends.
pub fn temp_folder(tag: &str) -> Scratch {
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    Scratch::new(&format!("dataset-test-{n}-{tag}"))
}

/// A folder holding exactly `files`.
pub fn folder(tag: &str, files: &[(&str, &str)]) -> Scratch {
    let dir = temp_folder(tag);
    for (name, text) in files {
        std::fs::write(dir.join(name), text).unwrap();
    }
    dir
}

/// `inputs.csv` with `n` rows at 10 Hz from t = 0.
pub fn inputs_text(n: usize) -> String {
    let mut s = String::from("t,f_e,f_n,f_u\n");
    for i in 0..n {
        s += &format!("{},0.001,-0.002,9.8\n", i as f64 / 10.0);
    }
    s
}

pub const MEAS_OK: &str =
    "t,v_e,v_n,lat_deg,lon_deg\n1,0.5,0.1,45.78,126.63\n2,0.5,0.1,45.78001,126.63001\n";

/// Reads a folder made of the given files (inputs.csv and measurements.csv default to good
/// ones when not given) and returns the error's text; fails the test if reading succeeds.
pub fn read_error(tag: &str, files: &[(&str, &str)]) -> String {
    let inputs = inputs_text(50);
    let mut all: Vec<(&str, &str)> = files.to_vec();
    if !files.iter().any(|(n, _)| *n == "inputs.csv") {
        all.push(("inputs.csv", &inputs));
    }
    if !files.iter().any(|(n, _)| *n == "measurements.csv") {
        all.push(("measurements.csv", MEAS_OK));
    }
    let result = Dataset::read(&folder(tag, &all));
    match result {
        Ok(d) => panic!("{tag}: expected an error, read {} inputs", d.inputs.len()),
        Err(e) => e.to_string(),
    }
}

/// Asserts that `message` contains every one of `parts`.
pub fn assert_mentions(message: &str, parts: &[&str]) {
    for p in parts {
        assert!(
            message.contains(p),
            "error message does not mention {p:?}:\n{message}"
        );
    }
}

/// A small dataset: 50 inputs at 10 Hz, measurements at 1 Hz with an odometer-only and a
/// GPS-only row, truth, provenance, non-default noise, and awkward floats.
pub fn sample(name: &str) -> Dataset {
    let awkward = [
        0.1 + 0.2,
        1.0 / 3.0,
        -0.0,
        1e-300,
        -2.5e-7,
        f64::MIN_POSITIVE,
        123_456_789.123_456_78,
        f64::MAX,
    ];
    let inputs = (0..50)
        .map(|i| {
            let x = i as f64;
            InputSample {
                t: x / 10.0,
                f: navkf_dynamics::kinematics::platform_input([
                    awkward[i % awkward.len()],
                    (0.37 * x).sin() * 0.05,
                    9.806_65 + 1e-7 * x,
                ]),
            }
        })
        .collect();
    let measurements = vec![
        Measurement {
            t: 0.0,
            velocity: Some([0.0, 0.0]),
            speed: None,
            nhc: None,
            zupt: None,
            position_deg: Some([45.78, 126.63]),
        },
        Measurement {
            t: 1.0,
            velocity: Some([1.0 / 3.0, -0.1]),
            speed: None,
            nhc: None,
            zupt: None,
            position_deg: None,
        },
        Measurement {
            t: 2.0,
            velocity: Some([0.7, 2.0_f64.sqrt()]),
            speed: None,
            nhc: None,
            zupt: None,
            position_deg: Some([45.780_012_345_678_9, 126.630_000_1]),
        },
        Measurement {
            t: 3.0,
            velocity: None,
            speed: None,
            nhc: None,
            zupt: None,
            position_deg: Some([45.780_03, -126.63]),
        },
        Measurement {
            t: 4.0,
            velocity: Some([1e-9, -0.0]),
            speed: None,
            nhc: None,
            zupt: None,
            position_deg: Some([-45.78, 359.9]),
        },
    ];
    let truth = Truth {
        names: vec!["phi_x".into(), "phi_y".into(), "Ka2x".into()],
        t: vec![0.0, 1.0, 4.0],
        states: vec![
            vec![1e-5, -2e-5, 0.0],
            vec![1.000_000_000_000_000_2e-5, 3.0 / 7.0, 1e-12],
            vec![f64::EPSILON, -1.0, 5e-324],
        ],
    };
    Dataset {
        name: name.to_owned(),
        inputs,
        measurements,
        noise: NoiseConfig {
            gyro_psd: 2.5e-14,
            accel_psd: 1.0 / 3.0 * 1e-8,
            odometer_rel: 0.002,
            odometer_floor: 0.01,
            gps_m: 2.0,
            nhc_m_s: None,
            zupt_m_s: None,
        },
        noise_stated: true,
        prior: PlatformPrior {
            level_rad: Some(1.0 / 3.0 * 1e-4),
            azimuth_rad: None,
            coefficients: [("Kg0x".to_string(), 4.8e-7), ("kod".to_string(), 0.01)].into(),
        },
        provenance: Some(Provenance {
            seed: Some(42),
            run: Some(3),
            effects: vec!["ka2".into(), "scale \"quoted\"".into()],
            note: Some("hand-built, with a comma and a \"quote\"\nand a newline".into()),
        }),
        truth: Some(truth),
        model: Default::default(),
        initial: None,
        effects: Vec::new(),
    }
}

pub fn bits_of(d: &Dataset) -> Vec<u64> {
    let mut v: Vec<u64> = Vec::new();
    for s in &d.inputs {
        v.extend([s.t, s.f[0], s.f[1], s.f[2]].map(f64::to_bits));
    }
    for m in &d.measurements {
        v.push(m.t.to_bits());
        v.extend(m.velocity.into_iter().flatten().map(f64::to_bits));
        v.extend(m.position_deg.into_iter().flatten().map(f64::to_bits));
    }
    if let Some(t) = &d.truth {
        v.extend(t.t.iter().map(|x| x.to_bits()));
        v.extend(t.states.iter().flatten().map(|x| x.to_bits()));
    }
    v
}
