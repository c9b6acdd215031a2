//! `navkf plan`: which coefficients the test of a study file identifies, predicted from the
//! information along it, without Monte Carlo (see `navkf_study::plan`). Several study files,
//! or one with a `[sweep]`, are compared design by design.

use crate::study_file::StudyFile;
use navkf_study::plan::{comparison_table, plan, table, Comparison, Design};
use navkf_study::plan_output::{write_comparison, write_plan};
use navkf_study::{Study, StudyConfig};
use rayon::prelude::*;
use std::path::PathBuf;

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
        crate::warn_undrawn(&write_plan(&p, dir, &command, true)?);
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
    // A sweep's points share one model family; files compared side by side are labelled
    // by the first's.
    let model = designs
        .first()
        .map_or(navkf_dynamics::ModelKind::Platform, |d| d.2.model.kind);
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
            let figures = write_plan(
                &p,
                &dir.join(format!("design-{i:02}")),
                &command,
                one_figure_each,
            )
            .map_err(|e| e.to_string())?;
            crate::warn_undrawn(&figures);
            Ok(Design::of(label, v, &p))
        })
        .collect::<Result<Vec<Design>, String>>()?;
    let comparison = Comparison {
        key,
        model,
        designs: planned,
    };
    let figures = write_comparison(&comparison, dir, &command)?;
    crate::warn_undrawn(&figures);
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
