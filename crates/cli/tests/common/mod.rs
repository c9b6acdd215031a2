//! What the CLI tests share: running the built `navkf` and reading its output.
#![allow(dead_code)] // each test file uses a subset

pub mod study_files;

use std::process::{Command, Output};

/// Runs the `navkf` binary of this build with `args` (paths may be any OS string).
pub fn navkf<I, S>(args: I) -> Output
where
    I: IntoIterator<Item = S>,
    S: AsRef<std::ffi::OsStr>,
{
    Command::new(env!("CARGO_BIN_EXE_navkf"))
        .args(args)
        .output()
        .expect("navkf runs")
}

/// Output bytes as text (lossy).
pub fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}
