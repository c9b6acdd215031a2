//! What the CLI tests share: running the built `navkf`, reading its output, and scratch
//! folders that go when the test ends.
#![allow(dead_code)] // each test file uses a subset

pub mod study_files;

#[path = "../../../dynamics/tests/common/scratch.rs"]
mod scratch;

pub use scratch::Scratch;

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
