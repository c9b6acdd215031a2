//! The path coloured by how badly the model fits there, so that the places where it fails
//! show on the map.

use super::style::{position_channels, Geo};
use crate::fit::pass::Fit;
use navkf_report::figure::*;
use plotters::prelude::*;

/// Half-width of the running mean that colours the path, s.
pub const PATH_MISFIT_HALF_WINDOW_S: f64 = 30.0;

/// Colour classes of the path by local NIS / dof: upper limit, colour, label.
const MISFIT_CLASSES: [(f64, RGBColor, &str); 4] = [
    (1.5, RGBColor(44, 160, 44), "NIS / dof below 1.5: fits"),
    (3.0, RGBColor(240, 170, 0), "NIS / dof 1.5 to 3"),
    (10.0, RGBColor(230, 85, 13), "NIS / dof 3 to 10"),
    (f64::INFINITY, RGBColor(165, 0, 38), "NIS / dof above 10"),
];

/// Local NIS / dof: the running mean of NIS over the running mean of the dimension, over
/// `+-half` seconds around each update.
fn local_misfit(fit: &Fit, half: f64) -> Vec<f64> {
    let n = fit.t.len();
    let mut out = Vec::with_capacity(n);
    let (mut lo, mut hi) = (0usize, 0usize);
    let (mut sum_nis, mut sum_dim) = (0.0, 0usize);
    for i in 0..n {
        while hi < n && fit.t[hi] <= fit.t[i] + half {
            if fit.nis[hi].is_finite() {
                sum_nis += fit.nis[hi];
                sum_dim += fit.dims[hi];
            }
            hi += 1;
        }
        while fit.t[lo] < fit.t[i] - half {
            if fit.nis[lo].is_finite() {
                sum_nis -= fit.nis[lo];
                sum_dim -= fit.dims[lo];
            }
            lo += 1;
        }
        out.push(if sum_dim > 0 {
            sum_nis / sum_dim as f64
        } else {
            f64::NAN
        });
    }
    out
}

fn misfit_class(r: f64) -> usize {
    MISFIT_CLASSES
        .iter()
        .position(|(hi, _, _)| r < *hi)
        .unwrap_or(MISFIT_CLASSES.len() - 1)
}

/// Size of one panel of the path figure, pixels.
const CELL: (u32, u32) = (820, 820);

/// The path coloured by the local NIS per degree of freedom: of the base model (`base`, the
/// model before any effect was named) and, when the diagnosis named effects, beside it of the
/// final model (`fin`), so that where the base model fails shows and the final model's fit
/// there too. Each is `(fit, label)`.
pub fn path_misfit(base: (&Fit, &str), fin: Option<(&Fit, &str)>, geo: &Geo) -> Grid {
    let mut panels = vec![path_panel(base.0, geo, base.1)];
    if let Some((fit, label)) = fin {
        panels.push(path_panel(fit, geo, &format!("final model: {label}")));
    }
    let legend = MISFIT_CLASSES
        .iter()
        .map(|(_, c, l)| entry(*l, c.stroke_width(4), Mark::Line))
        .collect();
    Grid {
        title: if fin.is_some() {
            "Where the base model fails (left), and how the final model fits there (right)".into()
        } else {
            "Where the model fails".into()
        },
        cols: panels.len(),
        panels,
        cell: CELL,
        legend,
    }
}

/// One panel: the path of `fit` (named `label`) coloured by its local NIS per degree of
/// freedom.
fn path_panel(fit: &Fit, geo: &Geo, label: &str) -> Panel {
    let misfit = local_misfit(fit, PATH_MISFIT_HALF_WINDOW_S);
    let mut p = Panel::new(
        label.to_string(),
        "east of the first fix (m)",
        "north of the first fix (m)".into(),
        Scale::Linear,
        BIG,
    );
    p.notes_above = true;
    let (la, lo) = position_channels(fit);
    // The predicted positions (the fixes' own noise would scribble over the colours), each
    // with its colour class.
    let pts: Vec<(f64, f64, usize)> = fit
        .z
        .iter()
        .zip(&fit.z_hat)
        .zip(&misfit)
        .filter_map(|((z, zh), r)| {
            let pos = |c: usize| geo.show(c, if zh[c].is_finite() { zh[c] } else { z[c] });
            let (north, east) = (pos(la), pos(lo));
            let k = if r.is_finite() { misfit_class(*r) } else { 0 };
            (north.is_finite() && east.is_finite()).then_some((east, north, k))
        })
        .collect();
    let Some(&(e0, n0, _)) = pts.first() else {
        return p;
    };
    let ext = |f: fn(&(f64, f64, usize)) -> f64| {
        pts.iter()
            .map(f)
            .fold((f64::MAX, f64::MIN), |(a, b), v| (a.min(v), b.max(v)))
    };
    let (e_ext, n_ext) = (ext(|q| q.0), ext(|q| q.1));
    // Equal metres per pixel on both axes: the plot area is the cell less the axes' labels,
    // the margins, and the caption and note above it.
    let (w, h) = (e_ext.1 - e_ext.0, n_ext.1 - n_ext.0);
    let (plot_w, plot_h) = ((CELL.0 - 112) as f64, (CELL.1 - 109) as f64);
    let ratio = plot_w / plot_h;
    let (ce, cn) = (0.5 * (e_ext.0 + e_ext.1), 0.5 * (n_ext.0 + n_ext.1));
    let (w, h) = if w > h * ratio {
        (w, w / ratio)
    } else {
        (h * ratio, h)
    };
    // The x axis is drawn as given, 10 % wider than the path; the y axis is padded 5 % each
    // side by the figure kit, so it is given 10 % less.
    p.x_include = vec![ce - 0.55 * w, ce + 0.55 * w];
    p.y_include = vec![cn - 0.5 * h, cn + 0.5 * h];
    // Points closer than two pixels to the last one drawn are left out, and the path is drawn
    // a segment at a time: a wide polyline that turns back on itself (the noise of a
    // standstill) is drawn by plotters' bitmap backend with mitre spikes across the figure.
    let min_step = 2.0 * 1.1 * w / plot_w;
    let mut last = (e0, n0);
    for &(e, n, k) in &pts[1..] {
        if (e - last.0).hypot(n - last.1) >= min_step {
            p.line(
                MISFIT_CLASSES[k].1.stroke_width(4),
                false,
                vec![last, (e, n)],
            );
            last = (e, n);
        }
    }
    p.line(BLACK.filled(), false, vec![(e0, n0)]);
    // "start" 30 pixels from the first point, on the side away from where the path leaves
    // it (the label is anchored at its bottom centre, 7 pixels under its middle).
    let px = 1.1 * w / plot_w;
    let away = pts
        .iter()
        .find(|q| (q.0 - e0).hypot(q.1 - n0) > 30.0 * px)
        .map_or((0.0, -1.0), |q| {
            let d = (q.0 - e0).hypot(q.1 - n0);
            ((e0 - q.0) / d, (n0 - q.1) / d)
        });
    p.labels.push((
        e0 + 30.0 * px * away.0,
        n0 + 30.0 * px * away.1 - 7.0 * px,
        "start".into(),
        BLACK,
    ));
    p.notes.push(format!(
        "colour: NIS per degree of freedom averaged over +-{PATH_MISFIT_HALF_WINDOW_S:.0} s \
         (about 1 where the model fits)"
    ));
    p
}
