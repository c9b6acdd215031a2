//! A strapdown dataset folder (`[model] kind = "strapdown"`): `imu.csv` as rates or as
//! increments, `measurements.csv` with the odometer's speed, `[initial]`; written and read back
//! bit for bit, and every refusal naming its file, line and column or key.

use crate::dataset_files;

use dataset_files::*;
use navkf_dynamics::dataset::{Dataset, Doubt};
use navkf_dynamics::strapdown::model::StrapdownModel;
use navkf_dynamics::strapdown::simulate::StrapdownSimulator;
use navkf_dynamics::strapdown::state::STATE_NAMES;
use navkf_dynamics::strapdown::unit_class::UnitClass;
use navkf_dynamics::{ModelKind, NoiseConfig, Trajectory, TrajectoryConfig};
use std::collections::BTreeMap;
use std::sync::Arc;

const CONFIG: &str = "[model]\nkind = \"strapdown\"\n\n[noise]\ngps_m = 3.0\nnhc_m_s = 0.1\n";
const MEASUREMENTS: &str = "t,speed,lat_deg,lon_deg\n0.5,0,45.0,7.0\n1.0,,45.0,7.0\n1.5,0.2,,\n";

fn simulated() -> Dataset {
    simulated_at(10.0)
}

fn simulated_at(imu_hz: f64) -> Dataset {
    let traj = Arc::new(
        Trajectory::build(&TrajectoryConfig {
            duration_s: 500.0,
            initial_standstill_s: 20.0,
            leg_north_m: 800.0,
            leg_east_m: 500.0,
            ..TrajectoryConfig::default()
        })
        .unwrap(),
    );
    let unit = UnitClass::Mems.errors();
    let noise = unit.noise(NoiseConfig {
        nhc_m_s: Some(0.1),
        ..NoiseConfig::default()
    });
    let model = Arc::new(StrapdownModel::base(&noise));
    let sim =
        StrapdownSimulator::new(model, traj, imu_hz, 1.0, unit, &BTreeMap::new(), noise).unwrap();
    let run = sim.run(5, 2);
    sim.dataset("drive", 5, &run, 5e-3, 0.035)
}

#[test]
fn a_simulated_strapdown_dataset_is_read_back_bit_for_bit() {
    let ds = simulated();
    let dir = temp_folder("sd-roundtrip");
    ds.write(&dir).unwrap();
    for file in ["imu.csv", "measurements.csv", "dataset.toml", "truth.csv"] {
        assert!(dir.join(file).is_file(), "{file}");
    }
    assert!(!dir.join("inputs.csv").exists());
    let text = std::fs::read_to_string(dir.join("dataset.toml")).unwrap();
    assert!(text.starts_with("[model]\nkind = \"strapdown\""), "{text}");
    assert!(text.contains("heading_rad = 0.035") && text.contains("nhc_m_s = 0.1"));
    let back = Dataset::read(&dir).unwrap();
    assert_eq!(back.model, ModelKind::Strapdown);
    assert_eq!(
        back,
        Dataset {
            name: back.name.clone(),
            ..ds.clone()
        }
    );
    assert_eq!(bits_of(&back), bits_of(&ds));
    // The odometer reads exactly zero at the standstill, its speed elsewhere; the heading
    // stated is the true one off by the alignment's draw.
    assert_eq!(back.measurements[0].speed, Some(0.0));
    assert!(back.measurements.iter().any(|m| m.speed.unwrap() > 10.0));
    let a = back.initial.unwrap();
    let true_heading = back.truth.as_ref().unwrap().states[0][2].to_degrees();
    assert!(a.heading_deg != true_heading && (a.heading_deg - true_heading).abs() < 10.0);
}

#[test]
fn increments_are_read_as_mean_rates_at_the_middle_of_their_interval() {
    // A rate ramp w_x = 0.1 t sampled as increments every 0.5 s: the mean over (t - 0.5, t]
    // is the value at t - 0.25, exactly, for a linear signal.
    let mut imu = String::from("t,dtheta_x,dtheta_y,dtheta_z,dv_x,dv_y,dv_z\n");
    for k in 0..=4 {
        let t = 0.5 * k as f64;
        let (a, b) = (t - 0.5, t);
        let dtheta = 0.05 * (b * b - a * a);
        imu += &format!("{t},{dtheta},0,0,0.5,0,4.9\n");
    }
    let dir = folder(
        "sd-increments",
        &[
            ("imu.csv", &imu),
            ("dataset.toml", CONFIG),
            (
                "measurements.csv",
                "t,speed,lat_deg,lon_deg\n0.5,0,45.0,7.0\n1.5,0.2,,\n",
            ),
        ],
    );
    let ds = Dataset::read(&dir).unwrap();
    // The first row marks the start: four readings from five rows.
    assert_eq!(ds.inputs.len(), 4);
    for (s, t_mid) in ds.inputs.iter().zip([0.25, 0.75, 1.25, 1.75]) {
        assert!((s.t - t_mid).abs() < 1e-15, "{}", s.t);
        assert!((s.f[0] - 0.1 * t_mid).abs() < 1e-12, "{:?}", s.f);
        assert_eq!([s.f[3], s.f[5]], [1.0, 9.8]);
    }
    // Empty speed and empty GPS cells: no reading, not zero.
    let m = &ds.measurements;
    assert_eq!((m[0].speed, m[1].speed), (Some(0.0), Some(0.2)));
    assert!(m[1].position_deg.is_none());
}

#[test]
fn bad_strapdown_files_are_refused_where_they_are_wrong() {
    let imu = "t,w_x,w_y,w_z,f_x,f_y,f_z\n0,0,0,0,0,0,9.8\n0.5,0,0,0,0,0,9.8\n1,0,0,0,0,0,9.8\n1.5,0,0,0,0,0,9.8\n";
    type Case<'a> = (&'a str, Vec<(&'a str, String)>, &'a [&'a str]);
    let cases: [Case; 10] = [
        (
            "empty-imu-cell",
            vec![(
                "imu.csv",
                imu.replace("0.5,0,0,0,0,0,9.8", "0.5,0,,0,0,0,9.8"),
            )],
            &["imu.csv:3:", "w_y", "one whole reading"],
        ),
        (
            "platform-header",
            vec![(
                "imu.csv",
                imu.replace("t,w_x,w_y,w_z,f_x,f_y,f_z", "t,f_e,f_n,f_u"),
            )],
            &["imu.csv:1:", "w_x"],
        ),
        (
            "platform-measurements",
            vec![(
                "measurements.csv",
                "t,v_e,v_n,lat_deg,lon_deg\n0.5,0,0,45,7\n".to_string(),
            )],
            &["measurements.csv:1:", "speed"],
        ),
        (
            "pitch-90",
            vec![(
                "dataset.toml",
                format!("{CONFIG}\n[initial]\nroll_deg = 0\npitch_deg = 90\nheading_deg = 10\n"),
            )],
            &["dataset.toml:10:", "initial.pitch_deg", "singular"],
        ),
        ("no-imu", vec![("imu.csv", String::new())], &["imu.csv"]),
        (
            // A unit's clock that restarts mid-file.
            "clock-restarts",
            vec![(
                "imu.csv",
                imu.replace("1.5,0,0,0,0,0,9.8", "0,0,0,0,0,0,9.8"),
            )],
            &[
                "imu.csv:5:",
                "column `t`",
                "t = 0 is not after t = 1 on line 4",
                "goes back by 1 s",
                "restarted",
            ],
        ),
        (
            // The family's own key, on its own line (the platform's word was named).
            "heading-prior-zero",
            vec![(
                "dataset.toml",
                format!("{CONFIG}\n[prior]\nheading_rad = 0\n"),
            )],
            &["dataset.toml:9:", "prior.heading_rad", "finite and > 0"],
        ),
        (
            // The platform's word, which a strapdown file may use too: named as written.
            "azimuth-prior-zero",
            vec![(
                "dataset.toml",
                format!("{CONFIG}\n[prior]\nazimuth_rad = 0\n"),
            )],
            &["dataset.toml:9:", "prior.azimuth_rad", "finite and > 0"],
        ),
        (
            "truth-outside-imu",
            vec![(
                "truth.csv",
                format!(
                    "t,{}\n7,{}\n",
                    STATE_NAMES[..7].join(","),
                    ["0"; 7].join(",")
                ),
            )],
            &["truth.csv:2:", "outside the span of imu.csv"],
        ),
        (
            "platform-initial",
            vec![(
                "dataset.toml",
                "[initial]\nroll_deg = 0\npitch_deg = 0\nheading_deg = 10\n".to_string(),
            )],
            &["dataset.toml", "[initial]", "strapdown"],
        ),
    ];
    for (tag, replace, expect) in cases {
        let mut files: Vec<(&str, String)> = vec![
            ("imu.csv", imu.to_string()),
            ("measurements.csv", MEASUREMENTS.to_string()),
            ("dataset.toml", CONFIG.to_string()),
        ];
        for (name, text) in replace {
            files.retain(|(n, _)| *n != name);
            files.push((name, text));
        }
        if tag == "platform-initial" {
            // A platform dataset: inputs.csv and the platform's measurements.
            files = vec![
                ("inputs.csv", inputs_text(20)),
                (
                    "measurements.csv",
                    "t,v_e,v_n,lat_deg,lon_deg\n0.5,0,0,45,7\n".to_string(),
                ),
                files.pop().unwrap(),
            ];
        }
        let borrowed: Vec<(&str, &str)> = files.iter().map(|(n, t)| (*n, t.as_str())).collect();
        let e = read_error(tag, &borrowed);
        assert_mentions(&e, expect);
    }
}

/// The implausibility checks read a strapdown dataset's own files and columns: its
/// odometer's `speed` (in mm/s went unseen when only an East-North velocity was read), and
/// `imu.csv` for a gap or a unit off the ground (named `inputs.csv` and `f_e,f_n,f_u`).
#[test]
fn implausible_strapdown_data_are_named_in_the_strapdown_files() {
    use navkf_dynamics::dataset::Implausibility;
    let clean = simulated();
    let mut mm = clean.clone();
    mm.measurements
        .iter_mut()
        .filter_map(|m| m.speed.as_mut())
        .for_each(|v| *v *= 1000.0);
    let found = mm.implausibilities();
    assert!(
        matches!(found[..], [Implausibility::OdometerTooFast { .. }]),
        "{found:?}"
    );
    let text = found[0].to_string();
    assert!(
        text.starts_with("measurements.csv: column `speed`"),
        "{text}"
    );
    let mut gap = clean.clone();
    gap.inputs.retain(|i| !(100.0..=110.0).contains(&i.t));
    let mut falling = clean.clone();
    falling
        .inputs
        .iter_mut()
        .filter(|i| (100.0..=110.0).contains(&i.t))
        .for_each(|i| i.f[3..].fill(0.0));
    for (ds, start) in [
        (gap, "imu.csv: column"),
        (falling, "imu.csv: columns `f_x,f_y,f_z`"),
    ] {
        let found = ds.implausibilities();
        assert_eq!(found.len(), 1, "{found:?}");
        let text = found[0].to_string();
        assert!(text.starts_with(start), "{text}");
    }
}

/// A GPS jump is held against the strapdown odometer's own speed, not against the fastest
/// road vehicle's: 250 m in one second is caught on this drive, under 20 m/s (it passed as a
/// vehicle at 150 m/s, with "no odometer", when only an East-North velocity was read).
#[test]
fn a_gps_jump_is_held_against_the_strapdown_odometers_speed() {
    use navkf_dynamics::dataset::Implausibility;
    let clean = simulated();
    let mut jumped = clean.clone();
    let north_250_m = 250.0 / 111_000.0;
    jumped
        .measurements
        .iter_mut()
        .filter(|m| m.t >= 300.0)
        .filter_map(|m| m.position_deg.as_mut())
        .for_each(|p| p[0] += north_250_m);
    let found = jumped.implausibilities();
    let [Implausibility::PositionJump {
        speed_m_s: Some(speed),
        from_s,
        count: 1,
        ..
    }] = found[..]
    else {
        panic!("{found:?}");
    };
    assert!(speed < 20.0, "{speed}");
    assert!((298.0..300.0).contains(&from_s), "{from_s}");
    assert!(
        !found[0].to_string().contains("no odometer"),
        "{}",
        found[0]
    );
}

#[test]
fn readings_in_the_wrong_unit_axes_or_form_are_warned_of_and_clean_ones_are_not() {
    let clean = simulated();
    assert_eq!(clean.warnings(), vec![]);
    assert_eq!(clean.implausibilities(), vec![]);
    let s = clean.summary();
    assert!(s.speed.unwrap().max > 10.0, "{s}");
    assert!(s.turn.max_turn_rate_deg_s.unwrap() > 3.0, "{s}");
    // The unit's own axes, not the navigation frame's: horizontal only while it is level.
    assert!(
        s.to_string()
            .contains("specific force in the unit's x-y plane max"),
        "{s}"
    );
    let with = |edit: &dyn Fn(&mut [f64; 6]), ds: &Dataset| {
        let mut ds = ds.clone();
        for i in &mut ds.inputs {
            edit(&mut i.f);
        }
        ds.warnings().iter().map(|w| w.doubt).collect::<Vec<_>>()
    };
    let in_g = |f: &mut [f64; 6]| {
        f[3..]
            .iter_mut()
            .for_each(|v| *v /= navkf_dynamics::earth::STANDARD_GRAVITY)
    };
    assert_eq!(with(&in_g, &clean), [Doubt::SpecificForceNotGravity]);
    let in_degrees = |f: &mut [f64; 6]| f[..3].iter_mut().for_each(|v| *v = v.to_degrees());
    assert_eq!(with(&in_degrees, &clean), [Doubt::RatesInDegrees]);
    let upside_down = |f: &mut [f64; 6]| {
        for k in [1, 2, 4, 5] {
            f[k] = -f[k];
        }
    };
    assert_eq!(with(&upside_down, &clean), [Doubt::UpsideDown]);
    // The odometer speed in km/h or mph is warned of; 5 % off (a scale error) is not.
    for (scale, unit) in [
        (3.6, Some("km/h")),
        (1.0 / 0.447_04, Some("mph")),
        (1.05, None),
    ] {
        let mut ds = clean.clone();
        for m in &mut ds.measurements {
            if let Some(v) = m.speed.as_mut() {
                *v *= scale;
            }
        }
        let w = ds.warnings();
        match unit {
            Some(unit) => {
                assert_eq!(w.len(), 1, "{w:?}");
                assert_eq!(w[0].doubt, Doubt::OdometerNotMetresPerSecond);
                let text = w[0].to_string();
                assert!(
                    text.starts_with("measurements.csv: column `speed`"),
                    "{text}"
                );
                assert!(text.contains(unit), "{text}");
            }
            None => assert_eq!(w, vec![]),
        }
    }
    // Increments under the rates' header, at 100 Hz: a hundredth of the readings.
    let fast = simulated_at(100.0);
    assert_eq!(fast.warnings(), vec![]);
    let increments = |f: &mut [f64; 6]| f.iter_mut().for_each(|v| *v *= 0.01);
    assert_eq!(with(&increments, &fast), [Doubt::IncrementsReadAsRates]);
    let w = &{
        let mut ds = fast.clone();
        ds.inputs.iter_mut().for_each(|i| increments(&mut i.f));
        ds
    }
    .warnings()[0];
    assert!(
        w.to_string().starts_with("imu.csv: column `f_x,f_y,f_z`"),
        "{w}"
    );
    assert!(w.message.contains("t,dtheta_x"), "{w}");
}

/// A MEMS drive of `segments`, seed `seed`, as a dataset without `[initial]`.
fn unaligned(segments: Vec<navkf_dynamics::segments::SegmentSpec>, seed: u64) -> Dataset {
    unaligned_with(segments, seed, UnitClass::Mems, 3.0)
}

/// [`unaligned`] for a unit of `class`, stating its levelling accuracy (bias over g), with a
/// GPS of `gps_m`.
fn unaligned_with(
    segments: Vec<navkf_dynamics::segments::SegmentSpec>,
    seed: u64,
    class: UnitClass,
    gps_m: f64,
) -> Dataset {
    let traj = Arc::new(
        Trajectory::build(&TrajectoryConfig {
            duration_s: 200.0,
            segments,
            ..TrajectoryConfig::default()
        })
        .unwrap(),
    );
    let unit = class.errors();
    let noise = unit.noise(NoiseConfig {
        gps_m,
        ..NoiseConfig::default()
    });
    let sim = StrapdownSimulator::new(
        Arc::new(StrapdownModel::base(&noise)),
        traj,
        50.0,
        1.0,
        unit,
        &BTreeMap::new(),
        noise,
    )
    .unwrap();
    let level = unit.accel_bias / navkf_dynamics::earth::STANDARD_GRAVITY;
    let mut ds = sim.dataset("drive", seed, &sim.run(seed, 0), level, 0.035);
    ds.initial = None;
    ds
}

#[test]
fn the_data_align_drawn_units_on_drawn_drives_within_their_sigmas() {
    use navkf_dynamics::segments::SegmentSpec::*;
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(20261125);
    let (mut level2, mut heading2, mut worst) = (0.0, 0.0, 0.0f64);
    let runs = 40;
    for seed in 0..runs {
        let class = UnitClass::ALL[rng.gen_range(0..3)];
        let speed = rng.gen_range(3.0..20.0);
        let drive = vec![
            Hold {
                duration_s: rng.gen_range(10.0..60.0),
            },
            Speed {
                to: speed,
                accel: 1.0,
                climb_m: 0.0,
            },
            Turn {
                angle_deg: rng.gen_range(-150.0..150.0),
                rate_deg: 8.0,
                climb_m: 0.0,
            },
            Cruise {
                duration_s: Some(60.0),
                distance_m: None,
                climb_m: 0.0,
            },
        ];
        let ds = unaligned_with(drive, seed, class, rng.gen_range(0.5..8.0));
        let a = ds.align_from_data().unwrap();
        let truth = &ds.truth.as_ref().unwrap().states[0];
        let e = [
            (a.attitude.roll_deg.to_radians() - truth[0]) / a.level_sigma,
            (a.attitude.pitch_deg.to_radians() - truth[1]) / a.level_sigma,
            (a.attitude.heading_deg.to_radians() - truth[2]) / a.heading_sigma,
        ];
        level2 += e[0] * e[0] + e[1] * e[1];
        heading2 += e[2] * e[2];
        worst = worst.max(e[2].abs());
    }
    let n = runs as f64;
    assert!(
        (53.5..112.3).contains(&level2),
        "level chi-square {level2} of {}",
        2.0 * n
    );
    let rms = (heading2 / n).sqrt();
    assert!(
        (0.2..1.2).contains(&rms) && worst < 4.0,
        "heading RMS {rms} sigma, worst {worst}"
    );
}

#[test]
fn the_data_align_the_unit_within_the_sigmas_they_state() {
    use navkf_dynamics::segments::SegmentSpec::*;
    // Moving off, turning 37 deg to the right at once, then straight: the heading at the
    // first reading is the track's bearing less what the gyro turned before it.
    let drive = || {
        vec![
            Hold { duration_s: 30.0 },
            Speed {
                to: 5.0,
                accel: 1.0,
                climb_m: 0.0,
            },
            Turn {
                angle_deg: 37.0,
                rate_deg: 8.0,
                climb_m: 0.0,
            },
            Speed {
                to: 12.0,
                accel: 1.0,
                climb_m: 0.0,
            },
            Cruise {
                duration_s: Some(100.0),
                distance_m: None,
                climb_m: 0.0,
            },
        ]
    };
    let (mut level2, mut heading2, mut worst) = (0.0, 0.0, 0.0f64);
    let runs = 40;
    for seed in 0..runs {
        let ds = unaligned(drive(), seed);
        let a = ds.align_from_data().unwrap();
        let truth = &ds.truth.as_ref().unwrap().states[0];
        let e = [
            (a.attitude.roll_deg.to_radians() - truth[0]) / a.level_sigma,
            (a.attitude.pitch_deg.to_radians() - truth[1]) / a.level_sigma,
            (a.attitude.heading_deg.to_radians() - truth[2]) / a.heading_sigma,
        ];
        level2 += e[0] * e[0] + e[1] * e[1];
        heading2 += e[2] * e[2];
        worst = worst.max(e[2].abs());
        assert_eq!(
            a.level_from[1], 30.0,
            "the standstill ends where the odometer moves"
        );
        assert!(a.heading_from[0] > 30.0);
    }
    // The level's error is the accelerometer bias over g: chi-square with 80 dof (99 %:
    // 53.5-112.3). The heading's sigma bounds its error (GPS chord and gyro bias), RMS
    // within it and no error beyond 4 of it.
    let n = runs as f64;
    assert!(
        (53.5..112.3).contains(&level2),
        "level chi-square {level2} of {}",
        2.0 * n
    );
    let rms = (heading2 / n).sqrt();
    assert!(
        (0.2..1.2).contains(&rms) && worst < 4.0,
        "heading RMS {rms} sigma, worst {worst}"
    );
}

/// The level comes from the readings of the odometer's standstill, not from every reading
/// before it moves: readings before the odometer's first (a unit carried to the car, 20 s
/// tilted by 0.3 rad) leave the level as it was; the heading, carried back to the first
/// reading, is another by what the gyro turned in between (nothing here).
#[test]
fn readings_before_the_odometer_starts_are_not_taken_for_a_standstill() {
    use navkf_dynamics::segments::SegmentSpec::*;
    let drive = vec![
        Hold { duration_s: 30.0 },
        Speed {
            to: 8.0,
            accel: 1.0,
            climb_m: 0.0,
        },
        Cruise {
            duration_s: Some(100.0),
            distance_m: None,
            climb_m: 0.0,
        },
    ];
    let ds = unaligned(drive, 3);
    let still = ds.align_from_data().unwrap();
    let first_odometer = ds
        .measurements
        .iter()
        .find(|m| m.speed.is_some())
        .unwrap()
        .t;
    assert_eq!(still.level_from, [first_odometer, 30.0]);
    let mut carried = ds.clone();
    let t0 = ds.inputs[0].t;
    let g = navkf_dynamics::earth::STANDARD_GRAVITY;
    let before: Vec<_> = (1..=1000)
        .rev()
        .map(|k| {
            let mut s = ds.inputs[0];
            s.t = t0 - 0.02 * k as f64;
            s.f = [0.0, 0.0, 0.0, 0.0, g * 0.3f64.sin(), g * 0.3f64.cos()];
            s
        })
        .collect();
    carried.inputs.splice(0..0, before);
    let a = carried.align_from_data().unwrap();
    assert_eq!(
        (a.attitude.roll_deg, a.attitude.pitch_deg, a.level_from),
        (
            still.attitude.roll_deg,
            still.attitude.pitch_deg,
            still.level_from
        )
    );
    // No reading inside the standstill: no level (not a NaN one).
    let mut gap = ds.clone();
    gap.inputs
        .retain(|i| !(first_odometer..=30.0).contains(&i.t));
    let e = gap.align_from_data().unwrap_err();
    assert!(e.to_string().contains("no standstill"), "{e}");
}

#[test]
fn without_a_standstill_or_a_straight_track_the_alignment_says_what_is_missing() {
    use navkf_dynamics::segments::SegmentSpec::*;
    let moving_at_once = unaligned(
        vec![
            Hold { duration_s: 2.0 },
            Speed {
                to: 10.0,
                accel: 1.0,
                climb_m: 0.0,
            },
            Cruise {
                duration_s: Some(150.0),
                distance_m: None,
                climb_m: 0.0,
            },
        ],
        1,
    );
    let e = moving_at_once.align_from_data().unwrap_err();
    assert!(e.to_string().contains("no standstill"), "{e}");
    let only_turning = unaligned(
        vec![
            Hold { duration_s: 20.0 },
            Speed {
                to: 3.0,
                accel: 1.0,
                climb_m: 0.0,
            },
            Repeat {
                count: 9,
                segments: vec![Turn {
                    angle_deg: 90.0,
                    rate_deg: 10.0,
                    climb_m: 0.0,
                }],
            },
        ],
        1,
    );
    let e = only_turning.align_from_data().unwrap_err();
    assert!(e.to_string().contains("no straight GPS track"), "{e}");
}
