//! The standing corpus of bad input (`tests/corpus/`, `tests/corpus-studies/`): one case per
//! validation rule of data-format.md and per kind of bad study file, each with the exit code
//! and the words its message must contain. A change that loses a check, its location or its
//! wording fails here.
//!
//! A dataset case is a folder with the files as a user would bring them and `expect.txt`
//! (`exit N`, then one expected fragment per line), run through `navkf inspect`. A study case
//! is a TOML file whose `# expect: ...` lines give the fragments, run through `navkf study`
//! (always refused: exit 1, nothing written).

use crate::common;

use common::{navkf, text, Scratch};
use std::path::{Path, PathBuf};

fn cases(dir: &str) -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests")
        .join(dir);
    let mut v: Vec<PathBuf> = std::fs::read_dir(&root)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    v.sort();
    v
}

/// Whether `s` holds a control character other than a line break (a terminal escape echoed
/// from the data).
fn has_control(s: &str) -> bool {
    s.chars().any(|c| c.is_control() && c != '\n')
}

#[test]
fn every_bad_dataset_gets_its_message_and_exit_code() {
    let cases = cases("corpus");
    assert!(cases.len() >= 30, "{} cases", cases.len());
    let mut failures = Vec::new();
    for case in &cases {
        let expect = std::fs::read_to_string(case.join("expect.txt")).unwrap();
        let mut lines = expect.lines();
        let exit: i32 = lines
            .next()
            .and_then(|l| l.strip_prefix("exit "))
            .and_then(|n| n.parse().ok())
            .expect("expect.txt starts with `exit N`");
        let o = navkf(["inspect".as_ref(), case.as_os_str()]);
        let said = text(&o.stderr) + &text(&o.stdout);
        let name = case.file_name().unwrap().to_string_lossy();
        if o.status.code() != Some(exit) || said.contains("panicked") {
            failures.push(format!(
                "{name}: exit {:?}, expected {exit}:\n{said}",
                o.status.code()
            ));
            continue;
        }
        if has_control(&said) {
            failures.push(format!("{name}: prints a raw control character: {said:?}"));
        }
        for fragment in lines.filter(|l| !l.is_empty()) {
            if !said.contains(fragment) {
                failures.push(format!("{name}: lacks {fragment:?}:\n{said}"));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

#[test]
fn every_bad_study_file_is_refused_with_its_message() {
    let cases = cases("corpus-studies");
    assert!(cases.len() >= 10, "{} cases", cases.len());
    let dir = Scratch::new("corpus");
    let out = dir.join("out");
    let mut failures = Vec::new();
    for case in &cases {
        let body = std::fs::read_to_string(case).unwrap();
        let o = navkf([
            "study".as_ref(),
            case.as_os_str(),
            "--quiet".as_ref(),
            "--out".as_ref(),
            out.as_os_str(),
        ]);
        let said = text(&o.stderr);
        let name = case.file_name().unwrap().to_string_lossy();
        if o.status.code() != Some(1) || said.contains("panicked") {
            failures.push(format!("{name}: exit {:?}:\n{said}", o.status.code()));
            continue;
        }
        if has_control(&said) {
            failures.push(format!("{name}: prints a raw control character: {said:?}"));
        }
        for fragment in body.lines().filter_map(|l| l.strip_prefix("# expect: ")) {
            if !said.contains(fragment) {
                failures.push(format!("{name}: lacks {fragment:?}:\n{said}"));
            }
        }
        if out.exists() {
            failures.push(format!("{name}: wrote {}", out.display()));
            let _ = std::fs::remove_dir_all(&out);
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}
