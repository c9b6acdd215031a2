//! Trajectories written as segments: they end where the segments say, grades reach fz and
//! integrate back to level, and a malformed segment is refused with its location.

use navkf_dynamics::earth::{meridian_radius, prime_vertical_radius};
use navkf_dynamics::{DynamicsError, Trajectory, TrajectoryConfig};

fn config(text: &str) -> TrajectoryConfig {
    toml::from_str(text).expect("parses")
}

fn built(text: &str) -> Trajectory {
    Trajectory::build(&config(text)).expect("builds")
}

fn key_of(text: &str) -> String {
    match Trajectory::build(&config(text)) {
        Err(DynamicsError::Config { key, message }) => format!("{key}: {message}"),
        other => panic!("expected a located error, got {:?}", other.map(|_| ())),
    }
}

/// North and East displacement at time `t` from the start, m.
fn built_prefix(traj: &Trajectory, t: f64) -> [f64; 2] {
    let c = traj.config();
    let (lat0, lon0) = (c.start_lat_deg.to_radians(), c.start_lon_deg.to_radians());
    let p = traj.state(t).pos;
    [
        (p[0] - lat0) * meridian_radius(lat0.sin()),
        (p[1] - lon0) * prime_vertical_radius(lat0.sin()) * lat0.cos(),
    ]
}

/// North and East displacement of the end from the start, m.
fn displacement(t: &Trajectory) -> [f64; 2] {
    built_prefix(t, t.duration())
}

#[test]
fn a_test_of_segments_ends_where_the_segments_say() {
    // A figure of eight is two mirrored full turns: what one turn moves East the other moves
    // West, and the heading is North again after it (a turn whose rate rises and falls does
    // not close a circle on its own, so North it moves on). A slalom's pairs of turns keep
    // the heading too.
    let t = built(
        r#"
        duration_s = 400.0
        [[segment]]
        kind = "hold"
        duration_s = 10.0
        [[segment]]
        kind = "speed"
        to = 10.0
        accel = 1.0
        [[segment]]
        kind = "figure_eight"
        rate_deg = 10.0
        [[segment]]
        kind = "cruise"
        distance_m = 300.0
        [[segment]]
        kind = "slalom"
        count = 3
        angle_deg = 20.0
        rate_deg = 10.0
        "#,
    );
    let eight_end = t.segments()[3].start + t.segments()[3].duration;
    let d = displacement(&t);
    let st = t.state(eight_end + 1.0);
    assert!(
        st.v[0].abs() < 1e-9 && (st.v[1] - 10.0).abs() < 1e-9,
        "{:?}",
        st.v
    );
    let before_slalom = t.segments()[4].start + t.segments()[4].duration;
    let mid = built_prefix(&t, before_slalom);
    assert!(
        mid[1].abs() < 1e-3,
        "the figure of eight moved East by {} m",
        mid[1]
    );
    let end = t.state(399.0);
    assert!(
        end.v[0].abs() < 1e-9 && (end.v[1] - 10.0).abs() < 1e-9,
        "{:?}",
        end.v
    );
    assert!(
        d[1] > 0.0,
        "the slalom's right-first turns drift East: {d:?}"
    );
    // After the last segment it keeps cruising until the end of the test.
    assert_eq!(t.segments().last().unwrap().label, "cruise");
    let seg_end = t
        .segments()
        .iter()
        .map(|s| s.start + s.duration)
        .fold(0.0, f64::max);
    assert!((seg_end - 400.0).abs() < 1e-9, "padded to the duration");

    // A plainer one, exact: out 100 m to speed, 1000 m cruise, 100 m to stop.
    let t = built(
        r#"
        duration_s = 300.0
        [[segment]]
        kind = "speed"
        to = 10.0
        accel = 1.0
        [[segment]]
        kind = "cruise"
        distance_m = 1000.0
        [[segment]]
        kind = "speed"
        to = 0.0
        accel = 1.0
        "#,
    );
    let d = displacement(&t);
    assert!((d[0] - 1200.0).abs() < 0.05 && d[1].abs() < 1e-6, "{d:?}");

    // A square of four right turns returns to its start.
    let t = built(
        r#"
        duration_s = 600.0
        [[segment]]
        kind = "speed"
        to = 8.0
        accel = 1.0
        [[segment]]
        kind = "repeat"
        count = 4
        segments = [
          { kind = "cruise", distance_m = 400.0 },
          { kind = "turn", angle_deg = 90.0, rate_deg = 6.0 },
        ]
        [[segment]]
        kind = "speed"
        to = 0.0
        accel = 1.0
        "#,
    );
    let d = displacement(&t);
    // Start-up and stop are 64 m North each; the square itself closes (to centimetres: the
    // path is integrated on the ellipsoid).
    assert!((d[0] - 128.0).abs() < 0.2 && d[1].abs() < 0.2, "{d:?}");
}

#[test]
fn a_grade_reaches_fz_and_levels_out() {
    let t = built(
        r#"
        duration_s = 100.0
        [[segment]]
        kind = "speed"
        to = 10.0
        accel = 1.0
        [[segment]]
        kind = "cruise"
        duration_s = 60.0
        climb_m = 12.0
        "#,
    );
    let cruise = t.segments()[1];
    assert_eq!(cruise.climb, 12.0);
    let g = t.specific_force(5.0)[2];
    // Integrate the upward acceleration twice over the climb: it rises by 12 m and ends level.
    let (mut w, mut h) = (0.0, 0.0);
    let dt = 0.001;
    let n = (cruise.duration / dt) as usize;
    for k in 0..n {
        let tt = cruise.start + (k as f64 + 0.5) * dt;
        let a = t.state(tt).a_up;
        h += w * dt + 0.5 * a * dt * dt;
        w += a * dt;
    }
    assert!(w.abs() < 1e-6, "vertical speed at the end {w}");
    assert!((h - 12.0).abs() < 1e-3, "rise {h}");
    let peak = t.specific_force(cruise.start + cruise.duration / 4.0)[2] - g;
    assert!(peak > 0.0 && (peak - 12.0 * 2.0 * std::f64::consts::PI / 3600.0).abs() < 1e-4);
}

#[test]
fn a_malformed_segment_is_refused_where_it_stands() {
    let cases = [
        ("[[segment]]\nkind = \"turn\"\nangle_deg = 90.0\nrate_deg = 6.0\n", "trajectory.segment[0]: a turn at rest"),
        ("[[segment]]\nkind = \"speed\"\nto = 5.0\naccel = 0.0\n", "trajectory.segment[0].accel"),
        (
            "[[segment]]\nkind = \"speed\"\nto = 5.0\naccel = 1.0\n[[segment]]\nkind = \"hold\"\nduration_s = 5.0\n",
            "trajectory.segment[1]: a hold while moving",
        ),
        (
            "[[segment]]\nkind = \"speed\"\nto = 5.0\naccel = 1.0\n[[segment]]\nkind = \"cruise\"\n",
            "exactly one of duration_s and distance_m",
        ),
        (
            "[[segment]]\nkind = \"speed\"\nto = 5.0\naccel = 1.0\n[[segment]]\nkind = \"repeat\"\ncount = 2\nsegments = [{ kind = \"speed\", to = 5.0, accel = 1.0 }]\n",
            "trajectory.segment[1].segments[0].to",
        ),
        ("duration_s = 10.0\n[[segment]]\nkind = \"hold\"\nduration_s = 20.0\n", "trajectory.duration_s"),
        ("leg_north_m = 5.0\n[[segment]]\nkind = \"hold\"\nduration_s = 20.0\n", "trajectory.leg_north_m"),
    ];
    for (text, needle) in cases {
        let e = key_of(text);
        assert!(e.contains(needle), "{text}\n-> {e}");
    }
    // Unknown kinds and keys are refused by the parser, with their line.
    for text in [
        "[[segment]]\nkind = \"wheelie\"\n",
        "[[segment]]\nkind = \"hold\"\nduration_s = 1.0\naccel = 2.0\n",
        // A road cannot rise under a vehicle standing still.
        "[[segment]]\nkind = \"hold\"\nduration_s = 1.0\nclimb_m = 2.0\n",
    ] {
        let e = toml::from_str::<TrajectoryConfig>(text)
            .unwrap_err()
            .to_string();
        assert!(e.contains("line"), "{e}");
    }
}

#[test]
fn a_test_of_segments_written_back_reads_back_the_same() {
    // A results folder keeps the study file as run: written back, a segment list must come
    // back as the same test, without the O-A-B-C-O settings it would refuse beside it.
    let original = config(
        "duration_s = 900.0\n[[segment]]\nkind = \"hold\"\nduration_s = 30.0\n\
         [[segment]]\nkind = \"repeat\"\ncount = 2\nsegments = [\
         { kind = \"speed\", to = 20.0, accel = 2.0 }, \
         { kind = \"turn\", angle_deg = 180.0, rate_deg = 4.0, climb_m = 3.0 }, \
         { kind = \"speed\", to = 0.0, accel = 2.0 }, { kind = \"hold\", duration_s = 5.0 }]\n",
    );
    let written = toml::to_string(&original).expect("writes");
    assert!(!written.contains("leg_north_m"), "{written}");
    let back = config(&written);
    assert_eq!(back, original);
    Trajectory::build(&back).expect("the file as run builds");
    // The O-A-B-C-O path keeps every one of its settings.
    let paper = TrajectoryConfig::default();
    let written = toml::to_string(&paper).expect("writes");
    assert!(written.contains("leg_north_m"), "{written}");
    assert_eq!(config(&written), paper);
}
