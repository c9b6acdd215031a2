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
    (1.5, RGBColor(44, 160, 44), "fits: NIS/dof < 1.5"),
    (3.0, RGBColor(240, 170, 0), "1.5 - 3"),
    (10.0, RGBColor(230, 85, 13), "3 - 10"),
    (f64::INFINITY, RGBColor(165, 0, 38), "> 10"),
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

/// The path of `fit` (named `label`) coloured by the local NIS per degree of freedom.
pub fn path_misfit(fit: &Fit, geo: &Geo, label: &str) -> Grid {
    let misfit = local_misfit(fit, PATH_MISFIT_HALF_WINDOW_S);
    let mut p = Panel::new(
        format!("Path coloured by the local NIS / dof ({label})"),
        "east of the first fix (m)",
        "north of the first fix (m)".into(),
        Scale::Linear,
        BIG,
    );
    // Runs of one colour class, each ending where the next starts so the path is unbroken.
    let mut run: Vec<(f64, f64)> = Vec::new();
    let mut class = None;
    let (la, lo) = position_channels(fit);
    let (mut e_ext, mut n_ext) = ((f64::MAX, f64::MIN), (f64::MAX, f64::MIN));
    // The predicted positions: the fixes' own noise would scribble over the colours.
    for ((z, zh), r) in fit.z.iter().zip(&fit.z_hat).zip(&misfit) {
        let pos = |c: usize| {
            if zh[c].is_finite() {
                geo.show(c, zh[c])
            } else {
                geo.show(c, z[c])
            }
        };
        let (north, east) = (pos(la), pos(lo));
        if !(north.is_finite() && east.is_finite()) {
            continue;
        }
        e_ext = (e_ext.0.min(east), e_ext.1.max(east));
        n_ext = (n_ext.0.min(north), n_ext.1.max(north));
        let k = if r.is_finite() { misfit_class(*r) } else { 0 };
        run.push((east, north));
        if class != Some(k) {
            if let Some(prev) = class {
                let pts = std::mem::replace(&mut run, vec![(east, north)]);
                p.line(MISFIT_CLASSES[prev].1.stroke_width(4), false, pts);
            }
            class = Some(k);
        }
    }
    if let Some(k) = class {
        p.line(MISFIT_CLASSES[k].1.stroke_width(4), false, run);
    }
    if let Some(z) = fit
        .z
        .iter()
        .find(|z| z[la].is_finite() && z[lo].is_finite())
    {
        p.labels
            .push((geo.show(lo, z[lo]), geo.show(la, z[la]), "start".into()));
    }
    // Equal metres per pixel on both axes (the plot area is about 830 x 700 pixels).
    if e_ext.0 <= e_ext.1 {
        let (w, h) = (e_ext.1 - e_ext.0, n_ext.1 - n_ext.0);
        let ratio = 830.0 / 700.0;
        let (ce, cn) = (0.5 * (e_ext.0 + e_ext.1), 0.5 * (n_ext.0 + n_ext.1));
        let (w, h) = if w > h * ratio {
            (w, w / ratio)
        } else {
            (h * ratio, h)
        };
        p.x_include = vec![ce - 0.55 * w, ce + 0.55 * w];
        p.y_include = vec![cn - 0.55 * h, cn + 0.55 * h];
    }
    p.notes.push(format!(
        "NIS / dof averaged over +-{PATH_MISFIT_HALF_WINDOW_S:.0} s; about 1 where the model fits"
    ));
    let legend = MISFIT_CLASSES
        .iter()
        .map(|(_, c, l)| entry(*l, c.stroke_width(4), Mark::Line))
        .collect();
    Grid {
        title: "Where the model fails".into(),
        panels: vec![p],
        cols: 1,
        cell: (1000, 860),
        legend,
    }
}
