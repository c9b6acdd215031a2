//! The one executor: results in index order whatever the thread count, and shards that tile
//! the units (the stop on request is in `executor_stop.rs`, its own process: the request is
//! process-wide, and a test beside it would see it).

use navkf_report::executor::{shard_range, Executor};

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
