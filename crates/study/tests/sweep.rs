//! Sweeps: a `[sweep]` expands into one checked study per value, changing only the swept
//! setting; bad keys and values are refused with their name; and the points' summaries
//! measure what the setting does.

use crate::common;

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
fn a_setting_inside_a_list_is_swept_by_its_index() {
    // A trajectory of segments: the speed of the second segment, and a cruise's duration
    // inside a repeat, indexed as the located errors write them.
    let text = "[study]\nname = \"laps\"\nruns = 2\nseed = 1\nfilters = [\"ekf\"]\n\
        [trajectory]\nduration_s = 600.0\n\
        [[trajectory.segment]]\nkind = \"hold\"\nduration_s = 10.0\n\
        [[trajectory.segment]]\nkind = \"speed\"\nto = 10.0\naccel = 2.0\n\
        [[trajectory.segment]]\nkind = \"repeat\"\ncount = 2\nsegments = [\
        { kind = \"cruise\", duration_s = 60.0 }, \
        { kind = \"turn\", angle_deg = 180.0, rate_deg = 6.0 }]\n";
    let sweep = |key: &str, values: &str| {
        StudyConfig::parse(&format!(
            "{text}[sweep]\nkey = \"{key}\"\nvalues = {values}\n"
        ))
        .and_then(|c| points(&c))
    };
    let speed = |c: &StudyConfig| match &c.trajectory.segments[1] {
        navkf_dynamics::segments::SegmentSpec::Speed { to, .. } => *to,
        other => panic!("{other:?}"),
    };
    let p = sweep("trajectory.segment[1].to", "[5.0, 20.0]").unwrap();
    assert_eq!(p.iter().map(speed).collect::<Vec<_>>(), [5.0, 20.0]);
    let mut same = p[1].clone();
    same.trajectory.segments[1] = p[0].trajectory.segments[1].clone();
    assert_eq!(same, p[0], "only the swept segment differs");
    let p = sweep("trajectory.segment[2].segments[0].duration_s", "[30.0]").unwrap();
    let navkf_dynamics::segments::SegmentSpec::Repeat { segments, .. } =
        &p[0].trajectory.segments[2]
    else {
        panic!("a repeat")
    };
    assert!(matches!(
        segments[0],
        navkf_dynamics::segments::SegmentSpec::Cruise { duration_s: Some(d), .. } if d == 30.0
    ));
    // An integer inside a list stays an integer.
    assert!(sweep("trajectory.segment[2].count", "[3.0]").is_ok());
    assert!(sweep("trajectory.segment[2].count", "[2.5]")
        .unwrap_err()
        .contains("not a whole number"));
    // Out of range, not a list, a malformed index, and a value the segment refuses.
    for (key, needle) in [
        ("trajectory.segment[7].to", "has 3 entries, not 8"),
        ("trajectory.duration_s[0]", "is not a list"),
        ("trajectory.segment[x].to", "expected an index"),
        ("trajectory.segment[1.to", "expected an index in brackets"),
        ("trajectory.segment[1].accel", "trajectory.segment[1].accel"),
    ] {
        let values = if key.ends_with("accel") {
            "[-1.0]"
        } else {
            "[1.0]"
        };
        let e = sweep(key, values).unwrap_err();
        assert!(e.contains(needle), "{key}: {e}");
    }
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
