//! Measurement rows that cannot be what they say: positions in radians where degrees are
//! expected, half an odometer or GPS pair, rows saying nothing, files with too few rows.

use crate::dataset_files;

use dataset_files::*;
use navkf_dynamics::dataset::Dataset;

/// 20 s of inputs; measurements at 1 Hz from t = 1 driving north at `speed` m/s, GPS from
/// `gps(k)` for k = 0.. (odometer cells empty when `speed` is None).
fn moving_folder(tag: &str, speed: Option<f64>, gps: impl Fn(f64) -> [f64; 2]) -> Scratch {
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
    assert_eq!(d.unwrap().measurements.len(), 16);
    // And standing at the origin without odometer.
    let dir = moving_folder("null-island-still", None, |_| [0.0, 0.0]);
    let d = Dataset::read(&dir);
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
    assert_mentions(&e, &["inputs.csv", "not found", "t,f_e,f_n,f_u"]);
}

#[test]
fn a_missing_folder_is_named() {
    let base = temp_folder("gone");
    let e = Dataset::read(&base.join("does-not-exist"))
        .unwrap_err()
        .to_string();
    assert_mentions(&e, &["does-not-exist", "not a folder"]);
}

// ---- dataset.toml --------------------------------------------------------------------------
