//! Sharding: shards run separately and merged equal the single run exactly, `merge` refuses
//! an incomplete or overlapping set of shard files, and it refuses a shard file whose counts,
//! arrays or sums do not fit the study, naming the file and the field, without panicking.

use crate::common;

use common::{short_config, temp_dir, without_timings};
use navkf_dynamics::state::NAV_DIM;
use navkf_study::merge::read_partials;
use navkf_study::output::fold;
use navkf_study::partial::{shard_blocks, Partial};
use navkf_study::tally::Tally;
use navkf_study::{Study, StudyError};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// 35 runs: 4 blocks (the last one of 5 runs), split 1 + 1 + 2 over three shards.
const RUNS: usize = 35;

/// The study, its unsharded tally (without timings) and its three shards, computed once for
/// all the tests of this file.
struct Fixture {
    study: Study,
    whole: Tally,
    parts: Vec<Partial>,
}

fn fixture() -> &'static Fixture {
    static FIXTURE: OnceLock<Fixture> = OnceLock::new();
    FIXTURE.get_or_init(|| {
        let study = Study::new(short_config(RUNS)).unwrap();
        let whole = without_timings(common::run_all(&study));
        let parts = shards(&study);
        Fixture {
            study,
            whole,
            parts,
        }
    })
}

/// The three shards as `navkf study --shard i/3` makes them, the example run in its shard.
fn shards(study: &Study) -> Vec<Partial> {
    (0..3)
        .map(|i| {
            let mut example = None;
            let blocks = study
                .run_blocks(shard_blocks(study.block_count(), i, 3), &|_| {}, |rec| {
                    example = Some(study.example_of(rec))
                })
                .expect("not interrupted");
            Partial {
                config: study.config.clone(),
                shard: (i, 3),
                blocks,
                example,
            }
        })
        .collect()
}

fn write(dir: &Path, p: &Partial) -> PathBuf {
    let path = dir.join(format!("partial-{}-of-{}.json", p.shard.0, p.shard.1));
    std::fs::write(&path, serde_json::to_string(p).unwrap()).unwrap();
    path
}

#[test]
fn merged_shards_equal_the_unsharded_study_and_merge_checks_the_set() {
    let Fixture {
        study,
        whole,
        parts,
    } = fixture();
    let whole = whole.clone();
    assert_eq!(study.block_count(), 4);
    assert_eq!(whole.runs, RUNS);
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
        read[0].example.is_some(),
        "the example run comes with shard 0"
    );
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
}

/// An edit of one shard file of a valid set: which shard, what it does to the JSON, and what
/// the refusal must say.
struct Edit {
    what: &'static str,
    shard: usize,
    edit: Box<dyn Fn(&mut Value)>,
    says: String,
}

fn edit(what: &'static str, shard: usize, f: impl Fn(&mut Value) + 'static, says: String) -> Edit {
    Edit {
        what,
        shard,
        edit: Box::new(f),
        says,
    }
}

/// The value at JSON pointer `at` (it must exist).
fn at<'a>(v: &'a mut Value, at: &str) -> &'a mut Value {
    v.pointer_mut(at)
        .unwrap_or_else(|| panic!("the shard file has {at}"))
}

/// Removes the last entry of the array at `at` (it must have one).
fn pop(v: &mut Value, at_: &str) {
    let a = at(v, at_).as_array_mut().expect("an array");
    assert!(a.pop().is_some(), "{at_} has an entry to remove");
}

/// Whether `read_partials` on `paths` refuses, without panicking, with a `Config` error on
/// `path` whose message contains `says`; if not, what it did.
fn refusal(what: &str, paths: &[PathBuf], path: &Path, says: &str) -> Result<(), String> {
    match std::panic::catch_unwind(|| read_partials(paths)) {
        Err(_) => Err(format!("{what}: merge panicked")),
        Ok(Ok(_)) => Err(format!("{what}: merge accepted the edited shard")),
        Ok(Err(StudyError::Config { path: p, message })) if p == path => {
            match message.contains(says) {
                true => Ok(()),
                false => Err(format!("{what}: the message lacks {says:?}: {message}")),
            }
        }
        Ok(Err(e)) => Err(format!("{what}: not a refusal of the edited file: {e}")),
    }
}

/// [`refusal`], asserted.
fn refused(what: &str, paths: &[PathBuf], path: &Path, says: &str) {
    if let Err(e) = refusal(what, paths, path, says) {
        panic!("{e}");
    }
}

#[test]
fn every_edited_shard_is_refused_with_the_file_and_the_field() {
    let f = fixture();
    let times = f.study.times.len();
    let last = times - 1;
    let states = f.study.names.len();
    let example_steps = f.parts[0].example.as_ref().unwrap().filters[1].t.len();
    assert!(f
        .parts
        .iter()
        .all(|p| p.blocks.iter().all(|b| b.filters.iter().all(|t| t.ok > 0))));
    let dir = temp_dir("edited-shards");
    let valid: Vec<PathBuf> = f.parts.iter().map(|p| write(&dir, p)).collect();
    let json: Vec<Value> = f
        .parts
        .iter()
        .map(|p| serde_json::to_value(p).unwrap())
        .collect();
    let example = json[0]["example"].clone();
    let edits = [
        edit(
            "a shortened array",
            2,
            move |v| pop(v, &format!("/blocks/1/filters/0/sum_sq_err/{last}")),
            format!(
                "blocks[1].filters[0].sum_sq_err[{last}] has {} values; expected {states} (one per state)",
                states - 1
            ),
        ),
        edit(
            "a shortened time series",
            0,
            |v| pop(v, "/blocks/0/filters/2/sum_nees"),
            format!(
                "blocks[0].filters[2].sum_nees has {last} values; expected {times} (one per stored time)"
            ),
        ),
        edit(
            "a shortened bound",
            1,
            |v| pop(v, "/blocks/0/bound/sum_var"),
            format!("blocks[0].bound.sum_var has {last} rows; expected {times}"),
        ),
        edit(
            "an example run with a row less",
            0,
            |v| pop(v, "/example/filters/1/estimate"),
            format!(
                "example.filters[1].estimate has {} rows; expected {example_steps} (one per time in its t)",
                example_steps - 1
            ),
        ),
        edit(
            "an example run with a short row",
            0,
            |v| pop(v, "/example/filters/0/sigma/5"),
            format!(
                "example.filters[0].sigma[5] has {} values; expected {states}",
                states - 1
            ),
        ),
        edit(
            "an example run with a name less",
            0,
            |v| pop(v, "/example/names"),
            format!("example.names has {} names; expected {states}", states - 1),
        ),
        edit(
            "an example run without truth",
            0,
            |v| *at(v, "/example/truth") = json!([]),
            "example.truth has 0 rows".into(),
        ),
        edit(
            "the example run removed",
            0,
            |v| *at(v, "/example") = Value::Null,
            "example is missing: the example run 0 (study.example_run)".into(),
        ),
        edit(
            "the example run in another shard",
            1,
            move |v| *at(v, "/example") = example.clone(),
            "example: this shard holds runs 10..20, not the example run 0".into(),
        ),
        edit(
            "an ok count beyond the runs",
            0,
            |v| *at(v, "/blocks/0/filters/1/ok") = json!(1000030),
            "blocks[0].filters[1].ok = 1000030: more than the block's 10 runs".into(),
        ),
        edit(
            "an ok count short of the runs",
            2,
            |v| *at(v, "/blocks/1/filters/0/ok") = json!(4),
            "blocks[1].filters[0]: ok = 4 and 0 diverged runs make 4; expected the block's 5 runs"
                .into(),
        ),
        edit(
            "a divergence added",
            1,
            |v| {
                let d = json!({"run": 12, "cause": "non-finite", "reason": "edited"});
                at(v, "/blocks/0/filters/2/diverged")
                    .as_array_mut()
                    .unwrap()
                    .push(d)
            },
            "blocks[0].filters[2]: ok = 10 and 1 diverged runs make 11".into(),
        ),
        edit(
            "a block's filters emptied",
            1,
            |v| *at(v, "/blocks/0/filters") = json!([]),
            "blocks[0].filters has 0 entries; expected 3 (one per filter in study.filters)".into(),
        ),
        edit(
            "a negative sum of squares",
            2,
            move |v| {
                *at(v, &format!("/blocks/0/filters/0/sum_sq_err/{last}/{NAV_DIM}")) = json!(-1e-3)
            },
            format!(
                "blocks[0].filters[0].sum_sq_err[{last}][{NAV_DIM}] = -0.001: expected a finite sum >= 0 (it adds squared errors)"
            ),
        ),
        edit(
            "a negative NEES sum",
            0,
            |v| *at(v, "/blocks/0/filters/1/sum_nees/3") = json!(-5.0),
            "blocks[0].filters[1].sum_nees[3] = -5: expected a finite sum >= 0 (it adds NEES)"
                .into(),
        ),
        edit(
            "no updates counted",
            0,
            |v| *at(v, "/blocks/0/filters/0/nis_count") = json!(0),
            "blocks[0].filters[0].nis_count = 0: expected".into(),
        ),
        edit(
            "a step cost beyond any nanoseconds",
            0,
            |v| *at(v, "/blocks/0/filters/0/step_cost") = json!({"99999": 1}),
            "blocks[0].filters[0].step_cost has bin 99999".into(),
        ),
        edit(
            "a pair of other filters",
            0,
            |v| *at(v, "/blocks/0/pairs/0/a") = json!("x"),
            "blocks[0].pairs[0] compares \"x\" with".into(),
        ),
        edit(
            "a pair counting more runs than its filters finished",
            0,
            |v| *at(v, "/blocks/0/pairs/1/n") = json!(11),
            "blocks[0].pairs[1].n = 11: expected 10 to 10 runs".into(),
        ),
        edit(
            "a wrong first_run",
            2,
            |v| *at(v, "/blocks/1/first_run") = json!(40),
            "blocks[1].first_run = 40: expected 30".into(),
        ),
        edit(
            "a wrong number of runs",
            2,
            |v| *at(v, "/blocks/1/runs") = json!(10),
            "blocks[1].runs = 10: expected 5 (the block of runs 30..35 in a study of 35 runs)"
                .into(),
        ),
        edit(
            "the last block removed",
            2,
            |v| pop(v, "/blocks"),
            "blocks has 1 entries; expected 2 (shard 2/3 holds blocks 2..4".into(),
        ),
        edit(
            "a shard index i >= n",
            1,
            |v| *at(v, "/shard") = json!([3, 3]),
            "shard = (3, 3): expected shard i of n with 0 <= i < n".into(),
        ),
        edit(
            "a shard of zero",
            1,
            |v| *at(v, "/shard") = json!([0, 0]),
            "shard = (0, 0)".into(),
        ),
        edit(
            "a shard of another split",
            1,
            // shard_blocks(4, 1, 4) is block 1 too: only the other shards' n tells.
            |v| *at(v, "/shard") = json!([1, 4]),
            "shard = (1, 4): the first shard is one of 3".into(),
        ),
    ];
    let mut wrong = Vec::new();
    for (k, e) in edits.iter().enumerate() {
        let mut v = json[e.shard].clone();
        (e.edit)(&mut v);
        let path = dir.join(format!("edit-{k}.json"));
        std::fs::write(&path, serde_json::to_string(&v).unwrap()).unwrap();
        let mut paths = valid.clone();
        paths[e.shard] = path.clone();
        wrong.extend(refusal(e.what, &paths, &path, &e.says).err());
    }
    assert!(
        wrong.is_empty(),
        "{} of {} edits:\n{}",
        wrong.len(),
        edits.len(),
        wrong.join("\n")
    );
    // The valid set still reads.
    assert!(read_partials(&valid).is_ok());
}

#[test]
fn one_shard_of_all_blocks_merges_the_same_and_a_block_missing_from_its_middle_is_refused() {
    let f = fixture();
    let dir = temp_dir("one-shard");
    let one = Partial {
        config: f.study.config.clone(),
        shard: (0, 1),
        blocks: f.parts.iter().flat_map(|p| p.blocks.clone()).collect(),
        example: f.parts[0].example.clone(),
    };
    let path = write(&dir, &one);
    let read = read_partials(std::slice::from_ref(&path)).expect("one shard of every block");
    assert!(without_timings(fold(&read[0].blocks)) == f.whole);
    let mut v = serde_json::to_value(&one).unwrap();
    at(&mut v, "/blocks").as_array_mut().unwrap().remove(1);
    std::fs::write(&path, serde_json::to_string(&v).unwrap()).unwrap();
    refused(
        "a block missing from the middle",
        std::slice::from_ref(&path),
        &path,
        "blocks[1].first_run = 20: expected 10 (shard 0/1 holds blocks 0..4 of the study's 4, 10 runs each; a block missing?)",
    );
}

#[test]
fn sums_that_are_not_finite_are_refused() {
    let f = fixture();
    // JSON holds no infinity or NaN: a number beyond the largest double is refused as it is
    // parsed, at its place in the file.
    let dir = temp_dir("non-finite");
    let mut v = serde_json::to_value(&f.parts[1]).unwrap();
    *at(&mut v, "/blocks/0/filters/0/sum_nis") = json!(123456.789);
    let text = serde_json::to_string(&v)
        .unwrap()
        .replace("123456.789", "1e999");
    let path = dir.join("huge.json");
    std::fs::write(&path, text).unwrap();
    let paths = [path.clone()];
    refused(
        "a number beyond the doubles",
        &paths,
        &path,
        "not a shard file: number out of range",
    );
    // A shard built in memory can hold them: the check names the field.
    for (bad, shown) in [(f64::INFINITY, "inf"), (f64::NAN, "NaN")] {
        let mut p = f.parts[1].clone();
        p.blocks[0].filters[2].sum_var[4][1] = bad;
        let err = navkf_study::merge::shard_check::check(&p, &f.study).unwrap_err();
        assert_eq!(
            err,
            format!("blocks[0].filters[2].sum_var[4][1] = {shown}: expected a finite sum >= 0 (it adds variances)")
        );
        let mut p = f.parts[1].clone();
        p.blocks[0].pairs[2].sum_d[NAV_DIM] = bad;
        let err = navkf_study::merge::shard_check::check(&p, &f.study).unwrap_err();
        assert_eq!(
            err,
            format!("blocks[0].pairs[2].sum_d[{NAV_DIM}] = {shown}: expected a finite sum")
        );
    }
    // Finite sums that overflow when merge adds them: refused before the fold.
    let huge = |p: &Partial| {
        let mut v = serde_json::to_value(p).unwrap();
        *at(&mut v, "/blocks/0/filters/1/sum_run_nis_sq") = json!(1e308);
        v
    };
    let paths: Vec<PathBuf> = f
        .parts
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let path = dir.join(format!("overflow-{i}.json"));
            let v = if i < 2 {
                huge(p)
            } else {
                serde_json::to_value(p).unwrap()
            };
            std::fs::write(&path, serde_json::to_string(&v).unwrap()).unwrap();
            path
        })
        .collect();
    let err = read_partials(&paths).unwrap_err().to_string();
    assert_eq!(
        err,
        "shard 1/3: its blocks bring the merged filters[1].sum_run_nis_sq to inf: sums too large for any run"
    );
}

/// The median over `runs` runs of the first filter's largest final coefficient error, in
/// initial sigmas: a divergence bound that about half the runs exceed.
fn median_final_error(runs: usize) -> f64 {
    let study = Study::new(short_config(runs)).unwrap();
    let mut ratios: Vec<f64> = (0..runs)
        .map(|r| {
            let last = study.run_one(r).filters[0].err.last().unwrap().clone();
            (NAV_DIM..last.len())
                .map(|i| last[i].abs() / study.initial_sigma[i])
                .fold(0.0, f64::max)
        })
        .collect();
    ratios.sort_by(f64::total_cmp);
    0.5 * (ratios[runs / 2 - 1] + ratios[runs / 2])
}

#[test]
fn shards_with_diverged_runs_pass_the_check() {
    // With the median bound, some runs finish and some diverge, so blocks hold filters with
    // runs left out (and pairs with fewer runs than either filter); with 1e-6, filters with
    // none finished (empty sums, no pair).
    const RUNS: usize = 20;
    for (bound, mixed) in [(median_final_error(RUNS), true), (1e-6, false)] {
        let mut c = short_config(RUNS);
        c.divergence.max_error_initial_sigmas = bound;
        let study = Study::new(c).unwrap();
        let dir = temp_dir(&format!("diverged-{mixed}"));
        let paths: Vec<PathBuf> = (0..2)
            .map(|i| {
                let mut example = None;
                let blocks = study
                    .run_blocks(shard_blocks(2, i, 2), &|_| {}, |rec| {
                        example = Some(study.example_of(rec))
                    })
                    .expect("not interrupted");
                let p = Partial {
                    config: study.config.clone(),
                    shard: (i, 2),
                    blocks,
                    example,
                };
                write(&dir, &p)
            })
            .collect();
        let read = read_partials(&paths).expect("valid shards with diverged runs");
        let total = fold(&[read[0].blocks.clone(), read[1].blocks.clone()].concat());
        let ok: Vec<u64> = total.filters.iter().map(|t| t.ok).collect();
        let diverged: Vec<usize> = total.filters.iter().map(|t| t.diverged.len()).collect();
        assert_eq!(diverged[0] + ok[0] as usize, RUNS);
        if mixed {
            assert!(
                ok[0] > 0 && diverged[0] > 0,
                "bound {bound}: {ok:?} finished"
            );
        } else {
            assert_eq!(ok, [0, 0, 0], "bound {bound}: none finishes");
        }
    }
}
