//! The strapdown family from the command line: `simulate --model strapdown` writes a
//! dataset that `inspect` reads, `diagnose` refuses it in words (its diagnosis is the
//! platform's only so far), a strapdown setting without `--model strapdown` is refused, and
//! `plan` and `study` take a strapdown study file.

mod common;

use common::{navkf, text};
use std::path::PathBuf;

fn fresh(tag: &str) -> PathBuf {
    let dir =
        std::env::temp_dir().join(format!("navkf-cli-strapdown-{}-{tag}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

#[test]
fn a_simulated_strapdown_dataset_is_inspected_and_its_diagnosis_refused_in_words() {
    let out = fresh("sim");
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
    let o = navkf([std::ffi::OsStr::new("diagnose"), out.as_os_str()]);
    assert!(!o.status.success());
    let e = text(&o.stderr);
    assert!(
        e.contains("strapdown dataset") && e.contains("platform family only"),
        "{e}"
    );
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn strapdown_settings_are_refused_where_they_mean_nothing() {
    let out = fresh("refused");
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
        text(&o.stderr).contains("no strapdown effect"),
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
    assert!(!out.exists(), "nothing is written when refused");
}
