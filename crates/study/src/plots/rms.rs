//! RMS error over runs of a coefficient against time, over its initial sigma, with the
//! truth-linearised bound.

use crate::monte_carlo::Study;
use crate::tally::Tally;
use navkf_report::figure::*;
use plotters::prelude::*;

pub(super) fn rms_panel(study: &Study, tally: &Tally, i: usize) -> Panel {
    let name = &study.names[i];
    let s0 = study.initial_sigma.get(i).copied().unwrap_or(f64::NAN);
    let (norm, caption) = if s0.is_finite() && s0 > 0.0 {
        (s0, name.clone())
    } else {
        (1.0, format!("{name} (not normalised)"))
    };
    let mut p = Panel::new(
        caption,
        "time (s)",
        "RMS error / initial sigma".into(),
        Scale::Log,
        SMALL,
    );
    for (k, (fname, ft)) in study.filter_names().iter().zip(&tally.filters).enumerate() {
        if ft.ok == 0 {
            p.notes.push(format!("{fname}: no run finished"));
            continue;
        }
        let ok = ft.ok as f64;
        let pts = study
            .times
            .iter()
            .enumerate()
            .map(|(s, t)| {
                let v = ft.sum_sq_err.get(s).and_then(|r| r.get(i)).copied();
                (*t, v.map_or(f64::NAN, |v| (v / ok).sqrt() / norm))
            })
            .collect();
        p.line(filter_line(k, study.filter_names().len()), false, pts);
    }
    if let (true, Some(Some(j))) = (tally.bound.count > 0, study.to_truth.get(i)) {
        let n = tally.bound.count as f64;
        let pts = study
            .times
            .iter()
            .enumerate()
            .map(|(s, t)| {
                let v = tally.bound.sum_var.get(s).and_then(|r| r.get(*j)).copied();
                (*t, v.map_or(f64::NAN, |v| (v / n).sqrt() / norm))
            })
            .collect();
        p.line(BLACK.stroke_width(2), true, pts);
    }
    p
}
