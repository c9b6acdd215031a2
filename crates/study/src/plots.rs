//! Figures of a study, each written as PNG and SVG into the results folder:
//!
//! - `estimates_<coefficient>`: the example run's estimate of one coefficient by every filter,
//!   with its +-1 sigma band, against the true value (the paper's Figures 2 and 3);
//!   `estimates_all` puts every coefficient in one grid.
//! - `rms_over_time`: RMS error over runs of every coefficient against time, divided by the
//!   coefficient's initial sigma so all share one log axis, with the truth-linearised bound.
//! - `step_cost`: median and 90th percentile of one predict + update, and the distribution.
//! - `nees_nis_over_time`: average NEES and NIS against time with their 95 % chi-square bands.
//!
//! Text is drawn with DejaVu Sans, compiled in from `assets/fonts/` (see the LICENSE there)
//! and registered with plotters once, so figures render the same on a machine without fonts.
//! Degenerate data (a filter with every run diverged, NaN, a zero range, a single stored time)
//! gives an empty or partial panel with a note, never a panic.

use crate::error::StudyError;
use crate::monte_carlo::{ExampleRun, Study};
use crate::output::write_atomic;
use crate::stats::mean_chi2_bounds;
use crate::summary::Summary;
use crate::tally::{bin_value, Tally};
use navkf_dynamics::state::NAV_DIM;
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use plotters::style::FontStyle;
use std::path::Path;
use std::sync::OnceLock;

/// The bundled font (DejaVu Sans; license in `assets/fonts/LICENSE`).
static FONT_BYTES: &[u8] = include_bytes!("../../../assets/fonts/DejaVuSans.ttf");
/// The family every figure asks for; the bundled font is registered under it.
const FONT: &str = "sans-serif";

/// Registers the bundled font with plotters (once per process; later calls return the first
/// call's outcome).
pub fn register_font() -> Result<(), StudyError> {
    static REGISTERED: OnceLock<Result<(), String>> = OnceLock::new();
    REGISTERED
        .get_or_init(|| {
            plotters::style::register_font(FONT, FontStyle::Normal, FONT_BYTES)
                .map_err(|_| "the bundled font assets/fonts/DejaVuSans.ttf is not a font".into())
        })
        .clone()
        .map_err(StudyError::Other)
}

/// A figure written (or not) by [`write_all`].
#[derive(Debug, Clone)]
pub struct FigureOutcome {
    /// File stem: the figure is `<name>.png` and `<name>.svg`.
    pub name: String,
    /// What it shows, in words.
    pub caption: String,
    /// `Err(reason)` when it could not be drawn.
    pub result: Result<(), String>,
}

/// Title of `rms_over_time`.
pub const RMS_TITLE: &str = "RMS error over time, divided by the initial sigma";
/// Title of `step_cost`.
pub const STEP_COST_TITLE: &str = "Cost of one filter step (predict + update)";
/// Title of `nees_nis_over_time`.
pub const NEES_NIS_TITLE: &str = "Average NEES and NIS over time, with 95 % bands";
/// Title of `estimates_all` (followed by the run index).
pub const ESTIMATES_ALL_TITLE: &str = "Coefficient estimates against the truth";

/// Draws every figure into `dir`. A figure that fails (or panics) is reported in its outcome;
/// the others are still drawn.
pub fn write_all(
    study: &Study,
    tally: &Tally,
    summary: &Summary,
    example: Option<&ExampleRun>,
    dir: &Path,
) -> Vec<FigureOutcome> {
    let mut out = Vec::new();
    let mut run = |name: String, caption: String, f: &dyn Fn() -> Result<(), StudyError>| {
        let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(f))
            .unwrap_or_else(|_| Err(StudyError::Other("the figure code panicked".into())))
            .map_err(|e| e.to_string());
        out.push(FigureOutcome {
            name,
            caption,
            result,
        });
    };
    if let Some(ex) = example {
        run(
            "estimates_all".into(),
            format!(
                "Estimates of every coefficient against the truth, run {}",
                ex.run
            ),
            &|| estimates_all(study, ex, dir),
        );
        for i in NAV_DIM..ex.names.len() {
            run(
                format!("estimates_{}", ex.names[i]),
                format!("{} in run {}", ex.names[i], ex.run),
                &|| estimates(study, ex, i, dir),
            );
        }
    }
    run(
        "rms_over_time".into(),
        "RMS error over time / initial sigma, with the bound".into(),
        &|| rms_over_time(study, tally, dir),
    );
    run(
        "nees_nis_over_time".into(),
        "Average NEES and NIS over time with 95 % bands".into(),
        &|| nees_nis_over_time(study, tally, dir),
    );
    run(
        "step_cost".into(),
        "Cost of one filter step".into(),
        &|| step_cost(study, tally, summary, dir),
    );
    out
}

/// `estimates_<name>`: the example run's estimates of coefficient `i` (a filter state index)
/// by every filter, with +-1 sigma bands, against the true value.
pub fn estimates(study: &Study, ex: &ExampleRun, i: usize, dir: &Path) -> Result<(), StudyError> {
    let name = ex
        .names
        .get(i)
        .ok_or_else(|| StudyError::Other(format!("estimates: no state {i}")))?;
    render(
        dir,
        &format!("estimates_{name}"),
        &Fig::Estimates { study, ex, i },
    )
}

/// `estimates_all`: one small panel per coefficient.
pub fn estimates_all(study: &Study, ex: &ExampleRun, dir: &Path) -> Result<(), StudyError> {
    render(dir, "estimates_all", &Fig::EstimatesAll { study, ex })
}

/// `rms_over_time`: one log panel per coefficient.
pub fn rms_over_time(study: &Study, tally: &Tally, dir: &Path) -> Result<(), StudyError> {
    render(dir, "rms_over_time", &Fig::Rms { study, tally })
}

/// `step_cost`: median and p90 per filter (from the summary), and the distributions.
pub fn step_cost(
    study: &Study,
    tally: &Tally,
    summary: &Summary,
    dir: &Path,
) -> Result<(), StudyError> {
    render(
        dir,
        "step_cost",
        &Fig::StepCost {
            study,
            tally,
            summary,
        },
    )
}

/// `nees_nis_over_time`: average NEES and NIS per filter with their 95 % bands.
pub fn nees_nis_over_time(study: &Study, tally: &Tally, dir: &Path) -> Result<(), StudyError> {
    render(dir, "nees_nis_over_time", &Fig::NeesNis { study, tally })
}

// ---------------------------------------------------------------------------------------------
// Units

const G: f64 = 9.80665;
const RAD_S_TO_DEG_H: f64 = 180.0 / std::f64::consts::PI * 3600.0;

/// The factor and unit a state is shown in: deg/h for drifts, deg/h/g for g-sensitive drifts,
/// micro-g for accelerometer biases, ppm for scale factors; other units as they are.
pub fn display_unit(unit: &str) -> (f64, String) {
    match unit {
        "rad/s" => (RAD_S_TO_DEG_H, "deg/h".into()),
        "rad/s/(m/s^2)" => (RAD_S_TO_DEG_H * G, "deg/h/g".into()),
        "m/s^2" => (1e6 / G, "µg".into()),
        "1" => (1e6, "ppm".into()),
        "rad" => (RAD_S_TO_DEG_H, "arcsec".into()),
        "" => (1.0, "-".into()),
        u => (1.0, u.into()),
    }
}

fn unit_of(study: &Study, i: usize) -> (f64, String) {
    display_unit(study.filter_model.units().get(i).map_or("", String::as_str))
}

/// Tick label: up to 4 significant digits, exponent form outside 1e-3..1e5; a value below a
/// millionth of the axis' `span` is the rounding error of a zero tick.
fn tick(v: f64, span: f64) -> String {
    if !v.is_finite() {
        return String::new();
    }
    let a = v.abs();
    if a == 0.0 || a < 1e-6 * span {
        return "0".into();
    }
    if (1e-3..1e5).contains(&a) {
        let decimals = (3 - a.log10().floor() as i32).clamp(0, 7) as usize;
        let s = format!("{v:.decimals$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    } else {
        format!("{v:.1e}").replace(".0e", "e")
    }
}

// ---------------------------------------------------------------------------------------------
// Panels: data first, then one drawing routine that copes with empty and degenerate data.

const PALETTE: [RGBColor; 6] = [
    RGBColor(214, 39, 40),
    RGBColor(31, 119, 180),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
];

fn color(i: usize) -> RGBColor {
    PALETTE[i % PALETTE.len()]
}

/// The line of filter `k` of `n`: earlier filters wider, so that filters whose curves
/// coincide show as nested stripes instead of hiding one another.
fn filter_line(k: usize, n: usize) -> ShapeStyle {
    let w = if n <= 1 {
        2
    } else {
        (2 * (n - 1 - k.min(n - 1)) + 1).min(7)
    };
    color(k).stroke_width(w as u32)
}

const GREY: RGBColor = RGBColor(110, 110, 110);

#[derive(Clone, Copy)]
struct Sizes {
    caption: u32,
    desc: u32,
    tick: u32,
    note: u32,
}

const BIG: Sizes = Sizes {
    caption: 22,
    desc: 17,
    tick: 14,
    note: 15,
};
const SMALL: Sizes = Sizes {
    caption: 16,
    desc: 13,
    tick: 11,
    note: 12,
};

/// A polyline; non-finite points (and non-positive ones on a log axis) break it.
struct Line {
    style: ShapeStyle,
    dashed: bool,
    pts: Vec<(f64, f64)>,
}

/// A filled region between two curves sampled at the same abscissae.
struct Band {
    style: ShapeStyle,
    pts: Vec<(f64, f64, f64)>,
}

#[derive(Clone, Copy, PartialEq)]
enum Mark {
    Line,
    Dashed,
    Box,
}

/// A legend row.
struct Entry {
    label: String,
    style: ShapeStyle,
    mark: Mark,
}

#[derive(Clone, Copy, PartialEq)]
enum Scale {
    Linear,
    Log,
}

struct Panel {
    caption: String,
    x_desc: String,
    y_desc: String,
    x_scale: Scale,
    y_scale: Scale,
    lines: Vec<Line>,
    bands: Vec<Band>,
    /// Bars `(x_lo, x_hi, height, style)` from y = 0.
    bars: Vec<(f64, f64, f64, ShapeStyle)>,
    /// Text at data coordinates (centre, bottom).
    labels: Vec<(f64, f64, String)>,
    /// Said in the panel's top-left corner (why something is missing).
    notes: Vec<String>,
    /// Limits the y axis (a filter far off would squash the others).
    y_limit: Option<(f64, f64)>,
    /// Forces the axes to include these values (only with other data to draw).
    x_include: Vec<f64>,
    /// See `x_include`.
    y_include: Vec<f64>,
    /// No numbers on the x axis (categorical bars).
    hide_x_ticks: bool,
    sizes: Sizes,
}

impl Panel {
    fn new(caption: String, x_desc: &str, y_desc: String, y_scale: Scale, sizes: Sizes) -> Self {
        Panel {
            caption,
            x_desc: x_desc.into(),
            y_desc,
            x_scale: Scale::Linear,
            y_scale,
            lines: Vec::new(),
            bands: Vec::new(),
            bars: Vec::new(),
            labels: Vec::new(),
            notes: Vec::new(),
            y_limit: None,
            x_include: Vec::new(),
            y_include: Vec::new(),
            hide_x_ticks: false,
            sizes,
        }
    }

    fn line(&mut self, style: ShapeStyle, dashed: bool, pts: Vec<(f64, f64)>) {
        self.lines.push(Line { style, dashed, pts });
    }
}

fn usable(v: f64, scale: Scale) -> bool {
    v.is_finite() && (scale == Scale::Linear || v > 0.0)
}

/// Finite (and for a log axis positive) extent of `vals`.
fn extent(vals: impl Iterator<Item = f64>, scale: Scale) -> Option<(f64, f64)> {
    vals.filter(|v| usable(*v, scale))
        .fold(None, |acc, v| match acc {
            None => Some((v, v)),
            Some((lo, hi)) => Some((lo.min(v), hi.max(v))),
        })
}

/// Pads an extent into an axis range that plotters can draw: never empty, never a zero
/// width; a log range spans at least one decade.
fn axis_range((lo, hi): (f64, f64), scale: Scale, pad: bool) -> (f64, f64) {
    match scale {
        Scale::Linear => {
            let w = hi - lo;
            if !(w > 1e-12 * lo.abs().max(hi.abs())) || !(w > f64::MIN_POSITIVE) {
                let d = if lo != 0.0 { lo.abs() * 0.1 } else { 1.0 };
                (lo - d, hi + d)
            } else if pad {
                (lo - 0.05 * w, hi + 0.05 * w)
            } else {
                (lo, hi)
            }
        }
        Scale::Log => {
            // At least two powers of ten inside, so that the axis has two labels.
            let (mut lo, mut hi) = (lo, hi);
            let first = lo.log10().ceil();
            let last = hi.log10().floor();
            if last < first {
                lo = lo.min(10f64.powf(first - 1.0));
                hi = hi.max(10f64.powf(first));
            } else if last == first {
                // One inside: reach for the nearer neighbour.
                if lo.log10() - (first - 1.0) < (first + 1.0) - hi.log10() {
                    lo = 10f64.powf(first - 1.0);
                } else {
                    hi = 10f64.powf(first + 1.0);
                }
            }
            if pad {
                (lo / 1.15, hi * 1.15)
            } else {
                (lo, hi)
            }
        }
    }
}

/// Splits a polyline at unusable points; keeps points inside the axis range.
fn segments(
    pts: &[(f64, f64)],
    xs: Scale,
    ys: Scale,
    xr: (f64, f64),
    yr: (f64, f64),
) -> Vec<Vec<(f64, f64)>> {
    let mut out = Vec::new();
    let mut cur: Vec<(f64, f64)> = Vec::new();
    for &(x, y) in pts {
        if usable(x, xs) && usable(y, ys) {
            cur.push((x.clamp(xr.0, xr.1), y.clamp(yr.0, yr.1)));
        } else if !cur.is_empty() {
            out.push(std::mem::take(&mut cur));
        }
    }
    if !cur.is_empty() {
        out.push(cur);
    }
    out
}

/// Error text of a plotters failure.
trait Msg<T> {
    fn m(self) -> Result<T, String>;
}

impl<T, E: std::fmt::Display> Msg<T> for Result<T, E> {
    fn m(self) -> Result<T, String> {
        self.map_err(|e| e.to_string())
    }
}

fn text_style(size: u32, color: RGBColor) -> TextStyle<'static> {
    (FONT, size).into_font().color(&color)
}

/// Writes `lines` of text from the top-left corner of `area` (pixels).
fn draw_notes<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    notes: &[String],
    at: (i32, i32),
    size: u32,
) -> Result<(), String> {
    let style = text_style(size, RGBColor(150, 20, 20));
    for (k, n) in notes.iter().enumerate() {
        area.draw_text(n, &style, (at.0, at.1 + k as i32 * (size as i32 + 4)))
            .m()?;
    }
    Ok(())
}

/// Draws a legend in `area`, one row per entry, from its top-left corner.
fn draw_legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    entries: &[Entry],
    size: u32,
    top: i32,
) -> Result<(), String> {
    let row = size as i32 + 10;
    let style = text_style(size, BLACK).pos(Pos::new(HPos::Left, VPos::Center));
    for (k, e) in entries.iter().enumerate() {
        let y = top + row / 2 + k as i32 * row;
        let (x0, x1) = (10, 44);
        match e.mark {
            Mark::Line => area.draw(&PathElement::new(vec![(x0, y), (x1, y)], e.style)),
            Mark::Dashed => area.draw(&DashedPathElement::new(
                vec![(x0, y), (x1, y)],
                7,
                4,
                e.style,
            )),
            Mark::Box => area.draw(&Rectangle::new([(x0, y - 6), (x1, y + 6)], e.style)),
        }
        .m()?;
        area.draw_text(&e.label, &style, (x1 + 8, y)).m()?;
    }
    Ok(())
}

/// Draws one panel: axes, bands, bars, lines and notes; or, without usable data, its caption
/// and a note saying so.
fn draw_panel<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, p: &Panel) -> Result<(), String> {
    let xs = p
        .lines
        .iter()
        .flat_map(|l| l.pts.iter().map(|q| q.0))
        .chain(p.bands.iter().flat_map(|b| b.pts.iter().map(|q| q.0)))
        .chain(p.bars.iter().flat_map(|b| [b.0, b.1]));
    let x_ext = extent(xs, p.x_scale)
        .and_then(|e| extent(p.x_include.iter().copied().chain([e.0, e.1]), p.x_scale));
    let ys = p
        .lines
        .iter()
        .flat_map(|l| l.pts.iter().map(|q| q.1))
        .chain(
            p.bands
                .iter()
                .flat_map(|b| b.pts.iter().flat_map(|q| [q.1, q.2])),
        )
        .chain(p.bars.iter().flat_map(|b| [0.0, b.2]));
    let mut y_ext = extent(ys, p.y_scale)
        .and_then(|e| extent(p.y_include.iter().copied().chain([e.0, e.1]), p.y_scale));
    if let (Some((lo, hi)), Some((a, b))) = (y_ext, p.y_limit) {
        let (lo, hi) = (lo.max(a), hi.min(b));
        y_ext = (lo <= hi).then_some((lo, hi)).or(Some((a, b)));
    }
    let (Some(x_ext), Some(y_ext)) = (x_ext, y_ext) else {
        let (w, h) = area.dim_in_pixel();
        area.draw(&Rectangle::new(
            [(1, 1), (w as i32 - 2, h as i32 - 2)],
            RGBColor(200, 200, 200),
        ))
        .m()?;
        let cap = text_style(p.sizes.caption, BLACK).pos(Pos::new(HPos::Center, VPos::Top));
        area.draw_text(&p.caption, &cap, (w as i32 / 2, 6)).m()?;
        let mut notes = p.notes.clone();
        notes.push("no data to draw".into());
        return draw_notes(
            area,
            &notes,
            (16, p.sizes.caption as i32 + 20),
            p.sizes.note,
        );
    };
    let xr = axis_range(x_ext, p.x_scale, false);
    let mut yr = axis_range(y_ext, p.y_scale, true);
    if let Some((a, b)) = p.y_limit {
        if a.max(yr.0) < b.min(yr.1) {
            yr = (a.max(yr.0), b.min(yr.1));
        }
    }
    let y_fmt = |v: &f64| tick(*v, yr.1 - yr.0);
    let x_fmt = |v: &f64| tick(*v, xr.1 - xr.0);
    let blank = |_: &f64| String::new();
    let mut b = ChartBuilder::on(area);
    b.caption(&p.caption, (FONT, p.sizes.caption))
        .margin(8)
        .margin_right(18)
        .x_label_area_size(p.sizes.tick * 2 + p.sizes.desc + 8)
        .y_label_area_size(p.sizes.tick * 4 + p.sizes.desc + 12);
    macro_rules! finish {
        ($chart:expr) => {{
            let mut chart = $chart.m()?;
            let mut mesh = chart.configure_mesh();
            mesh.x_desc(p.x_desc.as_str())
                .y_desc(p.y_desc.as_str())
                .x_labels(6)
                .y_labels(6)
                .y_label_formatter(&y_fmt)
                .label_style((FONT, p.sizes.tick))
                .axis_desc_style((FONT, p.sizes.desc))
                .bold_line_style(RGBColor(215, 215, 215))
                .light_line_style(RGBColor(240, 240, 240));
            if p.hide_x_ticks {
                mesh.x_label_formatter(&blank).disable_x_mesh();
            } else {
                mesh.x_label_formatter(&x_fmt);
            }
            mesh.draw().m()?;
            draw_content(&mut chart, p, xr, yr)?;
        }};
    }
    match (p.x_scale, p.y_scale) {
        (Scale::Linear, Scale::Linear) => finish!(b.build_cartesian_2d(xr.0..xr.1, yr.0..yr.1)),
        (Scale::Linear, Scale::Log) => {
            finish!(b.build_cartesian_2d(xr.0..xr.1, (yr.0..yr.1).log_scale()))
        }
        (Scale::Log, Scale::Linear) => {
            finish!(b.build_cartesian_2d((xr.0..xr.1).log_scale(), yr.0..yr.1))
        }
        (Scale::Log, Scale::Log) => {
            finish!(b.build_cartesian_2d((xr.0..xr.1).log_scale(), (yr.0..yr.1).log_scale()))
        }
    }
    let left = (p.sizes.tick * 4 + p.sizes.desc + 30) as i32;
    draw_notes(
        area,
        &p.notes,
        (left, p.sizes.caption as i32 + 22),
        p.sizes.note,
    )
}

fn draw_content<DB: DrawingBackend, CT: CoordTranslate<From = (f64, f64)>>(
    chart: &mut ChartContext<'_, DB, CT>,
    p: &Panel,
    xr: (f64, f64),
    yr: (f64, f64),
) -> Result<(), String> {
    let (xs, ys) = (p.x_scale, p.y_scale);
    let inside = |x: f64, y: f64| (x.clamp(xr.0, xr.1), y.clamp(yr.0, yr.1));
    for band in &p.bands {
        let mut run: Vec<(f64, f64, f64)> = Vec::new();
        let mut flush = |run: &mut Vec<(f64, f64, f64)>| -> Result<(), String> {
            if run.len() >= 2 {
                let mut poly: Vec<(f64, f64)> = run.iter().map(|q| inside(q.0, q.2)).collect();
                poly.extend(run.iter().rev().map(|q| inside(q.0, q.1)));
                chart
                    .draw_series(std::iter::once(Polygon::new(poly, band.style)))
                    .m()?;
            }
            run.clear();
            Ok(())
        };
        for &q in &band.pts {
            if usable(q.0, xs) && usable(q.1, ys) && usable(q.2, ys) {
                run.push(q);
            } else {
                flush(&mut run)?;
            }
        }
        flush(&mut run)?;
    }
    for &(x0, x1, h, style) in &p.bars {
        if usable(h, ys) && usable(x0, xs) && usable(x1, xs) {
            let base = if ys == Scale::Log { yr.0 } else { 0.0 };
            chart
                .draw_series(std::iter::once(Rectangle::new(
                    [inside(x0, base), inside(x1, h)],
                    style,
                )))
                .m()?;
        }
    }
    for line in &p.lines {
        for seg in segments(&line.pts, xs, ys, xr, yr) {
            if seg.len() == 1 {
                chart
                    .draw_series(std::iter::once(Circle::new(seg[0], 3, line.style.filled())))
                    .m()?;
            } else if line.dashed {
                chart
                    .draw_series(std::iter::once(DashedPathElement::new(
                        seg, 7, 4, line.style,
                    )))
                    .m()?;
            } else {
                chart
                    .draw_series(std::iter::once(PathElement::new(seg, line.style)))
                    .m()?;
            }
        }
    }
    let style = text_style(p.sizes.note, BLACK).pos(Pos::new(HPos::Center, VPos::Bottom));
    for (x, y, s) in &p.labels {
        if usable(*x, xs) && usable(*y, ys) {
            chart
                .draw_series(std::iter::once(Text::new(
                    s.clone(),
                    inside(*x, *y),
                    style.clone(),
                )))
                .m()?;
        }
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// The figures' data

/// `big`: the single figure (full caption, large type); else a grid cell.
fn estimate_panel(study: &Study, ex: &ExampleRun, i: usize, big: bool) -> Panel {
    let name = &ex.names[i];
    let (scale, unit) = unit_of(study, i);
    let (caption, sizes) = if big {
        (format!("{name}: estimate vs truth, run {}", ex.run), BIG)
    } else {
        (name.clone(), SMALL)
    };
    let mut p = Panel::new(
        caption,
        "time (s)",
        format!("{name} ({unit})"),
        Scale::Linear,
        sizes,
    );
    let truth: Vec<(f64, f64)> =
        ex.t.iter()
            .zip(&ex.truth)
            .map(|(t, r)| (*t, r.get(i).copied().unwrap_or(f64::NAN) * scale))
            .collect();
    let truth_at_start = truth.iter().map(|q| q.1).find(|v| v.is_finite());
    for (k, f) in ex.filters.iter().enumerate() {
        let c = color(k);
        let pts: Vec<(f64, f64, f64)> =
            f.t.iter()
                .zip(f.estimate.iter().zip(&f.sigma))
                .map(|(t, (x, s))| {
                    let x = x.get(i).copied().unwrap_or(f64::NAN) * scale;
                    let s = s.get(i).copied().unwrap_or(f64::NAN) * scale;
                    (*t, x, s)
                })
                .collect();
        if !pts.iter().any(|q| q.1.is_finite()) {
            p.notes
                .push(format!("{}: no estimates in this run", f.name));
            continue;
        }
        p.bands.push(Band {
            style: c.mix(0.13).filled(),
            pts: pts.iter().map(|q| (q.0, q.1 - q.2, q.1 + q.2)).collect(),
        });
        p.line(
            filter_line(k, ex.filters.len()),
            false,
            pts.iter().map(|q| (q.0, q.1)).collect(),
        );
    }
    match truth_at_start {
        Some(_) => p.line(BLACK.stroke_width(2), true, truth),
        None if ex.t.is_empty() => p.notes.push("no true values recorded".into()),
        None => p
            .notes
            .push(format!("the truth model has no {name}: no true value")),
    }
    let s0 = study.initial_sigma.get(i).copied().unwrap_or(f64::NAN) * scale;
    if s0.is_finite() && s0 > 0.0 {
        let c = truth_at_start.unwrap_or(0.0);
        p.y_limit = Some((c - 6.0 * s0, c + 6.0 * s0));
    }
    p
}

fn estimate_legend(ex: &ExampleRun) -> Vec<Entry> {
    let mut e: Vec<Entry> = ex
        .filters
        .iter()
        .enumerate()
        .map(|(k, f)| Entry {
            label: format!("{} estimate", f.name),
            style: filter_line(k, ex.filters.len()),
            mark: Mark::Line,
        })
        .collect();
    e.push(Entry {
        label: "±1 sigma (filter's own)".into(),
        style: GREY.mix(0.3).filled(),
        mark: Mark::Box,
    });
    e.push(Entry {
        label: "true value".into(),
        style: BLACK.stroke_width(2),
        mark: Mark::Dashed,
    });
    e
}

fn rms_panel(study: &Study, tally: &Tally, i: usize) -> Panel {
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
fn consistency_panel(study: &Study, tally: &Tally, nis: bool) -> (Panel, Vec<Entry>) {
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
        Scale::Log,
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

fn step_cost_panels(study: &Study, tally: &Tally, summary: &Summary) -> (Panel, Panel) {
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
            ));
            bars.labels.push((x, h + top * 0.1, fname.clone()));
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

// ---------------------------------------------------------------------------------------------
// Figures and rendering

enum Fig<'a> {
    Estimates {
        study: &'a Study,
        ex: &'a ExampleRun,
        i: usize,
    },
    EstimatesAll {
        study: &'a Study,
        ex: &'a ExampleRun,
    },
    Rms {
        study: &'a Study,
        tally: &'a Tally,
    },
    StepCost {
        study: &'a Study,
        tally: &'a Tally,
        summary: &'a Summary,
    },
    NeesNis {
        study: &'a Study,
        tally: &'a Tally,
    },
}

const GRID_COLS: usize = 4;
const CELL: (u32, u32) = (430, 320);
const TITLE_H: u32 = 56;
const LEGEND_W: u32 = 300;

fn coefficient_count(names: &[String]) -> usize {
    names.len().saturating_sub(NAV_DIM)
}

fn grid_size(panels: usize) -> (u32, u32) {
    let cells = panels + 1; // and the legend
    let rows = cells.div_ceil(GRID_COLS).max(1) as u32;
    (GRID_COLS as u32 * CELL.0, rows * CELL.1 + TITLE_H)
}

impl Fig<'_> {
    fn size(&self) -> (u32, u32) {
        match self {
            Fig::Estimates { .. } => (1200, 650),
            Fig::EstimatesAll { ex, .. } => grid_size(coefficient_count(&ex.names)),
            Fig::Rms { study, .. } => grid_size(coefficient_count(&study.names)),
            Fig::StepCost { .. } => (1400, 620),
            Fig::NeesNis { .. } => (1400, 1000),
        }
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let title = |s: &str| root.titled(s, (FONT, 26)).m();
        match *self {
            Fig::Estimates { study, ex, i } => {
                let (plot, side) = root.split_horizontally(1200 - LEGEND_W);
                draw_panel(&plot, &estimate_panel(study, ex, i, true))?;
                draw_legend(&side, &estimate_legend(ex), 16, 60)
            }
            Fig::EstimatesAll { study, ex } => {
                let area = title(&format!("{ESTIMATES_ALL_TITLE}, run {}", ex.run))?;
                let m = coefficient_count(&ex.names);
                let rows = (m + 1).div_ceil(GRID_COLS).max(1);
                let cells = area.split_evenly((rows, GRID_COLS));
                for (c, i) in cells.iter().zip(NAV_DIM..ex.names.len()) {
                    draw_panel(c, &estimate_panel(study, ex, i, false))?;
                }
                match cells.get(m) {
                    Some(cell) => draw_legend(cell, &estimate_legend(ex), 14, 30),
                    None => Ok(()),
                }
            }
            Fig::Rms { study, tally } => {
                let ok: Vec<String> = study
                    .filter_names()
                    .iter()
                    .zip(&tally.filters)
                    .map(|(n, f)| format!("{n} {}", f.ok))
                    .collect();
                let area = title(&format!(
                    "{RMS_TITLE} (runs finished: {} of {})",
                    ok.join(", "),
                    tally.runs
                ))?;
                let m = coefficient_count(&study.names);
                let rows = (m + 1).div_ceil(GRID_COLS).max(1);
                let cells = area.split_evenly((rows, GRID_COLS));
                for (c, i) in cells.iter().zip(NAV_DIM..study.names.len()) {
                    draw_panel(c, &rms_panel(study, tally, i))?;
                }
                let mut legend: Vec<Entry> = study
                    .filter_names()
                    .iter()
                    .enumerate()
                    .map(|(k, f)| Entry {
                        label: format!("{f} RMS error"),
                        style: filter_line(k, study.filter_names().len()),
                        mark: Mark::Line,
                    })
                    .collect();
                legend.push(Entry {
                    label: if tally.bound.count > 0 {
                        "bound (truth-linearised)".into()
                    } else {
                        "bound: not available".into()
                    },
                    style: BLACK.stroke_width(2),
                    mark: Mark::Dashed,
                });
                match cells.get(m) {
                    Some(cell) => draw_legend(cell, &legend, 14, 30),
                    None => Ok(()),
                }
            }
            Fig::StepCost {
                study,
                tally,
                summary,
            } => {
                let area = title(STEP_COST_TITLE)?;
                let (l, r) = area.split_horizontally(600);
                let (bars, cdf) = step_cost_panels(study, tally, summary);
                draw_panel(&l, &bars)?;
                let (plot, side) = r.split_horizontally(800 - LEGEND_W);
                draw_panel(&plot, &cdf)?;
                let mut legend: Vec<Entry> = study
                    .filter_names()
                    .iter()
                    .enumerate()
                    .map(|(k, f)| Entry {
                        label: f.clone(),
                        style: color(k).filled(),
                        mark: Mark::Box,
                    })
                    .collect();
                legend.push(Entry {
                    label: "pale bars: p90".into(),
                    style: GREY.mix(0.45).filled(),
                    mark: Mark::Box,
                });
                draw_legend(&side, &legend, 15, 50)
            }
            Fig::NeesNis { study, tally } => {
                let area = title(NEES_NIS_TITLE)?;
                let (plot, side) = area.split_horizontally(1400 - LEGEND_W - 40);
                let (top, bottom) = plot.split_vertically(472);
                let (nees, legend) = consistency_panel(study, tally, false);
                let (nis, _) = consistency_panel(study, tally, true);
                draw_panel(&top, &nees)?;
                draw_panel(&bottom, &nis)?;
                draw_legend(&side, &legend, 15, 50)
            }
        }
    }
}

/// Draws `fig` as `<name>.svg` and `<name>.png` in `dir`, each written atomically.
fn render(dir: &Path, name: &str, fig: &Fig) -> Result<(), StudyError> {
    register_font()?;
    let size = fig.size();
    let err = |e: String| StudyError::Other(format!("figure {name}: {e}"));
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        root.fill(&WHITE).m().map_err(err)?;
        fig.draw(&root).map_err(err)?;
        root.present().m().map_err(err)?;
    }
    write_atomic(&dir.join(format!("{name}.svg")), svg.as_bytes())?;
    std::fs::create_dir_all(dir).map_err(|source| StudyError::Io {
        path: dir.to_path_buf(),
        source,
    })?;
    // The PNG encoder picks the format from the extension: the temporary name ends in .png.
    let tmp = dir.join(format!(".{name}.tmp{}.png", std::process::id()));
    let drawn = (|| {
        let root = BitMapBackend::new(&tmp, size).into_drawing_area();
        root.fill(&WHITE).m()?;
        fig.draw(&root)?;
        root.present().m()
    })();
    if let Err(e) = drawn {
        let _ = std::fs::remove_file(&tmp);
        return Err(err(e));
    }
    let path = dir.join(format!("{name}.png"));
    std::fs::rename(&tmp, &path).map_err(|source| StudyError::Io { path, source })
}
