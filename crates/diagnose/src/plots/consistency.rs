//! The figures of the consistency tests: NIS in sliding windows and per motion phase against
//! its bounds, each channel's autocorrelation, and the coefficients' errors against the truth.

use super::style::{model_label, AFTER, BEFORE, BOUNDS};
use crate::catalogue::channel_title;
use crate::consistency::phase_name;
use crate::diagnosis::{Diagnosis, Fits};
use crate::summary::FitSummary;
use navkf_dynamics::trajectory::Phase;
use navkf_report::figure::*;
use plotters::prelude::*;

/// NIS per degree of freedom in sliding windows and per motion phase, before and after.
pub fn nis(d: &Diagnosis, fits: &Fits) -> Grid {
    let after_label = model_label(&fits.model.effects);
    let mut sets: Vec<(&FitSummary, RGBColor, String)> = Vec::new();
    if let Some(b) = &d.before {
        sets.push((b, BEFORE, "before: base model".into()));
    }
    let after_name = if d.before.is_some() {
        format!("after: {after_label}")
    } else {
        after_label
    };
    sets.push((&d.model, AFTER, after_name));

    let mut windows = Panel::new(
        "NIS / dof in sliding windows".into(),
        "time (s), window centre",
        "NIS / dof".into(),
        Scale::Log,
        BIG,
    );
    windows.bands.push(Band {
        style: BOUNDS.mix(0.25).filled(),
        pts: d
            .model
            .nis_windows
            .iter()
            .map(|w| {
                (
                    0.5 * (w.t[0] + w.t[1]),
                    w.stat.bounds[0] / w.stat.dof,
                    w.stat.bounds[1] / w.stat.dof,
                )
            })
            .collect(),
    });
    let (t0, t1) = d
        .model
        .nis_windows
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), w| {
            (a.min(w.t[0]), b.max(w.t[1]))
        });
    if t0 <= t1 {
        windows.line(BLACK.stroke_width(1), true, vec![(t0, 1.0), (t1, 1.0)]);
    }
    for (s, c, _) in &sets {
        windows.line(
            c.stroke_width(2),
            false,
            s.nis_windows
                .iter()
                .map(|w| (0.5 * (w.t[0] + w.t[1]), w.stat.mean / w.stat.dof))
                .collect(),
        );
    }
    windows.y_include = vec![0.5, 2.0];

    let mut phases = Panel::new(
        "NIS / dof per motion phase".into(),
        "",
        "NIS / dof".into(),
        Scale::Log,
        BIG,
    );
    phases.hide_x_ticks = true;
    let all = [
        Phase::Standstill,
        Phase::Accelerating,
        Phase::Cruising,
        Phase::Turning,
        Phase::Decelerating,
    ];
    let width = 0.8 / sets.len() as f64;
    for (i, ph) in all.iter().enumerate() {
        let name = phase_name(*ph);
        let x = i as f64;
        let mut top = 1.0f64;
        let mut any = false;
        for (k, (s, c, _)) in sets.iter().enumerate() {
            let Some(st) = s.nis_by_phase.get(name).filter(|st| st.count > 0) else {
                continue;
            };
            any = true;
            let x0 = x - 0.4 + k as f64 * width;
            let r = st.mean / st.dof;
            phases
                .bars
                .push((x0, x0 + width * 0.9, r, c.mix(0.75).filled()));
            let (lo, hi) = (st.bounds[0] / st.dof, st.bounds[1] / st.dof);
            let xm = x0 + 0.45 * width;
            phases.line(BLACK.stroke_width(2), false, vec![(xm, lo), (xm, hi)]);
            top = top.max(r).max(hi);
        }
        let text = if any {
            name.to_string()
        } else {
            format!("{name}: none")
        };
        phases.labels.push((x, top * 1.25, text));
    }
    phases.line(BLACK.stroke_width(1), true, vec![(-0.5, 1.0), (4.5, 1.0)]);
    phases.x_include = vec![-0.5, 4.5];

    let mut legend: Vec<Entry> = sets
        .iter()
        .map(|(_, c, l)| entry(l.clone(), c.stroke_width(3), Mark::Line))
        .collect();
    legend.push(entry(
        "95 % bounds (band; whiskers)",
        BOUNDS.mix(0.25).filled(),
        Mark::Box,
    ));
    legend.push(entry("expected: 1", BLACK.stroke_width(1), Mark::Dashed));
    Grid {
        title: "NIS against its chi-square bounds".into(),
        panels: vec![windows, phases],
        cols: 1,
        cell: (1100, 430),
        legend,
    }
}

/// Each channel's innovation autocorrelation with its white-noise band.
pub fn whiteness(d: &Diagnosis) -> Grid {
    let panels = d
        .model
        .whiteness
        .iter()
        .enumerate()
        .map(|(c, w)| {
            let title = channel_title(&w.channel);
            let mut p = Panel::new(
                format!(
                    "{}: autocorrelation",
                    title.split(',').next().unwrap_or(title)
                ),
                "lag (updates)",
                "autocorrelation".into(),
                Scale::Linear,
                SMALL,
            );
            let lags = w.autocorrelation.len();
            p.bands.push(Band {
                style: BOUNDS.mix(0.25).filled(),
                pts: (1..=lags).map(|l| (l as f64, -w.band, w.band)).collect(),
            });
            if let Some(b) = d.before.as_ref().and_then(|b| b.whiteness.get(c)) {
                p.line(BEFORE.stroke_width(2), true, ac_points(&b.autocorrelation));
            }
            p.line(AFTER.stroke_width(2), false, ac_points(&w.autocorrelation));
            p.y_include = vec![-2.0 * w.band, 2.0 * w.band];
            let before = d.before.as_ref().and_then(|b| b.whiteness.get(c));
            for (who, w) in [("before: ", before), ("", Some(w))] {
                let Some(w) = w else { continue };
                let who = if before.is_some() && who.is_empty() {
                    "after: "
                } else {
                    who
                };
                p.notes.push(if w.count > 0 {
                    format!(
                        "{who}Ljung-Box {:.0} (99 % critical {:.0}), mean {:+.2}, variance {:.2}: {}",
                        w.ljung_box,
                        w.critical,
                        w.mean,
                        w.variance,
                        if w.white { "white" } else { "not white" }
                    )
                } else {
                    format!("{who}no measurements of this channel")
                });
            }
            p
        })
        .collect();
    let mut legend = Vec::new();
    if d.before.is_some() {
        legend.push(entry(
            "before: base model",
            BEFORE.stroke_width(2),
            Mark::Dashed,
        ));
    }
    legend.push(entry(
        model_label(&d.model.effects),
        AFTER.stroke_width(2),
        Mark::Line,
    ));
    legend.push(entry(
        "95 % band of white noise",
        BOUNDS.mix(0.25).filled(),
        Mark::Box,
    ));
    Grid {
        title: "Whiteness of the normalised innovations".into(),
        panels,
        cols: 2,
        cell: (620, 380),
        legend,
    }
}

fn ac_points(ac: &[f64]) -> Vec<(f64, f64)> {
    ac.iter()
        .enumerate()
        .map(|(l, r)| ((l + 1) as f64, *r))
        .collect()
}

/// Each coefficient's error against the truth over its initial sigma, before and after.
pub fn coefficient_errors(d: &Diagnosis) -> Grid {
    let mut sets: Vec<(&FitSummary, RGBColor, String)> = Vec::new();
    if let Some(b) = &d.before {
        sets.push((b, BEFORE, "before: base model".into()));
    }
    sets.push((&d.model, AFTER, model_label(&d.model.effects)));
    // Every coefficient of the model under test (a superset of the base model's).
    let names: Vec<&str> = d
        .model
        .coefficients
        .iter()
        .map(|c| c.name.as_str())
        .collect();
    let mut p = Panel::new(
        "|estimate - truth| / initial sigma, at the end of the dataset".into(),
        "",
        "error / initial sigma".into(),
        Scale::Log,
        BIG,
    );
    p.hide_x_ticks = true;
    let width = 0.8 / sets.len() as f64;
    for (i, name) in names.iter().enumerate() {
        let x = i as f64;
        let mut top = 0.0f64;
        for (k, (s, c, _)) in sets.iter().enumerate() {
            let Some(coef) = s.coefficients.iter().find(|q| q.name == *name) else {
                continue;
            };
            let Some(t) = coef.truth else { continue };
            let e = ((coef.estimate - t) / coef.prior_sigma).abs();
            let x0 = x - 0.4 + k as f64 * width;
            p.bars.push((x0, x0 + 0.9 * width, e, c.mix(0.8).filled()));
            top = top.max(e);
        }
        if top > 0.0 {
            p.labels.push((x, top * 1.3, name.to_string()));
        }
    }
    p.x_include = vec![-0.5, names.len() as f64 - 0.5];
    if d.model.coefficients.iter().any(|c| c.truth.is_none()) {
        p.notes
            .push("a coefficient without a bar has no true value in truth.csv".into());
    }
    let legend = sets
        .iter()
        .map(|(_, c, l)| entry(l.clone(), c.mix(0.8).filled(), Mark::Box))
        .collect();
    Grid {
        title: "Coefficient errors against the truth".into(),
        panels: vec![p],
        cols: 1,
        cell: ((90 * names.len() as u32).max(900), 600),
        legend,
    }
}
