//! Figures of a sweep ([`crate::sweep`]), against the swept value, one line per filter:
//!
//! - `sweep_accuracy`: the final heading error's RMS over its truth-linearised bound, and the
//!   geometric mean over the coefficients of their final RMS over bound;
//! - `sweep_nees`: the largest average NEES over the stored times (the early phase, while the
//!   initial error is large, is where a filter that linearises badly turns optimistic) and
//!   the average NEES at the end, divided by the state dimension, with the 95 % band of a
//!   consistent filter at one time.
//!
//! The swept axis is logarithmic when every value is positive and they span more than a
//! factor of 20 (an initial misalignment from arcminutes to tens of degrees).

use super::units::swept_axis;
use super::{outcome, FigureOutcome};
use crate::sweep::{PointFilter, SweepSummary};
use navkf_report::figure::*;
use plotters::prelude::*;
use std::path::Path;

/// Title of `sweep_accuracy`.
pub const ACCURACY_TITLE: &str = "Final accuracy against the swept setting (1 = the bound)";
/// Title of `sweep_nees`.
pub const NEES_TITLE: &str = "Average NEES / state dimension against the swept setting";

fn x_scale(s: &SweepSummary) -> Scale {
    let (lo, hi) = s
        .points
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(lo, hi), p| {
            (lo.min(p.value), hi.max(p.value))
        });
    if lo > 0.0 && hi / lo > 20.0 {
        Scale::Log
    } else {
        Scale::Linear
    }
}

fn legend(s: &SweepSummary) -> Vec<Entry> {
    let n = s.filters.len();
    s.filters
        .iter()
        .enumerate()
        .map(|(k, f)| entry(f.clone(), filter_line(k, n), Mark::Line))
        .collect()
}

/// A panel with one line per filter of `y(point's filter)` against the swept value.
fn per_filter(
    s: &SweepSummary,
    caption: &str,
    y_desc: &str,
    y_scale: Scale,
    y: impl Fn(&PointFilter) -> f64,
) -> Panel {
    let (words, factor) = swept_axis(&s.key, s.model);
    let mut p = Panel::new(caption.into(), &words, y_desc.into(), y_scale, BIG);
    p.x_scale = x_scale(s);
    let n = s.filters.len();
    for (k, f) in s.filters.iter().enumerate() {
        let pts = s
            .points
            .iter()
            .map(|pt| (pt.value * factor, pt.filters.get(f).map_or(f64::NAN, &y)))
            .collect();
        p.line(filter_line(k, n), false, pts);
    }
    p
}

/// Adds the 95 % band of a consistent filter's average NEES / dimension (the widest over
/// the filters at each point: runs excluded as diverged widen it) and the line at 1.
fn nees_band(p: &mut Panel, s: &SweepSummary, dim: f64, bounds: impl Fn(&PointFilter) -> [f64; 2]) {
    let factor = swept_axis(&s.key, s.model).1;
    let pts: Vec<(f64, f64, f64)> = s
        .points
        .iter()
        .map(|pt| {
            let (lo, hi) = pt
                .filters
                .values()
                .map(&bounds)
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), b| {
                    (lo.min(b[0]), hi.max(b[1]))
                });
            (pt.value * factor, lo / dim, hi / dim)
        })
        .filter(|(_, lo, hi)| lo.is_finite() && hi.is_finite())
        .collect();
    if let (Some(a), Some(b)) = (pts.first(), pts.last()) {
        p.line(GREY.stroke_width(1), true, vec![(a.0, 1.0), (b.0, 1.0)]);
    }
    p.y_include.push(1.0);
    p.bands.push(Band {
        style: GREY.mix(0.18).filled(),
        pts,
    });
}

/// Draws `sweep_accuracy` and `sweep_nees` into `dir`; `dim` is the filters' state
/// dimension. A figure that fails (or panics) is reported in its outcome.
pub fn draw(s: &SweepSummary, dim: usize, dir: &Path) -> Vec<FigureOutcome> {
    let mut out = Vec::new();
    let accuracy = Grid {
        title: ACCURACY_TITLE.into(),
        panels: vec![
            per_filter(s, "heading error", "final RMS / bound", Scale::Log, |f| {
                f.heading_rms / f.heading_bound
            }),
            per_filter(
                s,
                "coefficients (geometric mean)",
                "final RMS / bound",
                Scale::Log,
                |f| f.rms_over_bound_mean,
            ),
        ],
        cols: 2,
        cell: (560, 420),
        legend: legend(s),
    };
    let d = dim as f64;
    let mut early = per_filter(
        s,
        "largest over the run",
        "average NEES / dimension",
        Scale::Log,
        |f| f.nees_peak / d,
    );
    nees_band(&mut early, s, d, |f| f.nees_final_bounds);
    let mut last = per_filter(
        s,
        "at the end",
        "average NEES / dimension",
        Scale::Log,
        |f| f.nees_final / d,
    );
    nees_band(&mut last, s, d, |f| f.nees_final_bounds);
    let mut nees_legend = legend(s);
    nees_legend.push(entry(
        "95 % band of a consistent filter",
        GREY.mix(0.3).filled(),
        Mark::Box,
    ));
    let nees = Grid {
        title: NEES_TITLE.into(),
        panels: vec![early, last],
        cols: 2,
        cell: (560, 420),
        legend: nees_legend,
    };
    for (name, caption, question, fig) in [
        (
            "sweep_accuracy",
            ACCURACY_TITLE,
            "Along the sweep, which filter stays closest to its bound, and where does each fail?",
            &accuracy,
        ),
        (
            "sweep_nees",
            NEES_TITLE,
            "Along the sweep, which filter still knows its own error, and where does each stop?",
            &nees,
        ),
    ] {
        out.push(outcome(name, caption, question, || render(dir, name, fig)));
    }
    out
}
