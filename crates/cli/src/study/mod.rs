//! `navkf study` and `navkf merge`: run a study of any kind (or a shard of it) and combine
//! shards. The study file says its kind; each kind's command is a file here.

mod diagnosis;
mod merge;
mod sweep;

use diagnosis::{run_diagnosis_study, say_targets};
pub use merge::{merge, MergeArgs};
use sweep::run_sweep;

use crate::study_file::StudyFile;
use navkf_report::progress::bar as progress_bar;
use navkf_report::{ResultsDir, ShardFolder};
use navkf_study::output::write_results;
use navkf_study::partial::{shard_blocks, Partial};
use navkf_study::{guard, Study};
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
