//! Plausibility: data that parse but are written in the wrong unit are warned about, with the
//! file and column, and good data of many shapes are not; a track across the antimeridian
//! reads as one continuous track; inputs slower than the measurements are refused.

use crate::common;
use crate::common::scratch;

use common::datasets::{self, short};
use navkf_dynamics::dataset::{Dataset, Doubt};
use navkf_dynamics::{NoiseConfig, Trajectory, TrajectoryConfig};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use scratch::Scratch;

/// A simulated dataset; `effects` as `simulate --effects` takes them (`name=value`).
fn simulated(effects: &str, trajectory: TrajectoryConfig, seed: u64) -> Dataset {
    datasets::simulated(
        "plausible",
        effects,
        &trajectory,
        NoiseConfig::default(),
        seed,
    )
}

fn doubts(ds: &Dataset) -> Vec<Doubt> {
    ds.warnings().iter().map(|w| w.doubt).collect()
}

fn temp(tag: &str) -> Scratch {
    Scratch::new(&format!("plausible-{tag}"))
}

#[test]
fn good_data_of_many_shapes_raise_no_warning() {
    // Paths, places, speeds and effects drawn at random, some far larger than any catalogued
    // typical size: none of it is a unit error, so none may be called one.
    let mut rng = ChaCha8Rng::seed_from_u64(20261124);
    let effects = [
        "",
        "odometer-scale=0.05",
        "gps-latency=0.8",
        "accel-cross-axis,gyro-fz=1e-6",
        "torquer-scale=0.02",
    ];
    let mut tried = 0;
    let mut k = 0;
    while k < 20 {
        tried += 1;
        assert!(tried < 200, "too few drawn paths build");
        let t = TrajectoryConfig {
            start_lat_deg: rng.gen_range(-75.0..75.0),
            start_lon_deg: rng.gen_range(-180.0..180.0),
            cruise_speed: rng.gen_range(3.0..35.0),
            peak_accel: rng.gen_range(0.3..4.0),
            leg_north_m: rng.gen_range(500.0..6000.0),
            leg_east_m: rng.gen_range(500.0..6000.0),
            duration_s: 2400.0,
            initial_standstill_s: rng.gen_range(0.0..200.0),
            ..Default::default()
        };
        let t = TrajectoryConfig {
            turn_speed: t.cruise_speed.min(5.0),
            ..t
        };
        if Trajectory::build(&t).is_err() {
            continue; // a path that does not fit its duration: draw another
        }
        let ds = simulated(effects[k % effects.len()], t.clone(), k as u64);
        assert!(ds.warnings().is_empty(), "{t:?}: {:?}", ds.warnings());
        k += 1;
    }
}

#[test]
fn wrong_units_are_warned_about_with_their_file_and_column() {
    let base = simulated("", short(), 7);
    assert!(base.warnings().is_empty());

    // Times in milliseconds (every file's time column).
    let mut ds = base.clone();
    ds.inputs.iter_mut().for_each(|i| i.t *= 1000.0);
    ds.measurements.iter_mut().for_each(|m| m.t *= 1000.0);
    let w = ds.warnings();
    assert_eq!(doubts(&ds), [Doubt::TimesInMilliseconds], "{w:?}");
    assert!(
        w[0].to_string().contains("measurements.csv: column `t`"),
        "{}",
        w[0]
    );
    // ... also without an odometer to compare with: the input rate tells.
    ds.measurements.iter_mut().for_each(|m| m.velocity = None);
    assert_eq!(doubts(&ds), [Doubt::TimesInMilliseconds]);
    assert!(ds.warnings()[0].to_string().contains("inputs.csv"));

    // Inputs at 1 Hz, the slowest data-format.md allows, are seconds: no warning, with the
    // odometer to compare or without it.
    let mut slow = base.clone();
    slow.inputs = base.inputs.iter().step_by(10).copied().collect();
    assert_eq!(doubts(&slow), [], "{:?}", slow.warnings());
    slow.measurements.iter_mut().for_each(|m| m.velocity = None);
    assert_eq!(doubts(&slow), [], "{:?}", slow.warnings());

    // Latitude in radians, longitude in degrees (the reader's radians check cannot see it),
    // and the other way round.
    for (axis, doubt, column) in [
        (0, Doubt::LatitudeInRadians, "lat_deg"),
        (1, Doubt::LongitudeInRadians, "lon_deg"),
    ] {
        let mut ds = base.clone();
        for m in &mut ds.measurements {
            if let Some(p) = m.position_deg.as_mut() {
                p[axis] = p[axis].to_radians();
            }
        }
        assert_eq!(doubts(&ds), [doubt], "{:?}", ds.warnings());
        assert!(ds.warnings()[0].to_string().contains(column));
    }

    // Both columns in radians (the reader refuses such a file; a dataset made in memory
    // reaches these checks): the GPS track 57 times short is radians, not milliseconds.
    let mut ds = base.clone();
    for p in ds
        .measurements
        .iter_mut()
        .filter_map(|m| m.position_deg.as_mut())
    {
        *p = [p[0].to_radians(), p[1].to_radians()];
    }
    assert_eq!(
        doubts(&ds),
        [Doubt::LatitudeInRadians, Doubt::LongitudeInRadians],
        "{:?}",
        ds.warnings()
    );

    // An odometer in km/h or in mph; one 5 % off (a scale error, not a unit) is no doubt.
    for (scale, unit) in [
        (3.6, Some("km/h")),
        (1.0 / 0.447_04, Some("mph")),
        (1.05, None),
    ] {
        let mut ds = base.clone();
        for m in &mut ds.measurements {
            if let Some(v) = m.velocity.as_mut() {
                *v = v.map(|x| x * scale);
            }
        }
        let w = ds.warnings();
        match unit {
            Some(unit) => {
                assert_eq!(doubts(&ds), [Doubt::OdometerNotMetresPerSecond], "{w:?}");
                let text = w[0].to_string();
                assert!(
                    text.contains("measurements.csv: column `v_e,v_n`"),
                    "{text}"
                );
                assert!(text.contains(unit), "{text}");
            }
            None => assert_eq!(doubts(&ds), [], "{w:?}"),
        }
    }

    // Specific force in g, in mg, absurd.
    for (scale, hint) in [
        (1.0 / 9.81, "in g?"),
        (1000.0 / 9.81, "in mg?"),
        (1e299, ""),
    ] {
        let mut ds = base.clone();
        ds.inputs
            .iter_mut()
            .for_each(|i| i.f = i.f.map(|x| x * scale));
        let w = ds.warnings();
        assert_eq!(doubts(&ds), [Doubt::SpecificForceNotGravity], "{w:?}");
        assert!(w[0].to_string().contains("inputs.csv") && w[0].to_string().contains(hint));
    }
}

#[test]
fn a_track_across_the_antimeridian_is_one_continuous_track() {
    let t = TrajectoryConfig {
        start_lon_deg: 179.99,
        ..short()
    };
    let ds = simulated("", t, 3);
    let dir = temp("antimeridian");
    ds.write(&dir).unwrap();
    // Wrap the longitudes as a recorder would: beyond +180 they come back from -180.
    let path = dir.join("measurements.csv");
    let text = std::fs::read_to_string(&path).unwrap();
    let mut wrapped = 0;
    let lines: Vec<String> = text
        .lines()
        .map(|l| {
            let mut cells: Vec<String> = l.split(',').map(str::to_owned).collect();
            if let Ok(lon) = cells[4].parse::<f64>() {
                if lon > 180.0 {
                    cells[4] = format!("{}", lon - 360.0);
                    wrapped += 1;
                }
            }
            cells.join(",")
        })
        .collect();
    assert!(wrapped > 10, "the test track must cross the antimeridian");
    std::fs::write(&path, lines.join("\n") + "\n").unwrap();
    let back = Dataset::read(&dir).unwrap();
    let extent = back.summary().extent.unwrap();
    assert!(
        extent.east_m < 5_000.0,
        "extent {} m east-west",
        extent.east_m
    );
    // Every fix within a metre of the unwrapped original.
    for (a, b) in back.measurements.iter().zip(&ds.measurements) {
        if let (Some(p), Some(q)) = (a.position_deg, b.position_deg) {
            assert!((p[1] - q[1]).abs() < 1e-9, "{p:?} against {q:?}");
        }
    }
}

#[test]
fn inputs_slower_than_the_measurements_are_refused() {
    let ds = simulated("", short(), 5);
    for keep_every in [20, 100] {
        let mut slow = ds.clone();
        slow.inputs = ds.inputs.iter().step_by(keep_every).copied().collect();
        let dir = temp(&format!("slow-{keep_every}"));
        slow.write(&dir).unwrap();
        let e = Dataset::read(&dir).unwrap_err().to_string();
        assert!(
            e.contains("inputs.csv") && e.contains("slower than the measurements"),
            "{e}"
        );
    }
    // As fast as the measurements is accepted.
    let mut same = ds.clone();
    same.inputs = ds.inputs.iter().step_by(10).copied().collect();
    let dir = temp("same-rate");
    same.write(&dir).unwrap();
    let read = Dataset::read(&dir);
    read.unwrap();
}
