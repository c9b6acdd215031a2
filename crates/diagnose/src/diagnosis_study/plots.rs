//! The figure of a diagnosis study: `detection`, one panel per catalogued effect, the share of
//! datasets that named it against its size (binned, with 95 % intervals), the fitted logistic
//! curve and the size named 90 % of the time.

use super::rates::{sig, Rates};
use navkf_report::figure::*;
use plotters::prelude::*;
use std::path::Path;

const RATE: RGBColor = RGBColor(31, 119, 180);
const CURVE: RGBColor = RGBColor(214, 39, 40);
const TARGET: RGBColor = RGBColor(150, 150, 150);

/// What `detection` answers.
pub const DETECTION_QUESTION: &str =
    "From what size is each catalogued effect named, and how sharply does naming rise?";

/// Draws the detection curves into `dir` (`detection.png` and `.svg`).
pub fn detection(rates: &Rates, dir: &Path) -> Result<(), navkf_report::ReportError> {
    let panels: Vec<Panel> = rates
        .detection
        .iter()
        .map(|d| {
            let mut p = Panel::new(
                format!("{} (n = {})", d.effect, d.n),
                "size, multiples of the typical size",
                "share named".into(),
                Scale::Linear,
                SMALL,
            );
            p.x_scale = Scale::Log;
            p.y_include = vec![0.0, 1.0];
            // The note (the 90 % size, or why there is none) would sit over the points and
            // the limit line at the top left; above the chart it covers nothing.
            p.notes_above = true;
            for b in &d.bins {
                if b.named.n == 0 {
                    continue;
                }
                let x = (b.multiples[0] * b.multiples[1]).sqrt();
                p.line(
                    RATE.stroke_width(1),
                    false,
                    vec![(x, b.named.interval[0]), (x, b.named.interval[1])],
                );
                p.line(RATE.stroke_width(3), false, vec![(x, b.named.rate)]);
            }
            let (lo, hi) = d.points.iter().fold((f64::INFINITY, 0.0f64), |(l, h), q| {
                (l.min(q.0), h.max(q.0))
            });
            if let Some([a, b]) = d.logistic {
                let pts: Vec<(f64, f64)> = (0..=60)
                    .map(|k| {
                        let m = (lo.ln() + (hi.ln() - lo.ln()) * k as f64 / 60.0).exp();
                        (m, 1.0 / (1.0 + (-(a + b * m.ln())).exp()))
                    })
                    .collect();
                p.line(CURVE.stroke_width(2), false, pts);
            }
            if lo.is_finite() {
                p.line(TARGET.stroke_width(1), true, vec![(lo, 0.9), (hi, 0.9)]);
            }
            match (d.limit_multiple, &d.no_limit) {
                (Some(m), _) => {
                    p.line(CURVE.stroke_width(1), true, vec![(m, 0.0), (m, 1.0)]);
                    p.notes.push(format!("90 % at {} x typical", sig(m, 3)));
                }
                (None, Some(why)) => p.notes.push(why.clone()),
                _ => {}
            }
            if let Some(u) = d.unseen.as_ref().filter(|u| u.named.n > 0) {
                p.notes.push(format!(
                    "sizes seen by a test; {} hiding only the unseen part left out (named on {})",
                    u.named.n, u.named.k
                ));
            }
            p
        })
        .collect();
    let grid = Grid {
        title: "How often the diagnosis names a hidden effect, against its size".into(),
        panels,
        cols: 3,
        cell: (520, 360),
        legend: vec![
            entry(
                "share named, per size bin",
                RATE.stroke_width(3),
                Mark::Line,
            ),
            entry("95 % interval", RATE.stroke_width(1), Mark::Line),
            entry("logistic fit", CURVE.stroke_width(2), Mark::Line),
            entry(
                "size named 90 % of the time",
                CURVE.stroke_width(1),
                Mark::Dashed,
            ),
            entry("90 %", TARGET.stroke_width(1), Mark::Dashed),
        ],
    };
    render(dir, "detection", &grid)
}
