//! Shards of a study, and of a sweep, merge into what the study gives on one machine,
//! whatever its example run holds.

use crate::common;

use common::{navkf, text, Scratch};
use std::path::Path;

#[test]
fn shards_whose_example_truth_lacks_a_filter_state_merge() {
    // The filters model the odometer scale; the truth does not carry it, so the example
    // run's truth is NaN for kod, which JSON can only write as null.
    let dir = Scratch::new("merge-nan");
    let study = dir.join("kod.toml");
    let text_of = include_str!("../../../studies/paper.toml").replace(
        "effects = []               # the filters' model",
        "effects = [\"odometer-scale\"]  # the filters' model",
    );
    assert!(text_of.contains("odometer-scale"), "the edit applies");
    std::fs::write(&study, text_of).unwrap();
    let s = |args: &[&str]| {
        let mut all = vec!["study", study.to_str().unwrap(), "--runs", "20", "--quiet"];
        all.extend_from_slice(args);
        navkf(all)
    };
    let shards = dir.join("shards");
    let whole = dir.join("whole");
    for i in ["0/2", "1/2"] {
        let o = s(&["--shard", i, "--out", shards.to_str().unwrap()]);
        assert!(o.status.success(), "{}", text(&o.stderr));
    }
    assert!(s(&["--out", whole.to_str().unwrap()]).status.success());
    let merged = dir.join("merged");
    let o = navkf([
        "merge".as_ref(),
        shards.join("partial-0-of-2.json").as_os_str(),
        shards.join("partial-1-of-2.json").as_os_str(),
        "--out".as_ref(),
        merged.as_os_str(),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    for file in ["rms_over_time.csv", "example_run.csv"] {
        let read = |d: &Path| std::fs::read(d.join(file)).unwrap();
        assert!(read(&merged) == read(&whole), "{file} differs");
    }
}

/// `sweep.json` without the step costs (timings differ from run to run).
fn without_timings(path: &Path) -> serde_json::Value {
    fn strip(v: &mut serde_json::Value) {
        match v {
            serde_json::Value::Object(m) => {
                m.remove("step_ns_median");
                m.values_mut().for_each(strip);
            }
            serde_json::Value::Array(a) => a.iter_mut().for_each(strip),
            _ => {}
        }
    }
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    strip(&mut v);
    v
}

#[test]
fn shards_of_a_sweep_merge_into_the_single_machine_sweep() {
    let dir = Scratch::new("merge-sweep");
    let mut file = String::new();
    for line in include_str!("../../../studies/paper.toml").lines() {
        let line = match line.split(" =").next() {
            Some("runs") => "runs = 25",
            Some("example_run") => "example_run = 12",
            Some("duration_s") => "duration_s = 600.0",
            Some("initial_standstill_s") => "initial_standstill_s = 30.0",
            Some("leg_north_m") => "leg_north_m = 1500.0",
            Some("leg_east_m") => "leg_east_m = 1000.0",
            _ => line,
        };
        file.push_str(line);
        file.push('\n');
    }
    file.push_str("\n[sweep]\nkey = \"noise.gps_m\"\nvalues = [3.0, 30.0]\n");
    let study = dir.join("sweep.toml");
    std::fs::write(&study, file).unwrap();
    let s = |args: &[&str]| {
        let mut all = vec!["study", study.to_str().unwrap(), "--quiet"];
        all.extend_from_slice(args);
        navkf(all)
    };
    let shards = dir.join("shards");
    let whole = dir.join("whole");
    // 25 runs a point are 3 blocks: three shards, each with one thread count of its own.
    for (i, threads) in [("0/3", "1"), ("1/3", "2"), ("2/3", "1")] {
        let o = s(&[
            "--shard",
            i,
            "--threads",
            threads,
            "--out",
            shards.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", text(&o.stderr));
    }
    let o = s(&["--out", whole.to_str().unwrap()]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let part = |i: usize| shards.join(format!("partial-{i}-of-3.json"));
    let merged = dir.join("merged");
    let o = navkf([
        "merge".as_ref(),
        part(2).as_os_str(),
        part(0).as_os_str(),
        part(1).as_os_str(),
        "--out".as_ref(),
        merged.as_os_str(),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    for point in ["point-00", "point-01"] {
        for file in ["rms_over_time.csv", "example_run.csv"] {
            let read = |d: &Path| std::fs::read(d.join(point).join(file)).unwrap();
            assert!(read(&merged) == read(&whole), "{point}/{file} differs");
        }
    }
    assert_eq!(
        without_timings(&merged.join("sweep.json")),
        without_timings(&whole.join("sweep.json")),
        "sweep.json differs beyond its step costs"
    );
    // A shard missing is refused, naming the point.
    let o = navkf([
        "merge".as_ref(),
        part(0).as_os_str(),
        part(2).as_os_str(),
        "--out".as_ref(),
        dir.join("incomplete").as_os_str(),
    ]);
    assert_eq!(o.status.code(), Some(1));
    let err = text(&o.stderr);
    assert!(
        err.contains("sweep point 0") && err.contains("shard missing"),
        "{err}"
    );
}
