//! Writing a plan (`plan.json`, `plan.md`, `plan_sigma`) and a comparison of designs
//! (`designs.json`, `designs.md`, `plan_sweep`) into a results folder: the library writes
//! every result file, the command line only says what was written.

use crate::error::StudyError;
use crate::plan::{comparison_table, table, Comparison, Plan, IDENTIFIED_BELOW};
use crate::plots::plan::{draw, draw_sweep};
use navkf_report::figure::FigureOutcome;
use navkf_report::write_atomic;
use std::path::Path;

fn json<T: serde::Serialize>(value: &T) -> Result<String, StudyError> {
    serde_json::to_string_pretty(value).map_err(|e| StudyError::Other(e.to_string()))
}

/// Writes one plan's `plan.json` and `plan.md` into `dir` (made by `command`), and with
/// `figure` its `plan_sigma`; returns the figures' outcomes.
pub fn write_plan(
    p: &Plan,
    dir: &Path,
    command: &str,
    figure: bool,
) -> Result<Vec<FigureOutcome>, StudyError> {
    write_atomic(&dir.join("plan.json"), json(p)?.as_bytes())?;
    let mut md = format!(
        "# Plan of `{}`\n\nCommand: `{command}`\n\nPredicted by the truth-linearised bound \
         along run 0 of the study's seed ({:.0} s test), without Monte Carlo.\n\n```text\n{}```\n",
        p.study,
        p.duration_s,
        table(p)
    );
    let mut figures = Vec::new();
    if figure {
        let f = draw(p, dir);
        md.push_str(&format!("\n{}", f.markdown(2)));
        figures.push(f);
    }
    write_atomic(&dir.join("plan.md"), md.as_bytes())?;
    Ok(figures)
}

/// Writes a comparison of designs into `dir`: `designs.json`, `designs.md` and, for a
/// sweep's points, `plan_sweep`; returns the figures' outcomes.
pub fn write_comparison(
    comparison: &Comparison,
    dir: &Path,
    command: &str,
) -> Result<Vec<FigureOutcome>, StudyError> {
    let mut md = format!(
        "# Test designs compared\n\nCommand: `{command}`\n\nPredicted final sigma / prior \
         of every coefficient (in bold: identified, below {}); each design's plan in \
         `design-NN/`.\n\n{}",
        IDENTIFIED_BELOW,
        comparison_table(comparison)
    );
    let mut figures = Vec::new();
    if comparison.key.is_some() {
        let f = draw_sweep(comparison, dir);
        md.push_str(&format!("\n{}", f.markdown(2)));
        figures.push(f);
    }
    write_atomic(&dir.join("designs.json"), json(comparison)?.as_bytes())?;
    write_atomic(&dir.join("designs.md"), md.as_bytes())?;
    Ok(figures)
}
