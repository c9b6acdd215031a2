//! A stop on request ends the executor within a unit: what has not started is skipped and a
//! group is never passed on half done. Its own test binary: the request is process-wide.

use navkf_report::executor::Executor;
use navkf_report::interrupt;

#[test]
fn a_stop_skips_the_units_not_started_and_passes_on_no_half_group() {
    let mut passed = Vec::new();
    let result = Executor::new("datasets", 10).run(
        0..100,
        &|i| {
            if i == 25 {
                interrupt::request();
            }
            i
        },
        &|_done| {},
        |i, _| passed.push(i),
    );
    interrupt::clear();
    let stop = result.unwrap_err();
    assert_eq!((stop.total, stop.what), (100, "datasets"));
    assert!(stop.done < 100, "{stop:?}");
    // Whole groups, in order, and nothing past the group where the stop came (units of
    // that group that had started may all finish: then it is passed on whole).
    assert_eq!(passed, (0..passed.len()).collect::<Vec<_>>());
    assert!(passed.len() % 10 == 0 && passed.len() <= 30, "{passed:?}");
    assert!(stop.to_string().contains("nothing was written"), "{stop}");
}
