//! Average NEES and NIS over time against the 95 % band of a consistent filter. The question
//! it answers: is each filter's covariance honest, and when does it stop being so?
//!
//! The axes are linear and fitted to the band and the curves, so the band is as tall as the
//! spread it allows (on a log axis over a decade the band of 250 runs was a hairline under
//! the lines). A curve far above the band (a diverging start) is cut at the top of the axis,
//! and the panel says how far it went.

use crate::monte_carlo::Study;
use crate::tally::Tally;
use navkf_report::figure::*;
use navkf_report::stats::mean_chi2_bounds;
use plotters::prelude::*;

/// How far above the band's top a curve may rise before it is cut (4x: the band, the
/// expected value and a factor-four misfit all stay readable on one linear axis).
const CUT_ABOVE_BAND: f64 = 4.0;

/// The 95 % band of the average NIS over one stored interval: the window mean over about `w`
/// updates of `d` degrees of freedom each, averaged over `ok` runs.
fn nis_window_stats(study: &Study, ft: &crate::tally::FilterTally) -> Option<(f64, [f64; 2])> {
    if ft.ok == 0 || ft.nis_count == 0 || study.times.is_empty() {
        return None;
    }
    let d = ft.nis_dof as f64 / ft.nis_count as f64;
    let w = ft.nis_count as f64 / (ft.ok as f64 * study.times.len() as f64);
    let n = ft.ok as f64 * w;
    Some((d, mean_chi2_bounds(n * d, n)))
}

/// The NEES or NIS panel; `nis` picks which.
pub(super) fn consistency_panel(study: &Study, tally: &Tally, nis: bool) -> (Panel, Vec<Entry>) {
    let what = if nis { "NIS" } else { "NEES" };
    let caption = if nis {
        "NIS averaged over each stored interval and over runs"
    } else {
        "NEES averaged over runs"
    };
    let mut p = Panel::new(
        caption.into(),
        "time (s)",
        format!("average {what} (dimensionless)"),
        Scale::Linear,
        BIG,
    );
    let mut legend = Vec::new();
    let mut bands: Vec<(usize, f64, [f64; 2])> = Vec::new();
    let (t0, t1) = match (study.times.first(), study.times.last()) {
        (Some(a), Some(b)) => (*a, *b),
        _ => (0.0, 0.0),
    };
    for (k, (fname, ft)) in study.filter_names().iter().zip(&tally.filters).enumerate() {
        legend.push(Entry {
            label: fname.clone(),
            style: filter_line(k, study.filter_names().len()),
            mark: Mark::Line,
        });
        if ft.ok == 0 {
            p.notes.push(format!("{fname}: no run finished"));
            continue;
        }
        let ok = ft.ok as f64;
        let (sums, dof, bound) = if nis {
            match nis_window_stats(study, ft) {
                Some((d, b)) => (&ft.sum_nis_window, d, b),
                None => {
                    p.notes.push(format!("{fname}: no updates"));
                    continue;
                }
            }
        } else {
            let n = study.names.len() as f64;
            (&ft.sum_nees, n, mean_chi2_bounds(ok * n, ok))
        };
        let pts = study
            .times
            .iter()
            .enumerate()
            .map(|(s, t)| (*t, sums.get(s).map_or(f64::NAN, |v| v / ok)))
            .collect();
        p.line(filter_line(k, study.filter_names().len()), false, pts);
        bands.push((k, dof, bound));
    }
    let same = bands.windows(2).all(|w| {
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * a.abs().max(b.abs());
        close(w[0].1, w[1].1) && close(w[0].2[0], w[1].2[0]) && close(w[0].2[1], w[1].2[1])
    });
    // Cut a curve far above every band, so the band keeps a readable height; say so.
    let top_band = bands.iter().map(|b| b.2[1]).fold(f64::NAN, f64::max);
    let highest = p
        .lines
        .iter()
        .flat_map(|l| l.pts.iter().map(|q| q.1))
        .filter(|v| v.is_finite())
        .fold(f64::NAN, f64::max);
    if top_band.is_finite() && highest > CUT_ABOVE_BAND * top_band {
        let cut = CUT_ABOVE_BAND * top_band;
        p.y_limit = Some((0.0, cut));
        p.notes.push(format!(
            "{what} above {} is off the top (it reaches {})",
            tick(cut, cut),
            tick(highest, highest)
        ));
    }
    let flat = |v: f64| vec![(t0, v), (t1, v)];
    if same {
        if let Some(&(_, dof, b)) = bands.first() {
            p.bands.push(Band {
                style: GREY.mix(0.18).filled(),
                pts: vec![(t0, b[0], b[1]), (t1, b[0], b[1])],
            });
            p.line(GREY.stroke_width(1), true, flat(dof));
            p.y_include.extend([b[0], b[1]]);
            legend.push(Entry {
                label: "95 % band of a consistent filter".into(),
                style: GREY.mix(0.3).filled(),
                mark: Mark::Box,
            });
            legend.push(Entry {
                label: format!("expected value ({})", tick(dof, 0.0)),
                style: GREY.stroke_width(1),
                mark: Mark::Dashed,
            });
        }
    } else {
        for &(k, dof, b) in &bands {
            p.line(color(k).stroke_width(1), true, flat(b[0]));
            p.line(color(k).stroke_width(1), true, flat(b[1]));
            p.line(GREY.stroke_width(1), true, flat(dof));
            p.y_include.extend([b[0], b[1]]);
        }
        if !bands.is_empty() {
            legend.push(Entry {
                label: "95 % band (dashed, filter's colour)".into(),
                style: GREY.stroke_width(1),
                mark: Mark::Dashed,
            });
        }
    }
    (p, legend)
}
