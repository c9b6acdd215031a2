//! Shared helpers of the study tests: the paper's study file on a short trajectory.
#![allow(dead_code)] // each test file uses a subset

use navkf_study::output::fold;
use navkf_study::tally::Tally;
use navkf_study::{Study, StudyConfig};

#[path = "../../../dynamics/tests/common/scratch.rs"]
mod scratch;

pub use scratch::Scratch;

/// studies/paper.toml, as committed.
pub const PAPER: &str = include_str!("../../../../studies/paper.toml");

/// The paper's study on a 600 s trajectory with `runs` runs.
pub fn short_config(runs: usize) -> StudyConfig {
    let mut c = StudyConfig::parse(PAPER).expect("studies/paper.toml parses");
    c.trajectory.duration_s = 600.0;
    c.trajectory.initial_standstill_s = 30.0;
    c.trajectory.leg_north_m = 1500.0;
    c.trajectory.leg_east_m = 1000.0;
    c.study.runs = runs;
    c.study.example_run = 0;
    c
}

/// Runs every block of `study` on the current rayon pool and folds them.
pub fn run_all(study: &Study) -> Tally {
    fold(
        &study
            .run_blocks(0..study.block_count(), &|_| {}, |_| {})
            .expect("not interrupted"),
    )
}

/// The tally without its step-cost histograms (timings differ from run to run).
pub fn without_timings(mut t: Tally) -> Tally {
    for f in &mut t.filters {
        f.step_cost.clear();
    }
    t
}

/// A fresh, empty folder under the system temporary folder, removed when the test ends.
pub fn temp_dir(name: &str) -> Scratch {
    Scratch::new(&format!("study-{name}"))
}
