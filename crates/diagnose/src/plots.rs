//! Figures of a diagnosis, each written as PNG and SVG next to `report.md`:
//!
//! - `measured_vs_predicted`: every measured channel against the filter's prediction of it.
//! - `innovations`: each channel's innovations inside their predicted +-2 sigma band;
//!   `innovations_before` the same for the base model when `--with` added effects.
//! - `path_misfit`: the vehicle's path (from the GPS fixes) coloured by the local NIS per
//!   degree of freedom, so that the places where the model fails show on the map.
//! - `nis`: NIS per degree of freedom in sliding windows and per motion phase, against the
//!   95 % chi-square bounds; before and after when `--with` is given.
//! - `whiteness`: each channel's innovation autocorrelation with its white-noise band.
//! - `coefficient_errors` (when the dataset has `truth.csv`): each coefficient's error divided
//!   by its initial sigma, before and after.
//!
//! Positions are shown in metres north and east of the first fix and velocities in m/s, so
//! that a misfit reads in the units a navigation engineer thinks in. A figure that cannot be
//! drawn is reported in its [`FigureOutcome`]; the others are still drawn.

use super::{phase_name, Diagnosis, Fit, FitSummary, Fits};
use navkf_dynamics::earth::{meridian_radius, prime_vertical_radius};
use navkf_dynamics::state::MEAS_DIM;
use navkf_dynamics::trajectory::Phase;
use navkf_report::figure::FigureOutcome;
use navkf_report::figure::*;
use plotters::prelude::*;
use std::path::Path;

/// Half-width of the running mean that colours the path, s.
pub const PATH_MISFIT_HALF_WINDOW_S: f64 = 30.0;
/// Points drawn per curve at most (longer series are thinned evenly).
const MAX_POINTS: usize = 4000;

/// The channels as drawn: title and unit.
const CHANNELS: [(&str, &str); MEAS_DIM] = [
    ("east velocity v_x", "m/s"),
    ("north velocity v_y", "m/s"),
    ("latitude L, as metres north of the first fix", "m"),
    ("longitude lambda, as metres east of the first fix", "m"),
];

/// Colour classes of the path by local NIS / dof: upper limit, colour, label.
const MISFIT_CLASSES: [(f64, RGBColor, &str); 4] = [
    (1.5, RGBColor(44, 160, 44), "fits: NIS/dof < 1.5"),
    (3.0, RGBColor(240, 170, 0), "1.5 - 3"),
    (10.0, RGBColor(230, 85, 13), "3 - 10"),
    (f64::INFINITY, RGBColor(165, 0, 38), "> 10"),
];

const MEASURED: RGBColor = RGBColor(120, 120, 120);
const AFTER: RGBColor = RGBColor(31, 119, 180);
const BEFORE: RGBColor = RGBColor(214, 39, 40);
const BOUNDS: RGBColor = RGBColor(150, 150, 150);

/// Draws every figure of a diagnosis into `dir`.
pub fn draw(d: &Diagnosis, fits: &Fits, dir: &Path) -> Vec<FigureOutcome> {
    let geo = Geo::of(&fits.model);
    let mut out = Vec::new();
    let mut run = |name: &str, caption: String, fig: &dyn Fn() -> Grid| {
        out.push(navkf_report::figure::outcome(name, caption, || {
            render(dir, name, &fig())
        }));
    };
    let model_label = model_label(&fits.model.effects);
    run(
        "measured_vs_predicted",
        "Measured channels against the model's prediction".into(),
        &|| measured_vs_predicted(&fits.model, &geo, &model_label),
    );
    run(
        "innovations",
        format!("Innovations with their +-2 sigma bands ({model_label})"),
        &|| innovations(&fits.model, &geo, &model_label),
    );
    if let Some(b) = &fits.before {
        run(
            "innovations_before",
            "Innovations with their +-2 sigma bands (base model, before)".into(),
            &|| innovations(b, &geo, "base model"),
        );
    }
    run(
        "path_misfit",
        "The path coloured by how badly the model fits there".into(),
        &|| path_misfit(&fits.model, &geo, &model_label),
    );
    run(
        "nis",
        "NIS in sliding windows and per motion phase, with 95 % bounds".into(),
        &|| nis(d, fits),
    );
    run(
        "whiteness",
        "Autocorrelation of each channel's innovations".into(),
        &|| whiteness(d),
    );
    let has_truth = d.model.coefficients.iter().any(|c| c.truth.is_some());
    if has_truth {
        run(
            "coefficient_errors",
            "Coefficient errors against the truth, divided by the initial sigma".into(),
            &|| coefficient_errors(d),
        );
    }
    out
}

fn model_label(effects: &[String]) -> String {
    if effects.is_empty() {
        "base model".into()
    } else {
        format!("with {}", effects.join(", "))
    }
}

/// Local metric frame at the first GPS fix: channel values to display units.
struct Geo {
    lat0: f64,
    lon0: f64,
    north_per_rad: f64,
    east_per_rad: f64,
}

impl Geo {
    fn of(fit: &Fit) -> Self {
        let first = fit.z.iter().find(|z| z[2].is_finite() && z[3].is_finite());
        let (lat0, lon0) = first.map_or((0.0, 0.0), |z| (z[2], z[3]));
        let s = lat0.sin();
        Geo {
            lat0,
            lon0,
            north_per_rad: meridian_radius(s),
            east_per_rad: prime_vertical_radius(s) * lat0.cos(),
        }
    }

    /// Factor from channel `c`'s units to display units.
    fn scale(&self, c: usize) -> f64 {
        match c {
            2 => self.north_per_rad,
            3 => self.east_per_rad,
            _ => 1.0,
        }
    }

    /// A measured or predicted value of channel `c` in display units.
    fn show(&self, c: usize, v: f64) -> f64 {
        match c {
            2 => (v - self.lat0) * self.north_per_rad,
            3 => (v - self.lon0) * self.east_per_rad,
            _ => v,
        }
    }
}

/// Every `stride`-th index of a series of `n`, so that at most [`MAX_POINTS`] are drawn.
fn stride(n: usize) -> usize {
    n.div_ceil(MAX_POINTS).max(1)
}

fn measured_vs_predicted(fit: &Fit, geo: &Geo, label: &str) -> Grid {
    let step = stride(fit.t.len());
    let panels = (0..MEAS_DIM)
        .map(|c| {
            let (title, unit) = CHANNELS[c];
            let mut p = Panel::new(title.into(), "time (s)", unit.into(), Scale::Linear, SMALL);
            let series = |v: &[[f64; MEAS_DIM]]| -> Vec<(f64, f64)> {
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

fn innovations(fit: &Fit, geo: &Geo, label: &str) -> Grid {
    let step = stride(fit.t.len());
    let panels = (0..MEAS_DIM)
        .map(|c| {
            let (title, unit) = CHANNELS[c];
            let s = geo.scale(c);
            let mut p = Panel::new(
                format!("{} innovation", title.split(',').next().unwrap_or(title)),
                "time (s)",
                unit.into(),
                Scale::Linear,
                SMALL,
            );
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

fn path_misfit(fit: &Fit, geo: &Geo, label: &str) -> Grid {
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
        let (north, east) = (pos(2), pos(3));
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
    if let Some(z) = fit.z.iter().find(|z| z[2].is_finite() && z[3].is_finite()) {
        p.labels
            .push((geo.show(3, z[3]), geo.show(2, z[2]), "start".into()));
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

fn nis(d: &Diagnosis, fits: &Fits) -> Grid {
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

fn whiteness(d: &Diagnosis) -> Grid {
    let panels = d
        .model
        .whiteness
        .iter()
        .enumerate()
        .map(|(c, w)| {
            let title = CHANNELS.get(c).map_or(w.channel.as_str(), |ch| ch.0);
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

fn coefficient_errors(d: &Diagnosis) -> Grid {
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
