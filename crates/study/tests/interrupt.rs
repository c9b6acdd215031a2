//! A stop asked for (Ctrl-C) ends a study within one group of runs, with what it completed.
//! Its own test binary: the request is process-wide.

mod common;

use common::short_config;
use navkf_report::interrupt;
use navkf_study::Study;

#[test]
fn a_requested_stop_ends_the_study_after_the_runs_in_flight() {
    let study = Study::new(short_config(200)).unwrap();
    interrupt::clear();
    // Asked for after the 5th run: the group in flight finishes, no other starts.
    let progress = |done: usize| {
        if done >= 5 {
            interrupt::request();
        }
    };
    let tally = study.run_folded(0..study.block_count(), &progress, |_| {});
    assert!(interrupt::requested());
    assert!(tally.runs >= 5 && tally.runs < 40, "{} runs", tally.runs);
    // Blocks are whole: a stopped study holds complete blocks only.
    assert_eq!(tally.runs % navkf_study::tally::BLOCK, 0);
    interrupt::clear();
    let tally = study.run_folded(0..2, &|_| {}, |_| {});
    assert_eq!(
        tally.runs,
        2 * navkf_study::tally::BLOCK,
        "cleared: runs again"
    );
}
