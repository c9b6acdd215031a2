//! Files that are not what the CLI was told they are: a device or a FIFO where a file is
//! named, a study file too large to be one, a CSV header or a TOML line of megabytes. Each is
//! refused without being read whole, naming the file.

use crate::common;

use common::study_files::{refused_at_once, scratch, study_file};
use common::{navkf, text};
use std::path::Path;
use std::time::{Duration, Instant};

#[test]
fn a_device_is_refused_unread_wherever_a_file_is_named() {
    // /dev/zero never ends: read whole, it took memory until the kernel killed navkf.
    let dir = scratch("device");
    let study = study_file(&dir, "s.toml", &[]);
    let zero = Path::new("/dev/zero");
    let out = dir.join("out");
    let cases: [(&str, Vec<&Path>); 4] = [
        ("a study file", vec![Path::new("study"), zero]),
        (
            "a study's summary.json",
            vec![
                Path::new("study"),
                &study,
                Path::new("--baseline"),
                zero,
                Path::new("--out"),
                &out,
                Path::new("--quiet"),
            ],
        ),
        ("a shard file", vec![Path::new("merge"), zero]),
        (
            "a TOML file with a [trajectory] table",
            vec![
                Path::new("simulate"),
                Path::new("--out"),
                &out,
                Path::new("--trajectory"),
                zero,
            ],
        ),
    ];
    for (expected, args) in cases {
        let t = Instant::now();
        let o = navkf(args);
        refused_at_once(&o, t.elapsed(), "/dev/zero: not a regular file");
        let err = text(&o.stderr);
        assert!(err.contains(&format!("expected {expected}")), "{err}");
    }
    assert!(!out.exists(), "nothing written");
}

#[cfg(unix)]
#[test]
fn a_fifo_study_file_is_refused_without_blocking() {
    // Opening a FIFO for reading blocks until a writer comes: the file must be looked at
    // before it is opened.
    let dir = scratch("fifo");
    let fifo = dir.join("study.toml");
    let made = std::process::Command::new("mkfifo").arg(&fifo).status();
    if !made.is_ok_and(|s| s.success()) {
        return; // no mkfifo here: nothing to show
    }
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_navkf"))
        .args([Path::new("study"), &fifo, Path::new("--quiet")])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let t = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if t.elapsed() > Duration::from_secs(10) {
            let _ = child.kill();
            let _ = child.wait();
            panic!("navkf study on a FIFO still runs after 10 s: it blocks");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let mut err = String::new();
    std::io::Read::read_to_string(&mut child.stderr.take().unwrap(), &mut err).unwrap();
    assert_eq!(status.code(), Some(1), "{err}");
    assert!(err.contains("not a regular file (a FIFO"), "{err}");
    assert!(err.contains("expected a study file (TOML)"), "{err}");
}

#[test]
fn an_oversized_study_file_is_refused_by_its_size() {
    let dir = scratch("oversized");
    let study = dir.join("big.toml");
    let file = std::fs::File::create(&study).unwrap();
    if file.set_len(300 << 20).is_err() {
        return; // a file system without sparse files
    }
    drop(file);
    let t = Instant::now();
    let o = navkf([Path::new("study"), &study, Path::new("--quiet")]);
    refused_at_once(&o, t.elapsed(), "big.toml: 314.573 MB");
    assert!(
        text(&o.stderr).contains("at most 16 MiB"),
        "{}",
        text(&o.stderr)
    );
}

#[test]
fn a_giant_csv_header_is_refused_with_its_line_before_it_is_read_whole() {
    // A 20 MB header. Before the line limit, a 100 MB one took 6.7 GB; now navkf stops
    // after 64 KiB of it (peak RSS measured by hand: about 4.5 MB).
    let dir = scratch("header");
    let header = format!("t,{}\n0,0,0,9.8\n0.1,0,0,9.8\n", "f".repeat(20 << 20));
    std::fs::write(dir.join("inputs.csv"), header).unwrap();
    std::fs::write(
        dir.join("measurements.csv"),
        "t,v_e,v_n,lat_deg,lon_deg\n0.1,0.5,0.1,45.78,126.63\n",
    )
    .unwrap();
    let t = Instant::now();
    let o = navkf([Path::new("inspect"), &dir]);
    refused_at_once(&o, t.elapsed(), "inputs.csv:1:");
    let err = text(&o.stderr);
    assert!(err.contains("line longer than 64 KiB"), "{err}");
    assert!(err.len() < 1000, "{} bytes of stderr", err.len());
}

#[test]
fn a_toml_error_on_a_megabyte_line_prints_a_short_cut_of_it() {
    // The toml crate's message quotes the whole line: a 50 MB line printed 100 MB.
    let dir = scratch("long-line");
    let mut text_of_study = include_str!("../../../studies/paper.toml").to_owned();
    let lines = text_of_study.lines().count();
    text_of_study += &format!(
        "x = \"{}\" \" {}\n",
        "a".repeat(1 << 19),
        "b".repeat(1 << 19)
    );
    let study = dir.join("long.toml");
    std::fs::write(&study, text_of_study).unwrap();
    let t = Instant::now();
    let o = navkf([Path::new("study"), &study, Path::new("--quiet")]);
    let at = format!(
        "long.toml:{}:{}: TOML parse error",
        lines + 1,
        (1 << 19) + 8
    );
    refused_at_once(&o, t.elapsed(), &at);
    let err = text(&o.stderr);
    assert!(err.len() < 2048, "{} bytes of stderr", err.len());
    assert!(
        err.contains("aaa\" \" bbb"),
        "the cut shows the column: {err}"
    );
}
