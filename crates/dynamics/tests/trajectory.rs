//! The vehicle test path: closes on itself, fits its duration, and the error-free model driven
//! by the derived specific force reproduces it.

use navkf_dynamics::earth::{meridian_radius, prime_vertical_radius};
use navkf_dynamics::integrate::InputWindow;
use navkf_dynamics::state::*;
use navkf_dynamics::system::propagate_generic;
use navkf_dynamics::trajectory::Phase;
use navkf_dynamics::{NoiseConfig, PlatformModel, SystemModel, Trajectory, TrajectoryConfig};

fn metres(a: [f64; 2], b: [f64; 2]) -> (f64, f64) {
    let s = a[0].sin();
    (
        (b[0] - a[0]) * meridian_radius(s),
        (b[1] - a[1]) * prime_vertical_radius(s) * a[0].cos(),
    )
}

#[test]
fn default_path_closes_on_itself_and_has_every_phase() {
    let traj = Trajectory::build(&TrajectoryConfig::default()).unwrap();
    let start = traj.state(0.0).pos;
    let end = traj.end_position();
    let (dn, de) = metres(start, end);
    // Catches a wrong leg solve or a position integration that is not the model's own.
    assert!(
        dn.abs() < 1e-6 && de.abs() < 1e-6,
        "closure error {dn} m N, {de} m E"
    );
    // It goes somewhere: the far corner is kilometres away.
    let far = traj.state(traj.duration() * 0.5).pos;
    let (fn_, fe) = metres(start, far);
    assert!(fn_.hypot(fe) > 3000.0);
    let phases: std::collections::HashSet<Phase> =
        traj.segments().iter().map(|s| s.phase()).collect();
    for p in [
        Phase::Standstill,
        Phase::Accelerating,
        Phase::Cruising,
        Phase::Turning,
        Phase::Decelerating,
    ] {
        assert!(phases.contains(&p), "missing phase {p:?}");
    }
    // Ends standing still at O, after 2400 s.
    assert_eq!(traj.duration(), 2400.0);
    assert_eq!(traj.state(2400.0).v, [0.0, 0.0]);
    let last = traj.segments().last().unwrap();
    assert_eq!(last.phase(), Phase::Standstill);
    // Three right turns of 90 degrees: the heading ends West.
    let turns = traj
        .segments()
        .iter()
        .filter(|s| s.phase() == Phase::Turning)
        .count();
    assert_eq!(turns, 3);
}

#[test]
fn path_too_long_for_duration_is_a_config_error() {
    let cfg = TrajectoryConfig {
        duration_s: 600.0,
        ..Default::default()
    };
    let err = Trajectory::build(&cfg).unwrap_err().to_string();
    assert!(err.contains("trajectory.duration_s"), "{err}");
    let cfg = TrajectoryConfig {
        turn_speed: 30.0,
        ..Default::default()
    };
    let err = Trajectory::build(&cfg).unwrap_err().to_string();
    assert!(err.contains("trajectory.turn_speed"), "{err}");
}

#[test]
fn error_free_model_follows_the_path() {
    // With every error zero the model, driven by the derived specific force, must reproduce
    // the path's velocity and position (catches a sign or a Coriolis term in f).
    let traj = Trajectory::build(&TrajectoryConfig::default()).unwrap();
    let model = PlatformModel::base(&NoiseConfig::default());
    let mut x = vec![0.0; model.dim()];
    let s0 = traj.state(0.0);
    x[LAT] = s0.pos[0];
    x[LON] = s0.pos[1];
    let mut scratch = vec![0.0; model.scratch_len(1)];
    let mut w = InputWindow::with_capacity(2);
    let h = 0.05;
    let steps = (traj.duration() / h) as usize;
    let mut worst_v: f64 = 0.0;
    for k in 0..steps {
        let (t0, t1) = (k as f64 * h, (k + 1) as f64 * h);
        w.clear();
        w.push_with_mid(t0, traj.specific_force(t0), [0.0; 3]);
        w.push_with_mid(
            t1,
            traj.specific_force(t1),
            traj.specific_force(0.5 * (t0 + t1)),
        );
        propagate_generic(&model, &mut x, None, &w, &mut scratch);
        let st = traj.state(t1);
        worst_v = worst_v
            .max((x[V_X] - st.v[0]).abs())
            .max((x[V_Y] - st.v[1]).abs());
    }
    let end = traj.end_position();
    let (dn, de) = metres(end, [x[LAT], x[LON]]);
    assert!(
        worst_v < 1e-6,
        "velocity departs from the path by {worst_v} m/s"
    );
    assert!(
        dn.abs() < 1e-3 && de.abs() < 1e-3,
        "ends {dn} m N, {de} m E off the path"
    );
}
