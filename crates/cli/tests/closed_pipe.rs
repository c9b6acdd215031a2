//! A reader that has gone before the results are printed (`navkf diagnose d | head -1`, a
//! pager quit early) ends a command's output quietly: the command still succeeds, its files
//! written, and nothing panics with "failed printing to stdout: Broken pipe" (Rust ignores
//! SIGPIPE, so a write to a closed pipe is an error every print must expect).

use crate::common;

use common::{text, Scratch};
use std::ffi::OsStr;
use std::process::{Command, Stdio};

/// Runs `navkf args` with its standard output a pipe whose reading end is closed at once.
fn with_stdout_closed(args: &[&OsStr]) -> std::process::Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_navkf"))
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("navkf runs");
    drop(child.stdout.take());
    child.wait_with_output().expect("navkf ends")
}

#[test]
fn simulate_and_diagnose_end_quietly_when_their_reader_has_gone() {
    let dir = Scratch::new("closed-pipe");
    let (platform, strapdown) = (dir.join("platform"), dir.join("strapdown"));
    let model = [
        (&platform, None),
        (&strapdown, Some(["--model", "strapdown", "--unit", "mems"])),
    ];
    for (out, family) in model {
        let mut args: Vec<&OsStr> = vec!["simulate".as_ref(), "--out".as_ref(), out.as_os_str()];
        args.extend(family.iter().flatten().map(OsStr::new));
        let o = with_stdout_closed(&args);
        let err = text(&o.stderr);
        assert!(o.status.success() && !err.contains("panicked"), "{err}");
        assert!(out.join("dataset.toml").is_file());
        if family.is_some() {
            // The same prints; a strapdown drive's diagnosis takes a minute, the platform's
            // a second.
            continue;
        }
        let report = out.with_extension("diagnosis");
        let o = with_stdout_closed(&[
            "diagnose".as_ref(),
            out.as_os_str(),
            "--out".as_ref(),
            report.as_os_str(),
        ]);
        let err = text(&o.stderr);
        assert!(o.status.success() && !err.contains("panicked"), "{err}");
        assert!(report.join("report.md").is_file());
    }
}
