//! The strapdown family from the command line: `simulate --model strapdown` writes a
//! dataset that `inspect` reads and `diagnose` judges with the strapdown catalogue, a strapdown
//! setting without `--model strapdown` is refused, and
//! `plan` and `study` take a strapdown study file.

use crate::common;

use common::{navkf, text, Scratch};
use std::path::PathBuf;

fn scratch(tag: &str) -> Scratch {
    Scratch::new(&format!("cli-strapdown-{tag}"))
}

#[test]
fn a_simulated_strapdown_dataset_is_inspected_and_diagnosed() {
    let dir = scratch("sim");
    let out = dir.join("sim");
    let o = navkf(
        [
            "simulate",
            "--model",
            "strapdown",
            "--unit",
            "tactical",
            "--imu-rate",
            "20",
            "--duration",
            "2400",
            "--seed",
            "4",
            "--out",
        ]
        .into_iter()
        .map(Into::into)
        .chain([out.clone().into_os_string()])
        .collect::<Vec<std::ffi::OsString>>(),
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(text(&o.stderr).contains("tactical unit, IMU at 20 Hz"));
    assert!(out.join("imu.csv").is_file() && !out.join("inputs.csv").exists());
    let o = navkf([std::ffi::OsStr::new("inspect"), out.as_os_str()]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let s = text(&o.stdout);
    assert!(
        s.contains("20 Hz") && s.contains("roll, pitch, heading"),
        "{s}"
    );
    assert!(!s.to_lowercase().contains("warning"), "{s}");
    assert!(s.contains("attitude      stated: roll"), "{s}");
    // Without [initial], the data align the unit and say from what.
    let toml = std::fs::read_to_string(out.join("dataset.toml")).unwrap();
    let without: String = toml
        .lines()
        .filter(|l| {
            !["[initial]", "roll_deg", "pitch_deg", "heading_deg"]
                .iter()
                .any(|k| l.starts_with(k))
        })
        .map(|l| format!("{l}\n"))
        .collect();
    std::fs::write(out.join("dataset.toml"), without).unwrap();
    let o = navkf([std::ffi::OsStr::new("inspect"), out.as_os_str()]);
    let s = text(&o.stdout);
    assert!(
        s.contains("aligned from the data") && s.contains("GPS track"),
        "{s}"
    );
    // The diagnosis takes it with the strapdown catalogue: the body's sideslip and bounce
    // (the file's constraint readings are zeros) are a tolerance it fits, and nothing is
    // named on this clean drive.
    let report = out.with_file_name(format!(
        "{}-diagnosis",
        out.file_name().unwrap().to_string_lossy()
    ));
    let o = navkf([
        std::ffi::OsStr::new("diagnose"),
        out.as_os_str(),
        std::ffi::OsStr::new("--out"),
        report.as_os_str(),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let d: serde_json::Value =
        serde_json::from_slice(&std::fs::read(report.join("diagnosis.json")).unwrap()).unwrap();
    assert_eq!(d["family"], "strapdown");
    assert_eq!(d["effects"], serde_json::json!([]));
    // It starts from the alignment, and its report says so.
    assert_eq!(d["start_attitude"]["source"]["kind"], "aligned", "{d}");
    let md = std::fs::read_to_string(report.join("report.md")).unwrap();
    assert!(
        md.contains("aligned from the data (dataset.toml has no [initial])"),
        "{md}"
    );
    assert!(
        text(&o.stdout).contains("constraint tolerance"),
        "{}",
        text(&o.stdout)
    );
    let o = navkf([
        std::ffi::OsStr::new("diagnose"),
        out.as_os_str(),
        std::ffi::OsStr::new("--with"),
        std::ffi::OsStr::new("gyro-fz"),
    ]);
    assert!(!o.status.success());
    assert!(
        text(&o.stderr).contains("unknown strapdown effect"),
        "{}",
        text(&o.stderr)
    );
}

/// Every catalogued strapdown effect hidden by `simulate` gives a dataset navkf reads back,
/// its states in truth.csv included (a bias instability's departures were refused on reading,
/// so `simulate` wrote nothing).
#[test]
fn every_strapdown_effect_simulates_and_reads_back() {
    let dir = scratch("every");
    let catalogue = navkf_dynamics::strapdown::effects::StrapdownRegistry::catalogue();
    for name in catalogue.names() {
        let out = dir.join(name);
        let o = navkf([
            "simulate",
            "--model",
            "strapdown",
            "--unit",
            "mems",
            "--effects",
            name,
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{name}: {}", text(&o.stderr));
        let o = navkf([std::ffi::OsStr::new("inspect"), out.as_os_str()]);
        assert!(o.status.success(), "{name}: {}", text(&o.stderr));
    }
}

#[test]
fn strapdown_settings_are_refused_where_they_mean_nothing() {
    let dir = scratch("refused");
    let out = dir.join("out");
    let o = navkf(["simulate", "--unit", "mems", "--out", out.to_str().unwrap()]);
    assert!(!o.status.success());
    assert!(
        text(&o.stderr).contains("--unit: a strapdown setting"),
        "{}",
        text(&o.stderr)
    );
    let o = navkf([
        "simulate",
        "--model",
        "strapdown",
        "--effects",
        "gyro-fz",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!o.status.success());
    assert!(
        text(&o.stderr).contains("--effects") && text(&o.stderr).contains("gyro-scale"),
        "{}",
        text(&o.stderr)
    );
    let o = navkf([
        "simulate",
        "--model",
        "strapdown",
        "--imu-rate",
        "2.5",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!o.status.success());
    assert!(
        text(&o.stderr).contains("--imu-rate"),
        "{}",
        text(&o.stderr)
    );
    for (model, motion, expected) in [
        ("platform", "0.1", "--body-motion: a strapdown setting"),
        (
            "strapdown",
            "inf",
            "--body-motion inf: expected a velocity > 0 and at most 1 m/s",
        ),
        ("strapdown", "-0.1", "--body-motion -0.1: expected"),
        ("strapdown", "5", "--body-motion 5: expected"),
    ] {
        let o = navkf([
            "simulate",
            "--model",
            model,
            &format!("--body-motion={motion}"),
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(!o.status.success());
        assert!(text(&o.stderr).contains(expected), "{}", text(&o.stderr));
    }
    // A sideslip of metres a second is a unit's mistake, not a car.
    let o = navkf([
        "simulate",
        "--model",
        "strapdown",
        "--nhc-sigma",
        "10",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!o.status.success());
    assert!(
        text(&o.stderr).contains("--nhc-sigma 10: expected at most 1 m/s"),
        "{}",
        text(&o.stderr)
    );
    assert!(!out.exists(), "nothing is written when refused");
}

#[test]
fn a_kitti_oxts_folder_is_converted_and_read_back() {
    // Four seconds at rest at 10 Hz, in KITTI's layout: yaw 0 (East), az gravity.
    let dir = scratch("kitti");
    let oxts = dir.join("oxts");
    std::fs::create_dir_all(oxts.join("data")).unwrap();
    let mut stamps = String::new();
    for k in 0..=40 {
        stamps += &format!("2011-09-26 13:02:{:012.9}\n", 10.0 + 0.1 * k as f64);
        let mut v = vec!["0".to_string(); 30];
        v[0] = "49.0".into();
        v[1] = "8.4".into();
        v[13] = "9.81".into();
        v[23] = "0.3".into();
        std::fs::write(oxts.join("data").join(format!("{k:010}.txt")), v.join(" ")).unwrap();
    }
    std::fs::write(oxts.join("timestamps.txt"), stamps).unwrap();
    let out = dir.join("kitti-out");
    let o = navkf([
        std::ffi::OsStr::new("convert"),
        std::ffi::OsStr::new("kitti"),
        oxts.as_os_str(),
        std::ffi::OsStr::new("--out"),
        out.as_os_str(),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(
        text(&o.stderr).contains("41 readings, 4 measurements"),
        "{}",
        text(&o.stderr)
    );
    let toml = std::fs::read_to_string(out.join("dataset.toml")).unwrap();
    assert!(
        toml.contains("heading_deg = 90") && toml.contains("gps_m = 0.3"),
        "{toml}"
    );
    assert!(toml.contains("not a wheel odometer"), "{toml}");
    assert!(text(&o.stderr).contains("note: converted from KITTI"));
    let o = navkf([std::ffi::OsStr::new("inspect"), out.as_os_str()]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    // A period longer than the drive is refused by its option, not by an empty file.
    let o = navkf([
        std::ffi::OsStr::new("convert"),
        std::ffi::OsStr::new("kitti"),
        oxts.as_os_str(),
        std::ffi::OsStr::new("--out"),
        dir.join("too-rare").as_os_str(),
        std::ffi::OsStr::new("--every"),
        std::ffi::OsStr::new("10"),
    ]);
    let err = text(&o.stderr);
    assert!(
        !o.status.success() && err.contains("--every") && err.contains("shorter than the drive"),
        "{err}"
    );
    // Frames without a positive position accuracy: the GPS sigma is the default, and the
    // dataset says so.
    for k in 0..=40 {
        let frame = oxts.join("data").join(format!("{k:010}.txt"));
        let mut v: Vec<String> = std::fs::read_to_string(&frame)
            .unwrap()
            .split_whitespace()
            .map(str::to_string)
            .collect();
        v[23] = "0".into();
        std::fs::write(&frame, v.join(" ")).unwrap();
    }
    let no_accuracy = dir.join("no-accuracy");
    let o = navkf([
        std::ffi::OsStr::new("convert"),
        std::ffi::OsStr::new("kitti"),
        oxts.as_os_str(),
        std::ffi::OsStr::new("--out"),
        no_accuracy.as_os_str(),
    ]);
    let err = text(&o.stderr);
    assert!(
        o.status.success() && err.contains("navkf's default"),
        "{err}"
    );
    let toml = std::fs::read_to_string(no_accuracy.join("dataset.toml")).unwrap();
    assert!(toml.contains("no frame giving a positive posacc"), "{toml}");
}

#[test]
fn a_strapdown_study_in_shards_merges_to_the_single_run() {
    // Before the shard check knew the family's rows, merge refused the strapdown's five.
    let study = include_str!("../../../studies/strapdown.toml")
        .replace("runs = 500", "runs = 20")
        .replace("name = \"strapdown\"", "name = \"sd-shards\"")
        .replace("duration_s = 2400.0", "duration_s = 600.0")
        .replace("leg_north_m = 9000.0", "leg_north_m = 1500.0")
        .replace("leg_east_m = 6500.0", "leg_east_m = 1000.0")
        .replace(
            "initial_standstill_s = 120.0",
            "initial_standstill_s = 30.0",
        );
    let dir = scratch("shards");
    let file = dir.join("sd.toml");
    std::fs::write(&file, study).unwrap();
    let (one, parts, merged) = (dir.join("one"), dir.join("parts"), dir.join("merged"));
    let run = |args: Vec<std::ffi::OsString>| {
        let o = navkf(args);
        assert!(o.status.success(), "{}", text(&o.stderr));
    };
    let os = |s: &str| std::ffi::OsString::from(s);
    run(vec![
        os("study"),
        file.clone().into(),
        os("--quiet"),
        os("--out"),
        one.clone().into(),
    ]);
    for shard in ["0/2", "1/2"] {
        run(vec![
            os("study"),
            file.clone().into(),
            os("--quiet"),
            os("--shard"),
            os(shard),
            os("--out"),
            parts.clone().into(),
        ]);
    }
    let mut merge = vec![os("merge")];
    for p in ["partial-0-of-2.json", "partial-1-of-2.json"] {
        merge.push(parts.join(p).into());
    }
    merge.extend([os("--out"), merged.clone().into()]);
    run(merge);
    let csv = |d: &PathBuf| std::fs::read(d.join("rms_over_time.csv")).unwrap();
    assert_eq!(csv(&one), csv(&merged));
}
