//! `navkf plan`: which coefficients the test of a study file identifies, predicted from the
//! information along it, without Monte Carlo (see `navkf_study::plan`). Several study files,
//! or one with a `[sweep]`, are compared design by design.

use crate::study_file::StudyFile;
use navkf_report::write_atomic;
use navkf_study::plan::{comparison_table, plan, table, Comparison, Design, Plan};
use navkf_study::{Study, StudyConfig};
use rayon::prelude::*;
use std::path::{Path, PathBuf};

#[derive(clap::Args)]
pub struct Args {
    /// The study file whose test to plan (e.g. studies/paper.toml); several files, or one
    /// with a [sweep], compare designs.
    #[arg(required = true)]
    files: Vec<PathBuf>,
    /// Output folder (default results/plan/<study name>).
    #[arg(long)]
    out: Option<PathBuf>,
}

pub fn run(a: Args) -> Result<(), Box<dyn std::error::Error>> {
    let mut configs = Vec::with_capacity(a.files.len());
    for f in &a.files {
        match crate::study_file::load(f)? {
            StudyFile::MonteCarlo(config) => configs.push(*config),
            StudyFile::Diagnosis(_) => {
                return Err(format!(
                    "{}: a diagnosis study ([study] kind = \"diagnosis\"); plan predicts what \
                     the test of a Monte Carlo study file identifies (e.g. studies/paper.toml), \
                     and a diagnosis study has no single test to plan",
                    f.display()
                )
                .into());
            }
        }
    }
    let out = a
        .out
        .unwrap_or_else(|| PathBuf::from("results/plan").join(&configs[0].study.name));
    let staged = navkf_report::ResultsDir::begin(&out)?;
    let dir = staged.path();
    let started = std::time::Instant::now();
    let command = navkf_report::provenance::command_line();
    if configs.len() == 1 && configs[0].sweep.is_none() {
        let study = Study::new(configs.into_iter().next().expect("one"))?;
        let p = plan(&study)?;
        write_plan(&p, dir, &command, true)?;
        staged.commit()?;
        say!("{}", table(&p).trim_end());
        eprintln!(
            "planned {} in {:.2} s, wrote {}",
            p.study,
            started.elapsed().as_secs_f64(),
            out.display()
        );
        return Ok(());
    }
    // The designs: a sweep's points, or the files.
    let mut designs: Vec<(String, Option<f64>, StudyConfig)> = Vec::new();
    let mut key = None;
    if configs.len() == 1 {
        let c = &configs[0];
        let sweep = c.sweep.as_ref().expect("a sweep");
        key = Some(sweep.key.clone());
        for (p, v) in navkf_study::sweep::points(c)?
            .into_iter()
            .zip(&sweep.values)
        {
            designs.push((format!("{} = {v}", sweep.key), Some(*v), p));
        }
    } else {
        for (f, c) in a.files.iter().zip(configs) {
            if let Some(s) = &c.sweep {
                return Err(format!(
                    "{}: sweeps `{}`; compare several files or sweep one, not both",
                    f.display(),
                    s.key
                )
                .into());
            }
            let label = f
                .file_stem()
                .map_or_else(|| f.display().to_string(), |s| s.to_string_lossy().into());
            designs.push((label, None, c));
        }
    }
    // Every design is built, and so checked, before any planning; each is dropped at once
    // and built again when planned, so memory holds the designs in flight, not all of them.
    let build = |i: usize, label: &str, c: StudyConfig| {
        Study::new(c).map_err(|e| format!("design {i} ({label}): {e}"))
    };
    for (i, (label, _, c)) in designs.iter().enumerate() {
        if navkf_report::interrupt::requested() {
            return Err("interrupted while checking the designs".into());
        }
        build(i, label, c.clone())?;
    }
    // Files are a few designs, each worth its own figure; a sweep's points are many, and
    // its figure is the one across them.
    let one_figure_each = key.is_none();
    let planned = designs
        .into_par_iter()
        .enumerate()
        .map(|(i, (label, v, c))| {
            let study = build(i, &label, c)?;
            let p = plan(&study).map_err(|e| format!("design {label}: {e}"))?;
            write_plan(
                &p,
                &dir.join(format!("design-{i:02}")),
                &command,
                one_figure_each,
            )
            .map_err(|e| e.to_string())?;
            Ok(Design::of(label, v, &p))
        })
        .collect::<Result<Vec<Design>, String>>()?;
    let comparison = Comparison {
        key,
        designs: planned,
    };
    let mut md = format!(
        "# Test designs compared\n\nCommand: `{command}`\n\nPredicted final sigma / prior \
         of every coefficient (in bold: identified, below {}); each design's plan in \
         `design-NN/`.\n\n{}",
        navkf_study::plan::IDENTIFIED_BELOW,
        comparison_table(&comparison)
    );
    if comparison.key.is_some() {
        let f = navkf_study::plots::plan::draw_sweep(&comparison, dir);
        if f.result.is_ok() {
            md.push_str(&format!("\n![{}]({}.png)\n", f.caption, f.name));
        }
        crate::warn_undrawn(std::slice::from_ref(&f));
    }
    write_atomic(
        &dir.join("designs.json"),
        serde_json::to_string_pretty(&comparison)?.as_bytes(),
    )?;
    write_atomic(&dir.join("designs.md"), md.as_bytes())?;
    staged.commit()?;
    say!("{}", comparison_table(&comparison).trim_end());
    eprintln!(
        "planned {} designs in {:.2} s, wrote {}",
        comparison.designs.len(),
        started.elapsed().as_secs_f64(),
        out.display()
    );
    Ok(())
}

/// Writes one plan's `plan.json` and `plan.md` (and, with `figure`, `plan_sigma`) into `dir`.
fn write_plan(
    p: &Plan,
    dir: &Path,
    command: &str,
    figure: bool,
) -> Result<(), Box<dyn std::error::Error>> {
    write_atomic(
        &dir.join("plan.json"),
        serde_json::to_string_pretty(p)?.as_bytes(),
    )?;
    let mut md = format!(
        "# Plan of `{}`\n\nCommand: `{command}`\n\nPredicted by the truth-linearised bound \
         along run 0 of the study's seed ({:.0} s test), without Monte Carlo.\n\n```text\n{}```\n",
        p.study,
        p.duration_s,
        table(p)
    );
    if figure {
        let f = navkf_study::plots::plan::draw(p, dir);
        if f.result.is_ok() {
            md.push_str(&format!("\n![{}]({}.png)\n", f.caption, f.name));
        }
        crate::warn_undrawn(std::slice::from_ref(&f));
    }
    write_atomic(&dir.join("plan.md"), md.as_bytes())?;
    Ok(())
}
