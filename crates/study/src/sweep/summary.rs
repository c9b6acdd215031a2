//! A sweep's results across points: each point's row (`sweep.json`), its results folder,
//! and `sweep.md` with the figures.

use super::point_folder;
use crate::error::StudyError;
use crate::monte_carlo::{ExampleRun, Study};
use crate::output::write_results;
use crate::summary::{paired_difference, PairedDifference, Summary, EQUIVALENCE_MARGIN};
use crate::tally::Tally;
use navkf_dynamics::state::PHI_Z;
use navkf_filters::DivergenceCause;
use navkf_report::figure::FigureOutcome;
use navkf_report::markdown::{number, Number, Table};
use navkf_report::stats::MeanChi2;
use navkf_report::write_atomic;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::fmt::Write;
use std::path::Path;

/// One filter at one point of a sweep.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PointFilter {
    /// RMS over runs of the final heading error (`phi_z`), rad.
    pub heading_rms: f64,
    /// The truth-linearised bound of the final heading error, rad.
    pub heading_bound: f64,
    /// Final RMS / bound of each coefficient.
    pub rms_over_bound: BTreeMap<String, f64>,
    /// Their geometric mean.
    pub rms_over_bound_mean: f64,
    /// Average NEES at the first stored time, when the initial error is largest.
    pub nees_early: f64,
    /// Its 95 % bounds for a consistent filter.
    pub nees_early_bounds: [f64; 2],
    /// Average NEES at the final time.
    pub nees_final: f64,
    /// Its 95 % bounds.
    pub nees_final_bounds: [f64; 2],
    /// The largest average NEES over the stored times, and when.
    pub nees_peak: f64,
    /// Time of `nees_peak`, s.
    pub nees_peak_t: f64,
    /// Runs excluded as diverged, and by cause.
    pub diverged: u64,
    /// Those runs by cause.
    pub diverged_by_cause: BTreeMap<DivergenceCause, u64>,
    /// Runs included.
    pub runs_ok: u64,
    /// Median cost of one predict + update, ns.
    pub step_ns_median: f64,
}

impl PointFilter {
    /// The average NEES at the first stored time with its bounds.
    pub fn nees_early_chi2(&self) -> MeanChi2 {
        MeanChi2 {
            mean: self.nees_early,
            bounds: self.nees_early_bounds,
        }
    }
    /// The average NEES at the final time with its bounds.
    pub fn nees_final_chi2(&self) -> MeanChi2 {
        MeanChi2 {
            mean: self.nees_final,
            bounds: self.nees_final_bounds,
        }
    }
}

/// One point of a sweep.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SweepPoint {
    /// The swept setting's value.
    pub value: f64,
    /// Its results folder, relative to the sweep's.
    pub folder: String,
    /// Per filter, by label.
    pub filters: BTreeMap<String, PointFilter>,
    /// Paired differences of the final heading error, per pair of filters.
    pub paired_heading: Vec<PairedDifference>,
    /// Paired differences of the coefficients (as in the point's `summary.json`).
    pub paired: Vec<PairedDifference>,
}

/// `sweep.json`: every point's results, side by side.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SweepSummary {
    /// Study name.
    pub study: String,
    /// The swept key.
    pub key: String,
    /// The model family the study runs (the platform unless said): the axis names the
    /// strapdown unit's `azimuth_rad` what it is, its heading.
    #[serde(
        default,
        skip_serializing_if = "navkf_dynamics::ModelKind::is_platform"
    )]
    pub model: navkf_dynamics::ModelKind,
    /// Runs per point.
    pub runs: usize,
    /// Filters, in the study's order.
    pub filters: Vec<String>,
    /// The points, in the order of the values.
    pub points: Vec<SweepPoint>,
}

/// The summary of point `index` (value `value`) from its study, tally and summary.
pub fn point(
    index: usize,
    value: f64,
    study: &Study,
    tally: &Tally,
    summary: &Summary,
) -> SweepPoint {
    let last = study.times.len() - 1;
    let n = study.names.len();
    let truth_phi_z = study.to_truth[PHI_Z];
    let bound_of = |s: usize, j: usize| {
        if tally.bound.count > 0 {
            (tally.bound.sum_var[s][j] / tally.bound.count as f64).sqrt()
        } else {
            f64::NAN
        }
    };
    let mut filters = BTreeMap::new();
    for (name, ft) in study.filter_names().iter().zip(&tally.filters) {
        let s = &summary.filters[name];
        let ok = ft.ok as f64;
        let mean_nees = |k: usize| {
            if ft.ok > 0 {
                ft.sum_nees[k] / ok
            } else {
                f64::NAN
            }
        };
        let (mut peak, mut peak_t) = (f64::NAN, f64::NAN);
        for (k, t) in study.times.iter().enumerate() {
            let v = mean_nees(k);
            if !(v <= peak) && v.is_finite() {
                (peak, peak_t) = (v, *t);
            }
        }
        let rms_over_bound: BTreeMap<String, f64> = s
            .final_rms
            .iter()
            .filter_map(|(c, r)| s.final_bound.get(c).map(|b| (c.clone(), r / b)))
            .collect();
        let logs: Vec<f64> = rms_over_bound.values().map(|v| v.ln()).collect();
        // The average NEES at stored time k, the mean of `ok` chi-square variables of n
        // degrees of freedom each, with its bounds.
        let nees_at = |k: usize| {
            if ft.ok > 0 {
                MeanChi2::of_sum(ft.sum_nees[k], ok * n as f64, ok)
            } else {
                MeanChi2::of_sum(0.0, 0.0, 0.0)
            }
        };
        let (early, last_nees) = (nees_at(0), nees_at(last));
        filters.insert(
            name.clone(),
            PointFilter {
                heading_rms: s
                    .final_rms_nav
                    .get(&study.names[PHI_Z])
                    .copied()
                    .unwrap_or(f64::NAN),
                heading_bound: truth_phi_z.map_or(f64::NAN, |j| bound_of(last, j)),
                rms_over_bound_mean: if logs.is_empty() {
                    f64::NAN
                } else {
                    (logs.iter().sum::<f64>() / logs.len() as f64).exp()
                },
                rms_over_bound,
                nees_early: early.mean,
                nees_early_bounds: early.bounds,
                nees_final: last_nees.mean,
                nees_final_bounds: last_nees.bounds,
                nees_peak: peak,
                nees_peak_t: peak_t,
                diverged: s.diverged,
                diverged_by_cause: s.diverged_by_cause.clone(),
                runs_ok: s.runs_ok,
                step_ns_median: s.step_ns_median,
            },
        );
    }
    let paired_heading = tally
        .pairs
        .iter()
        .filter(|p| p.n >= 2)
        .map(|p| paired_difference(study, tally, p, PHI_Z))
        .collect();
    SweepPoint {
        value,
        folder: point_folder(index),
        filters,
        paired_heading,
        paired: summary.paired.clone(),
    }
}

/// Writes point `index` (value `value`) of a sweep: its results folder, `point-NN/` of
/// `dir` (as any study's), and returns its row of the sweep's summary.
pub fn write_point(
    index: usize,
    value: f64,
    study: &Study,
    tally: &Tally,
    example: Option<&ExampleRun>,
    dir: &Path,
) -> Result<SweepPoint, StudyError> {
    let summary = write_results(study, tally, example, &dir.join(point_folder(index)))?;
    Ok(point(index, value, study, tally, &summary))
}

/// Writes the sweep's own files into `dir`: its figures, `sweep.json` and `sweep.md` (with
/// `command`); returns the figures' outcomes.
pub fn write_sweep(
    summary: &SweepSummary,
    state_count: usize,
    dir: &Path,
    command: &str,
) -> Result<Vec<FigureOutcome>, StudyError> {
    let figures = crate::plots::sweep::draw(summary, state_count, dir);
    let json =
        serde_json::to_string_pretty(summary).map_err(|e| StudyError::Other(e.to_string()))?;
    write_atomic(&dir.join("sweep.json"), json.as_bytes())?;
    write_atomic(
        &dir.join("sweep.md"),
        markdown(summary, command, &figures).as_bytes(),
    )?;
    Ok(figures)
}

fn cell(v: f64, digits: usize) -> String {
    number(v, Number::Fixed(digits))
}

/// `sweep.md`: the points side by side, one table per quantity, then the paired tests of the
/// heading error. `figures` are the sweep's figures; those not drawn are said so.
pub fn markdown(s: &SweepSummary, command: &str, figures: &[FigureOutcome]) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "# Sweep `{}` over `{}`\n", s.study, s.key);
    let _ = writeln!(out, "Command: `{command}`\n");
    let _ = writeln!(
        out,
        "{} points, {} runs each, the same seeds at every point and for every filter. Each \
         point's full results are in its folder (`point-NN/`).\n",
        s.points.len(),
        s.runs
    );
    for f in figures {
        let _ = writeln!(out, "{}", f.markdown(2));
    }
    type Column = fn(&PointFilter) -> String;
    let tables: [(&str, Column); 8] = [
        ("Final heading error, RMS / bound", |f| {
            cell(f.heading_rms / f.heading_bound, 3)
        }),
        ("Final heading error, RMS (deg)", |f| {
            cell(f.heading_rms.to_degrees(), 4)
        }),
        (
            "Coefficients: geometric mean over them of final RMS / bound",
            |f| cell(f.rms_over_bound_mean, 3),
        ),
        ("Average NEES at the first stored time [95 % bounds]", |f| {
            format!(
                "{} [{}, {}]",
                cell(f.nees_early, 2),
                cell(f.nees_early_bounds[0], 1),
                cell(f.nees_early_bounds[1], 1)
            )
        }),
        ("Largest average NEES over the run, and when", |f| {
            format!("{} at {} s", cell(f.nees_peak, 2), cell(f.nees_peak_t, 0))
        }),
        ("Average NEES at the end [95 % bounds]", |f| {
            format!(
                "{} [{}, {}]",
                cell(f.nees_final, 2),
                cell(f.nees_final_bounds[0], 1),
                cell(f.nees_final_bounds[1], 1)
            )
        }),
        ("Diverged runs", |f| format!("{}", f.diverged)),
        ("Median cost of one step (us)", |f| {
            cell(f.step_ns_median / 1e3, 1)
        }),
    ];
    for (title, column) in tables {
        let _ = writeln!(out, "## {title}\n");
        let mut table =
            Table::new(std::iter::once(s.key.as_str()).chain(s.filters.iter().map(String::as_str)));
        for p in &s.points {
            let cells = s
                .filters
                .iter()
                .map(|f| p.filters.get(f).map_or("-".into(), column));
            table.row(std::iter::once(format!("{:e}", p.value)).chain(cells));
        }
        out.push_str(&table.render());
        out.push('\n');
    }
    let _ = writeln!(
        out,
        "## Paired differences of the final heading error\n\nMean over runs of \
         `e_a^2 - e_b^2` (rad^2) with its 95 % confidence interval, and relative to `b`'s mean \
         squared error. The verdict is a study report's: a filter is worse where the \
         interval excludes zero and reaches beyond {margin} % of `b`'s mean squared error, \
         and the two are equal within {margin} % where the whole interval lies inside.\n",
        margin = 100.0 * EQUIVALENCE_MARGIN
    );
    let mut heading = Table::new([
        s.key.as_str(),
        "a",
        "b",
        "mean difference",
        "95 % CI",
        "relative",
        "verdict",
    ]);
    for p in &s.points {
        for d in &p.paired_heading {
            heading.row([
                format!("{:e}", p.value),
                d.a.clone(),
                d.b.clone(),
                number(d.mean_sq_err_diff, Number::Sci(3)),
                format!(
                    "[{}, {}]",
                    number(d.ci95[0], Number::Sci(3)),
                    number(d.ci95[1], Number::Sci(3))
                ),
                number(d.relative, Number::SignedPercent(2)),
                d.verdict_words(),
            ]);
        }
    }
    out.push_str(&heading.render());
    let _ = writeln!(
        out,
        "\n## Paired differences of the coefficients\n\nPer point, how many of the paired \
         tests (pairs of filters x coefficients) find one filter worse by more than \
         {margin} % of the other's mean squared error, how many more exclude zero within \
         that margin, and the largest relative difference of the first kind.\n",
        margin = 100.0 * EQUIVALENCE_MARGIN
    );
    let mut coefficients = Table::new([
        s.key.as_str(),
        "worse / tests",
        "equal but excluding zero",
        "largest relative",
    ]);
    for p in &s.points {
        let sig: Vec<&PairedDifference> = p.paired.iter().filter(|d| d.significant()).collect();
        let largest = sig
            .iter()
            .max_by(|a, b| a.relative.abs().total_cmp(&b.relative.abs()))
            .map_or("-".to_string(), |d| {
                format!(
                    "{} vs {} on {}: {}",
                    d.a,
                    d.b,
                    d.coefficient,
                    number(d.relative, Number::SignedPercent(2))
                )
            });
        let equal_but_nonzero = p
            .paired
            .iter()
            .filter(|d| d.excludes_zero() && !d.significant())
            .count();
        coefficients.row([
            format!("{:e}", p.value),
            format!("{} / {}", sig.len(), p.paired.len()),
            equal_but_nonzero.to_string(),
            largest,
        ]);
    }
    out.push_str(&coefficients.render());
    out
}
