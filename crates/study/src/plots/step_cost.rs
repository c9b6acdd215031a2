//! The cost of one filter step: median and 90th percentile, and the distribution.

use crate::monte_carlo::Study;
use crate::summary::Summary;
use crate::tally::{bin_value, Tally};
use navkf_report::figure::*;
use plotters::prelude::*;

pub(super) fn step_cost_panels(study: &Study, tally: &Tally, summary: &Summary) -> (Panel, Panel) {
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
                BLACK,
            ));
            bars.labels.push((x, h + top * 0.1, fname.clone(), BLACK));
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
