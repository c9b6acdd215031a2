//! Study files written for a test, scratch folders, and the check that a command was refused
//! before any computing.

use super::{text, Scratch};
use std::path::{Path, PathBuf};
use std::process::Output;
use std::time::Duration;

/// studies/paper.toml with 2 runs and the given replacements of whole `key = value` lines.
pub fn study_file(dir: &Path, file: &str, replace: &[(&str, &str)]) -> PathBuf {
    let text = include_str!("../../../../studies/paper.toml");
    let mut replace: Vec<(&str, &str)> = replace.to_vec();
    replace.push(("runs", "2"));
    let edited: String = text
        .lines()
        .map(|l| {
            for (key, value) in &replace {
                if l.starts_with(&format!("{key} =")) {
                    return format!("{key} = {value}\n");
                }
            }
            format!("{l}\n")
        })
        .collect();
    let path = dir.join(file);
    std::fs::write(&path, edited).unwrap();
    path
}

/// A fresh scratch folder `navkf-bad-input-<name>-<pid>`, removed when the test ends.
pub fn scratch(name: &str) -> Scratch {
    Scratch::new(&format!("bad-input-{name}"))
}

/// Fails with exit 1 within a second (refused before the runs), stderr containing `needle`.
pub fn refused_at_once(o: &Output, took: Duration, needle: &str) {
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains(needle), "stderr lacks {needle:?}: {err}");
    assert!(!err.contains("panicked"), "{err}");
    assert!(took < Duration::from_secs(2), "took {took:?}: refused late");
}
