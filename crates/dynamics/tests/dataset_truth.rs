//! `truth.csv`'s checks, the dataset summary, and what reading refuses of files that are not
//! text or not regular files.

use crate::dataset_files;

use dataset_files::*;
use navkf_dynamics::dataset::{Dataset, InputSample, Measurement};
use navkf_dynamics::earth::meridian_radius;
use navkf_dynamics::{NoiseConfig, PlatformPrior};

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
                speed: None,
                nhc: None,
                zupt: None,
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
        model: Default::default(),
        initial: None,
        effects: Vec::new(),
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
    assert!(
        s.to_string().contains("horizontal specific force max"),
        "{s}"
    );

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
        model: Default::default(),
        initial: None,
        effects: Vec::new(),
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
    }
    let dir = folder(
        "folder",
        &[("inputs.csv", &inputs), ("measurements.csv", MEAS_OK)],
    );
    std::fs::create_dir(dir.join("truth.csv")).unwrap();
    let e = Dataset::read(&dir).unwrap_err().to_string();
    assert_mentions(&e, &["truth.csv", "a folder"]);
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
}
