//! A diagnosis study spreads over machines like a Monte Carlo study: `--shard i/n` on each,
//! then `merge`, gives the summary one machine gives, byte for byte; a set of shards that
//! does not tile the run is refused, naming the file.

use crate::common;

use common::{navkf, text, Scratch};
use std::path::{Path, PathBuf};

/// A short diagnosis study: two clean datasets, one with an effect hidden, one outside the
/// catalogue, one with misstated noise (a mix of slow and fast diagnoses).
const STUDY: &str = r#"
[study]
name = "shard-test"
kind = "diagnosis"
seed = 11

[trajectory]
duration_s = 900.0
initial_standstill_s = 60.0
leg_north_m = 2000.0
leg_east_m = 1500.0

[[content]]
kind = "nothing"
count = 2

[[content]]
kind = "pair"
count = 1
effects = ["odometer-scale", "gps-latency"]

[[content]]
kind = "outside"
effect = "drag"
count = 1
sizes = [5.0, 30.0]

[[content]]
kind = "misstated-noise"
count = 1
sizes = [3.0, 30.0]
"#;

fn scratch() -> Scratch {
    Scratch::new("shard-diagnosis")
}

fn ok(args: &[&Path]) {
    let o = navkf(args);
    assert!(o.status.success(), "{:?}: {}", args, text(&o.stderr));
}

#[test]
fn shards_of_a_diagnosis_study_merge_to_the_single_machine_summary() {
    let dir = scratch();
    let study = dir.join("study.toml");
    std::fs::write(&study, STUDY).unwrap();
    let whole = dir.join("whole");
    ok(&[
        Path::new("study"),
        &study,
        Path::new("--out"),
        &whole,
        Path::new("--quiet"),
    ]);
    // Three shards with different thread counts, into one shard folder.
    let shards = dir.join("shards");
    for (i, threads) in [(0, "1"), (1, "2"), (2, "1")] {
        ok(&[
            Path::new("study"),
            &study,
            Path::new("--shard"),
            Path::new(&format!("{i}/3")),
            Path::new("--threads"),
            Path::new(threads),
            Path::new("--out"),
            &shards,
            Path::new("--quiet"),
        ]);
    }
    let files: Vec<PathBuf> = (0..3)
        .map(|i| shards.join(format!("partial-{i}-of-3.json")))
        .collect();
    // Given out of order: merge sorts them.
    let merged = dir.join("merged");
    let mut args: Vec<&Path> = vec![Path::new("merge"), &files[2], &files[0], &files[1]];
    args.extend([Path::new("--out"), merged.as_path()]);
    ok(&args);
    let read = |d: &Path| std::fs::read(d.join("summary.json")).unwrap();
    assert_eq!(
        read(&whole),
        read(&merged),
        "merged shards must give the single machine's summary.json"
    );
    // The report embeds its detection figure under the question it answers.
    let md = std::fs::read_to_string(whole.join("report.md")).unwrap();
    assert!(md.contains("](detection.png)"), "{md}");
    let unasked = navkf_report::figure::embeds_without_question(&md);
    assert!(
        unasked.is_empty(),
        "embedded without a question: {unasked:?}"
    );

    // A shard missing, or given twice, is refused.
    let o = navkf([Path::new("merge"), &files[0], &files[1]]);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        text(&o.stderr).contains("shards [2] of 3 are missing"),
        "{}",
        text(&o.stderr)
    );
    let o = navkf([Path::new("merge"), &files[0], &files[1], &files[1]]);
    assert_eq!(o.status.code(), Some(1));
    let err = text(&o.stderr);
    assert!(
        err.contains("partial-1-of-3.json") && err.contains("given twice"),
        "{err}"
    );
    // An edited record index is refused with the field.
    let edited = dir.join("edited.json");
    let t = std::fs::read_to_string(&files[1]).unwrap();
    let t = t.replacen("\"index\":2", "\"index\":7", 1);
    std::fs::write(&edited, t).unwrap();
    let o = navkf([Path::new("merge"), &files[0], &edited, &files[2]]);
    assert_eq!(o.status.code(), Some(1));
    let err = text(&o.stderr);
    assert!(
        err.contains("edited.json") && err.contains("records[1].index = 7: expected 2"),
        "{err}"
    );
    // More shards than datasets is refused before any work.
    let o = navkf([
        Path::new("study"),
        &study,
        Path::new("--shard"),
        Path::new("0/6"),
        Path::new("--out"),
        &dir.join("too-many"),
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        text(&o.stderr).contains("5 datasets"),
        "{}",
        text(&o.stderr)
    );
}
