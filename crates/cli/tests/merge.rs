//! Shards of a study merge into what the study gives on one machine, whatever its example
//! run holds.

mod common;

use common::{navkf, text};
use std::path::Path;

#[test]
fn shards_whose_example_truth_lacks_a_filter_state_merge() {
    // The filters model the odometer scale; the truth does not carry it, so the example
    // run's truth is NaN for kod, which JSON can only write as null.
    let dir = std::env::temp_dir().join(format!("navkf-merge-nan-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
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
    let _ = std::fs::remove_dir_all(&dir);
}
