//! Sharding: shards run separately and merged equal the single run exactly, and `merge`
//! refuses an incomplete or overlapping set of shard files.

mod common;

use common::{short_config, temp_dir, without_timings};
use navkf_study::output::{fold, read_partials, shard_blocks, Partial};
use navkf_study::Study;
use std::path::PathBuf;

/// 35 runs: 4 blocks (the last one of 5 runs), split 1 + 1 + 2 over three shards.
const RUNS: usize = 35;

fn shards(study: &Study) -> Vec<Partial> {
    (0..3)
        .map(|i| Partial {
            config: study.config.clone(),
            shard: (i, 3),
            blocks: study.run_blocks(shard_blocks(study.block_count(), i, 3), &|_| {}, |_| {}),
            example: None,
        })
        .collect()
}

fn write(dir: &std::path::Path, p: &Partial) -> PathBuf {
    let path = dir.join(format!("partial-{}-of-{}.json", p.shard.0, p.shard.1));
    std::fs::write(&path, serde_json::to_string(p).unwrap()).unwrap();
    path
}

#[test]
fn merged_shards_equal_the_unsharded_study_and_merge_checks_the_set() {
    let study = Study::new(short_config(RUNS)).unwrap();
    assert_eq!(study.block_count(), 4);
    let whole = without_timings(common::run_all(&study));
    assert_eq!(whole.runs, RUNS);
    let parts = shards(&study);
    assert_eq!(
        parts.iter().map(|p| p.blocks.len()).collect::<Vec<_>>(),
        [1, 1, 2],
        "uneven shards"
    );
    let blocks: Vec<_> = parts.iter().flat_map(|p| p.blocks.clone()).collect();
    assert!(
        without_timings(fold(&blocks)) == whole,
        "merged shards differ from the unsharded study"
    );

    // Through shard files, as `navkf merge` reads them, given in any order.
    let dir = temp_dir("shards");
    let paths: Vec<PathBuf> = parts.iter().map(|p| write(&dir, p)).collect();
    let read = read_partials(&[paths[2].clone(), paths[0].clone(), paths[1].clone()])
        .expect("a complete set of shards");
    let blocks: Vec<_> = read.iter().flat_map(|p| p.blocks.clone()).collect();
    assert!(
        without_timings(fold(&blocks)) == whole,
        "shards merged from their JSON files differ from the unsharded study"
    );

    // A missing middle shard.
    let err = read_partials(&[paths[0].clone(), paths[2].clone()])
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("expected the block starting at run 10") && err.contains("missing"),
        "{err}"
    );
    // A missing last shard.
    let err = read_partials(&paths[..2]).unwrap_err().to_string();
    assert!(err.contains("some shards are missing"), "{err}");
    // A shard given twice (the second copy under another name).
    let copy = dir.join("copy-of-1.json");
    std::fs::copy(&paths[1], &copy).unwrap();
    let err = read_partials(&[paths[0].clone(), paths[1].clone(), copy, paths[2].clone()])
        .unwrap_err()
        .to_string();
    assert!(err.contains("given twice"), "{err}");
    // A shard of another study.
    let mut other = parts[1].clone();
    other.config.study.seed += 1;
    let other = {
        let p = dir.join("other.json");
        std::fs::write(&p, serde_json::to_string(&other).unwrap()).unwrap();
        p
    };
    let err = read_partials(&[paths[0].clone(), other, paths[2].clone()])
        .unwrap_err()
        .to_string();
    assert!(err.contains("different study file"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}
