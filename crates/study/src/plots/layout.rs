//! How the study's figures are laid out: one panel or a grid of them, sized to fit.

use super::consistency::consistency_panel;
use super::estimates::{estimate_legend, estimate_panel};
use super::rms::rms_panel;
use super::step_cost::step_cost_panels;
use super::{ESTIMATES_ALL_TITLE, NEES_NIS_TITLE, RMS_TITLE, STEP_COST_TITLE};
use crate::monte_carlo::{ExampleRun, Study};
use crate::summary::Summary;
use crate::tally::Tally;
use navkf_dynamics::state::NAV_DIM;
use navkf_report::figure::*;
use plotters::coord::Shift;
use plotters::prelude::*;

pub(super) enum Fig<'a> {
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
