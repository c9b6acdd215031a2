//! The figures of the innovations: every measured channel against the model's prediction of
//! it, and each channel's innovations inside their predicted +-2 sigma band.

use super::style::{quantity, stride, Geo, AFTER, BEFORE, MEASURED};
use crate::catalogue::MAX_CHANNELS;
use crate::fit::pass::Fit;
use navkf_report::figure::*;
use plotters::prelude::*;

/// Measured channels against the prediction of the model `fit` (named `label`).
pub fn measured_vs_predicted(fit: &Fit, geo: &Geo, label: &str) -> Grid {
    let step = stride(fit.t.len());
    let panels = (0..fit.channels.len())
        .map(|c| {
            let title = fit.channels[c].title;
            let y = quantity(fit.channels[c].kind);
            let mut p = Panel::new(title.into(), "time (s)", y.into(), Scale::Linear, SMALL);
            p.notes_above = true;
            let series = |v: &[[f64; MAX_CHANNELS]]| -> Vec<(f64, f64)> {
                fit.t
                    .iter()
                    .zip(v)
                    .step_by(step)
                    .map(|(t, z)| (*t, geo.show(c, z[c])))
                    .collect()
            };
            p.line(MEASURED.stroke_width(3), false, series(&fit.z));
            p.line(AFTER.stroke_width(1), false, series(&fit.z_hat));
            if fit.z.iter().all(|z| !z[c].is_finite()) {
                p.notes.push("no measurements of this channel".into());
            }
            p
        })
        .collect();
    let mut legend = vec![
        entry("measured", MEASURED.stroke_width(3), Mark::Line),
        entry(
            format!("predicted ({label})"),
            AFTER.stroke_width(2),
            Mark::Line,
        ),
    ];
    if let Some(f) = &fit.failure {
        legend.push(entry(
            format!("filter failed: {}", shorten(&f.reason)),
            BEFORE.stroke_width(2),
            Mark::Box,
        ));
    }
    Grid {
        title: format!("Measured against predicted, {label}"),
        panels,
        cols: 2,
        cell: (620, 380),
        legend,
    }
}

fn shorten(s: &str) -> String {
    let mut out: String = s.chars().take(60).collect();
    if out.len() < s.len() {
        out.push_str("...");
    }
    out
}

/// Innovations of `fit` (named `label`) with their +-2 sigma bands.
pub fn innovations(fit: &Fit, geo: &Geo, label: &str) -> Grid {
    let step = stride(fit.t.len());
    let panels = (0..fit.channels.len())
        .map(|c| {
            let (title, unit) = (fit.channels[c].title, fit.channels[c].unit());
            let s = geo.scale(c);
            let mut p = Panel::new(
                format!("{} innovation", title.split(',').next().unwrap_or(title)),
                "time (s)",
                format!("measured - predicted ({unit})"),
                Scale::Linear,
                SMALL,
            );
            p.notes_above = true;
            let (mut outside, mut count) = (0usize, 0usize);
            let mut band = Vec::new();
            let mut line = Vec::new();
            for (i, ((t, z), (zh, sg))) in fit
                .t
                .iter()
                .zip(&fit.z)
                .zip(fit.z_hat.iter().zip(&fit.s_sigma))
                .enumerate()
            {
                let nu = (z[c] - zh[c]) * s;
                let two = 2.0 * sg[c] * s;
                if nu.is_finite() && two.is_finite() {
                    count += 1;
                    if nu.abs() > two {
                        outside += 1;
                    }
                }
                if i % step == 0 {
                    band.push((*t, -two, two));
                    line.push((*t, nu));
                }
            }
            p.bands.push(Band {
                style: AFTER.mix(0.18).filled(),
                pts: band,
            });
            p.line(BLACK.stroke_width(1), false, line);
            if count > 0 {
                p.notes.push(format!(
                    "{:.1} % outside +-2 sigma (4.6 % expected)",
                    100.0 * outside as f64 / count as f64
                ));
            } else {
                p.notes.push("no measurements of this channel".into());
            }
            p
        })
        .collect();
    Grid {
        title: format!("Innovations with their +-2 sigma bands, {label}"),
        panels,
        cols: 2,
        cell: (620, 380),
        legend: vec![
            entry(
                "innovation (measured - predicted)",
                BLACK.stroke_width(2),
                Mark::Line,
            ),
            entry("+-2 sigma predicted", AFTER.mix(0.18).filled(), Mark::Box),
        ],
    }
}
