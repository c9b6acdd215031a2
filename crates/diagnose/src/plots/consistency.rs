//! The figures of the consistency tests: NIS in sliding windows and per motion phase against
//! its bounds, and each channel's autocorrelation.

use super::style::{base_label, model_label, AFTER, BEFORE, BOUNDS};
use crate::catalogue::channel_title;
use crate::consistency::phase_name;
use crate::diagnosis::{Diagnosis, Fits};
use crate::summary::FitSummary;
use navkf_dynamics::trajectory::Phase;
use navkf_report::figure::*;
use plotters::prelude::*;

/// NIS per degree of freedom drawn at most this high: a base model far off would flatten the
/// 95 % band (about 0.9 - 1.1) into a hairline; what lies above is cut and said in a note.
const NIS_TOP: f64 = 6.0;

/// NIS per degree of freedom in sliding windows and per motion phase, before and after, on
/// linear axes that show the 95 % band.
pub fn nis(d: &Diagnosis, fits: &Fits) -> Grid {
    let after_label = model_label(&fits.model.effects);
    let mut sets: Vec<(&FitSummary, RGBColor, String)> = Vec::new();
    if let Some(b) = &d.before {
        sets.push((b, BEFORE, format!("before: {}", base_label(d))));
    }
    let after_name = if d.before.is_some() {
        format!("after: {after_label}")
    } else {
        after_label
    };
    sets.push((&d.model, AFTER, after_name));
    // A window's length: from its first update to its last, and one update's step more.
    let span = d.model.nis_windows.first().map_or(0.0, |w| {
        let n = w.stat.count.max(2) as f64;
        (w.t[1] - w.t[0]) * n / (n - 1.0)
    });
    let mut windows = Panel::new(
        "NIS per degree of freedom in sliding windows".into(),
        &format!("time of the window's centre (s); windows {span:.0} s long"),
        "NIS per degree of freedom".into(),
        Scale::Linear,
        BIG,
    );
    windows.notes_above = true;
    windows.bands.push(Band {
        style: BOUNDS.mix(0.45).filled(),
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
    for (s, c, name) in &sets {
        let pts: Vec<(f64, f64)> = s
            .nis_windows
            .iter()
            .map(|w| (0.5 * (w.t[0] + w.t[1]), w.stat.mean / w.stat.dof))
            .collect();
        let top = pts.iter().map(|q| q.1).fold(0.0, f64::max);
        if top > NIS_TOP {
            windows
                .notes
                .push(format!("{name}: up to {top:.1}, cut at {NIS_TOP}"));
        }
        windows.line(c.stroke_width(2), false, pts);
    }
    windows.y_include = vec![0.0, 1.5];
    windows.y_limit = Some((0.0, NIS_TOP));
    if windows.notes.is_empty() {
        windows
            .notes
            .push("grey band: 95 % bounds of a window's mean for a model that fits".into());
    }

    let mut phases = Panel::new(
        "NIS per degree of freedom per motion phase".into(),
        "motion phase",
        "NIS per degree of freedom".into(),
        Scale::Linear,
        BIG,
    );
    phases.notes_above = true;
    let all = [
        Phase::Standstill,
        Phase::Accelerating,
        Phase::Cruising,
        Phase::Turning,
        Phase::Decelerating,
    ];
    let width = 0.8 / sets.len() as f64;
    let mut cut = Vec::new();
    let mut tops = Vec::new();
    for (i, ph) in all.iter().enumerate() {
        let name = phase_name(*ph);
        let x = i as f64;
        let mut top = 0.0f64;
        for (k, (s, c, _)) in sets.iter().enumerate() {
            let Some(st) = s.nis_by_phase.get(name).filter(|st| st.count > 0) else {
                continue;
            };
            let x0 = x - 0.4 + k as f64 * width;
            let r = st.mean / st.dof;
            if r > NIS_TOP {
                cut.push(format!("{name} {r:.1}"));
            }
            phases
                .bars
                .push((x0, x0 + width * 0.9, r, c.mix(0.75).filled()));
            let (lo, hi) = (st.bounds[0] / st.dof, st.bounds[1] / st.dof);
            let xm = x0 + 0.45 * width;
            phases.line(BLACK.stroke_width(2), false, vec![(xm, lo), (xm, hi)]);
            top = top.max(r.min(NIS_TOP)).max(hi);
        }
        tops.push((x, top, name));
    }
    phases.x_names = tops
        .iter()
        .map(|(x, top, name)| {
            let text = if *top > 0.0 {
                name.to_string()
            } else {
                format!("{name}: none")
            };
            (*x, text)
        })
        .collect();
    phases.y_include = vec![0.0, 1.5];
    phases.y_limit = Some((0.0, NIS_TOP));
    phases.notes.push(if cut.is_empty() {
        "whiskers: 95 % bounds of each phase's mean".into()
    } else {
        format!("cut at {NIS_TOP}: {}", cut.join(", "))
    });
    phases.line(BLACK.stroke_width(1), true, vec![(-0.5, 1.0), (4.5, 1.0)]);
    phases.x_include = vec![-0.5, 4.5];

    let mut legend: Vec<Entry> = sets
        .iter()
        .map(|(_, c, l)| entry(l.clone(), c.stroke_width(3), Mark::Line))
        .collect();
    legend.push(entry(
        "95 % bounds (band; whiskers)",
        BOUNDS.mix(0.45).filled(),
        Mark::Box,
    ));
    legend.push(entry("expected: 1", BLACK.stroke_width(1), Mark::Dashed));
    Grid {
        title: "NIS against its chi-square bounds".into(),
        panels: vec![windows, phases],
        cols: 1,
        cell: (1100, 460),
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
                "lag (measurement updates)",
                "autocorrelation (unitless)".into(),
                Scale::Linear,
                SMALL,
            );
            p.notes_above = true;
            let lags = w.autocorrelation.len();
            p.bands.push(Band {
                style: BOUNDS.mix(0.45).filled(),
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
            format!("before: {}", base_label(d)),
            BEFORE.stroke_width(2),
            Mark::Dashed,
        ));
    }
    let after = model_label(&d.model.effects);
    legend.push(entry(
        if d.before.is_some() {
            format!("after: {after}")
        } else {
            after
        },
        AFTER.stroke_width(2),
        Mark::Line,
    ));
    legend.push(entry(
        "95 % band of white noise",
        BOUNDS.mix(0.45).filled(),
        Mark::Box,
    ));
    Grid {
        title: "Whiteness of the normalised innovations".into(),
        panels,
        cols: 2,
        cell: (620, 420),
        legend,
    }
}

fn ac_points(ac: &[f64]) -> Vec<(f64, f64)> {
    ac.iter()
        .enumerate()
        .map(|(l, r)| ((l + 1) as f64, *r))
        .collect()
}
