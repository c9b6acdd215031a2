//! Memory stays flat in the number of runs: the tally holds sums, not runs, and running more
//! runs does not raise the process's peak memory.

mod common;

use common::short_config;
use navkf_study::Study;
use std::sync::Mutex;

/// The two tests measure the same process: one at a time.
static SERIAL: Mutex<()> = Mutex::new(());

/// Numbers in a JSON value.
fn numbers(v: &serde_json::Value) -> usize {
    use serde_json::Value;
    match v {
        Value::Number(_) => 1,
        Value::Array(a) => a.iter().map(numbers).sum(),
        Value::Object(o) => o.values().map(numbers).sum(),
        _ => 0,
    }
}

/// The folded tally of `runs` runs as JSON, without what may legitimately grow: the list of
/// diverged runs and the step-cost histogram (bins, bounded by the range of costs).
fn tally_json(runs: usize) -> serde_json::Value {
    let study = Study::new(short_config(runs)).unwrap();
    let mut tally = common::without_timings(common::run_all(&study));
    for f in &mut tally.filters {
        f.diverged.clear();
    }
    serde_json::to_value(&tally).unwrap()
}

#[test]
fn the_tally_does_not_grow_with_runs() {
    let _one = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let (a, b) = (tally_json(20), tally_json(60));
    let (la, lb) = (a.to_string().len(), b.to_string().len());
    println!("tally JSON: {la} bytes for 20 runs, {lb} bytes for 60 runs");
    assert_eq!(numbers(&a), numbers(&b), "numbers held by the tally");
    // The same numbers printed: lengths differ only by the digits each needs.
    assert!(
        (la as f64 - lb as f64).abs() < 0.05 * la as f64,
        "{la} vs {lb} bytes"
    );
}

/// Peak resident memory of this process so far (VmHWM), bytes.
fn peak_rss() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

// Measured through Linux's /proc; elsewhere the test is reported as ignored, never passed
// without measuring.
#[test]
#[cfg_attr(not(target_os = "linux"), ignore = "needs /proc/self/status (Linux)")]
fn peak_memory_does_not_grow_with_runs() {
    let _one = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    assert!(
        peak_rss().is_some(),
        "no VmHWM in /proc/self/status: peak memory cannot be measured"
    );
    // Every second stored: about 0.7 MB of records per run (3 filters and the bound, 600
    // stored times of 20 errors and variances) and about as much per block tally, so holding
    // every block's tally until the end would add about 7 MB from 20 to 100 runs, and holding
    // every run about 55 MB; folding as blocks complete holds one group of blocks.
    let study = |runs| {
        let mut c = short_config(runs);
        c.study.series_every_s = 1.0;
        Study::new(c).unwrap()
    };
    let run = |s: &Study| s.run_folded(0..s.block_count(), &|_| {}, |_| {}).unwrap();
    // Both prepared before measuring: a study's simulator holds its own inputs.
    let (small, large) = (study(20), study(100));
    let _ = run(&small); // warms up the allocator's arenas
    let _ = run(&small);
    let after_small = peak_rss().unwrap();
    assert_eq!(run(&large).runs, 100);
    let after_large = peak_rss().unwrap();
    let growth = after_large.saturating_sub(after_small);
    println!(
        "peak RSS: {:.1} MB after 20 runs, {:.1} MB after 100 runs (+{:.1} MB)",
        after_small as f64 / 1e6,
        after_large as f64 / 1e6,
        growth as f64 / 1e6
    );
    assert!(
        growth < 4_000_000,
        "peak memory grew by {:.1} MB from 20 to 100 runs",
        growth as f64 / 1e6
    );
}
