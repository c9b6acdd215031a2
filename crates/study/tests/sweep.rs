//! Sweeps: a `[sweep]` expands into one checked study per value, changing only the swept
//! setting; bad keys and values are refused with their name; and the points' summaries
//! measure what the setting does.

mod common;

use common::{run_all, short_config, PAPER};
use navkf_dynamics::Attitude;
use navkf_study::config::SweepSection;
use navkf_study::summary::summarize;
use navkf_study::sweep::{point, points};
use navkf_study::{Study, StudyConfig};

fn with_sweep(key: &str, values: &[f64]) -> StudyConfig {
    let mut c = StudyConfig::parse(PAPER).unwrap();
    c.sweep = Some(SweepSection {
        key: key.into(),
        values: values.to_vec(),
    });
    c
}

#[test]
fn each_point_changes_only_the_swept_setting() {
    let c = with_sweep("truth.initial_tilt.azimuth_rad", &[1e-3, 0.1, 0.5]);
    let p = points(&c).unwrap();
    assert_eq!(p.len(), 3);
    for (pt, v) in p.iter().zip([1e-3, 0.1, 0.5]) {
        assert_eq!(pt.truth.initial_tilt.azimuth_rad, v);
        assert!(pt.sweep.is_none());
        let mut same = pt.clone();
        same.truth.initial_tilt.azimuth_rad = c.truth.initial_tilt.azimuth_rad;
        let mut base = c.clone();
        base.sweep = None;
        assert_eq!(same, base, "only the swept key differs");
    }
    // A key left at its default, an integer key, and a variant's unset setting.
    assert_eq!(
        points(&with_sweep("noise.gps_m", &[1.0, 10.0])).unwrap()[1]
            .noise
            .gps_m,
        10.0
    );
    assert_eq!(
        points(&with_sweep("study.runs", &[7.0])).unwrap()[0]
            .study
            .runs,
        7
    );
    let text = PAPER.replace(
        r#"filters = ["ekf", "standard_ukf", "simplified_ukf"]"#,
        r#"filters = ["ekf", "small_alpha"]"#,
    ) + "\n[filter.variants.small_alpha]\nkind = \"simplified_ukf\"\n\n[sweep]\nkey = \"filter.variants.small_alpha.alpha\"\nvalues = [1e-3, 0.5]\n";
    let c = StudyConfig::parse(&text).unwrap();
    let p = points(&c).unwrap();
    assert_eq!(p[0].filter.plan("small_alpha").unwrap().scaling.alpha, 1e-3);
    assert_eq!(p[1].filter.variants["small_alpha"].alpha, Some(0.5));
}

#[test]
fn bad_sweeps_are_refused_with_their_key() {
    let err = |key: &str, values: &[f64]| points(&with_sweep(key, values)).unwrap_err();
    let e = err("truth.initial_tilt.azimut_rad", &[1.0]);
    assert!(e.contains("azimut_rad"), "{e}");
    let e = err("trajectry.duration_s", &[1.0]);
    assert!(e.contains("no table `trajectry`"), "{e}");
    let e = err("study.runs", &[2.5]);
    assert!(e.contains("not a whole number"), "{e}");
    let e = err("study.name", &[1.0]);
    assert!(e.contains("not a number"), "{e}");
    let e = err("truth.initial_tilt.azimuth_rad", &[]);
    assert!(e.contains("sweep.values is empty"), "{e}");
    let e = err("truth.initial_tilt.azimuth_rad", &[0.1, f64::NAN]);
    assert!(e.contains("sweep.values[1]"), "{e}");
    let e = err("truth.initial_tilt.azimuth_rad", &[0.1, 0.1]);
    assert!(e.contains("listed twice"), "{e}");
    // A value the study itself refuses, with the point's index.
    let e = err("noise.gps_m", &[3.0, -1.0]);
    assert!(
        e.contains("sweep.values[1] = -1") && e.contains("gps_m"),
        "{e}"
    );
    let e = err("sweep.key", &[1.0]);
    assert!(e.contains("dotted path"), "{e}");
    // Through a study file: the [sweep] table is read and checked on parse.
    let text = format!("{PAPER}\n[sweep]\nkey = \"noise.gps\"\nvalues = [1.0]\n");
    let e = StudyConfig::parse(&text).unwrap_err();
    assert!(e.contains("gps"), "{e}");
    let text = format!("{PAPER}\n[sweep]\nkey = \"noise.gps_m\"\nvalue = [1.0]\n");
    assert!(StudyConfig::parse(&text).is_err());
    // A swept study is not one study.
    let c = with_sweep("noise.gps_m", &[1.0, 2.0]);
    assert!(Study::new(c).is_err());
}

#[test]
fn a_larger_initial_azimuth_error_hurts_the_small_angle_filter_on_an_exact_truth() {
    let mut c = short_config(12);
    c.truth.attitude = Attitude::Exact;
    c.study.filters = vec!["ekf".into()];
    c.sweep = Some(SweepSection {
        key: "truth.initial_tilt.azimuth_rad".into(),
        values: vec![3e-4, 0.2],
    });
    let summaries: Vec<_> = points(&c)
        .unwrap()
        .into_iter()
        .enumerate()
        .map(|(i, p)| {
            let v = p.truth.initial_tilt.azimuth_rad;
            let study = Study::new(p).unwrap();
            let tally = run_all(&study);
            let summary = summarize(&study, &tally);
            point(i, v, &study, &tally, &summary)
        })
        .collect();
    let (small, large) = (&summaries[0].filters["ekf"], &summaries[1].filters["ekf"]);
    assert_eq!(summaries[1].value, 0.2);
    assert_eq!(summaries[1].folder, "point-01");
    // At an arcminute the small-angle EKF sits on the bound and is consistent...
    assert!(
        (small.heading_rms / small.heading_bound - 1.0).abs() < 0.3,
        "{small:?}"
    );
    assert!(small.nees_final < small.nees_final_bounds[1], "{small:?}");
    // ...at 11 degrees its linearisation is wrong: far above the bound, or diverged.
    assert!(
        large.diverged > 0 || large.rms_over_bound_mean > 1.5 * small.rms_over_bound_mean,
        "{large:?}"
    );
    assert!(large.nees_final > large.nees_final_bounds[1], "{large:?}");
}
