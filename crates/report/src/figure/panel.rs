//! A panel: lines, bands, bars, labels and notes on linear or log axes, as data, and the one
//! routine that draws it, coping with empty and degenerate data.

use super::style::{text_style, tick, Msg, Sizes};
use super::FONT;
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// A polyline; non-finite points (and non-positive ones on a log axis) break it.
pub struct Line {
    pub style: ShapeStyle,
    pub dashed: bool,
    pub pts: Vec<(f64, f64)>,
}

/// A filled region between two curves sampled at the same abscissae.
pub struct Band {
    pub style: ShapeStyle,
    pub pts: Vec<(f64, f64, f64)>,
}

#[derive(Clone, Copy, PartialEq)]
pub enum Mark {
    Line,
    Dashed,
    Box,
}

/// A legend row.
pub struct Entry {
    pub label: String,
    pub style: ShapeStyle,
    pub mark: Mark,
}

#[derive(Clone, Copy, PartialEq)]
pub enum Scale {
    Linear,
    Log,
}

pub struct Panel {
    pub caption: String,
    pub x_desc: String,
    pub y_desc: String,
    pub x_scale: Scale,
    pub y_scale: Scale,
    pub lines: Vec<Line>,
    pub bands: Vec<Band>,
    /// Bars `(x_lo, x_hi, height, style)` from y = 0.
    pub bars: Vec<(f64, f64, f64, ShapeStyle)>,
    /// Text at data coordinates (centre, bottom), in its colour.
    pub labels: Vec<(f64, f64, String, RGBColor)>,
    /// Said in the panel's top-left corner (why something is missing).
    pub notes: Vec<String>,
    /// The notes in a strip of their own under the caption, above the plot, instead of over
    /// its top-left corner (where they would cross curves that reach it).
    pub notes_above: bool,
    /// Limits the y axis (a filter far off would squash the others).
    pub y_limit: Option<(f64, f64)>,
    /// Forces the axes to include these values (only with other data to draw).
    pub x_include: Vec<f64>,
    /// See `x_include`.
    pub y_include: Vec<f64>,
    /// No numbers on the x axis (categorical bars).
    pub hide_x_ticks: bool,
    /// Names written under the x axis at these abscissae, in place of its ticks (the
    /// categories of bars).
    pub x_names: Vec<(f64, String)>,
    pub sizes: Sizes,
}

impl Panel {
    pub fn new(
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
            notes_above: false,
            y_limit: None,
            x_include: Vec::new(),
            y_include: Vec::new(),
            hide_x_ticks: false,
            x_names: Vec::new(),
            sizes,
        }
    }

    pub fn line(&mut self, style: ShapeStyle, dashed: bool, pts: Vec<(f64, f64)>) {
        self.lines.push(Line { style, dashed, pts });
    }
}

pub fn entry(label: impl Into<String>, style: ShapeStyle, mark: Mark) -> Entry {
    Entry {
        label: label.into(),
        style,
        mark,
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

/// How far past its end a log axis reaches, relative ([`axis_range`]).
const EDGE: f64 = 1e-9;

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
                // A power of ten at an end would be lost to rounding: plotters finds the
                // first labelled one as 10^ceil(ln lo / ln 10), -0.9999999999999998 for
                // lo = 0.1, and the last by multiplying up to 10.000000000000002 > 10.
                (lo * (1.0 - EDGE), hi * (1.0 + EDGE))
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

/// Writes `lines` of text from the top-left corner of `area` (pixels).
pub fn draw_notes<DB: DrawingBackend>(
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

/// Draws one panel: axes, bands, bars, lines and notes; or, without usable data, its caption
/// and a note saying so.
pub fn draw_panel<DB: DrawingBackend>(
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
    // Notes above the plot: the caption and the notes in a strip, the chart under it.
    let strip = (p.notes_above && !p.notes.is_empty())
        .then(|| p.sizes.caption + 14 + p.notes.len() as u32 * (p.sizes.note + 4));
    let (area, caption) = match strip {
        Some(h) => {
            let (top, rest) = area.split_vertically(h);
            let w = top.dim_in_pixel().0 as i32;
            let cap = text_style(p.sizes.caption, BLACK).pos(Pos::new(HPos::Center, VPos::Top));
            top.draw_text(&p.caption, &cap, (w / 2, 6)).m()?;
            let left = (p.sizes.tick * 4 + p.sizes.desc + 30) as i32;
            draw_notes(
                &top,
                &p.notes,
                (left, p.sizes.caption as i32 + 12),
                p.sizes.note,
            )?;
            (rest, None)
        }
        None => (area.clone(), Some(p.caption.as_str())),
    };
    let area = &area;
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
    if let Some(caption) = caption {
        b.caption(caption, (FONT, p.sizes.caption));
    }
    b.margin(8)
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
            if !p.x_names.is_empty() {
                mesh.x_labels(0).disable_x_mesh();
            } else if p.hide_x_ticks {
                mesh.x_label_formatter(&blank).disable_x_mesh();
            } else {
                mesh.x_label_formatter(&x_fmt);
            }
            mesh.draw().m()?;
            draw_content(&mut chart, p, xr, yr)?;
            let style = text_style(p.sizes.tick, BLACK).pos(Pos::new(HPos::Center, VPos::Top));
            let base = area.get_base_pixel();
            for (x, name) in &p.x_names {
                if usable(*x, p.x_scale) {
                    let (px, py) = chart.backend_coord(&(*x, yr.0));
                    area.draw_text(name, &style, (px - base.0, py - base.1 + 6))
                        .m()?;
                }
            }
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
    if strip.is_some() {
        return Ok(());
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
            } else if line.style.stroke_width > 1 {
                // Thick: cut where it turns back, each cut joined round (super::joins).
                let px: Vec<(i32, i32)> = seg
                    .iter()
                    .map(|q| chart.as_coord_spec().translate(q))
                    .collect();
                let pieces = super::joins::pieces(&px);
                let dot = (line.style.stroke_width / 2).max(1);
                for (k, piece) in pieces.iter().enumerate() {
                    let pts: Vec<(f64, f64)> = piece.iter().map(|&i| seg[i]).collect();
                    if k > 0 {
                        chart
                            .draw_series(std::iter::once(Circle::new(
                                pts[0],
                                dot,
                                line.style.filled(),
                            )))
                            .m()?;
                    }
                    chart
                        .draw_series(std::iter::once(PathElement::new(pts, line.style)))
                        .m()?;
                }
            } else {
                chart
                    .draw_series(std::iter::once(PathElement::new(seg, line.style)))
                    .m()?;
            }
        }
    }
    for (x, y, s, colour) in &p.labels {
        if usable(*x, xs) && usable(*y, ys) {
            let style = text_style(p.sizes.note, *colour).pos(Pos::new(HPos::Center, VPos::Bottom));
            chart
                .draw_series(std::iter::once(Text::new(s.clone(), inside(*x, *y), style)))
                .m()?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use plotters::coord::combinators::LogCoord;
    use plotters::coord::ranged1d::Ranged;

    /// The powers of ten plotters labels on a log axis drawn over `extent`.
    fn labelled_decades(extent: (f64, f64)) -> Vec<f64> {
        let (lo, hi) = axis_range(extent, Scale::Log, false);
        LogCoord::from((lo..hi).log_scale())
            .key_points(6)
            .into_iter()
            .filter(|v: &f64| (v.log10() - v.log10().round()).abs() < 1e-9)
            .collect()
    }

    #[test]
    fn a_log_axis_labels_a_power_of_ten_at_either_end() {
        // One decade inside (1), the axis reaching for 0.1 or 10: both ends must be labelled.
        // Before the range reached past its ends, 0.1 and 10 were lost to rounding and the
        // detection figures' size axes read "1" alone.
        assert_eq!(labelled_decades((0.1, 8.0)).len(), 2);
        assert_eq!(labelled_decades((0.2, 9.0)).len(), 2);
        assert_eq!(labelled_decades((0.1, 10.0)).len(), 3);
        assert_eq!(labelled_decades((1e-3, 1e3)).len(), 7);
    }
}
