//! The figure of a test plan ([`crate::plan`]): `plan_sigma`, the predicted sigma of every
//! coefficient over its prior against time, one panel per unit (gyro drifts, g-sensitive
//! drifts, accelerometer biases, scale factors, each effect's), with the line at half the
//! prior that counts as identified.

use super::{outcome, FigureOutcome};
use crate::plan::{Plan, IDENTIFIED_BELOW};
use navkf_report::figure::*;
use plotters::prelude::*;
use std::path::Path;

/// Title of `plan_sigma`.
pub const TITLE: &str = "Predicted sigma / prior against time (below the dashed line: identified)";

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
    let panels: Vec<Panel> = units
        .iter()
        .map(|unit| {
            let mut panel = Panel::new(
                format!("coefficients in {unit}"),
                "time (s)",
                "sigma / prior".into(),
                Scale::Log,
                BIG,
            );
            let members: Vec<usize> = (0..p.coefficients.len())
                .filter(|&i| p.coefficients[i].unit == *unit)
                .collect();
            for (k, &i) in members.iter().enumerate() {
                let style = color(k).stroke_width(2);
                let dashed = k >= 6;
                let pts =
                    p.t.iter()
                        .copied()
                        .zip(p.sigma_over_prior[i].iter().copied())
                        .collect();
                panel.line(style, dashed, pts);
                // Each curve named on itself, the names spread along the time axis (a legend
                // would repeat the colours of the other panels).
                let at = (k + 1) * p.t.len() / (members.len() + 1);
                if let (Some(&x), Some(&y)) = (p.t.get(at), p.sigma_over_prior[i].get(at)) {
                    panel.labels.push((x, y, p.coefficients[i].name.clone()));
                }
            }
            panel.line(
                GREY.stroke_width(1),
                true,
                vec![(t0, IDENTIFIED_BELOW), (t1, IDENTIFIED_BELOW)],
            );
            panel.y_include.extend([IDENTIFIED_BELOW, 1.0]);
            panel
        })
        .collect();
    let grid = Grid {
        title: TITLE.into(),
        cols: panels.len().min(2),
        panels,
        cell: (560, 400),
        legend: Vec::new(),
    };
    outcome("plan_sigma", TITLE, || render(dir, "plan_sigma", &grid))
}

/// Title of `plan_sweep`.
pub const SWEEP_TITLE: &str =
    "Predicted final sigma / prior against the swept setting (below the dashed line: identified)";

/// Draws `plan_sweep` into `dir`: one panel per coefficient, its predicted final sigma over
/// its prior against the swept value (designs without a value are left out).
pub fn draw_sweep(c: &crate::plan::Comparison, dir: &Path) -> FigureOutcome {
    let key = c.key.clone().unwrap_or_default();
    let points: Vec<(f64, &crate::plan::Design)> = c
        .designs
        .iter()
        .filter_map(|d| d.value.map(|v| (v, d)))
        .collect();
    let (lo, hi) = points
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(lo, hi), (v, _)| {
            (lo.min(*v), hi.max(*v))
        });
    let x_scale = if lo > 0.0 && hi / lo > 20.0 {
        Scale::Log
    } else {
        Scale::Linear
    };
    let names: Vec<String> = c
        .designs
        .first()
        .map(|d| d.coefficients.iter().map(|k| k.name.clone()).collect())
        .unwrap_or_default();
    let panels: Vec<Panel> = names
        .iter()
        .map(|name| {
            let mut panel = Panel::new(
                name.clone(),
                &key,
                "sigma / prior".into(),
                Scale::Log,
                SMALL,
            );
            panel.x_scale = x_scale;
            let pts = points
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
            panel.line(color(0).stroke_width(2), false, pts);
            if let (Some(a), Some(b)) = (points.first(), points.last()) {
                panel.line(
                    GREY.stroke_width(1),
                    true,
                    vec![(a.0, IDENTIFIED_BELOW), (b.0, IDENTIFIED_BELOW)],
                );
            }
            panel.y_include.extend([IDENTIFIED_BELOW, 1.0]);
            panel
        })
        .collect();
    let grid = Grid {
        title: SWEEP_TITLE.into(),
        cols: 4,
        panels,
        cell: (380, 280),
        legend: Vec::new(),
    };
    outcome("plan_sweep", SWEEP_TITLE, || {
        render(dir, "plan_sweep", &grid)
    })
}
