//! The one executor: results in index order whatever the thread count, groups never passed
//! on half done, and a stop that skips what has not started.

use navkf_report::executor::{shard_range, Executor};
use navkf_report::interrupt;

/// A float fold over the sink's order: any reordering changes its bits.
fn fold_on(threads: usize, group: usize) -> (Vec<usize>, f64) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let mut order = Vec::new();
        let mut sum = 0.0f64;
        Executor::new("units", group)
            .run(
                0..97,
                &|i| {
                    // Uneven work, so threads finish out of order.
                    let mut x = 1.0 + i as f64;
                    for _ in 0..(i % 7) * 2000 {
                        x = (x * 1.000_001).sin() + 1.0;
                    }
                    1.0 / (1.0 + i as f64).powf(1.3) + x * 1e-9
                },
                &|_done| {},
                |i, v| {
                    order.push(i);
                    sum = sum * 0.999_999_9 + v;
                },
            )
            .unwrap();
        (order, sum)
    })
}

#[test]
fn results_reach_the_sink_in_order_whatever_the_threads_and_group() {
    let (order, reference) = fold_on(1, 97);
    assert_eq!(order, (0..97).collect::<Vec<_>>());
    for (threads, group) in [(2, 5), (4, 1), (3, 200)] {
        let (order, sum) = fold_on(threads, group);
        assert_eq!(order, (0..97).collect::<Vec<_>>(), "{threads} threads");
        assert_eq!(
            sum.to_bits(),
            reference.to_bits(),
            "{threads} threads, group {group}"
        );
    }
}

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

#[test]
fn shards_tile_the_units_in_order() {
    for count in [1, 2, 7, 10, 98, 1000] {
        for n in 1..=count.min(13) {
            let ranges: Vec<_> = (0..n).map(|i| shard_range(count, i, n)).collect();
            assert_eq!(ranges[0].start, 0);
            assert_eq!(ranges[n - 1].end, count);
            for w in ranges.windows(2) {
                assert_eq!(w[0].end, w[1].start);
            }
            let (lo, hi) = (
                ranges.iter().map(|r| r.len()).min().unwrap(),
                ranges.iter().map(|r| r.len()).max().unwrap(),
            );
            assert!(lo >= 1 && hi - lo <= 1, "{count} into {n}: {ranges:?}");
        }
    }
}
