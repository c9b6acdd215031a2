//! A results folder is all-or-nothing: a run that fails leaves the old folder as it was, a
//! run that completes replaces it whole, and a folder navkf did not make, or that holds a
//! file it did not write, is never replaced.

use navkf_report::{FolderKind, ResultsDir, ShardFolder, MARKER};
use std::fs;

#[path = "../../dynamics/tests/common/scratch.rs"]
mod scratch;

use scratch::Scratch;

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
fn only_a_folder_navkf_made_is_replaced() {
    let root = temp_dir("results-dir-refused");
    // A user's own folder, even one holding files named like navkf's results.
    let theirs = root.join("thesis");
    fs::create_dir_all(theirs.join("photos")).unwrap();
    fs::write(theirs.join("thesis.tex"), "x").unwrap();
    fs::write(theirs.join("summary.json"), "{}").unwrap();
    fs::write(theirs.join("partial-draft.json"), "{}").unwrap();
    let e = ResultsDir::begin(&theirs).unwrap_err().to_string();
    assert!(e.contains("a folder navkf did not make"), "{e}");
    assert!(
        e.contains("`partial-draft.json`") && e.contains("and 1 more"),
        "{e}"
    );
    assert!(theirs.join("thesis.tex").is_file() && theirs.join("photos").is_dir());
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
    // An empty folder is taken; a marker of an earlier version (empty: it listed no files)
    // is not, since navkf cannot tell its files from the user's there.
    let empty = root.join("empty");
    fs::create_dir_all(&empty).unwrap();
    ResultsDir::begin(&empty).unwrap().commit().unwrap();
    assert!(empty.join(MARKER).is_file());
    let older = root.join("older");
    fs::create_dir_all(&older).unwrap();
    fs::write(older.join(MARKER), "").unwrap();
    fs::write(older.join("summary.json"), "{}").unwrap();
    let e = ResultsDir::begin(&older).unwrap_err().to_string();
    assert!(e.contains("cannot read"), "{e}");
    assert!(older.join("summary.json").is_file());
}

#[test]
fn the_marker_says_who_made_the_folder_and_lists_its_files() {
    let root = temp_dir("results-dir-marker");
    let out = root.join("study");
    let staged = ResultsDir::begin(&out).unwrap();
    // Written first, before any output.
    let first = fs::read_to_string(staged.path().join(MARKER)).unwrap();
    assert!(first.contains("\"made_by\": \"navkf "), "{first}");
    assert!(first.contains("\"command\""), "{first}");
    fs::create_dir_all(staged.path().join("point-00")).unwrap();
    fs::write(staged.path().join("point-00/summary.json"), "1").unwrap();
    fs::write(staged.path().join("report.md"), "1").unwrap();
    staged.commit().unwrap();
    let marker: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(out.join(MARKER)).unwrap()).unwrap();
    assert_eq!(marker["kind"], "results");
    assert_eq!(
        marker["files"],
        serde_json::json!(["point-00/summary.json", "report.md"])
    );
    // A file the user adds, at the top or inside, makes the folder theirs too: refused,
    // naming it, and nothing is deleted.
    for added in ["notes.txt", "point-00/mine.csv"] {
        fs::write(out.join(added), "mine").unwrap();
        let e = ResultsDir::begin(&out).unwrap_err().to_string();
        assert!(
            e.contains(&format!("`{added}`, which navkf did not write")),
            "{e}"
        );
        assert!(out.join(added).is_file());
        fs::remove_file(out.join(added)).unwrap();
    }
    // A write probe a killed run left is navkf's own, not a file of the user's.
    fs::write(out.join(".navkf-probe-4194999"), "").unwrap();
    ResultsDir::begin(&out).unwrap();
    // A file listed but gone (a clean clone lacks the ignored ones) is no obstacle.
    fs::remove_file(out.join("report.md")).unwrap();
    ResultsDir::begin(&out).unwrap().commit().unwrap();
    // A dataset folder that simulate made is not a results folder, and the reverse.
    let ds = root.join("dataset");
    ResultsDir::begin_kind(&ds, FolderKind::Dataset, &[])
        .unwrap()
        .commit()
        .unwrap();
    let e = ResultsDir::begin(&ds).unwrap_err().to_string();
    assert!(e.contains("a dataset folder navkf simulated"), "{e}");
    let e = ResultsDir::begin_kind(&out, FolderKind::Dataset, &[])
        .unwrap_err()
        .to_string();
    assert!(e.contains("a navkf results folder, not a dataset"), "{e}");
}

#[cfg(unix)]
#[test]
fn a_link_is_followed_to_its_folder_and_a_broken_one_refused() {
    let root = temp_dir("results-dir-link");
    let real = root.join("real");
    let link = root.join("link");
    fs::create_dir_all(&real).unwrap();
    std::os::unix::fs::symlink(&real, &link).unwrap();
    // The first run fills the empty folder the link names; the second replaces it. The link
    // stays a link, and no old results stay at its target.
    for run in ["1", "2"] {
        let staged = ResultsDir::begin(&link).unwrap();
        fs::write(staged.path().join(format!("run-{run}")), run).unwrap();
        staged.commit().unwrap();
    }
    assert!(fs::symlink_metadata(&link)
        .unwrap()
        .file_type()
        .is_symlink());
    assert!(real.join("run-2").is_file() && !real.join("run-1").exists());
    let dangling = root.join("dangling");
    std::os::unix::fs::symlink(root.join("nowhere"), &dangling).unwrap();
    let e = ResultsDir::begin(&dangling).unwrap_err().to_string();
    assert!(
        e.contains("a symbolic link to") && e.contains("cannot be followed"),
        "{e}"
    );
    let names: Vec<String> = fs::read_dir(&root)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains(".navkf-"))
        .collect();
    assert!(names.is_empty(), "{names:?}");
}

#[test]
fn a_shard_folder_is_checked_without_being_created() {
    let root = temp_dir("results-dir-shards");
    let out = root.join("shards");
    let folder = ShardFolder::check(&out).unwrap();
    assert!(!out.exists(), "a check creates nothing");
    folder.write("partial-0-of-2.json", b"{}").unwrap();
    assert!(out.join(".navkf-shards").is_file());
    // A user's file beside the shards is kept (shards remove nothing) ...
    fs::write(out.join("notes.txt"), "mine").unwrap();
    ShardFolder::check(&out)
        .unwrap()
        .write("partial-1-of-2.json", b"{}")
        .unwrap();
    // ... but then the merged results cannot replace the folder.
    let e = ResultsDir::begin_kind(&out, FolderKind::Results, &[FolderKind::Shards])
        .unwrap_err()
        .to_string();
    assert!(e.contains("`notes.txt`, which navkf did not write"), "{e}");
    fs::remove_file(out.join("notes.txt")).unwrap();
    ResultsDir::begin_kind(&out, FolderKind::Results, &[FolderKind::Shards])
        .unwrap()
        .commit()
        .unwrap();
    // A folder with other files and no shard marker is refused.
    let theirs = root.join("theirs");
    fs::create_dir_all(&theirs).unwrap();
    fs::write(theirs.join("notes.txt"), "mine").unwrap();
    let e = ShardFolder::check(&theirs).unwrap_err().to_string();
    assert!(e.contains("shards write only into a new folder"), "{e}");
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

/// A fresh, empty folder under the system temporary folder, removed when the test ends.
fn temp_dir(name: &str) -> Scratch {
    Scratch::new(&format!("report-{name}"))
}
