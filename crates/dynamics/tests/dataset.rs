//! Dataset folders: write -> read round trip, one test per validation error (each names the
//! file, the line, the column and what was expected), and the summary.

use navkf_dynamics::dataset::{Dataset, InputSample, Measurement, Provenance, Truth};
use navkf_dynamics::earth::meridian_radius;
use navkf_dynamics::{NoiseConfig, PlatformPrior, Registry};
use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};

static COUNTER: AtomicUsize = AtomicUsize::new(0);

/// A fresh, empty folder under the system temp dir, unique to this process and call.
fn temp_folder(tag: &str) -> PathBuf {
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    let dir = std::env::temp_dir().join(format!(
        "navkf-dataset-test-{}-{n}-{tag}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A folder holding exactly `files`.
fn folder(tag: &str, files: &[(&str, &str)]) -> PathBuf {
    let dir = temp_folder(tag);
    for (name, text) in files {
        std::fs::write(dir.join(name), text).unwrap();
    }
    dir
}

/// `inputs.csv` with `n` rows at 10 Hz from t = 0.
fn inputs_text(n: usize) -> String {
    let mut s = String::from("t,f_e,f_n,f_u\n");
    for i in 0..n {
        s += &format!("{},0.001,-0.002,9.8\n", i as f64 / 10.0);
    }
    s
}

const MEAS_OK: &str =
    "t,v_e,v_n,lat_deg,lon_deg\n1,0.5,0.1,45.78,126.63\n2,0.5,0.1,45.78001,126.63001\n";

/// Reads a folder made of the given files (inputs.csv and measurements.csv default to good
/// ones when not given) and returns the error's text; fails the test if reading succeeds.
fn read_error(tag: &str, files: &[(&str, &str)]) -> String {
    let inputs = inputs_text(50);
    let mut all: Vec<(&str, &str)> = files.to_vec();
    if !files.iter().any(|(n, _)| *n == "inputs.csv") {
        all.push(("inputs.csv", &inputs));
    }
    if !files.iter().any(|(n, _)| *n == "measurements.csv") {
        all.push(("measurements.csv", MEAS_OK));
    }
    let dir = folder(tag, &all);
    let result = Dataset::read(&dir);
    let _ = std::fs::remove_dir_all(&dir);
    match result {
        Ok(d) => panic!("{tag}: expected an error, read {} inputs", d.inputs.len()),
        Err(e) => e.to_string(),
    }
}

/// Asserts that `message` contains every one of `parts`.
fn assert_mentions(message: &str, parts: &[&str]) {
    for p in parts {
        assert!(
            message.contains(p),
            "error message does not mention {p:?}:\n{message}"
        );
    }
}

/// A small dataset: 50 inputs at 10 Hz, measurements at 1 Hz with an odometer-only and a
/// GPS-only row, truth, provenance, non-default noise, and awkward floats.
fn sample(name: &str) -> Dataset {
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
            position_deg: Some([45.78, 126.63]),
        },
        Measurement {
            t: 1.0,
            velocity: Some([1.0 / 3.0, -0.1]),
            position_deg: None,
        },
        Measurement {
            t: 2.0,
            velocity: Some([0.7, 2.0_f64.sqrt()]),
            position_deg: Some([45.780_012_345_678_9, 126.630_000_1]),
        },
        Measurement {
            t: 3.0,
            velocity: None,
            position_deg: Some([45.780_03, -126.63]),
        },
        Measurement {
            t: 4.0,
            velocity: Some([1e-9, -0.0]),
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
    }
}

fn bits_of(d: &Dataset) -> Vec<u64> {
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

#[test]
fn write_then_read_gives_the_same_dataset() {
    let dir = temp_folder("roundtrip");
    let name = dir.file_name().unwrap().to_string_lossy().into_owned();
    let original = sample(&name);
    original.write(&dir).unwrap();
    let back = Dataset::read(&dir).unwrap();
    assert_eq!(back, original);
    // == treats -0.0 and 0.0 alike: compare the bits too.
    assert_eq!(bits_of(&back), bits_of(&original));
    assert_eq!(
        back.noise.accel_psd.to_bits(),
        original.noise.accel_psd.to_bits()
    );

    // Empty cells for the missing sensors, and only the four files (no temporaries left).
    let meas = std::fs::read_to_string(dir.join("measurements.csv")).unwrap();
    assert!(
        meas.lines()
            .any(|l| l.starts_with("1,") && l.ends_with(",,")),
        "{meas}"
    );
    assert!(meas.lines().any(|l| l.starts_with("3,,,")), "{meas}");
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(
        names,
        [
            "dataset.toml",
            "inputs.csv",
            "measurements.csv",
            "truth.csv"
        ]
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn rewriting_without_truth_or_provenance_removes_them() {
    let dir = temp_folder("rewrite");
    let name = dir.file_name().unwrap().to_string_lossy().into_owned();
    let mut d = sample(&name);
    d.write(&dir).unwrap();
    d.truth = None;
    d.provenance = None;
    d.noise = NoiseConfig::default();
    d.write(&dir).unwrap();
    assert!(!dir.join("truth.csv").exists());
    let toml = std::fs::read_to_string(dir.join("dataset.toml")).unwrap();
    assert!(!toml.contains("[simulation]"), "{toml}");
    for key in [
        "gyro_psd",
        "accel_psd",
        "odometer_rel",
        "odometer_floor",
        "gps_m",
    ] {
        assert!(toml.contains(key), "{toml}");
    }
    assert_eq!(Dataset::read(&dir).unwrap(), d);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn write_creates_nested_folders_and_read_names_the_dataset_after_the_folder() {
    let base = temp_folder("nested");
    let dir = base.join("a").join("my-run");
    let d = sample("my-run");
    d.write(&dir).unwrap();
    let back = Dataset::read(&dir).unwrap();
    assert_eq!(back.name, "my-run");
    assert_eq!(back, d);
    std::fs::remove_dir_all(&base).unwrap();
}

#[test]
fn optional_files_absent_give_defaults() {
    let inputs = inputs_text(50);
    let dir = folder(
        "minimal",
        &[("inputs.csv", &inputs), ("measurements.csv", MEAS_OK)],
    );
    let d = Dataset::read(&dir).unwrap();
    assert_eq!(d.noise, NoiseConfig::default());
    assert_eq!(d.provenance, None);
    assert_eq!(d.truth, None);
    assert_eq!(d.inputs.len(), 50);
    assert_eq!(d.measurements.len(), 2);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn crlf_and_blanks_around_cells_are_accepted() {
    let dir = folder(
        "crlf",
        &[
            (
                "inputs.csv",
                "t, f_e, f_n, f_u\r\n0, 0, 0, 9.8\r\n0.1, 0, 0, 9.8\r\n",
            ),
            (
                "measurements.csv",
                "t,v_e,v_n,lat_deg,lon_deg\r\n0.05,1,0,,\r\n",
            ),
        ],
    );
    let d = Dataset::read(&dir).unwrap();
    assert_eq!(d.inputs[1].t, 0.1);
    assert_eq!(d.measurements[0].velocity, Some([1.0, 0.0]));
    std::fs::remove_dir_all(&dir).unwrap();
}

// ---- headers -------------------------------------------------------------------------------

#[test]
fn missing_input_column_is_named() {
    let e = read_error(
        "missing-col",
        &[("inputs.csv", "t,f_e,f_u\n0,0,9.8\n0.1,0,9.8\n")],
    );
    assert_mentions(
        &e,
        &["inputs.csv:1:", "column `f_n`", "missing", "t,f_e,f_n,f_u"],
    );
}

#[test]
fn misnamed_measurement_column_is_named() {
    let e = read_error(
        "misnamed-col",
        &[(
            "measurements.csv",
            "t,v_e,v_n,lat,lon_deg\n1,0.5,0.1,45.78,126.63\n",
        )],
    );
    assert_mentions(
        &e,
        &[
            "measurements.csv:1:",
            "column `lat_deg`",
            "missing",
            "`lat`",
            "t,v_e,v_n,lat_deg,lon_deg",
        ],
    );
}

#[test]
fn unexpected_input_column_is_named() {
    let e = read_error(
        "extra-col",
        &[(
            "inputs.csv",
            "t,f_e,f_n,f_u,f_x\n0,0,0,9.8,1\n0.1,0,0,9.8,1\n",
        )],
    );
    assert_mentions(
        &e,
        &[
            "inputs.csv:1:",
            "column `f_x`",
            "unexpected",
            "t,f_e,f_n,f_u",
        ],
    );
}

#[test]
fn columns_out_of_order_are_refused() {
    let e = read_error(
        "order",
        &[("inputs.csv", "t,f_n,f_e,f_u\n0,0,0,9.8\n0.1,0,0,9.8\n")],
    );
    assert_mentions(
        &e,
        &[
            "inputs.csv:1:",
            "column `f_e`",
            "column 2 is `f_n`",
            "t,f_e,f_n,f_u",
        ],
    );
}

// ---- cells ---------------------------------------------------------------------------------

#[test]
fn too_few_cells_name_the_missing_column() {
    let e = read_error(
        "few-cells",
        &[(
            "inputs.csv",
            "t,f_e,f_n,f_u\n0,0,0,9.8\n0.1,0,0,9.8\n0.2,0,0\n0.3,0,0,9.8\n",
        )],
    );
    assert_mentions(
        &e,
        &["inputs.csv:4:", "column `f_u`", "3 cells, expected 4"],
    );
}

#[test]
fn too_many_cells_are_refused() {
    let e = read_error(
        "many-cells",
        &[(
            "measurements.csv",
            "t,v_e,v_n,lat_deg,lon_deg\n1,0.5,0.1,45.78,126.63\n2,0.5,0.1,45.78,126.63,7\n",
        )],
    );
    assert_mentions(
        &e,
        &[
            "measurements.csv:3:",
            "column `-`",
            "6 cells, expected 5 (t,v_e,v_n,lat_deg,lon_deg)",
        ],
    );
}

#[test]
fn non_numeric_cell_is_named() {
    let mut inputs = inputs_text(50);
    inputs = inputs.replacen("0.3,0.001,-0.002", "0.3,0.001,abc", 1);
    let e = read_error("non-numeric", &[("inputs.csv", &inputs)]);
    assert_mentions(
        &e,
        &[
            "inputs.csv:5:",
            "column `f_n`",
            "`abc` is not a number",
            "expected a finite number",
        ],
    );
}

#[test]
fn nan_cell_is_refused() {
    let e = read_error(
        "nan",
        &[(
            "measurements.csv",
            "t,v_e,v_n,lat_deg,lon_deg\n1,0.5,0.1,45.78,126.63\n2,NaN,0.1,45.78,126.63\n",
        )],
    );
    assert_mentions(
        &e,
        &[
            "measurements.csv:3:",
            "column `v_e`",
            "`NaN` is not finite",
            "expected a finite number",
        ],
    );
}

#[test]
fn infinite_cell_is_refused() {
    let inputs = inputs_text(50).replacen("0.2,0.001,-0.002,9.8", "0.2,0.001,-0.002,inf", 1);
    let e = read_error("inf", &[("inputs.csv", &inputs)]);
    assert_mentions(
        &e,
        &["inputs.csv:4:", "column `f_u`", "`inf` is not finite"],
    );
}

#[test]
fn empty_time_cell_is_refused() {
    let e = read_error(
        "empty-t",
        &[(
            "measurements.csv",
            "t,v_e,v_n,lat_deg,lon_deg\n1,0.5,0.1,45.78,126.63\n,0.5,0.1,,\n",
        )],
    );
    assert_mentions(
        &e,
        &[
            "measurements.csv:3:",
            "column `t`",
            "empty cell",
            "expected a finite number",
        ],
    );
}

// ---- times ---------------------------------------------------------------------------------

#[test]
fn input_times_must_increase() {
    let e = read_error(
        "input-order",
        &[(
            "inputs.csv",
            "t,f_e,f_n,f_u\n0,0,0,9.8\n0.1,0,0,9.8\n0.2,0,0,9.8\n0.3,0,0,9.8\n0.4,0,0,9.8\n0.35,0,0,9.8\n",
        )],
    );
    assert_mentions(
        &e,
        &[
            "inputs.csv:7:",
            "column `t`",
            "t = 0.35 is not after t = 0.4 on line 6",
            "strictly increasing",
        ],
    );
}

#[test]
fn repeated_measurement_time_is_refused() {
    let e = read_error(
        "meas-order",
        &[(
            "measurements.csv",
            "t,v_e,v_n,lat_deg,lon_deg\n2,0.5,0.1,45.78,126.63\n2,0.5,0.1,45.78,126.63\n",
        )],
    );
    assert_mentions(
        &e,
        &[
            "measurements.csv:3:",
            "column `t`",
            "t = 2 is not after t = 2 on line 2",
            "strictly increasing",
        ],
    );
}

#[test]
fn measurement_after_the_inputs_is_refused() {
    let e = read_error(
        "after-span",
        &[(
            "measurements.csv",
            "t,v_e,v_n,lat_deg,lon_deg\n1,0.5,0.1,45.78,126.63\n2,0.5,0.1,45.78,126.63\n7,0.5,0.1,45.78,126.63\n",
        )],
    );
    assert_mentions(
        &e,
        &[
            "measurements.csv:4:",
            "column `t`",
            "t = 7 is outside the span of inputs.csv",
            "expected 0 <= t <= 4.9",
        ],
    );
}

#[test]
fn measurement_before_the_inputs_is_refused() {
    let e = read_error(
        "before-span",
        &[(
            "measurements.csv",
            "t,v_e,v_n,lat_deg,lon_deg\n-0.5,0.5,0.1,45.78,126.63\n",
        )],
    );
    assert_mentions(
        &e,
        &[
            "measurements.csv:2:",
            "column `t`",
            "t = -0.5 is outside",
            "0 <= t <= 4.9",
        ],
    );
}

// ---- positions -----------------------------------------------------------------------------

#[test]
fn latitude_beyond_90_is_refused() {
    let e = read_error(
        "lat-range",
        &[(
            "measurements.csv",
            "t,v_e,v_n,lat_deg,lon_deg\n1,0.5,0.1,45.78,126.63\n2,0.5,0.1,95.2,126.63\n",
        )],
    );
    assert_mentions(
        &e,
        &[
            "measurements.csv:3:",
            "column `lat_deg`",
            "95.2",
            "[-90, 90]",
            "degrees",
        ],
    );
}

#[test]
fn longitude_beyond_360_is_refused() {
    let e = read_error(
        "lon-range",
        &[(
            "measurements.csv",
            "t,v_e,v_n,lat_deg,lon_deg\n1,0.5,0.1,45.78,-400\n",
        )],
    );
    assert_mentions(
        &e,
        &[
            "measurements.csv:2:",
            "column `lon_deg`",
            "-400",
            "[-360, 360]",
        ],
    );
}

/// 20 s of inputs; measurements at 1 Hz from t = 1 driving north at `speed` m/s, GPS from
/// `gps(k)` for k = 0.. (odometer cells empty when `speed` is None).
fn moving_folder(tag: &str, speed: Option<f64>, gps: impl Fn(f64) -> [f64; 2]) -> PathBuf {
    let mut meas = String::from("t,v_e,v_n,lat_deg,lon_deg\n");
    for k in 0..16 {
        let [lat, lon] = gps(k as f64);
        let v = speed.map_or(",".to_owned(), |s| format!("0,{s}"));
        meas += &format!("{},{v},{lat},{lon}\n", k + 1);
    }
    folder(
        tag,
        &[
            ("inputs.csv", &inputs_text(200)),
            ("measurements.csv", &meas),
        ],
    )
}

#[test]
fn radian_positions_with_odometer_are_detected() {
    // Harbin in radians, 10 m/s north: 150 m of odometer travel.
    let dir = moving_folder("radians-odo", Some(10.0), |k| {
        [0.799 + 10.0 * k / 6.36e6, 2.2100]
    });
    let e = Dataset::read(&dir).unwrap_err().to_string();
    std::fs::remove_dir_all(&dir).unwrap();
    assert_mentions(
        &e,
        &[
            "measurements.csv:2:",
            "column `lat_deg`",
            "look like radians",
            "odometer",
            "expected degrees",
        ],
    );
}

#[test]
fn radian_positions_without_odometer_are_detected() {
    let dir = moving_folder("radians-still", None, |_| [0.799, 2.21]);
    let e = Dataset::read(&dir).unwrap_err().to_string();
    std::fs::remove_dir_all(&dir).unwrap();
    assert_mentions(
        &e,
        &[
            "measurements.csv:2:",
            "column `lat_deg`",
            "look like radians",
            "expected degrees",
        ],
    );
}

#[test]
fn degrees_near_the_origin_are_not_taken_for_radians() {
    // A synthetic run placed at (0, 0), in degrees, driving north at 10 m/s.
    let dir = moving_folder("null-island", Some(10.0), |k| [10.0 * k / 110_574.0, 0.0]);
    let d = Dataset::read(&dir);
    std::fs::remove_dir_all(&dir).unwrap();
    assert_eq!(d.unwrap().measurements.len(), 16);
    // And standing at the origin without odometer.
    let dir = moving_folder("null-island-still", None, |_| [0.0, 0.0]);
    let d = Dataset::read(&dir);
    std::fs::remove_dir_all(&dir).unwrap();
    assert!(d.is_ok(), "{:?}", d.err());
}

// ---- sensor pairs --------------------------------------------------------------------------

#[test]
fn half_an_odometer_pair_is_refused() {
    let e = read_error(
        "half-odo",
        &[(
            "measurements.csv",
            "t,v_e,v_n,lat_deg,lon_deg\n1,0.5,0.1,45.78,126.63\n2,0.5,,45.78,126.63\n",
        )],
    );
    assert_mentions(
        &e,
        &[
            "measurements.csv:3:",
            "column `v_n`",
            "empty while `v_e` has a value",
            "expected both odometer cells or neither",
        ],
    );
}

#[test]
fn half_a_gps_pair_is_refused() {
    let e = read_error(
        "half-gps",
        &[(
            "measurements.csv",
            "t,v_e,v_n,lat_deg,lon_deg\n1,0.5,0.1,,126.63\n",
        )],
    );
    assert_mentions(
        &e,
        &[
            "measurements.csv:2:",
            "column `lat_deg`",
            "empty while `lon_deg` has a value",
            "expected both GPS cells or neither",
        ],
    );
}

#[test]
fn a_measurement_row_saying_nothing_is_refused() {
    let e = read_error(
        "all-empty",
        &[(
            "measurements.csv",
            "t,v_e,v_n,lat_deg,lon_deg\n1,0.5,0.1,45.78,126.63\n2,,,,\n",
        )],
    );
    assert_mentions(
        &e,
        &[
            "measurements.csv:3:",
            "column `v_e,v_n,lat_deg,lon_deg`",
            "says nothing",
            "expected an odometer pair",
        ],
    );
}

// ---- whole files ---------------------------------------------------------------------------

#[test]
fn a_single_input_row_is_refused() {
    let e = read_error(
        "one-input",
        &[
            ("inputs.csv", "t,f_e,f_n,f_u\n0,0,0,9.8\n"),
            (
                "measurements.csv",
                "t,v_e,v_n,lat_deg,lon_deg\n0,0.5,0.1,,\n",
            ),
        ],
    );
    assert_mentions(
        &e,
        &[
            "inputs.csv:3:",
            "column `-`",
            "1 data row",
            "expected at least 2 input rows",
        ],
    );
}

#[test]
fn a_measurements_file_with_only_its_header_is_refused() {
    let e = read_error(
        "no-meas",
        &[("measurements.csv", "t,v_e,v_n,lat_deg,lon_deg\n")],
    );
    assert_mentions(
        &e,
        &[
            "measurements.csv:2:",
            "column `-`",
            "no measurement rows",
            "expected at least one",
        ],
    );
}

#[test]
fn an_empty_measurements_file_is_refused() {
    let e = read_error("empty-meas", &[("measurements.csv", "")]);
    assert_mentions(
        &e,
        &[
            "measurements.csv:1:",
            "empty file",
            "expected the header `t,v_e,v_n,lat_deg,lon_deg`",
        ],
    );
}

#[test]
fn a_missing_inputs_file_is_named() {
    let dir = folder("no-inputs", &[("measurements.csv", MEAS_OK)]);
    let e = Dataset::read(&dir).unwrap_err().to_string();
    std::fs::remove_dir_all(&dir).unwrap();
    assert_mentions(&e, &["inputs.csv", "not found", "t,f_e,f_n,f_u"]);
}

#[test]
fn a_missing_folder_is_named() {
    let base = temp_folder("gone");
    let e = Dataset::read(&base.join("does-not-exist"))
        .unwrap_err()
        .to_string();
    std::fs::remove_dir_all(&base).unwrap();
    assert_mentions(&e, &["does-not-exist", "not a folder"]);
}

// ---- dataset.toml --------------------------------------------------------------------------

#[test]
fn unknown_noise_key_is_refused_with_its_name() {
    let e = read_error(
        "toml-key",
        &[(
            "dataset.toml",
            "[noise]\ngyro_psd = 1e-14\ngyro_pds = 2e-14\n",
        )],
    );
    assert_mentions(&e, &["dataset.toml:3:1:", "gyro_pds", "unknown field"]);
}

#[test]
fn unknown_table_is_refused_with_its_name() {
    let e = read_error(
        "toml-table",
        &[("dataset.toml", "[noise]\ngps_m = 3.0\n\n[sensors]\nx = 1\n")],
    );
    assert_mentions(
        &e,
        &[
            "dataset.toml:4:2:",
            "sensors",
            "expected one of `noise`, `prior`, `simulation`",
        ],
    );
}

#[test]
fn unknown_simulation_key_is_refused_with_its_name() {
    let e = read_error("toml-sim", &[("dataset.toml", "[simulation]\nsead = 3\n")]);
    assert_mentions(&e, &["dataset.toml:2:1:", "sead"]);
}

#[test]
fn toml_syntax_error_gives_line_and_column() {
    let e = read_error("toml-syntax", &[("dataset.toml", "[noise]\ngps_m = = 3\n")]);
    assert_mentions(&e, &["dataset.toml:2:9:", "TOML parse error"]);
}

#[test]
fn invalid_noise_value_is_refused_with_its_line() {
    let e = read_error(
        "toml-value",
        &[(
            "dataset.toml",
            "# noise\n[noise]\ngyro_psd = 1e-14\ngps_m = -3.0\n",
        )],
    );
    assert_mentions(
        &e,
        &[
            "dataset.toml:4:",
            "column `noise.gps_m`",
            "expected a finite number > 0",
        ],
    );
}

#[test]
fn absent_noise_keys_take_defaults_and_simulation_is_read() {
    let inputs = inputs_text(50);
    let dir = folder(
        "toml-defaults",
        &[
            ("inputs.csv", &inputs),
            ("measurements.csv", MEAS_OK),
            (
                "dataset.toml",
                "[noise]\ngps_m = 5\n\n[simulation]\nseed = 9\neffects = [\"ka2\"]\n",
            ),
        ],
    );
    let d = Dataset::read(&dir).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
    assert_eq!(
        d.noise,
        NoiseConfig {
            gps_m: 5.0,
            ..NoiseConfig::default()
        }
    );
    assert_eq!(
        d.provenance,
        Some(Provenance {
            seed: Some(9),
            effects: vec!["ka2".into()],
            ..Provenance::default()
        })
    );
}

// ---- dataset.toml [prior] ------------------------------------------------------------------

#[test]
fn prior_table_is_read_with_base_and_effect_coefficients() {
    let inputs = inputs_text(50);
    let dir = folder(
        "prior-ok",
        &[
            ("inputs.csv", &inputs),
            ("measurements.csv", MEAS_OK),
            (
                "dataset.toml",
                "[prior]\nazimuth_rad = 2e-3\n\n[prior.coefficients]\nKg0x = 4.8e-7\nKa12x = 1e-3\n",
            ),
        ],
    );
    let d = Dataset::read(&dir).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
    assert_eq!(d.prior.level_rad, None);
    assert_eq!(d.prior.azimuth_rad, Some(2e-3));
    assert_eq!(d.prior.coefficients["Kg0x"], 4.8e-7);
    assert_eq!(d.prior.coefficients["Ka12x"], 1e-3);
}

#[test]
fn unknown_prior_key_is_refused_with_its_line() {
    let e = read_error(
        "prior-key",
        &[(
            "dataset.toml",
            "[prior]\nlevel_rad = 5e-5\nazimuth_deg = 0.1\n",
        )],
    );
    assert_mentions(&e, &["dataset.toml:3:1:", "azimuth_deg", "unknown field"]);
}

#[test]
fn unknown_prior_coefficient_is_refused_with_its_line_and_the_known_names() {
    let e = read_error(
        "prior-coef",
        &[(
            "dataset.toml",
            "[noise]\ngps_m = 3.0\n\n[prior.coefficients]\nKg0x = 1e-7\nKg0w = 1e-7\n",
        )],
    );
    assert_mentions(
        &e,
        &[
            "dataset.toml:6:",
            "column `prior.coefficients.Kg0w`",
            "unknown coefficient `Kg0w`",
            "Ka12x",
        ],
    );
    // A navigation state is not a coefficient, and the message says where its prior is.
    let e = read_error(
        "prior-nav",
        &[("dataset.toml", "[prior.coefficients]\nphi_z = 1e-3\n")],
    );
    assert_mentions(&e, &["dataset.toml:2:", "phi_z", "azimuth_rad"]);
}

#[test]
fn non_positive_or_malformed_prior_values_are_refused_with_their_line() {
    let e = read_error(
        "prior-neg",
        &[(
            "dataset.toml",
            "[prior]\nlevel_rad = 5e-5\nazimuth_rad = -1e-3\n",
        )],
    );
    assert_mentions(
        &e,
        &[
            "dataset.toml:3:",
            "column `prior.azimuth_rad`",
            "finite and > 0",
        ],
    );
    let e = read_error(
        "prior-zero",
        &[("dataset.toml", "[prior.coefficients]\nkod = 0.0\n")],
    );
    assert_mentions(&e, &["dataset.toml:2:", "prior.coefficients.kod", "> 0"]);
    let e = read_error(
        "prior-type",
        &[("dataset.toml", "[prior]\nlevel_rad = \"small\"\n")],
    );
    assert_mentions(&e, &["dataset.toml:2:13:", "invalid type", "level_rad"]);
}

#[test]
fn a_users_own_effect_coefficient_is_accepted_with_its_registry() {
    #[derive(Debug)]
    struct Drag;
    impl navkf_dynamics::Effect for Drag {
        fn terms(&self) -> navkf_dynamics::Terms {
            navkf_dynamics::Terms {
                rates: false,
                linear_rates: &[],
                measurement: navkf_dynamics::MeasurementTerm::None,
                noise: false,
            }
        }
        fn name(&self) -> &str {
            "drag"
        }
        fn description(&self) -> &str {
            "v' -= kd v"
        }
        fn coefficient_names(&self) -> &[&str] {
            &["kd"]
        }
        fn coefficient_units(&self) -> &[&str] {
            &["1/s"]
        }
        fn coefficient_sigma(&self) -> &[f64] {
            &[1e-5]
        }
    }
    let inputs = inputs_text(50);
    let files = [
        ("inputs.csv", inputs.as_str()),
        ("measurements.csv", MEAS_OK),
        ("dataset.toml", "[prior.coefficients]\nkd = 1e-4\n"),
    ];
    let dir = folder("prior-user", &files);
    assert!(
        Dataset::read(&dir).is_err(),
        "kd is unknown to the catalogue"
    );
    let mut registry = Registry::catalogue();
    registry.register(|| Box::new(Drag));
    let d = Dataset::read_with(&dir, &registry).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
    assert_eq!(
        d.prior,
        PlatformPrior {
            coefficients: [("kd".to_string(), 1e-4)].into(),
            ..Default::default()
        }
    );
}

// ---- truth.csv -----------------------------------------------------------------------------

#[test]
fn truth_must_start_with_t() {
    let e = read_error("truth-t", &[("truth.csv", "time,phi_x\n0,1\n")]);
    assert_mentions(&e, &["truth.csv:1:", "column `time`", "expected `t`"]);
}

#[test]
fn truth_needs_a_state_column() {
    let e = read_error("truth-none", &[("truth.csv", "t\n0\n")]);
    assert_mentions(
        &e,
        &["truth.csv:1:", "column `-`", "at least one state name"],
    );
}

#[test]
fn truth_columns_must_be_unique() {
    let e = read_error(
        "truth-dup",
        &[("truth.csv", "t,phi_x,phi_y,phi_x\n0,1,2,3\n")],
    );
    assert_mentions(
        &e,
        &[
            "truth.csv:1:",
            "column `phi_x`",
            "duplicate",
            "columns 2 and 4",
            "unique",
        ],
    );
}

#[test]
fn truth_times_must_increase() {
    let e = read_error(
        "truth-order",
        &[("truth.csv", "t,phi_x\n0,1\n1,2\n0.5,3\n")],
    );
    assert_mentions(
        &e,
        &[
            "truth.csv:4:",
            "column `t`",
            "t = 0.5 is not after t = 1 on line 3",
        ],
    );
}

#[test]
fn truth_values_must_be_finite_numbers() {
    let e = read_error(
        "truth-value",
        &[("truth.csv", "t,phi_x,Ka2x\n0,1,2\n1,2,-inf\n")],
    );
    assert_mentions(
        &e,
        &[
            "truth.csv:3:",
            "column `Ka2x`",
            "`-inf` is not finite",
            "expected a finite number",
        ],
    );
    let e = read_error(
        "truth-cells",
        &[("truth.csv", "t,phi_x,Ka2x\n0,1,2\n1,2\n")],
    );
    assert_mentions(
        &e,
        &["truth.csv:3:", "column `Ka2x`", "2 cells, expected 3"],
    );
}

#[test]
fn truth_needs_rows() {
    let e = read_error("truth-rows", &[("truth.csv", "t,phi_x\n")]);
    assert_mentions(&e, &["truth.csv:2:", "no rows", "expected at least one"]);
}

// ---- summary -------------------------------------------------------------------------------

/// 60 s: standing for 10 s, then 10 m/s north, turning right at 5 deg/s from 30 s to 40 s;
/// inputs at 10 Hz with 10.0..10.5 s missing; GPS missing from 21 s to 25 s.
fn drive() -> Dataset {
    let inputs = (0..600)
        .filter(|i| !(101..=105).contains(i))
        .map(|i| {
            let t = i as f64 / 10.0;
            let turning = (30.0..40.0).contains(&t);
            InputSample {
                t,
                f: navkf_dynamics::kinematics::platform_input([
                    if turning { 0.3 } else { 0.0 },
                    0.0,
                    9.8,
                ]),
            }
        })
        .collect();
    let mut heading: f64 = 0.0;
    let measurements = (0..60)
        .map(|k| {
            let t = k as f64;
            if (31.0..=40.0).contains(&t) {
                heading += 5f64.to_radians();
            }
            let speed = if t < 10.0 { 0.0 } else { 10.0 };
            Measurement {
                t,
                velocity: Some([speed * heading.sin(), speed * heading.cos()]),
                position_deg: (!(21.0..=25.0).contains(&t))
                    .then_some([45.0 + 1e-4 * t, 126.0 + 2e-4 * t]),
            }
        })
        .collect();
    Dataset {
        name: "drive".into(),
        inputs,
        measurements,
        noise: NoiseConfig::default(),
        noise_stated: true,
        prior: PlatformPrior::default(),
        provenance: None,
        truth: None,
    }
}

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}

#[test]
fn summary_reports_span_rates_gaps_speed_turns_and_extent() {
    let s = drive().summary();
    let span = s.span.unwrap();
    assert_eq!((span.start, span.end), (0.0, 59.9));
    assert!(close(span.duration, 59.9, 1e-12));

    let i = s.inputs.interval.unwrap();
    assert!(close(i.median, 0.1, 1e-9) && close(i.rate_hz, 10.0, 1e-6));
    assert!(close(i.max, 0.6, 1e-9), "{i:?}");
    assert_eq!(s.inputs.count, 595);
    assert_eq!(s.inputs.gaps.count, 1);
    let g = s.inputs.gaps.largest.unwrap();
    assert!(
        close(g.start, 10.0, 1e-9) && close(g.duration, 0.6, 1e-9),
        "{g:?}"
    );

    assert_eq!(
        (s.measurements.count, s.odometer.count, s.gps.count),
        (60, 60, 55)
    );
    assert_eq!(s.measurements.gaps.count, 0);
    assert!(close(s.odometer.interval.unwrap().rate_hz, 1.0, 1e-12));
    let g = s.gps.gaps.largest.unwrap();
    assert_eq!((s.gps.gaps.count, g.start, g.duration), (1, 20.0, 6.0));

    let v = s.speed.unwrap();
    assert!(close(v.max, 10.0, 1e-12), "{v:?}");
    assert!(close(v.still_fraction, 9.5 / 59.0, 1e-12), "{v:?}");
    assert!(
        close(v.mean, (0.5 * 10.0 + 49.0 * 10.0) / 59.0, 1e-9),
        "{v:?}"
    );

    let t = s.turn;
    assert!(close(t.max_turn_rate_deg_s.unwrap(), 5.0, 1e-9), "{t:?}");
    assert!(close(t.turning_time, 10.0, 1e-12), "{t:?}");
    assert!(close(t.turning_fraction, 10.0 / 59.9, 1e-12));
    assert_eq!(t.max_horizontal_force, Some(0.3));

    let e = s.extent.unwrap();
    assert_eq!((e.lat_min, e.lat_max), (45.0, 45.0 + 1e-4 * 59.0));
    let north =
        (1e-4 * 59.0f64).to_radians() * meridian_radius((45.0 + 0.5 * 59e-4f64).to_radians().sin());
    assert!(close(e.north_m, north, 1e-6 * north), "{e:?}");
    assert!(e.east_m > 0.5 * north && e.east_m < 2.0 * north, "{e:?}");
    assert_eq!(s.truth, None);

    let text = s.to_string();
    for part in [
        "dataset `drive`",
        "595 rows",
        "(10 Hz)",
        "largest 0.6 s at t = 10 s",
        "55 fixes",
        "largest 6 s at t = 20 s",
        "max 10 m/s",
        "max |heading rate| 5 deg/s",
        "turning (> 1 deg/s) 10 s",
        "m north-south",
        "truth         none",
    ] {
        assert!(text.contains(part), "summary lacks {part:?}:\n{text}");
    }
    // Serialisable (toml is already a dependency).
    let toml = toml::to_string(&s).unwrap();
    assert!(toml.contains("still_fraction"), "{toml}");
}

#[test]
fn summary_names_truth_columns_and_survives_an_empty_dataset() {
    let s = sample("x").summary();
    let truth = s.truth.as_ref().unwrap();
    assert_eq!(truth.columns, ["phi_x", "phi_y", "Ka2x"]);
    assert!(s.to_string().contains("3 columns: phi_x, phi_y, Ka2x"));

    let empty = Dataset {
        name: "empty".into(),
        inputs: vec![],
        measurements: vec![],
        noise: NoiseConfig::default(),
        noise_stated: true,
        prior: PlatformPrior::default(),
        provenance: None,
        truth: None,
    };
    let s = empty.summary();
    assert_eq!((s.span, s.speed, s.extent), (None, None, None));
    assert!(s.to_string().contains("span          empty"));
}

#[test]
fn an_error_on_line_2_is_reported_without_reading_the_rest() {
    // inputs.csv: a bad cell on line 2, then 64 GiB of NUL bytes (a sparse file: no disk
    // used). A reader that took the whole file before checking would hold one 64 GiB
    // "line" in memory; a streaming one stops at line 2.
    let dir = folder("sparse", &[("measurements.csv", MEAS_OK)]);
    let path = dir.join("inputs.csv");
    std::fs::write(&path, "t,f_e,f_n,f_u\n0,0.001,x,9.8\n").unwrap();
    let file = std::fs::OpenOptions::new().write(true).open(&path).unwrap();
    if file.set_len(64 << 30).is_err() {
        return; // a file system without sparse files: nothing to show here
    }
    drop(file);
    let e = Dataset::read(&dir).unwrap_err().to_string();
    let _ = std::fs::remove_dir_all(&dir);
    assert_mentions(&e, &["inputs.csv:2", "f_n"]);
}

#[test]
fn a_device_or_fifo_is_refused_not_read() {
    // /dev/zero never ends and a FIFO without a writer blocks: both refused before reading.
    if !std::path::Path::new("/dev/zero").exists() {
        return;
    }
    let inputs = inputs_text(50);
    for name in [
        "inputs.csv",
        "measurements.csv",
        "truth.csv",
        "dataset.toml",
    ] {
        let dir = folder(
            "device",
            &[("inputs.csv", &inputs), ("measurements.csv", MEAS_OK)],
        );
        let _ = std::fs::remove_file(dir.join(name));
        std::os::unix::fs::symlink("/dev/zero", dir.join(name)).unwrap();
        let e = Dataset::read(&dir).unwrap_err().to_string();
        assert_mentions(&e, &[name, "not a regular file"]);
        let _ = std::fs::remove_dir_all(&dir);
    }
    let dir = folder(
        "folder",
        &[("inputs.csv", &inputs), ("measurements.csv", MEAS_OK)],
    );
    std::fs::create_dir(dir.join("truth.csv")).unwrap();
    let e = Dataset::read(&dir).unwrap_err().to_string();
    assert_mentions(&e, &["truth.csv", "a folder"]);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn messages_escape_control_bytes_and_cut_long_cells() {
    // A terminal escape sequence in a cell, and a 60,000-character cell (a longer line is
    // refused as such, see tests/input_file.rs): the message shows the first escaped and the
    // second cut, with its length.
    let inputs = format!(
        "t,f_e,f_n,f_u\n0,\u{1b}[31mred,0,9.8\n{}",
        inputs_text(50)
            .lines()
            .skip(2)
            .collect::<Vec<_>>()
            .join("\n")
            + "\n"
    );
    let e = read_error("escape", &[("inputs.csv", &inputs)]);
    assert!(!e.contains('\u{1b}'), "{e:?}");
    assert_mentions(&e, &["\\u{1b}[31mred", "f_e"]);
    let long = "9".repeat(60_000);
    let inputs = format!("t,f_e,f_n,f_u\n0,x{long},0,9.8\n1,0,0,9.8\n");
    let e = read_error("long", &[("inputs.csv", &inputs)]);
    assert!(e.len() < 1000, "{} characters", e.len());
    assert_mentions(&e, &["characters)", "f_e"]);
}

#[test]
fn truth_columns_and_span_must_match_the_data() {
    let inputs = inputs_text(50); // 0 .. 4.9 s
    let meas = "t,v_e,v_n,lat_deg,lon_deg\n1,0.5,0.1,45.78,126.63\n2,0.5,0.1,45.78001,126.63001\n";
    let with_truth = |truth: &str| {
        read_error(
            "truth",
            &[
                ("inputs.csv", &inputs),
                ("measurements.csv", meas),
                ("truth.csv", truth),
            ],
        )
    };
    // A misspelt column would be left out of every comparison: refused, located.
    let e = with_truth("t,phi_x,Kg0xx\n0,0,0\n2,0,0\n");
    assert_mentions(&e, &["truth.csv:1", "Kg0xx", "misspelt"]);
    // A row beyond the inputs' span.
    let e = with_truth("t,phi_x\n0,0\n2,0\n9,0\n");
    assert_mentions(&e, &["truth.csv:4", "outside the span"]);
    // A truth that ends before the last measurement.
    let e = with_truth("t,phi_x\n0,0\n1,0\n");
    assert_mentions(&e, &["truth.csv:4", "before the last measurement"]);
}

#[test]
fn a_file_in_another_encoding_is_named_as_such_and_a_utf8_bom_is_accepted() {
    let inputs = inputs_text(50);
    // UTF-16 little-endian with a byte-order mark, as some exporters write.
    let mut utf16 = vec![0xFF, 0xFE];
    utf16.extend(inputs.encode_utf16().flat_map(|u| u.to_le_bytes()));
    let dir = folder("utf16", &[("measurements.csv", MEAS_OK)]);
    std::fs::write(dir.join("inputs.csv"), &utf16).unwrap();
    let e = Dataset::read(&dir).unwrap_err().to_string();
    assert_mentions(&e, &["inputs.csv", "UTF-16", "expected UTF-8"]);
    // The same without the mark.
    std::fs::write(dir.join("inputs.csv"), &utf16[2..]).unwrap();
    let e = Dataset::read(&dir).unwrap_err().to_string();
    assert_mentions(&e, &["inputs.csv", "UTF-16"]);
    // UTF-8 with a byte-order mark (a spreadsheet's "CSV UTF-8"): read as the same file.
    std::fs::write(dir.join("inputs.csv"), format!("\u{feff}{inputs}")).unwrap();
    let with_bom = Dataset::read(&dir).unwrap();
    std::fs::write(dir.join("inputs.csv"), &inputs).unwrap();
    assert_eq!(with_bom.inputs, Dataset::read(&dir).unwrap().inputs);
    let _ = std::fs::remove_dir_all(&dir);
}
