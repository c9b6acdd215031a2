//! The thread count changes nothing but speed: tallies and summaries are bit-identical on 1,
//! 2 and 4 threads (4 threads also puts two blocks in flight at once, a different grouping),
//! and folding blocks as they complete gives the same tally as folding them at the end.

use crate::common;

use common::{short_config, without_timings};
use navkf_study::summary::{summarize, Summary};
use navkf_study::tally::Tally;
use navkf_study::Study;

fn on_threads(study: &Study, threads: usize) -> Tally {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| common::run_all(study))
}

fn without_step_ns(mut s: Summary) -> Summary {
    for f in s.filters.values_mut() {
        f.step_ns_median = 0.0;
        f.step_ns_p90 = 0.0;
    }
    s
}

#[test]
fn one_two_and_four_threads_give_identical_results() {
    // 15 runs: a full block and a partial one.
    let study = Study::new(short_config(15)).unwrap();
    let one = on_threads(&study, 1);
    assert_eq!(one.runs, 15);
    assert!(one.filters.iter().all(|f| f.ok > 0), "runs finished");
    let s1 = without_step_ns(summarize(&study, &one));
    let one = without_timings(one);
    for threads in [2, 4] {
        let t = on_threads(&study, threads);
        let s = without_step_ns(summarize(&study, &t));
        assert!(
            without_timings(t) == one,
            "tally on {threads} threads differs from 1 thread"
        );
        assert!(
            s == s1,
            "summary on {threads} threads differs from 1 thread"
        );
    }
    // Folding as blocks complete (what `navkf study` does) is the same fold.
    let folded = study
        .run_folded(0..study.block_count(), &|_| {}, |_| {})
        .expect("not interrupted");
    assert!(
        without_timings(folded) == one,
        "run_folded differs from folding run_blocks"
    );
}
