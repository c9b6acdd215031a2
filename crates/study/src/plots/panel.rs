//! The drawing kit every figure shares: the bundled font, panels (lines, bands, bars, labels
//! and notes on linear or log axes), legends, and atomic PNG + SVG rendering.
//!
//! A figure is data first ([`Panel`]s), then one drawing routine that copes with empty and
//! degenerate data: non-finite points break a line, an empty panel says so in a note.

use crate::error::StudyError;
use crate::output::write_atomic;
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use plotters::style::FontStyle;
use std::path::Path;
use std::sync::OnceLock;

/// The bundled font (DejaVu Sans; license in `assets/fonts/LICENSE`).
static FONT_BYTES: &[u8] = include_bytes!("../../../../assets/fonts/DejaVuSans.ttf");
/// The family every figure asks for; the bundled font is registered under it.
pub(crate) const FONT: &str = "sans-serif";

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

/// Tick label: up to 4 significant digits, exponent form outside 1e-3..1e5; a value below a
/// millionth of the axis' `span` is the rounding error of a zero tick.
pub(crate) fn tick(v: f64, span: f64) -> String {
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

pub(crate) fn color(i: usize) -> RGBColor {
    PALETTE[i % PALETTE.len()]
}

/// The line of filter `k` of `n`: earlier filters wider, so that filters whose curves
/// coincide show as nested stripes instead of hiding one another.
pub(crate) fn filter_line(k: usize, n: usize) -> ShapeStyle {
    let w = if n <= 1 {
        2
    } else {
        (2 * (n - 1 - k.min(n - 1)) + 1).min(7)
    };
    color(k).stroke_width(w as u32)
}

pub(crate) const GREY: RGBColor = RGBColor(110, 110, 110);

#[derive(Clone, Copy)]
pub(crate) struct Sizes {
    pub(crate) caption: u32,
    pub(crate) desc: u32,
    pub(crate) tick: u32,
    pub(crate) note: u32,
}

pub(crate) const BIG: Sizes = Sizes {
    caption: 22,
    desc: 17,
    tick: 14,
    note: 15,
};
pub(crate) const SMALL: Sizes = Sizes {
    caption: 16,
    desc: 13,
    tick: 11,
    note: 12,
};

/// A polyline; non-finite points (and non-positive ones on a log axis) break it.
pub(crate) struct Line {
    pub(crate) style: ShapeStyle,
    pub(crate) dashed: bool,
    pub(crate) pts: Vec<(f64, f64)>,
}

/// A filled region between two curves sampled at the same abscissae.
pub(crate) struct Band {
    pub(crate) style: ShapeStyle,
    pub(crate) pts: Vec<(f64, f64, f64)>,
}

#[derive(Clone, Copy, PartialEq)]
pub(crate) enum Mark {
    Line,
    Dashed,
    Box,
}

/// A legend row.
pub(crate) struct Entry {
    pub(crate) label: String,
    pub(crate) style: ShapeStyle,
    pub(crate) mark: Mark,
}

#[derive(Clone, Copy, PartialEq)]
pub(crate) enum Scale {
    Linear,
    Log,
}

pub(crate) struct Panel {
    pub(crate) caption: String,
    pub(crate) x_desc: String,
    pub(crate) y_desc: String,
    pub(crate) x_scale: Scale,
    pub(crate) y_scale: Scale,
    pub(crate) lines: Vec<Line>,
    pub(crate) bands: Vec<Band>,
    /// Bars `(x_lo, x_hi, height, style)` from y = 0.
    pub(crate) bars: Vec<(f64, f64, f64, ShapeStyle)>,
    /// Text at data coordinates (centre, bottom).
    pub(crate) labels: Vec<(f64, f64, String)>,
    /// Said in the panel's top-left corner (why something is missing).
    pub(crate) notes: Vec<String>,
    /// Limits the y axis (a filter far off would squash the others).
    pub(crate) y_limit: Option<(f64, f64)>,
    /// Forces the axes to include these values (only with other data to draw).
    pub(crate) x_include: Vec<f64>,
    /// See `x_include`.
    pub(crate) y_include: Vec<f64>,
    /// No numbers on the x axis (categorical bars).
    pub(crate) hide_x_ticks: bool,
    pub(crate) sizes: Sizes,
}

impl Panel {
    pub(crate) fn new(
        caption: String,
        x_desc: &str,
        y_desc: String,
        y_scale: Scale,
        sizes: Sizes,
    ) -> Self {
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

    pub(crate) fn line(&mut self, style: ShapeStyle, dashed: bool, pts: Vec<(f64, f64)>) {
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
pub(crate) trait Msg<T> {
    fn m(self) -> Result<T, String>;
}

impl<T, E: std::fmt::Display> Msg<T> for Result<T, E> {
    fn m(self) -> Result<T, String> {
        self.map_err(|e| e.to_string())
    }
}

pub(crate) fn text_style(size: u32, color: RGBColor) -> TextStyle<'static> {
    (FONT, size).into_font().color(&color)
}

/// Writes `lines` of text from the top-left corner of `area` (pixels).
pub(crate) fn draw_notes<DB: DrawingBackend>(
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
pub(crate) fn draw_legend<DB: DrawingBackend>(
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
pub(crate) fn draw_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    p: &Panel,
) -> Result<(), String> {
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

/// A figure of panels in a grid under a title, with a legend strip on the right.
pub(crate) struct Grid {
    pub(crate) title: String,
    pub(crate) panels: Vec<Panel>,
    pub(crate) cols: usize,
    pub(crate) cell: (u32, u32),
    pub(crate) legend: Vec<Entry>,
}

const TITLE_H: u32 = 50;
const LEGEND_W: u32 = 290;

impl Figure for Grid {
    fn size(&self) -> (u32, u32) {
        let rows = self.panels.len().div_ceil(self.cols).max(1) as u32;
        let legend = if self.legend.is_empty() { 0 } else { LEGEND_W };
        (
            self.cols as u32 * self.cell.0 + legend,
            rows * self.cell.1 + TITLE_H,
        )
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let area = root.titled(&self.title, (FONT, 24)).m()?;
        let rows = self.panels.len().div_ceil(self.cols).max(1);
        let plot_w = self.cols as u32 * self.cell.0;
        let (plot, side) = area.split_horizontally(plot_w);
        for (cell, p) in plot
            .split_evenly((rows, self.cols))
            .iter()
            .zip(&self.panels)
        {
            draw_panel(cell, p)?;
        }
        if !self.legend.is_empty() {
            draw_legend(&side, &self.legend, 15, 40)?;
        }
        Ok(())
    }
}

pub(crate) fn entry(label: impl Into<String>, style: ShapeStyle, mark: Mark) -> Entry {
    Entry {
        label: label.into(),
        style,
        mark,
    }
}

/// A figure: its size in pixels and how to draw it on any backend.
pub(crate) trait Figure {
    fn size(&self) -> (u32, u32);
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String>;
}

/// Draws `fig` as `<name>.svg` and `<name>.png` in `dir`, each written atomically.
pub(crate) fn render<F: Figure>(dir: &Path, name: &str, fig: &F) -> Result<(), StudyError> {
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
