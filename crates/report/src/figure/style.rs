//! The look every figure shares: tick labels, the palette, filter line widths, text sizes.

use super::FONT;
use plotters::prelude::*;

/// Tick label: up to 4 significant digits, exponent form outside 1e-3..1e5; a value below a
/// millionth of the axis' `span` is the rounding error of a zero tick.
pub fn tick(v: f64, span: f64) -> String {
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

/// Ten colours a reader tells apart (Tableau's, without its grey, which marks bands and
/// reference lines here, and with navy in its place): a study compares at most ten filters
/// before a colour repeats. Six were too few: the seventh filter of the misalignment sweep
/// was drawn in the first one's red, thinner, on top of it, and could not be seen.
const PALETTE: [RGBColor; 10] = [
    RGBColor(214, 39, 40),
    RGBColor(31, 119, 180),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(23, 190, 207),
    RGBColor(188, 189, 34),
    RGBColor(0, 0, 128),
];

pub fn color(i: usize) -> RGBColor {
    PALETTE[i % PALETTE.len()]
}

/// `c` darkened to read as text on white while still naming the curve drawn in `c`: curves
/// that lie on one another are told apart by their names' colours.
pub fn text_color(c: RGBColor) -> RGBColor {
    let dark = |v: u8| (f64::from(v) * 0.7).round() as u8;
    RGBColor(dark(c.0), dark(c.1), dark(c.2))
}

/// The line of filter `k` of `n`: earlier filters wider, so that filters whose curves
/// coincide show as nested stripes instead of hiding one another. Widths step by 2 pixels
/// (a pixel each side) up to [`WIDEST_LINE`], so seven filters all show; a cap of 7 gave
/// the first four of seven one width, and the last drawn hid the other three.
pub fn filter_line(k: usize, n: usize) -> ShapeStyle {
    let w = if n <= 1 {
        2
    } else {
        (2 * (n - 1 - k.min(n - 1)) + 1).min(WIDEST_LINE)
    };
    color(k).stroke_width(w as u32)
}

/// The widest filter line, pixels (seven filters: 13, 11, ..., 1).
pub const WIDEST_LINE: usize = 13;

pub const GREY: RGBColor = RGBColor(110, 110, 110);

#[derive(Clone, Copy)]
pub struct Sizes {
    pub caption: u32,
    pub desc: u32,
    pub tick: u32,
    pub note: u32,
}

pub const BIG: Sizes = Sizes {
    caption: 22,
    desc: 17,
    tick: 14,
    note: 15,
};
pub const SMALL: Sizes = Sizes {
    caption: 16,
    desc: 13,
    tick: 11,
    note: 12,
};

/// Error text of a plotters failure.
pub trait Msg<T> {
    fn m(self) -> Result<T, String>;
}

impl<T, E: std::fmt::Display> Msg<T> for Result<T, E> {
    fn m(self) -> Result<T, String> {
        self.map_err(|e| e.to_string())
    }
}

pub fn text_style(size: u32, color: RGBColor) -> TextStyle<'static> {
    (FONT, size).into_font().color(&color)
}
