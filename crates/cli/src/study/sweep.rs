//! `navkf study` on a study with a `[sweep]`: every point a study of its own, or a shard
//! of every point.

use super::*;
use navkf_report::{ResultsDir, ShardFolder};
use navkf_study::partial::Partial;
use navkf_study::{Study, StudyConfig};
use std::path::PathBuf;
use std::sync::Mutex;

/// `navkf study` on a study with a `[sweep]`: every point run as a study of its own into
/// `point-NN/` of the results folder, then `sweep.json`, `sweep.md` and the sweep's figures;
/// or, with `--shard i/n`, shard `i` of every point's blocks into one shard file.
pub(super) fn run_sweep(a: Args, config: StudyConfig) -> Result<(), Box<dyn std::error::Error>> {
    use navkf_study::sweep;
    use navkf_study::sweep::shard::{max_shards, point_blocks, SweepShard};
    if a.baseline.is_some() {
        return Err(format!(
            "--baseline applies to a single study; this one sweeps `{}` (run each point's \
             study file on its own to guard it)",
            config.sweep.as_ref().map_or("", |s| s.key.as_str())
        )
        .into());
    }
    let shard = match a.shard.as_deref() {
        None => None,
        Some(s) => {
            let most = max_shards(&config)?;
            let (i, n) = parse_shard(s, usize::MAX, "run")?;
            if n > most {
                return Err(format!(
                    "--shard {s}: the sweep's smallest point has {most} blocks of {} runs; \
                     expected at most one shard per block",
                    navkf_study::tally::BLOCK
                )
                .into());
            }
            Some((i, n))
        }
    };
    set_threads(a.threads)?;
    let key = config.sweep.as_ref().expect("a sweep").key.clone();
    let values = config.sweep.as_ref().expect("a sweep").values.clone();
    let out = a
        .out
        .unwrap_or_else(|| PathBuf::from("results").join(&config.study.name));
    // Shards share their folder (each adds its file); a whole sweep replaces its folder whole.
    let (staged, shard_folder) = match shard {
        Some(_) => (None, Some(ShardFolder::check(&out)?)),
        None => (Some(ResultsDir::begin(&out)?), None),
    };
    // Every point is built, and so checked, before the first run; each is dropped at once
    // and built again when its turn comes, so memory does not grow with the points.
    let configs = sweep::points(&config)?;
    let build = |i: usize, c: StudyConfig| {
        Study::new(c).map_err(|e| format!("sweep point {i} ({key} = {}): {e}", values[i]))
    };
    let check_bar = progress_bar(a.quiet, configs.len(), "points checked");
    check_bar.set_prefix(config.study.name.clone());
    let mut total = 0;
    for (i, c) in configs.iter().enumerate() {
        if navkf_report::interrupt::requested() {
            check_bar.finish_and_clear();
            return Err(interrupted(i, configs.len(), "points checked", &out));
        }
        let study = build(i, c.clone())?;
        let blocks = match shard {
            Some(s) => point_blocks(study.block_count(), s),
            None => 0..study.block_count(),
        };
        total += runs_in(&study, blocks);
        check_bar.set_position(i as u64 + 1);
    }
    check_bar.finish_and_clear();
    let bar = progress_bar(a.quiet, total, "runs");
    let started = std::time::Instant::now();
    let mut points = Vec::new();
    let mut partials = Vec::new();
    let mut done_before = 0;
    let mut state_count = 0;
    for (i, c) in configs.into_iter().enumerate() {
        let study = build(i, c)?;
        state_count = study.names.len();
        bar.set_prefix(format!("{} {key} = {}", config.study.name, values[i]));
        let example = Mutex::new(None);
        let progress = |done| bar.set_position((done_before + done) as u64);
        let keep_example = |rec: &navkf_study::monte_carlo::RunRecord| {
            *example.lock().expect("no panics while holding it") = Some(study.example_of(rec))
        };
        let stopped = |stop: navkf_report::Interrupted| {
            bar.finish_and_clear();
            interrupted(done_before + stop.done, total, "runs", &out)
        };
        match (shard, &staged) {
            (Some(s), _) => {
                let blocks = point_blocks(study.block_count(), s);
                let runs = runs_in(&study, blocks.clone());
                let tallies = study
                    .run_blocks(blocks, &progress, keep_example)
                    .map_err(stopped)?;
                done_before += runs;
                partials.push(Partial {
                    config: study.config.clone(),
                    shard: s,
                    blocks: tallies,
                    example: example.into_inner().expect("not poisoned"),
                });
            }
            (None, Some(staged)) => {
                let tally = study
                    .run_folded(0..study.block_count(), &progress, keep_example)
                    .map_err(stopped)?;
                done_before += study.config.study.runs;
                let example = example.into_inner().expect("not poisoned");
                points.push(sweep::write_point(
                    i,
                    values[i],
                    &study,
                    &tally,
                    example.as_ref(),
                    staged.path(),
                )?);
            }
            (None, None) => unreachable!("a whole sweep is staged"),
        }
    }
    bar.finish_and_clear();
    let wall = started.elapsed().as_secs_f64();
    if let Some((i, n)) = shard {
        let file = SweepShard {
            config: config.clone(),
            shard: (i, n),
            points: partials,
        };
        let folder = shard_folder.expect("a shard checks its folder");
        let path = folder.write(
            &format!("partial-{i}-of-{n}.json"),
            serde_json::to_string(&file)?.as_bytes(),
        )?;
        eprintln!(
            "shard {i}/{n}: {total} runs of {} points in {wall:.1} s, wrote {}",
            values.len(),
            path.display()
        );
        return Ok(());
    }
    let staged = staged.expect("a whole sweep is staged");
    let summary = sweep::SweepSummary {
        study: config.study.name.clone(),
        key: key.clone(),
        runs: config.study.runs,
        filters: config.study.filters.clone(),
        model: config.model.kind,
        points,
    };
    let command = navkf_report::provenance::command_line();
    let figures = sweep::write_sweep(&summary, state_count, staged.path(), &command)?;
    crate::warn_undrawn(&figures);
    staged.commit()?;
    eprintln!(
        "{} points x {} runs in {wall:.1} s, wrote {}",
        summary.points.len(),
        summary.runs,
        out.display()
    );
    Ok(())
}

/// Runs in `blocks` of `study`.
fn runs_in(study: &Study, blocks: std::ops::Range<usize>) -> usize {
    let block = navkf_study::tally::BLOCK;
    let runs = study.config.study.runs;
    (blocks.end * block).min(runs) - (blocks.start * block).min(runs)
}
