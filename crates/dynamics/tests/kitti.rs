//! The KITTI raw OXTS converter (`dataset::kitti`) on an excerpt this test writes itself in
//! exactly KITTI's layout (`timestamps.txt`, `data/NNNNNNNNNN.txt` with 30 values a frame):
//! a drive made from a trajectory, so every converted value has a known answer. Real KITTI
//! data carry a licence the repository should not take on.

use crate::dataset_files;

use dataset_files::{assert_mentions, temp_folder, Scratch};
use navkf_dynamics::dataset::kitti::{read_kitti, OXTS_FIELDS};
use navkf_dynamics::dataset::Dataset;
use navkf_dynamics::segments::SegmentSpec;
use navkf_dynamics::strapdown::simulate::ideal_reading;
use navkf_dynamics::{ModelKind, Trajectory, TrajectoryConfig};
use std::path::Path;

const HZ: f64 = 20.0;

fn drive() -> Trajectory {
    Trajectory::build(&TrajectoryConfig {
        duration_s: 90.0,
        segments: vec![
            SegmentSpec::Hold { duration_s: 10.0 },
            SegmentSpec::Speed {
                to: 10.0,
                accel: 1.0,
                climb_m: 0.0,
            },
            SegmentSpec::Turn {
                angle_deg: 90.0,
                rate_deg: 10.0,
                climb_m: 0.0,
            },
            SegmentSpec::Cruise {
                duration_s: Some(20.0),
                distance_m: None,
                climb_m: 0.0,
            },
        ],
        ..TrajectoryConfig::default()
    })
    .unwrap()
}

/// Writes the drive as a KITTI `oxts` folder, the first frame's attitude `first` (roll,
/// pitch, yaw in KITTI's conventions) instead of the path's.
fn write_oxts(traj: &Trajectory, first: Option<[f64; 3]>) -> Scratch {
    let dir = temp_folder("kitti-oxts");
    std::fs::create_dir_all(dir.join("data")).unwrap();
    let frames = (traj.duration() * HZ) as usize;
    let mut stamps = String::new();
    for k in 0..=frames {
        let t = k as f64 / HZ;
        // Across midnight: the converter counts seconds, not clock readings.
        let clock = 86_400.0 - 30.0 + t;
        let (day, s) = if clock >= 86_400.0 {
            (27, clock - 86_400.0)
        } else {
            (26, clock)
        };
        let (h, m, sec) = ((s / 3600.0) as u32, ((s % 3600.0) / 60.0) as u32, s % 60.0);
        stamps += &format!("2011-09-{day} {h:02}:{m:02}:{sec:012.9}\n");
        let st = traj.state(t);
        let r = ideal_reading(&st);
        let yaw = std::f64::consts::FRAC_PI_2 - st.heading;
        let [roll, pitch, yaw] = match (k, first) {
            (0, Some(a)) => a,
            _ => [0.0, 0.0, yaw],
        };
        let mut v = [0.0; 30];
        let set = |v: &mut [f64; 30], name: &str, x: f64| {
            v[OXTS_FIELDS.iter().position(|f| *f == name).unwrap()] = x;
        };
        for (name, x) in [
            ("lat", st.pos[0].to_degrees()),
            ("lon", st.pos[1].to_degrees()),
            ("roll", roll),
            ("pitch", pitch),
            ("yaw", yaw),
            ("vn", st.v[1]),
            ("ve", st.v[0]),
            ("vf", st.speed),
            ("ax", r.f[0]),
            ("ay", r.f[1]),
            ("az", r.f[2]),
            ("wx", r.w[0]),
            ("wy", r.w[1]),
            ("wz", r.w[2]),
            ("posacc", 0.5 + 0.01 * (k % 7) as f64),
            ("navstat", 4.0),
            ("numsats", 9.0),
        ] {
            set(&mut v, name, x);
        }
        let line: Vec<String> = v.iter().map(|x| format!("{x}")).collect();
        std::fs::write(
            dir.join("data").join(format!("{k:010}.txt")),
            line.join(" "),
        )
        .unwrap();
    }
    std::fs::write(dir.join("timestamps.txt"), stamps).unwrap();
    dir
}

#[test]
fn a_kitti_excerpt_becomes_the_strapdown_dataset_of_its_drive() {
    let traj = drive();
    // KITTI's first attitude: left side up 0.1 rad, front down 0.05 rad, yaw 0 (East).
    let dir = write_oxts(&traj, Some([0.1, 0.05, 0.0]));
    let ds = read_kitti(&dir, "drive", 1.0).unwrap();
    assert_eq!(ds.model, ModelKind::Strapdown);
    let a = ds.initial.unwrap();
    assert!(
        (a.roll_deg - 0.1f64.to_degrees()).abs() < 1e-12,
        "left side up is right side down"
    );
    assert!(
        (a.pitch_deg + 0.05f64.to_degrees()).abs() < 1e-12,
        "front down is nose down"
    );
    assert!((a.heading_deg - 90.0).abs() < 1e-12, "yaw 0 is East");
    // Readings: the body axes as they are, times counted across midnight.
    assert_eq!(ds.inputs.len(), (traj.duration() * HZ) as usize + 1);
    for s in ds.inputs.iter().step_by(97) {
        let r = ideal_reading(&traj.state(s.t));
        for i in 0..3 {
            assert!((s.f[i] - r.w[i]).abs() < 1e-9 && (s.f[3 + i] - r.f[i]).abs() < 1e-9);
        }
    }
    // A measurement a second: the forward speed and the fix of the frame at that time.
    assert_eq!(ds.measurements.len(), traj.duration() as usize);
    for m in &ds.measurements {
        assert!((m.t - m.t.round()).abs() < 1e-6, "{}", m.t);
        let st = traj.state(m.t);
        assert!((m.speed.unwrap() - st.speed).abs() < 1e-9);
        let p = m.position_deg.unwrap();
        assert!((p[0] - st.pos[0].to_degrees()).abs() < 1e-9);
    }
    // posacc 0.50-0.56: its median is the GPS sigma.
    assert!((0.5..=0.56).contains(&ds.noise.gps_m), "{}", ds.noise.gps_m);
    // Written as a navkf dataset, it reads back unchanged and looks like clean data.
    let out = temp_folder("kitti-out");
    ds.write(&out).unwrap();
    let back = Dataset::read(&out).unwrap();
    assert_eq!(back.inputs, ds.inputs);
    assert_eq!(back.initial, ds.initial);
    assert_eq!(back.warnings(), vec![]);
    // Without a first attitude of its own, the first frame's yaw gives the path's heading.
    let plain = read_kitti(&write_oxts(&traj, None), "drive", 1.0).unwrap();
    let heading = plain.initial.unwrap().heading_deg;
    assert!(
        (heading - traj.state(0.0).heading.to_degrees()).abs() < 1e-9,
        "{heading}"
    );
}

fn with_frame(dir: &Path, k: usize, text: &str) {
    std::fs::write(dir.join("data").join(format!("{k:010}.txt")), text).unwrap();
}

#[test]
fn a_broken_excerpt_is_refused_where_it_is_broken() {
    let traj = drive();
    let dir = write_oxts(&traj, None);
    with_frame(&dir, 5, "1 2 3");
    let e = read_kitti(&dir, "d", 1.0).unwrap_err().to_string();
    assert_mentions(&e, &["0000000005.txt:1:", "3 values", "expected the 30"]);
    let dir = write_oxts(&traj, None);
    let line: Vec<String> = (0..30)
        .map(|i| if i == 19 { "nan".into() } else { "1".into() })
        .collect();
    with_frame(&dir, 7, &line.join(" "));
    let e = read_kitti(&dir, "d", 1.0).unwrap_err().to_string();
    assert_mentions(&e, &["0000000007.txt:1:", "wz", "not a finite number"]);
    let dir = write_oxts(&traj, None);
    let stamps = std::fs::read_to_string(dir.join("timestamps.txt")).unwrap();
    let mut lines: Vec<&str> = stamps.lines().collect();
    lines.swap(3, 4);
    std::fs::write(dir.join("timestamps.txt"), lines.join("\n")).unwrap();
    let e = read_kitti(&dir, "d", 1.0).unwrap_err().to_string();
    assert_mentions(&e, &["timestamps.txt:5:", "not after line 4"]);
    // A frame is a line of 30 numbers; a file of megabytes is refused unread, not parsed.
    let dir = write_oxts(&traj, None);
    with_frame(&dir, 3, &"1 ".repeat(100_000));
    let e = read_kitti(&dir, "d", 1.0).unwrap_err().to_string();
    assert_mentions(
        &e,
        &[
            "0000000003.txt",
            "expected a KITTI oxts frame",
            "at most 64 KiB",
        ],
    );
    let dir = write_oxts(&traj, None);
    std::fs::remove_file(dir.join("data").join("0000000010.txt")).unwrap();
    let e = read_kitti(&dir, "d", 1.0).unwrap_err().to_string();
    assert_mentions(&e, &["data", "1800 frame files", "1801 stamps"]);
    // A frame beyond the last stamp is not left out unsaid.
    let dir = write_oxts(&traj, None);
    with_frame(&dir, 5000, "1 2 3");
    let e = read_kitti(&dir, "d", 1.0).unwrap_err().to_string();
    assert_mentions(&e, &["1802 frame files", "1801 stamps"]);
}
