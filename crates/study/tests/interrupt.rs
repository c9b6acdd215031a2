//! A stop asked for (Ctrl-C) ends a study within one run, saying how many it completed.
//! Its own test binary: the request is process-wide.

mod common;

use common::short_config;
use navkf_report::interrupt;
use navkf_study::Study;

#[test]
fn a_requested_stop_ends_the_study_after_the_runs_in_flight() {
    let study = Study::new(short_config(200)).unwrap();
    interrupt::clear();
    // Asked for after the 5th run: the runs in flight finish, no other starts.
    let progress = |done: usize| {
        if done >= 5 {
            interrupt::request();
        }
    };
    let stop = study
        .run_folded(0..study.block_count(), &progress, |_| {})
        .unwrap_err();
    assert!(interrupt::requested());
    let threads = rayon::current_num_threads();
    assert!(
        stop.done >= 5 && stop.done < 5 + threads && stop.total == 200,
        "{stop:?} with {threads} threads"
    );
    interrupt::clear();
    let tally = study.run_folded(0..2, &|_| {}, |_| {}).unwrap();
    assert_eq!(
        tally.runs,
        2 * navkf_study::tally::BLOCK,
        "cleared: runs again"
    );
}
