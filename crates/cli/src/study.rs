//! `navkf study` and `navkf merge`: run a Monte Carlo study (or a shard of it) and combine
//! shards.

use crate::study_file::StudyFile;
use indicatif::{ProgressBar, ProgressStyle};
use navkf_report::{FolderKind, ResultsDir, ShardFolder, StudyKind};
use navkf_study::output::{fold, read_partials, shard_blocks, write_results, Partial};
use navkf_study::{guard, Study, StudyConfig};
use std::path::PathBuf;
use std::sync::Mutex;

#[derive(clap::Args)]
pub struct Args {
    /// The study file, e.g. studies/paper.toml.
    file: PathBuf,
    /// Override the number of runs.
    #[arg(long)]
    runs: Option<usize>,
    /// Output folder (default results/<study name>).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Run only shard i of n (`--shard 0/4`) and write its partial tallies for `merge`.
    #[arg(long)]
    shard: Option<String>,
    /// Worker threads (default: all cores). Results do not depend on it.
    #[arg(long)]
    threads: Option<usize>,
    /// No progress bar.
    #[arg(long)]
    quiet: bool,
    /// Compare the results with a baseline summary.json (same study file and seed) and fail
    /// with a table of what got worse (the CI accuracy guard: see navkf_study::guard).
    #[arg(long)]
    baseline: Option<PathBuf>,
}

#[derive(clap::Args)]
pub struct MergeArgs {
    /// Shard files written by `study --shard`.
    #[arg(required = true)]
    partials: Vec<PathBuf>,
    /// Output folder (default results/<study name>).
    #[arg(long)]
    out: Option<PathBuf>,
}

/// `--shard i/n` of a study of `units` runs or datasets (`what`): at most one shard per
/// unit (more would be empty, and an absurd n overflowed the block arithmetic).
fn parse_shard(s: &str, units: usize, what: &str) -> Result<(usize, usize), String> {
    let (i, n) = s
        .split_once('/')
        .ok_or_else(|| format!("--shard {s}: expected i/n, e.g. 0/4"))?;
    let i: usize = i
        .trim()
        .parse()
        .map_err(|_| format!("--shard {s}: `{i}` is not a whole number"))?;
    let n: usize = n
        .trim()
        .parse()
        .map_err(|_| format!("--shard {s}: `{n}` is not a whole number"))?;
    if n == 0 || i >= n {
        return Err(format!("--shard {s}: expected 0 <= i < n"));
    }
    if n > units {
        return Err(format!(
            "--shard {s}: the study has {units} {what}s; expected at most one shard per {what}"
        ));
    }
    Ok((i, n))
}

/// A progress bar over `total` `what` (runs, datasets), or a hidden one with `quiet`.
fn progress_bar(quiet: bool, total: usize, what: &str) -> ProgressBar {
    let bar = if quiet {
        ProgressBar::hidden()
    } else {
        ProgressBar::new(total as u64)
    };
    bar.set_style(
        ProgressStyle::with_template(&format!(
            "{{prefix}} [{{bar:40}}] {{pos}}/{{len}} {what}, {{elapsed}} elapsed, ETA {{eta}}"
        ))
        .expect("a valid template")
        .progress_chars("=> "),
    );
    bar
}

pub fn run(a: Args) -> Result<(), Box<dyn std::error::Error>> {
    let mut config = match crate::study_file::load(&a.file)? {
        StudyFile::Diagnosis(config) => return run_diagnosis_study(a, *config),
        StudyFile::MonteCarlo(config) => *config,
    };
    if let Some(r) = a.runs {
        if r == 0 {
            return Err("--runs 0: expected at least one run".into());
        }
        config.study.runs = r;
        config.study.example_run = config.study.example_run.min(r - 1);
    }
    if config.sweep.is_some() {
        return run_sweep(a, config);
    }
    let shard = a
        .shard
        .as_deref()
        .map(|s| parse_shard(s, config.study.runs, "run"))
        .transpose()?;
    let baseline = match &a.baseline {
        Some(_) if shard.is_some() => {
            return Err("--baseline compares a whole study: it cannot be used with --shard".into())
        }
        Some(path) => Some((path, guard::load_baseline(path)?)),
        None => None,
    };
    if let Some((path, base)) = &baseline {
        let diffs = guard::settings_differences(base, &config);
        if !diffs.is_empty() {
            return Err(format!(
                "{}: the baseline was made with other settings than this run ({}); the guard compares the same study and seed: rerun without --runs, or regenerate the baseline (see the study file's header)",
                path.display(),
                diffs.join("; ")
            )
            .into());
        }
    }
    set_threads(a.threads)?;
    let out = a
        .out
        .unwrap_or_else(|| PathBuf::from("results").join(&config.study.name));
    let study = Study::new(config)?;
    // Shards share their folder (each adds its file); a whole study replaces its folder whole.
    let (staged, shard_folder) = match shard {
        Some(_) => (None, Some(ShardFolder::check(&out)?)),
        None => (Some(ResultsDir::begin(&out)?), None),
    };
    let blocks = match shard {
        Some((i, n)) => shard_blocks(study.block_count(), i, n),
        None => 0..study.block_count(),
    };
    let total_runs: usize = blocks
        .clone()
        .map(|b| {
            ((b + 1) * navkf_study::tally::BLOCK).min(study.config.study.runs)
                - b * navkf_study::tally::BLOCK
        })
        .sum();
    let bar = progress_bar(a.quiet, total_runs, "runs");
    bar.set_prefix(study.config.study.name.clone());
    let example = Mutex::new(None);
    let started = std::time::Instant::now();
    let progress = |done| bar.set_position(done as u64);
    let keep_example = |rec: &navkf_study::monte_carlo::RunRecord| {
        *example.lock().expect("no panics while holding it") = Some(study.example_of(rec))
    };
    // A shard keeps its blocks for `merge`; a whole study folds them as they complete.
    let ran = match shard {
        Some(_) => study
            .run_blocks(blocks, &progress, keep_example)
            .map(|tallies| (tallies, Default::default())),
        None => study
            .run_folded(blocks, &progress, keep_example)
            .map(|tally| (Vec::new(), tally)),
    };
    bar.finish_and_clear();
    let (tallies, tally) = ran.map_err(|stop| interrupted(stop.done, stop.total, "runs", &out))?;
    let example = example.into_inner().expect("not poisoned");
    let wall = started.elapsed().as_secs_f64();
    match shard {
        Some((i, n)) => {
            let partial = Partial {
                config: study.config.clone(),
                shard: (i, n),
                blocks: tallies,
                example,
            };
            let folder = shard_folder.expect("a shard checks its folder");
            let path = folder.write(
                &format!("partial-{i}-of-{n}.json"),
                serde_json::to_string(&partial)?.as_bytes(),
            )?;
            eprintln!(
                "shard {i}/{n}: {total_runs} runs in {wall:.1} s, wrote {}",
                path.display()
            );
        }
        None => {
            let staged = staged.expect("a whole study is staged");
            let summary = write_results(&study, &tally, example.as_ref(), staged.path())?;
            staged.commit()?;
            eprintln!(
                "{} runs in {wall:.1} s, wrote {}",
                tally.runs,
                out.display()
            );
            say!("{}", navkf_study::report::table(&summary).trim_end());
            if let Some((path, base)) = &baseline {
                let report = guard::compare(base, &summary, guard::DEFAULT_K);
                say!("{}", report.table().trim_end());
                if !report.passed() {
                    return Err(format!(
                        "accuracy guard: {} of {} checks worse than {} (table above)",
                        report.worse.len(),
                        report.checks,
                        path.display()
                    )
                    .into());
                }
            }
        }
    }
    Ok(())
}

pub fn merge(a: MergeArgs) -> Result<(), Box<dyn std::error::Error>> {
    match shard_kind(&a.partials[0])? {
        ShardKind::Diagnosis => return merge_diagnosis_study(a),
        ShardKind::Sweep => return merge_sweep(a),
        ShardKind::MonteCarlo => {}
    }
    let parts = read_partials(&a.partials)?;
    let config = parts[0].config.clone();
    let out = a
        .out
        .unwrap_or_else(|| PathBuf::from("results").join(&config.study.name));
    let study = Study::new(config)?;
    // The shard folder itself may take the results: they keep the shard files they came from.
    let staged = ResultsDir::begin_kind(&out, FolderKind::Results, &[FolderKind::Shards])?;
    let blocks: Vec<_> = parts
        .iter()
        .flat_map(|p| p.blocks.iter().cloned())
        .collect();
    let example = parts.iter().find_map(|p| p.example.clone());
    let tally = fold(&blocks);
    let summary = write_results(&study, &tally, example.as_ref(), staged.path())?;
    // The shard files it merged stay beside the results they made.
    staged.carry_over(|name| name.starts_with("partial-") && name.ends_with(".json"))?;
    staged.commit()?;
    eprintln!(
        "merged {} shards ({} runs) into {}",
        parts.len(),
        tally.runs,
        out.display()
    );
    say!("{}", navkf_study::report::table(&summary).trim_end());
    Ok(())
}

/// What a shard file holds.
#[derive(PartialEq)]
enum ShardKind {
    MonteCarlo,
    Sweep,
    Diagnosis,
}

/// The kind of study a shard file ran: its `kind` (absent in a Monte Carlo study's shard),
/// and for a Monte Carlo study whether its `config` sweeps. A file that is not JSON is left
/// to the Monte Carlo reader, which names what is wrong.
fn shard_kind(path: &std::path::Path) -> Result<ShardKind, Box<dyn std::error::Error>> {
    #[derive(serde::Deserialize)]
    struct Head {
        #[serde(default)]
        kind: StudyKind,
        #[serde(default)]
        config: Option<HeadConfig>,
    }
    #[derive(serde::Deserialize)]
    struct HeadConfig {
        #[serde(default)]
        sweep: Option<serde::de::IgnoredAny>,
    }
    let text =
        navkf_dynamics::input_file::read_text(path, &navkf_dynamics::input_file::TextFile::SHARD)?;
    let Ok(head) = serde_json::from_str::<Head>(&text) else {
        return Ok(ShardKind::MonteCarlo);
    };
    Ok(match head.kind {
        StudyKind::Diagnosis => ShardKind::Diagnosis,
        StudyKind::MonteCarlo if head.config.is_some_and(|c| c.sweep.is_some()) => ShardKind::Sweep,
        StudyKind::MonteCarlo => ShardKind::MonteCarlo,
    })
}

/// `navkf merge` of a diagnosis study's shards: checked to tile one run, then the report a
/// single machine writes.
fn merge_diagnosis_study(a: MergeArgs) -> Result<(), Box<dyn std::error::Error>> {
    use navkf_diagnose::diagnosis_study::{report, shard};
    let (config, records) = shard::merge(&a.partials)?;
    let out = a
        .out
        .unwrap_or_else(|| PathBuf::from("results").join(&config.study.name));
    let staged = ResultsDir::begin_kind(&out, FolderKind::Results, &[FolderKind::Shards])?;
    let command = navkf_report::provenance::command_line();
    let summary = report::write(&config, records, staged.path(), &command, None)?;
    staged.carry_over(|name| name.starts_with("partial-") && name.ends_with(".json"))?;
    staged.commit()?;
    eprintln!(
        "merged {} shards ({} datasets) into {}",
        a.partials.len(),
        summary.records.len(),
        out.display()
    );
    say_targets(&summary.rates.targets);
    Ok(())
}

/// Each error-rate target of a diagnosis study, met or missed.
fn say_targets(targets: &[navkf_diagnose::diagnosis_study::rates::Target]) {
    for t in targets {
        say!(
            "{} {}: {} (target {})",
            if t.met { "met    " } else { "MISSED " },
            t.what,
            t.measured,
            t.target
        );
    }
}

/// `navkf study` on a diagnosis study: every dataset simulated and diagnosed, the error rates
/// written to `results/<name>/`.
fn run_diagnosis_study(
    a: Args,
    config: navkf_diagnose::diagnosis_study::DiagnosisStudyConfig,
) -> Result<(), Box<dyn std::error::Error>> {
    use navkf_diagnose::diagnosis_study::shard::DiagnosisShard;
    use navkf_diagnose::diagnosis_study::{dataset_count, report, run};
    if a.baseline.is_some() {
        return Err("--baseline applies to Monte Carlo studies, not to a diagnosis study".into());
    }
    let total = dataset_count(&config);
    let count = match a.runs {
        Some(0) => return Err("--runs 0: expected at least one dataset".into()),
        Some(r) => r.min(total),
        None => total,
    };
    let shard = a
        .shard
        .as_deref()
        .map(|s| parse_shard(s, count, "dataset"))
        .transpose()?;
    set_threads(a.threads)?;
    let out = a
        .out
        .unwrap_or_else(|| PathBuf::from("results").join(&config.study.name));
    // Shards share their folder (each adds its file); a whole study replaces its folder whole.
    let (staged, shard_folder) = match shard {
        Some(_) => (None, Some(ShardFolder::check(&out)?)),
        None => (Some(ResultsDir::begin(&out)?), None),
    };
    let datasets = match shard {
        Some((i, n)) => navkf_report::executor::shard_range(count, i, n),
        None => 0..count,
    };
    let bar = progress_bar(a.quiet, datasets.len(), "datasets");
    bar.set_prefix(config.study.name.clone());
    let started = std::time::Instant::now();
    let records =
        run(&config, Some(datasets), &|d| bar.set_position(d as u64)).map_err(|e| match e {
            navkf_diagnose::DiagnoseError::Report(navkf_report::ReportError::Interrupted(
                navkf_report::Interrupted { done, total, what },
            )) => interrupted(done, total, what, &out),
            e => e.into(),
        })?;
    bar.finish_and_clear();
    let timing = report::Timing {
        wall_s: started.elapsed().as_secs_f64(),
        threads: rayon::current_num_threads(),
    };
    if let Some((i, n)) = shard {
        let folder = shard_folder.expect("a shard checks its folder");
        let diagnosed = records.len();
        let part = DiagnosisShard::new(&config, (i, n), count, records);
        let path = folder.write(
            &format!("partial-{i}-of-{n}.json"),
            serde_json::to_string(&part)?.as_bytes(),
        )?;
        eprintln!(
            "shard {i}/{n}: {diagnosed} datasets in {:.0} s, wrote {}",
            timing.wall_s,
            path.display()
        );
        return Ok(());
    }
    let staged = staged.expect("a whole study is staged");
    let command = navkf_report::provenance::command_line();
    let summary = report::write(&config, records, staged.path(), &command, Some(timing))?;
    staged.commit()?;
    eprintln!(
        "diagnosed {} datasets in {:.0} s, wrote {}",
        summary.records.len(),
        timing.wall_s,
        out.display()
    );
    say_targets(&summary.rates.targets);
    Ok(())
}

/// `navkf study` on a study with a `[sweep]`: every point run as a study of its own into
/// `point-NN/` of the results folder, then `sweep.json`, `sweep.md` and the sweep's figures;
/// or, with `--shard i/n`, shard `i` of every point's blocks into one shard file.
fn run_sweep(a: Args, config: StudyConfig) -> Result<(), Box<dyn std::error::Error>> {
    use navkf_study::sweep;
    use navkf_study::sweep_shard::{max_shards, point_blocks, SweepShard};
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

/// `navkf merge` of a sweep's shards: every point's partials checked and folded in block
/// order, its results folder written, then the sweep's files; what one machine writes.
fn merge_sweep(a: MergeArgs) -> Result<(), Box<dyn std::error::Error>> {
    use navkf_study::{sweep, sweep_shard};
    let (config, per_point) = sweep_shard::read(&a.partials)?;
    let sweep_table = config
        .sweep
        .clone()
        .expect("a sweep's shard has its [sweep]");
    let out = a
        .out
        .unwrap_or_else(|| PathBuf::from("results").join(&config.study.name));
    let staged = ResultsDir::begin_kind(&out, FolderKind::Results, &[FolderKind::Shards])?;
    let mut points = Vec::with_capacity(per_point.len());
    let mut state_count = 0;
    for (i, parts) in per_point.into_iter().enumerate() {
        let study = Study::new(parts[0].config.clone())?;
        state_count = study.names.len();
        let blocks: Vec<_> = parts
            .iter()
            .flat_map(|p| p.blocks.iter().cloned())
            .collect();
        let example = parts.iter().find_map(|p| p.example.clone());
        let tally = fold(&blocks);
        points.push(sweep::write_point(
            i,
            sweep_table.values[i],
            &study,
            &tally,
            example.as_ref(),
            staged.path(),
        )?);
    }
    let summary = sweep::SweepSummary {
        study: config.study.name.clone(),
        key: sweep_table.key.clone(),
        runs: config.study.runs,
        filters: config.study.filters.clone(),
        points,
    };
    let command = navkf_report::provenance::command_line();
    let figures = sweep::write_sweep(&summary, state_count, staged.path(), &command)?;
    crate::warn_undrawn(&figures);
    staged.carry_over(|name| name.starts_with("partial-") && name.ends_with(".json"))?;
    staged.commit()?;
    eprintln!(
        "merged {} shards of {} points into {}",
        a.partials.len(),
        summary.points.len(),
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
/// The error of a study stopped by Ctrl-C: what was done, and that `out` is as it was.
fn interrupted(
    done: usize,
    total: usize,
    what: &'static str,
    out: &std::path::Path,
) -> Box<dyn std::error::Error> {
    let kept = if out.exists() {
        format!("{} is as it was", out.display())
    } else {
        format!("{} was not created", out.display())
    };
    format!(
        "{}; {kept}",
        navkf_report::Interrupted { done, total, what }
    )
    .into()
}

/// Most worker threads `--threads` takes, per core of the machine: more only adds start-up
/// time and memory (each thread has its own stack), and 100 000 took minutes to start.
const THREADS_PER_CORE: usize = 8;

/// Sets the worker threads of every parallel loop to `threads` (default: one per core),
/// refusing a count beyond [`THREADS_PER_CORE`] per core before any work.
fn set_threads(threads: Option<usize>) -> Result<(), Box<dyn std::error::Error>> {
    let Some(t) = threads else {
        return Ok(());
    };
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let most = (THREADS_PER_CORE * cores).max(16);
    if t == 0 || t > most {
        return Err(format!(
            "--threads {t}: expected 1 to {most} ({THREADS_PER_CORE} per core; this machine has \
             {cores}); results do not depend on it"
        )
        .into());
    }
    rayon::ThreadPoolBuilder::new()
        .num_threads(t)
        .build_global()?;
    Ok(())
}
