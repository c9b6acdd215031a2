//! A strapdown study (`[model] kind = "strapdown"`, studies/strapdown.toml) through the same
//! Monte Carlo code as the platform's: every filter finishes every run with errors its
//! covariance describes (NEES and NIS inside their 99 % bands), and the settings only the
//! platform reads are refused by key, not ignored.

use crate::common;

use common::run_all;
use navkf_report::stats::{mean_chi2_band, Band};
use navkf_study::summary::summarize;
use navkf_study::{Study, StudyConfig};

const STRAPDOWN: &str = include_str!("../../../studies/strapdown.toml");

/// studies/strapdown.toml on the short test of `common::short_config`.
fn short(runs: usize) -> StudyConfig {
    let mut c = StudyConfig::parse(STRAPDOWN).expect("studies/strapdown.toml parses");
    c.trajectory.duration_s = 600.0;
    c.trajectory.initial_standstill_s = 30.0;
    c.trajectory.leg_north_m = 1500.0;
    c.trajectory.leg_east_m = 1000.0;
    c.study.runs = runs;
    c
}

#[test]
fn every_filter_is_consistent_on_a_mems_strapdown_test() {
    let runs = 60;
    let study = Study::new(short(runs)).unwrap();
    assert_eq!(study.names.len(), 13);
    let summary = summarize(&study, &run_all(&study));
    for (name, f) in &summary.filters {
        assert_eq!(f.runs_ok, runs as u64, "{name}: {:?}", f.diverged_examples);
        let nees = mean_chi2_band(Band::Percent99, 13.0 * runs as f64, runs as f64);
        assert!(
            (nees[0]..=nees[1]).contains(&f.nees_mean),
            "{name}: NEES {} outside {nees:?}",
            f.nees_mean
        );
        // The NIS over ~600 updates a run against the rows present (five moving, four at a
        // standstill): its band is narrow, so a mis-stated sensor (the constraint's sigma met
        // by no error, say, which gave 3.05 for 5) shows.
        assert!(
            f.nis_dof > 4.5 && f.nis_dof < 5.0,
            "{name}: {} rows",
            f.nis_dof
        );
        assert!(
            (f.nis_mean / f.nis_dof - 1.0).abs() < 0.02,
            "{name}: NIS {} for {} rows",
            f.nis_mean,
            f.nis_dof
        );
        // The biases are learned: every gyro bias ends below its prior (50 deg/h).
        for b in ["bgx", "bgy", "bgz"] {
            assert!(
                f.final_rms[b] < 0.5 * 2.42e-4,
                "{name}: {b} {}",
                f.final_rms[b]
            );
        }
    }
}

#[test]
fn what_only_the_platform_reads_is_refused_by_key() {
    let refused = |edit: &dyn Fn(&str) -> String, key: &str| {
        let text = edit(STRAPDOWN);
        let e = StudyConfig::parse(&text).unwrap_err();
        assert!(e.contains(key), "expected `{key}` in: {e}");
    };
    let after = |table: &'static str, line: &'static str| {
        move |t: &str| t.replacen(table, &format!("{table}\n{line}"), 1)
    };
    refused(
        &after("[truth]", "effects = [\"gyro-fz\"]"),
        "truth.effects",
    );
    refused(
        &after("[filter]", "effects = [\"odometer-scale\", \"kod=abc\"]"),
        "filter.effects[1]",
    );
    refused(
        &after("[filter]", "attitude = \"exact\""),
        "filter.attitude",
    );
    refused(&after("[truth]", "rate_hz = 200.0"), "truth.rate_hz");
    refused(&after("[noise]", "gyro_psd = 1e-12"), "noise.gyro_psd");
    refused(
        &after("[truth.initial_tilt]", "alignment = \"gyrocompass\""),
        "truth.initial_tilt.alignment",
    );
    refused(
        &|t: &str| t.replace("unit = \"mems\"", "unit = \"consumer\""),
        "consumer",
    );
    // And the strapdown's keys on a platform study.
    let platform = include_str!("../../../studies/paper.toml");
    let e = StudyConfig::parse(&format!("{platform}\n[model]\nunit = \"mems\"\n")).unwrap_err();
    assert!(e.contains("model.unit"), "{e}");
    let e = StudyConfig::parse(&platform.replace("gps_m = 3.0", "gps_m = 3.0\nnhc_m_s = 0.1"))
        .unwrap_err();
    assert!(e.contains("noise.nhc_m_s"), "{e}");
}
