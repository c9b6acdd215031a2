//! The example run's estimate of a coefficient by every filter, with its band, against the
//! truth (the paper's Figures 2 and 3).

use super::units::unit_of;
use crate::monte_carlo::{ExampleRun, Study};
use navkf_report::figure::*;
use plotters::prelude::*;

/// `big`: the single figure (full caption, large type); else a grid cell.
pub(super) fn estimate_panel(study: &Study, ex: &ExampleRun, i: usize, big: bool) -> Panel {
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

pub(super) fn estimate_legend(ex: &ExampleRun) -> Vec<Entry> {
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
