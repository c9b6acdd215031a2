//! A results folder is all-or-nothing: a run that fails leaves the old folder as it was, a
//! run that completes replaces it whole, and a folder that holds anything but results is
//! never replaced.

mod common;

use common::temp_dir;
use navkf_study::output::{ResultsDir, MARKER};
use std::fs;

#[test]
fn a_results_folder_is_replaced_whole_or_not_at_all() {
    let root = temp_dir("results-dir");
    let out = root.join("study");

    // First run: nothing in place until the commit.
    let staged = ResultsDir::begin(&out).unwrap();
    fs::write(staged.path().join("summary.json"), "1").unwrap();
    fs::write(staged.path().join("old-only.png"), "1").unwrap();
    assert!(!out.exists());
    staged.commit().unwrap();
    assert!(out.join(MARKER).is_file());

    // A run that fails half-way (an error: the staging folder is dropped) leaves the old one.
    {
        let staged = ResultsDir::begin(&out).unwrap();
        fs::write(staged.path().join("summary.json"), "2").unwrap();
    }
    assert_eq!(fs::read_to_string(out.join("summary.json")).unwrap(), "1");
    assert!(out.join("old-only.png").is_file());

    // A run that completes replaces it whole: no file of the old run survives.
    let staged = ResultsDir::begin(&out).unwrap();
    fs::write(staged.path().join("summary.json"), "3").unwrap();
    staged.commit().unwrap();
    assert_eq!(fs::read_to_string(out.join("summary.json")).unwrap(), "3");
    assert!(!out.join("old-only.png").exists());

    // Nothing is left beside it: no staging or old folder.
    let names: Vec<String> = fs::read_dir(&root)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, ["study"], "{names:?}");
}

#[test]
fn only_a_results_folder_is_replaced() {
    let root = temp_dir("results-dir-refused");
    // A user's own folder.
    let theirs = root.join("thesis");
    fs::create_dir_all(&theirs).unwrap();
    fs::write(theirs.join("chapter1.tex"), "x").unwrap();
    let e = ResultsDir::begin(&theirs).unwrap_err().to_string();
    assert!(e.contains("something other than navkf results"), "{e}");
    assert!(theirs.join("chapter1.tex").is_file());
    // A file, `.` and `..`.
    fs::write(root.join("file"), "x").unwrap();
    let e = ResultsDir::begin(&root.join("file"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("is not a folder"), "{e}");
    for dot in [".", ".."] {
        let e = ResultsDir::begin(std::path::Path::new(dot))
            .unwrap_err()
            .to_string();
        assert!(e.contains("expected a folder name"), "{e}");
        // Inside a path, `.` names the folder itself: the user's, so refused.
        assert!(ResultsDir::begin(&theirs.join(dot)).is_err());
    }
    // An empty folder, and results of a version that wrote no marker, are replaced.
    for (name, file) in [("empty", None), ("older", Some("sweep.json"))] {
        let dir = root.join(name);
        fs::create_dir_all(&dir).unwrap();
        if let Some(f) = file {
            fs::write(dir.join(f), "{}").unwrap();
        }
        ResultsDir::begin(&dir).unwrap().commit().unwrap();
        assert!(dir.join(MARKER).is_file());
    }
}

#[test]
fn a_killed_run_leaves_a_named_partial_folder_that_the_next_run_removes() {
    let root = temp_dir("results-dir-killed");
    let out = root.join("study");
    // What a killed process leaves: its staging folder, named with its (no longer running)
    // process id. Process ids stay below 2^22 on Linux.
    let abandoned = root.join(".study.navkf-partial-4294967295");
    fs::create_dir_all(&abandoned).unwrap();
    fs::write(abandoned.join("summary.json"), "half").unwrap();
    let staged = ResultsDir::begin(&out).unwrap();
    if std::path::Path::new("/proc/self").exists() {
        assert!(!abandoned.exists(), "removed once its process is gone");
    }
    staged.commit().unwrap();
    assert!(!out.join("summary.json").exists());
}
