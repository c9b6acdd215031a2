//! Figures of a study, each written as PNG and SVG into the results folder:
//!
//! - `estimates_<coefficient>`: the example run's estimate of one coefficient by every filter,
//!   with its +-1 sigma band, against the true value (the paper's Figures 2 and 3);
//!   `estimates_all` puts every coefficient in one grid.
//! - `rms_over_time`: RMS error over runs of every coefficient against time, divided by the
//!   coefficient's initial sigma so all share one log axis, with the truth-linearised bound.
//! - `step_cost`: median and 90th percentile of one predict + update, and the distribution.
//! - `nees_nis_over_time`: average NEES and NIS against time with their 95 % chi-square bands.
//!
//! They are drawn with the figure kit of `navkf-report` (bundled font, panels, grids).
//! Degenerate data (a filter with every run diverged, NaN, a zero range, a single stored time)
//! gives an empty or partial panel with a note, never a panic.

pub mod plan;
pub mod sweep;

use crate::monte_carlo::{ExampleRun, Study};
use crate::summary::Summary;
use crate::tally::{bin_value, Tally};
use navkf_dynamics::state::NAV_DIM;
use navkf_report::figure::*;
pub use navkf_report::figure::{register_font, FigureOutcome};
use navkf_report::stats::mean_chi2_bounds;
use navkf_report::ReportError;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

/// Title of `rms_over_time`.
pub const RMS_TITLE: &str = "RMS error over time, divided by the initial sigma";
/// Title of `step_cost`.
pub const STEP_COST_TITLE: &str = "Cost of one filter step (predict + update)";
/// Title of `nees_nis_over_time`.
pub const NEES_NIS_TITLE: &str = "Average NEES and NIS over time, with 95 % bands";
/// Title of `estimates_all` (followed by the run index).
pub const ESTIMATES_ALL_TITLE: &str = "Coefficient estimates against the truth";

/// Draws every figure into `dir`. A figure that fails (or panics) is reported in its outcome;
/// the others are still drawn.
pub fn write_all(
    study: &Study,
    tally: &Tally,
    summary: &Summary,
    example: Option<&ExampleRun>,
    dir: &Path,
) -> Vec<FigureOutcome> {
    let mut out = Vec::new();
    let mut run = |name: String, caption: String, f: &dyn Fn() -> Result<(), ReportError>| {
        out.push(outcome(name, caption, f));
    };
    if let Some(ex) = example {
        run(
            "estimates_all".into(),
            format!(
                "Estimates of every coefficient against the truth, run {}",
                ex.run
            ),
            &|| estimates_all(study, ex, dir),
        );
        for i in NAV_DIM..ex.names.len() {
            run(
                format!("estimates_{}", ex.names[i]),
                format!("{} in run {}", ex.names[i], ex.run),
                &|| estimates(study, ex, i, dir),
            );
        }
    }
    run(
        "rms_over_time".into(),
        "RMS error over time / initial sigma, with the bound".into(),
        &|| rms_over_time(study, tally, dir),
    );
    run(
        "nees_nis_over_time".into(),
        "Average NEES and NIS over time with 95 % bands".into(),
        &|| nees_nis_over_time(study, tally, dir),
    );
    run(
        "step_cost".into(),
        "Cost of one filter step".into(),
        &|| step_cost(study, tally, summary, dir),
    );
    out
}

/// `estimates_<name>`: the example run's estimates of coefficient `i` (a filter state index)
/// by every filter, with +-1 sigma bands, against the true value.
pub fn estimates(study: &Study, ex: &ExampleRun, i: usize, dir: &Path) -> Result<(), ReportError> {
    let name = ex
        .names
        .get(i)
        .ok_or_else(|| ReportError::Figure(format!("estimates: no state {i}")))?;
    render(
        dir,
        &format!("estimates_{name}"),
        &Fig::Estimates { study, ex, i },
    )
}

/// `estimates_all`: one small panel per coefficient.
pub fn estimates_all(study: &Study, ex: &ExampleRun, dir: &Path) -> Result<(), ReportError> {
    render(dir, "estimates_all", &Fig::EstimatesAll { study, ex })
}

/// `rms_over_time`: one log panel per coefficient.
pub fn rms_over_time(study: &Study, tally: &Tally, dir: &Path) -> Result<(), ReportError> {
    render(dir, "rms_over_time", &Fig::Rms { study, tally })
}

/// `step_cost`: median and p90 per filter (from the summary), and the distributions.
pub fn step_cost(
    study: &Study,
    tally: &Tally,
    summary: &Summary,
    dir: &Path,
) -> Result<(), ReportError> {
    render(
        dir,
        "step_cost",
        &Fig::StepCost {
            study,
            tally,
            summary,
        },
    )
}

/// `nees_nis_over_time`: average NEES and NIS per filter with their 95 % bands.
pub fn nees_nis_over_time(study: &Study, tally: &Tally, dir: &Path) -> Result<(), ReportError> {
    render(dir, "nees_nis_over_time", &Fig::NeesNis { study, tally })
}

// ---------------------------------------------------------------------------------------------
// Units

const G: f64 = 9.80665;
const RAD_S_TO_DEG_H: f64 = 180.0 / std::f64::consts::PI * 3600.0;

/// The factor and unit a state is shown in: deg/h for drifts, deg/h/g for g-sensitive drifts,
/// micro-g for accelerometer biases, ppm for scale factors; other units as they are.
pub fn display_unit(unit: &str) -> (f64, String) {
    match unit {
        "rad/s" => (RAD_S_TO_DEG_H, "deg/h".into()),
        "rad/s/(m/s^2)" => (RAD_S_TO_DEG_H * G, "deg/h/g".into()),
        "m/s^2" => (1e6 / G, "µg".into()),
        "1" => (1e6, "ppm".into()),
        "rad" => (RAD_S_TO_DEG_H, "arcsec".into()),
        "" => (1.0, "-".into()),
        u => (1.0, u.into()),
    }
}

fn unit_of(study: &Study, i: usize) -> (f64, String) {
    display_unit(study.filter_model.units().get(i).map_or("", String::as_str))
}

// ---------------------------------------------------------------------------------------------
// The figures' data

/// `big`: the single figure (full caption, large type); else a grid cell.
fn estimate_panel(study: &Study, ex: &ExampleRun, i: usize, big: bool) -> Panel {
    let name = &ex.names[i];
    let (scale, unit) = unit_of(study, i);
    let (caption, sizes) = if big {
        (format!("{name}: estimate vs truth, run {}", ex.run), BIG)
    } else {
        (name.clone(), SMALL)
    };
    let mut p = Panel::new(
        caption,
        "time (s)",
        format!("{name} ({unit})"),
        Scale::Linear,
        sizes,
    );
    let truth: Vec<(f64, f64)> =
        ex.t.iter()
            .zip(&ex.truth)
            .map(|(t, r)| (*t, r.get(i).copied().unwrap_or(f64::NAN) * scale))
            .collect();
    let truth_at_start = truth.iter().map(|q| q.1).find(|v| v.is_finite());
    for (k, f) in ex.filters.iter().enumerate() {
        let c = color(k);
        let pts: Vec<(f64, f64, f64)> =
            f.t.iter()
                .zip(f.estimate.iter().zip(&f.sigma))
                .map(|(t, (x, s))| {
                    let x = x.get(i).copied().unwrap_or(f64::NAN) * scale;
                    let s = s.get(i).copied().unwrap_or(f64::NAN) * scale;
                    (*t, x, s)
                })
                .collect();
        if !pts.iter().any(|q| q.1.is_finite()) {
            p.notes
                .push(format!("{}: no estimates in this run", f.name));
            continue;
        }
        p.bands.push(Band {
            style: c.mix(0.13).filled(),
            pts: pts.iter().map(|q| (q.0, q.1 - q.2, q.1 + q.2)).collect(),
        });
        p.line(
            filter_line(k, ex.filters.len()),
            false,
            pts.iter().map(|q| (q.0, q.1)).collect(),
        );
    }
    match truth_at_start {
        Some(_) => p.line(BLACK.stroke_width(2), true, truth),
        None if ex.t.is_empty() => p.notes.push("no true values recorded".into()),
        None => p
            .notes
            .push(format!("the truth model has no {name}: no true value")),
    }
    let s0 = study.initial_sigma.get(i).copied().unwrap_or(f64::NAN) * scale;
    if s0.is_finite() && s0 > 0.0 {
        let c = truth_at_start.unwrap_or(0.0);
        p.y_limit = Some((c - 6.0 * s0, c + 6.0 * s0));
    }
    p
}

fn estimate_legend(ex: &ExampleRun) -> Vec<Entry> {
    let mut e: Vec<Entry> = ex
        .filters
        .iter()
        .enumerate()
        .map(|(k, f)| Entry {
            label: format!("{} estimate", f.name),
            style: filter_line(k, ex.filters.len()),
            mark: Mark::Line,
        })
        .collect();
    e.push(Entry {
        label: "±1 sigma (filter's own)".into(),
        style: GREY.mix(0.3).filled(),
        mark: Mark::Box,
    });
    e.push(Entry {
        label: "true value".into(),
        style: BLACK.stroke_width(2),
        mark: Mark::Dashed,
    });
    e
}

fn rms_panel(study: &Study, tally: &Tally, i: usize) -> Panel {
    let name = &study.names[i];
    let s0 = study.initial_sigma.get(i).copied().unwrap_or(f64::NAN);
    let (norm, caption) = if s0.is_finite() && s0 > 0.0 {
        (s0, name.clone())
    } else {
        (1.0, format!("{name} (not normalised)"))
    };
    let mut p = Panel::new(
        caption,
        "time (s)",
        "RMS error / initial sigma".into(),
        Scale::Log,
        SMALL,
    );
    for (k, (fname, ft)) in study.filter_names().iter().zip(&tally.filters).enumerate() {
        if ft.ok == 0 {
            p.notes.push(format!("{fname}: no run finished"));
            continue;
        }
        let ok = ft.ok as f64;
        let pts = study
            .times
            .iter()
            .enumerate()
            .map(|(s, t)| {
                let v = ft.sum_sq_err.get(s).and_then(|r| r.get(i)).copied();
                (*t, v.map_or(f64::NAN, |v| (v / ok).sqrt() / norm))
            })
            .collect();
        p.line(filter_line(k, study.filter_names().len()), false, pts);
    }
    if let (true, Some(Some(j))) = (tally.bound.count > 0, study.to_truth.get(i)) {
        let n = tally.bound.count as f64;
        let pts = study
            .times
            .iter()
            .enumerate()
            .map(|(s, t)| {
                let v = tally.bound.sum_var.get(s).and_then(|r| r.get(*j)).copied();
                (*t, v.map_or(f64::NAN, |v| (v / n).sqrt() / norm))
            })
            .collect();
        p.line(BLACK.stroke_width(2), true, pts);
    }
    p
}

/// The 95 % band of the average NIS over one stored interval: the window mean over about `w`
/// updates of `d` degrees of freedom each, averaged over `ok` runs.
fn nis_window_stats(study: &Study, ft: &crate::tally::FilterTally) -> Option<(f64, [f64; 2])> {
    if ft.ok == 0 || ft.nis_count == 0 || study.times.is_empty() {
        return None;
    }
    let d = ft.nis_dof as f64 / ft.nis_count as f64;
    let w = ft.nis_count as f64 / (ft.ok as f64 * study.times.len() as f64);
    let n = ft.ok as f64 * w;
    Some((d, mean_chi2_bounds(n * d, n)))
}

/// The NEES or NIS panel; `nis` picks which.
fn consistency_panel(study: &Study, tally: &Tally, nis: bool) -> (Panel, Vec<Entry>) {
    let what = if nis { "NIS" } else { "NEES" };
    let caption = if nis {
        "NIS averaged over each stored interval and over runs"
    } else {
        "NEES averaged over runs"
    };
    let mut p = Panel::new(
        caption.into(),
        "time (s)",
        format!("average {what} (dimensionless)"),
        Scale::Log,
        BIG,
    );
    let mut legend = Vec::new();
    let mut bands: Vec<(usize, f64, [f64; 2])> = Vec::new();
    let (t0, t1) = match (study.times.first(), study.times.last()) {
        (Some(a), Some(b)) => (*a, *b),
        _ => (0.0, 0.0),
    };
    for (k, (fname, ft)) in study.filter_names().iter().zip(&tally.filters).enumerate() {
        legend.push(Entry {
            label: fname.clone(),
            style: filter_line(k, study.filter_names().len()),
            mark: Mark::Line,
        });
        if ft.ok == 0 {
            p.notes.push(format!("{fname}: no run finished"));
            continue;
        }
        let ok = ft.ok as f64;
        let (sums, dof, bound) = if nis {
            match nis_window_stats(study, ft) {
                Some((d, b)) => (&ft.sum_nis_window, d, b),
                None => {
                    p.notes.push(format!("{fname}: no updates"));
                    continue;
                }
            }
        } else {
            let n = study.names.len() as f64;
            (&ft.sum_nees, n, mean_chi2_bounds(ok * n, ok))
        };
        let pts = study
            .times
            .iter()
            .enumerate()
            .map(|(s, t)| (*t, sums.get(s).map_or(f64::NAN, |v| v / ok)))
            .collect();
        p.line(filter_line(k, study.filter_names().len()), false, pts);
        bands.push((k, dof, bound));
    }
    let same = bands.windows(2).all(|w| {
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * a.abs().max(b.abs());
        close(w[0].1, w[1].1) && close(w[0].2[0], w[1].2[0]) && close(w[0].2[1], w[1].2[1])
    });
    let flat = |v: f64| vec![(t0, v), (t1, v)];
    if same {
        if let Some(&(_, dof, b)) = bands.first() {
            p.bands.push(Band {
                style: GREY.mix(0.18).filled(),
                pts: vec![(t0, b[0], b[1]), (t1, b[0], b[1])],
            });
            p.line(GREY.stroke_width(1), true, flat(dof));
            p.y_include.extend([b[0], b[1]]);
            legend.push(Entry {
                label: "95 % band of a consistent filter".into(),
                style: GREY.mix(0.3).filled(),
                mark: Mark::Box,
            });
            legend.push(Entry {
                label: format!("expected value ({})", tick(dof, 0.0)),
                style: GREY.stroke_width(1),
                mark: Mark::Dashed,
            });
        }
    } else {
        for &(k, dof, b) in &bands {
            p.line(color(k).stroke_width(1), true, flat(b[0]));
            p.line(color(k).stroke_width(1), true, flat(b[1]));
            p.line(GREY.stroke_width(1), true, flat(dof));
            p.y_include.extend([b[0], b[1]]);
        }
        if !bands.is_empty() {
            legend.push(Entry {
                label: "95 % band (dashed, filter's colour)".into(),
                style: GREY.stroke_width(1),
                mark: Mark::Dashed,
            });
        }
    }
    (p, legend)
}

fn step_cost_panels(study: &Study, tally: &Tally, summary: &Summary) -> (Panel, Panel) {
    let mut bars = Panel::new(
        "Median and 90th percentile".into(),
        "filter",
        "time per step (µs)".into(),
        Scale::Linear,
        BIG,
    );
    bars.hide_x_ticks = true;
    bars.y_limit = Some((0.0, f64::INFINITY));
    let n = study.filter_names().len();
    // Every filter's slot is on the axis, with or without a bar.
    bars.x_include.extend([-0.6, n as f64 - 0.4]);
    let mut cdf = Panel::new(
        "Distribution over all steps of all runs".into(),
        "time per step (µs, log scale)",
        "fraction of steps at most this long".into(),
        Scale::Linear,
        BIG,
    );
    cdf.x_scale = Scale::Log;
    cdf.y_include.extend([0.0, 1.0]);
    cdf.y_limit = Some((-0.02, 1.02));
    let costs: Vec<(f64, f64)> = study
        .filter_names()
        .iter()
        .map(|f| {
            summary.filters.get(f).map_or((f64::NAN, f64::NAN), |s| {
                (s.step_ns_median / 1e3, s.step_ns_p90 / 1e3)
            })
        })
        .collect();
    let top = costs
        .iter()
        .flat_map(|c| [c.0, c.1])
        .filter(|v| v.is_finite())
        .fold(0.0f64, f64::max);
    if top > 0.0 {
        // Room above the bars for the numbers and the names.
        bars.y_include.push(top * 1.3);
    }
    for (k, (fname, &(med, p90))) in study.filter_names().iter().zip(&costs).enumerate() {
        let c = color(k);
        let x = k as f64;
        if med.is_finite() && p90.is_finite() && top > 0.0 {
            bars.bars.push((x - 0.36, x - 0.02, med, c.filled()));
            bars.bars
                .push((x + 0.02, x + 0.36, p90, c.mix(0.45).filled()));
            let h = med.max(p90);
            bars.labels.push((
                x,
                h + top * 0.01,
                format!("{} / {} µs", tick(med, 0.0), tick(p90, 0.0)),
            ));
            bars.labels.push((x, h + top * 0.1, fname.clone()));
        } else {
            bars.notes.push(format!("{fname}: no steps timed"));
        }
        let hist = tally.filters.get(k).map(|f| &f.step_cost);
        let total: u64 = hist.map_or(0, |h| h.values().sum());
        if total == 0 {
            cdf.notes.push(format!("{fname}: no steps timed"));
            continue;
        }
        let mut acc = 0u64;
        let mut pts = Vec::new();
        for (&bin, &count) in hist.into_iter().flatten() {
            let lo = bin_value(bin) / 1e3;
            pts.push((lo, acc as f64 / total as f64));
            acc += count;
            pts.push((lo * 1.02, acc as f64 / total as f64));
        }
        cdf.line(filter_line(k, study.filter_names().len()), false, pts);
    }
    (bars, cdf)
}

// ---------------------------------------------------------------------------------------------
// Figures and rendering

enum Fig<'a> {
    Estimates {
        study: &'a Study,
        ex: &'a ExampleRun,
        i: usize,
    },
    EstimatesAll {
        study: &'a Study,
        ex: &'a ExampleRun,
    },
    Rms {
        study: &'a Study,
        tally: &'a Tally,
    },
    StepCost {
        study: &'a Study,
        tally: &'a Tally,
        summary: &'a Summary,
    },
    NeesNis {
        study: &'a Study,
        tally: &'a Tally,
    },
}

const GRID_COLS: usize = 4;
const CELL: (u32, u32) = (430, 320);
const TITLE_H: u32 = 56;
const LEGEND_W: u32 = 300;

fn coefficient_count(names: &[String]) -> usize {
    names.len().saturating_sub(NAV_DIM)
}

fn grid_size(panels: usize) -> (u32, u32) {
    let cells = panels + 1; // and the legend
    let rows = cells.div_ceil(GRID_COLS).max(1) as u32;
    (GRID_COLS as u32 * CELL.0, rows * CELL.1 + TITLE_H)
}

impl Figure for Fig<'_> {
    fn size(&self) -> (u32, u32) {
        match self {
            Fig::Estimates { .. } => (1200, 650),
            Fig::EstimatesAll { ex, .. } => grid_size(coefficient_count(&ex.names)),
            Fig::Rms { study, .. } => grid_size(coefficient_count(&study.names)),
            Fig::StepCost { .. } => (1400, 620),
            Fig::NeesNis { .. } => (1400, 1000),
        }
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let title = |s: &str| root.titled(s, (FONT, 26)).m();
        match *self {
            Fig::Estimates { study, ex, i } => {
                let (plot, side) = root.split_horizontally(1200 - LEGEND_W);
                draw_panel(&plot, &estimate_panel(study, ex, i, true))?;
                draw_legend(&side, &estimate_legend(ex), 16, 60)
            }
            Fig::EstimatesAll { study, ex } => {
                let area = title(&format!("{ESTIMATES_ALL_TITLE}, run {}", ex.run))?;
                let m = coefficient_count(&ex.names);
                let rows = (m + 1).div_ceil(GRID_COLS).max(1);
                let cells = area.split_evenly((rows, GRID_COLS));
                for (c, i) in cells.iter().zip(NAV_DIM..ex.names.len()) {
                    draw_panel(c, &estimate_panel(study, ex, i, false))?;
                }
                match cells.get(m) {
                    Some(cell) => draw_legend(cell, &estimate_legend(ex), 14, 30),
                    None => Ok(()),
                }
            }
            Fig::Rms { study, tally } => {
                let ok: Vec<String> = study
                    .filter_names()
                    .iter()
                    .zip(&tally.filters)
                    .map(|(n, f)| format!("{n} {}", f.ok))
                    .collect();
                let area = title(&format!(
                    "{RMS_TITLE} (runs finished: {} of {})",
                    ok.join(", "),
                    tally.runs
                ))?;
                let m = coefficient_count(&study.names);
                let rows = (m + 1).div_ceil(GRID_COLS).max(1);
                let cells = area.split_evenly((rows, GRID_COLS));
                for (c, i) in cells.iter().zip(NAV_DIM..study.names.len()) {
                    draw_panel(c, &rms_panel(study, tally, i))?;
                }
                let mut legend: Vec<Entry> = study
                    .filter_names()
                    .iter()
                    .enumerate()
                    .map(|(k, f)| Entry {
                        label: format!("{f} RMS error"),
                        style: filter_line(k, study.filter_names().len()),
                        mark: Mark::Line,
                    })
                    .collect();
                legend.push(Entry {
                    label: if tally.bound.count > 0 {
                        "bound (truth-linearised)".into()
                    } else {
                        "bound: not available".into()
                    },
                    style: BLACK.stroke_width(2),
                    mark: Mark::Dashed,
                });
                match cells.get(m) {
                    Some(cell) => draw_legend(cell, &legend, 14, 30),
                    None => Ok(()),
                }
            }
            Fig::StepCost {
                study,
                tally,
                summary,
            } => {
                let area = title(STEP_COST_TITLE)?;
                let (l, r) = area.split_horizontally(600);
                let (bars, cdf) = step_cost_panels(study, tally, summary);
                draw_panel(&l, &bars)?;
                let (plot, side) = r.split_horizontally(800 - LEGEND_W);
                draw_panel(&plot, &cdf)?;
                let mut legend: Vec<Entry> = study
                    .filter_names()
                    .iter()
                    .enumerate()
                    .map(|(k, f)| Entry {
                        label: f.clone(),
                        style: color(k).filled(),
                        mark: Mark::Box,
                    })
                    .collect();
                legend.push(Entry {
                    label: "pale bars: p90".into(),
                    style: GREY.mix(0.45).filled(),
                    mark: Mark::Box,
                });
                draw_legend(&side, &legend, 15, 50)
            }
            Fig::NeesNis { study, tally } => {
                let area = title(NEES_NIS_TITLE)?;
                let (plot, side) = area.split_horizontally(1400 - LEGEND_W - 40);
                let (top, bottom) = plot.split_vertically(472);
                let (nees, legend) = consistency_panel(study, tally, false);
                let (nis, _) = consistency_panel(study, tally, true);
                draw_panel(&top, &nees)?;
                draw_panel(&bottom, &nis)?;
                draw_legend(&side, &legend, 15, 50)
            }
        }
    }
}
