//! `navkf study` on a diagnosis study: every dataset simulated and diagnosed (or a shard
//! of them), the error rates written to `results/<name>/`.

use super::*;
use navkf_report::{ResultsDir, ShardFolder};
use std::path::PathBuf;

/// `navkf study` on a diagnosis study: every dataset simulated and diagnosed, the error rates
/// written to `results/<name>/`.
pub(super) fn run_diagnosis_study(
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

/// Each error-rate target of a diagnosis study, met or missed.
pub(super) fn say_targets(targets: &[navkf_diagnose::diagnosis_study::rates::Target]) {
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
