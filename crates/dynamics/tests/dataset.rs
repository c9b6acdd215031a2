//! Dataset folders: write -> read round trip, and one test per validation error of the CSV
//! files (each names the file, the line, the column and what was expected). The
//! configuration, truth and summary are in `dataset_config.rs` and `dataset_truth.rs`, positions
//! in the wrong unit and incomplete rows in `dataset_rows.rs`.

use crate::dataset_files;

use dataset_files::*;
use navkf_dynamics::dataset::Dataset;
use navkf_dynamics::NoiseConfig;

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
            // 0.4 - 0.35 is 0.05000000000000002 in floating point.
            "goes back by 0.05 s",
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
            "the same time twice",
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
