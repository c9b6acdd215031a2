//! The exact-attitude variant and sweeps from the command line: `simulate` and `diagnose`
//! take `--attitude`, a misaligned dataset diagnosed with the small-angle model is warned
//! about, and a study file with a `[sweep]` writes one folder per point plus the summary.

use crate::common;

use common::{navkf, text, Scratch};
use std::path::Path;

fn scratch(name: &str) -> Scratch {
    Scratch::new(&format!("attitude-{name}"))
}

#[test]
fn a_misaligned_dataset_is_consistent_with_the_exact_model_and_warned_about_without_it() {
    let dir = scratch("diagnose");
    let ds = dir.join("misaligned");
    let o = navkf([
        "simulate".as_ref(),
        "--out".as_ref(),
        ds.as_os_str(),
        "--attitude".as_ref(),
        "exact".as_ref(),
        "--azimuth-sigma".as_ref(),
        "0.17".as_ref(),
        "--seed".as_ref(),
        "3".as_ref(),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let diagnose = |attitude: &str, out: &Path| {
        navkf([
            "diagnose".as_ref(),
            ds.as_os_str(),
            "--attitude".as_ref(),
            attitude.as_ref(),
            "--azimuth-sigma".as_ref(),
            "0.17".as_ref(),
            "--out".as_ref(),
            out.as_os_str(),
        ])
    };
    let exact = dir.join("exact");
    let o = diagnose("exact", &exact);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let stdout = text(&o.stdout);
    assert!(stdout.starts_with("verdict: consistent"), "{stdout}");
    assert!(!stdout.contains("--attitude exact"), "{stdout}");
    let report = std::fs::read_to_string(exact.join("report.md")).unwrap();
    assert!(
        report.contains("Attitude equations of every fit: exact."),
        "{report}"
    );
    let json = std::fs::read_to_string(exact.join("diagnosis.json")).unwrap();
    assert!(json.contains("\"attitude\": \"exact\""), "{json}");

    let small = dir.join("small");
    let o = diagnose("small-angle", &small);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let stdout = text(&o.stdout);
    assert!(
        stdout.contains("Diagnose again with `--attitude exact`"),
        "{stdout}"
    );

    let o = diagnose("sideways", &dir.join("none"));
    assert_eq!(o.status.code(), Some(2));
    assert!(text(&o.stderr).contains("sideways"), "{}", text(&o.stderr));
}

#[test]
fn a_sweep_writes_every_point_and_the_summary_and_refuses_more_shards_than_blocks() {
    let dir = scratch("sweep");
    let paper = include_str!("../../../studies/paper.toml");
    let mut text_file = String::new();
    for line in paper.lines() {
        let line = match line.split(" =").next() {
            Some("runs") => "runs = 3".to_string(),
            Some("duration_s") => "duration_s = 600.0".to_string(),
            Some("initial_standstill_s") => "initial_standstill_s = 30.0".to_string(),
            Some("leg_north_m") => "leg_north_m = 1500.0".to_string(),
            Some("leg_east_m") => "leg_east_m = 1000.0".to_string(),
            Some("filters") => r#"filters = ["ekf", "ekf_exact"]"#.to_string(),
            _ => line.to_string(),
        };
        text_file.push_str(&line);
        text_file.push('\n');
    }
    text_file.push_str(
        "\n[filter.variants.ekf_exact]\nkind = \"ekf\"\nattitude = \"exact\"\n\n[sweep]\n\
         key = \"noise.gps_m\"\nvalues = [3.0, 30.0]\n",
    );
    let study = dir.join("sweep.toml");
    std::fs::write(&study, text_file).unwrap();
    let out = dir.join("out");
    let o = navkf([
        "study".as_ref(),
        study.as_os_str(),
        "--out".as_ref(),
        out.as_os_str(),
        "--quiet".as_ref(),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    for f in [
        "point-00/summary.json",
        "point-01/report.md",
        "sweep.json",
        "sweep.md",
    ] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    let md = std::fs::read_to_string(out.join("sweep.md")).unwrap();
    assert!(md.contains("| noise.gps_m | ekf | ekf_exact |"), "{md}");
    assert!(md.contains("| 3e1 |"), "{md}");
    let o = navkf([
        "study".as_ref(),
        study.as_os_str(),
        "--shard".as_ref(),
        "0/2".as_ref(),
        "--out".as_ref(),
        dir.join("shard").as_os_str(),
    ]);
    assert_eq!(o.status.code(), Some(1));
    // 3 runs a point: one block, so one shard at most.
    assert!(
        text(&o.stderr).contains("expected at most one shard per block"),
        "{}",
        text(&o.stderr)
    );
}
