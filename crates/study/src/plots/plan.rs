//! The figure of a test plan ([`crate::plan`]): `plan_sigma`, the predicted sigma of every
//! coefficient over its prior against time, one panel per unit (gyro drifts, g-sensitive
//! drifts, accelerometer biases, scale factors, each effect's), with the line at half the
//! prior that counts as identified.

use super::curve_labels::{place, Plot};
use super::units::display_unit;
use super::{outcome, FigureOutcome};
use crate::plan::{Plan, IDENTIFIED_BELOW};
use navkf_report::figure::*;
use plotters::prelude::*;
use std::path::Path;

/// Title of `plan_sigma`.
pub const TITLE: &str = "Predicted sigma / prior against time (below the dashed line: identified)";
/// What `plan_sigma` answers.
pub const QUESTION: &str = "Which coefficients does this test identify, and when in the test?";

/// The caption of the panel of the coefficients in `unit` (the model's, SI): named in the
/// unit the other figures show them in (deg/h, not rad/s; ppm, not 1).
fn caption_of(unit: &str) -> String {
    match display_unit(unit).1.as_str() {
        "-" => "coefficients without a unit".into(),
        u => format!("coefficients in {u}"),
    }
}

/// Draws `plan_sigma` into `dir`.
pub fn draw(p: &Plan, dir: &Path) -> FigureOutcome {
    let mut units: Vec<&str> = Vec::new();
    for c in &p.coefficients {
        if !units.contains(&c.unit.as_str()) {
            units.push(&c.unit);
        }
    }
    let (t0, t1) = (
        p.t.first().copied().unwrap_or(0.0),
        p.t.last().copied().unwrap_or(1.0),
    );
    let cell = (560, 400);
    let panels: Vec<Panel> = units
        .iter()
        .map(|unit| {
            let mut panel = Panel::new(
                caption_of(unit),
                "time (s)",
                "sigma / prior".into(),
                Scale::Log,
                BIG,
            );
            let members: Vec<usize> = (0..p.coefficients.len())
                .filter(|&i| p.coefficients[i].unit == *unit)
                .collect();
            let curves: Vec<(&str, Vec<(f64, f64)>)> = members
                .iter()
                .map(|&i| {
                    let pts =
                        p.t.iter()
                            .copied()
                            .zip(p.sigma_over_prior[i].iter().copied());
                    (p.coefficients[i].name.as_str(), pts.collect())
                })
                .collect();
            // The y axis as the figure kit would pad it (a decade at least, 15 % beyond the
            // data, the prior and the identified line), fixed so that the names' places are
            // known: from the lowest ratio, or 0.1, to the highest, or 1.
            let (lo, hi) = curves
                .iter()
                .flat_map(|c| c.1.iter().map(|q| q.1))
                .filter(|r| r.is_finite() && *r > 0.0)
                .fold((0.1f64, 1.0f64), |(lo, hi), r| (lo.min(r), hi.max(r)));
            let y = (lo / 1.15, hi * 1.15);
            panel.y_include.extend([y.0, y.1]);
            panel.y_limit = Some(y);
            let identified = vec![(t0, IDENTIFIED_BELOW), (t1, IDENTIFIED_BELOW)];
            // Each curve named on itself, the names spread along the time axis, clear of the
            // lines (a legend would repeat the colours of the other panels).
            let plot = Plot::in_cell(cell, BIG, (t0, t1), y);
            let places = place(&plot, &curves, std::slice::from_ref(&identified), BIG.note);
            for (k, ((name, pts), at)) in curves.into_iter().zip(places).enumerate() {
                panel.line(color(k).stroke_width(2), k >= 6, pts);
                if let Some((x, y)) = at {
                    panel
                        .labels
                        .push((x, y, name.to_string(), text_color(color(k))));
                }
            }
            panel.line(GREY.stroke_width(1), true, identified);
            panel
        })
        .collect();
    let grid = Grid {
        title: TITLE.into(),
        cols: panels.len().min(2),
        panels,
        cell,
        legend: Vec::new(),
    };
    outcome("plan_sigma", TITLE, QUESTION, || {
        render(dir, "plan_sigma", &grid)
    })
}

/// What `plan_sweep` answers.
pub const SWEEP_QUESTION: &str =
    "Which coefficients does the swept setting make identifiable, and from what value?";

/// Title of `plan_sweep`.
pub const SWEEP_TITLE: &str =
    "Predicted final sigma / prior against the swept setting (below the dashed line: identified)";

/// Draws `plan_sweep` into `dir`, answering "which coefficients does the swept setting make
/// identifiable?": one panel with a line for each coefficient whose predicted final sigma
/// over its prior changes across the designs (it crosses the identified line, or moves by
/// more than [`CHANGES_BY`]), and notes naming the others, identified or not at every value.
/// Designs without a value are left out.
pub fn draw_sweep(c: &crate::plan::Comparison, dir: &Path) -> FigureOutcome {
    let key = c.key.clone().unwrap_or_default();
    let (words, factor) = super::units::swept_axis(&key, c.model);
    let points: Vec<(f64, &crate::plan::Design)> = c
        .designs
        .iter()
        .filter_map(|d| d.value.map(|v| (v * factor, d)))
        .collect();
    let (lo, hi) = points
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(lo, hi), (v, _)| {
            (lo.min(*v), hi.max(*v))
        });
    let mut panel = Panel::new(
        "Coefficients whose identifiability the setting changes".into(),
        &words,
        "predicted final sigma / prior".into(),
        Scale::Log,
        BIG,
    );
    if lo > 0.0 && hi / lo > 20.0 {
        panel.x_scale = Scale::Log;
    }
    let names: Vec<String> = c
        .designs
        .first()
        .map(|d| d.coefficients.iter().map(|k| k.name.clone()).collect())
        .unwrap_or_default();
    let (mut always, mut never, mut drawn) = (Vec::new(), Vec::new(), Vec::new());
    for name in &names {
        let pts: Vec<(f64, f64)> = points
            .iter()
            .map(|(v, d)| {
                let r = d
                    .coefficients
                    .iter()
                    .find(|k| k.name == *name)
                    .map_or(f64::NAN, |k| k.ratio);
                (*v, r)
            })
            .collect();
        let ratios = pts.iter().map(|p| p.1).filter(|r| r.is_finite());
        let (min, max) = ratios.fold((f64::INFINITY, 0.0f64), |(a, b), r| (a.min(r), b.max(r)));
        let crosses = min < IDENTIFIED_BELOW && max >= IDENTIFIED_BELOW;
        if crosses || max > CHANGES_BY * min {
            drawn.push((name.clone(), pts));
        } else if max < IDENTIFIED_BELOW {
            always.push(name.as_str());
        } else {
            never.push(name.as_str());
        }
    }
    // Nested widths: coefficients whose curves coincide (Ka1x and Ka1y, say) both show.
    let mut legend = Vec::new();
    let n = drawn.len();
    for (k, (name, pts)) in drawn.into_iter().enumerate() {
        legend.push(entry(name, filter_line(k, n), Mark::Line));
        panel.line(filter_line(k, n), false, pts);
    }
    if let (Some(a), Some(b)) = (points.first(), points.last()) {
        panel.line(
            GREY.stroke_width(1),
            true,
            vec![(a.0, IDENTIFIED_BELOW), (b.0, IDENTIFIED_BELOW)],
        );
    }
    panel.y_include.extend([IDENTIFIED_BELOW, 1.0]);
    if legend.is_empty() {
        panel
            .notes
            .push("no coefficient changes across the designs".into());
    }
    for (what, list) in [
        ("identified at every value", &always),
        ("never identified", &never),
    ] {
        if !list.is_empty() {
            panel.notes.push(format!("{what}: {}", list.join(", ")));
        }
    }
    legend.push(entry(
        format!("identified below {IDENTIFIED_BELOW}"),
        GREY.stroke_width(1),
        Mark::Dashed,
    ));
    let grid = Grid {
        title: SWEEP_TITLE.into(),
        cols: 1,
        panels: vec![panel],
        cell: (900, 520),
        legend,
    };
    outcome("plan_sweep", SWEEP_TITLE, SWEEP_QUESTION, || {
        render(dir, "plan_sweep", &grid)
    })
}

/// A coefficient whose sigma ratio moves by more than this factor across the designs is
/// drawn even if it stays on one side of the identified line.
pub const CHANGES_BY: f64 = 1.25;
