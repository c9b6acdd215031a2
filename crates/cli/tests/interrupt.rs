//! Ctrl-C: a study stops after the runs in flight, says what it kept, and leaves the previous
//! results folder as it was, with nothing beside it; any other command stops at once, removes
//! what it was writing and says so. Either way within about a second, with exit code 130.
#![cfg(unix)]

mod common;

use common::{navkf, text, Scratch};
use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

/// Runs navkf with `args`, sends SIGINT after `after`, and returns its output and how long
/// it took to exit after the signal.
fn interrupt(args: &[&str], after: Duration) -> (Output, Duration) {
    let child = Command::new(env!("CARGO_BIN_EXE_navkf"))
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(after);
    let sent = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(sent.success());
    let signalled = Instant::now();
    let o = child.wait_with_output().unwrap();
    (o, signalled.elapsed())
}

fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

#[test]
fn ctrl_c_stops_a_study_and_keeps_the_previous_results() {
    let dir = Scratch::new("interrupt");
    let out = dir.join("paper");
    let out_s = out.to_str().unwrap();
    let paper = "../../studies/paper.toml";
    let first = navkf(["study", paper, "--runs", "2", "--quiet", "--out", out_s]);
    assert!(first.status.success(), "{}", text(&first.stderr));
    let previous = std::fs::read(out.join("summary.json")).unwrap();
    // The 500-run study takes far longer than this on any machine.
    let (o, took) = interrupt(
        &["study", paper, "--quiet", "--out", out_s],
        Duration::from_millis(1500),
    );
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(130), "{err}");
    assert!(err.contains("is as it was"), "{err}");
    assert!(
        took < Duration::from_secs(3),
        "took {took:?} after the signal"
    );
    assert_eq!(std::fs::read(out.join("summary.json")).unwrap(), previous);
    assert_eq!(names(&dir), ["paper"], "nothing left beside it");
}

#[test]
fn ctrl_c_stops_a_diagnosis_removes_its_partial_folder_and_says_so() {
    let dir = Scratch::new("interrupt-diag");
    let ds = dir.join("drive");
    let sim = navkf([
        "simulate",
        "--out",
        ds.to_str().unwrap(),
        "--effects",
        "gps-latency,odometer-scale",
    ]);
    assert!(sim.status.success(), "{}", text(&sim.stderr));
    let out = dir.join("diagnosis");
    // A diagnosis with effects takes seconds; the signal lands while it works.
    let (o, took) = interrupt(
        &[
            "diagnose",
            ds.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ],
        Duration::from_millis(300),
    );
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(130), "{err}");
    assert!(
        err.contains("interrupted: the partial output was removed")
            && err.contains("was not created"),
        "{err}"
    );
    assert!(
        took < Duration::from_secs(2),
        "took {took:?} after the signal"
    );
    assert_eq!(names(&dir), ["drive"], "nothing left beside the dataset");
}
