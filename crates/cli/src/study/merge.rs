//! `navkf merge`: the shards of any kind of study, recognised by what they hold, checked
//! and folded into what one machine writes.

use super::*;
use navkf_report::{FolderKind, ResultsDir, StudyKind};
use navkf_study::merge::read_partials;
use navkf_study::output::{fold, write_results};
use navkf_study::Study;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct MergeArgs {
    /// Shard files written by `study --shard`.
    #[arg(required = true)]
    partials: Vec<PathBuf>,
    /// Output folder (default results/<study name>).
    #[arg(long)]
    out: Option<PathBuf>,
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

/// `navkf merge` of a sweep's shards: every point's partials checked and folded in block
/// order, its results folder written, then the sweep's files; what one machine writes.
fn merge_sweep(a: MergeArgs) -> Result<(), Box<dyn std::error::Error>> {
    use navkf_study::sweep::{self, shard as sweep_shard};
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
        model: config.model.kind,
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
