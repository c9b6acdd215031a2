//! Ctrl-C during a study: it stops after the runs in flight, says what it kept, and leaves
//! the previous results folder as it was, with nothing beside it.
#![cfg(unix)]

mod common;

use common::text;
use std::process::{Command, Stdio};
use std::time::Duration;

#[test]
fn ctrl_c_stops_a_study_and_keeps_the_previous_results() {
    let dir = std::env::temp_dir().join(format!("navkf-interrupt-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let out = dir.join("paper");
    std::fs::create_dir_all(&out).unwrap();
    std::fs::write(out.join("summary.json"), "previous").unwrap();
    let child = Command::new(env!("CARGO_BIN_EXE_navkf"))
        .args(["study", "../../studies/paper.toml", "--quiet", "--out"])
        .arg(&out)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // The 500-run study takes far longer than this on any machine.
    std::thread::sleep(Duration::from_millis(1500));
    let sent = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(sent.success());
    let o = child.wait_with_output().unwrap();
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(
        err.contains("interrupted after") && err.contains("is as it was"),
        "{err}"
    );
    assert_eq!(
        std::fs::read_to_string(out.join("summary.json")).unwrap(),
        "previous"
    );
    let names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, ["paper"], "nothing left beside it");
    let _ = std::fs::remove_dir_all(&dir);
}
