//! Reading a figure's SVG twin for what a reviewer would reject: a blank figure, text that
//! runs off the canvas (a legend cut at its edge), text drawn over other text (a caption over
//! a bar's label) and text drawn over the data (a note across a curve or a bar). Each text's
//! box is measured with the bundled font, as plotters lays it out: the SVG gives its anchor
//! point, its alignment and its size. The data are the coloured lines and boxes: the grid,
//! the axes and the bands are grey or black.

use navkf_report::figure::{register_font, text_width};

/// One text of the SVG with its box on the canvas, pixels.
#[derive(Debug, Clone)]
pub struct TextBox {
    pub text: String,
    pub x: (f64, f64),
    pub y: (f64, f64),
}

/// The value of attribute `name` in the tag `tag`.
fn attr<'a>(tag: &'a str, name: &str) -> Option<&'a str> {
    let key = format!(" {name}=\"");
    let i = tag.find(&key)? + key.len();
    let rest = &tag[i..];
    Some(&rest[..rest.find('"')?])
}

fn unescape(s: &str) -> String {
    s.replace("&lt;", "<")
        .replace("&gt;", ">")
        .replace("&quot;", "\"")
        .replace("&apos;", "'")
        .replace("&amp;", "&")
}

fn num(tag: &str, name: &str) -> f64 {
    attr(tag, name)
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("no number {name} in {tag}"))
}

/// The canvas size of an SVG.
pub fn canvas(svg: &str) -> (f64, f64) {
    let tag = &svg[svg.find("<svg").expect("an <svg> tag")..];
    let tag = &tag[..tag.find('>').unwrap()];
    (num(tag, "width"), num(tag, "height"))
}

/// Every non-empty text of `svg` with its box.
pub fn texts(svg: &str) -> Vec<TextBox> {
    register_font().unwrap();
    let mut out = Vec::new();
    let mut rest = svg;
    while let Some(i) = rest.find("<text") {
        rest = &rest[i..];
        let end = rest.find('>').unwrap();
        let tag = &rest[..end];
        let close = rest.find("</text>").unwrap();
        let text = unescape(rest[end + 1..close].trim());
        rest = &rest[close..];
        if text.is_empty() {
            continue;
        }
        // plotters writes the font size divided by 1.24.
        let size = (num(tag, "font-size") * 1.24).round() as u32;
        let (w, h) = (text_width(&text, size) as f64, size as f64);
        let (x0, y0) = (num(tag, "x"), num(tag, "y"));
        let (a0, a1) = match attr(tag, "text-anchor") {
            Some("middle") => (-w / 2.0, w / 2.0),
            Some("end") => (-w, 0.0),
            _ => (0.0, w),
        };
        let (b0, b1) = match attr(tag, "dy") {
            Some("0.76em") => (0.0, h),
            Some("-0.5ex") => (-h, 0.0),
            _ => (-h / 2.0, h / 2.0),
        };
        // Turned text (an axis name): rotate(270) takes (a, b) to (b, -a) about the anchor,
        // rotate(90) to (-b, a).
        let (x, y) = match attr(tag, "transform") {
            Some(t) if t.starts_with("rotate(270") => ((x0 + b0, x0 + b1), (y0 - a1, y0 - a0)),
            Some(t) if t.starts_with("rotate(90") => ((x0 - b1, x0 - b0), (y0 + a0, y0 + a1)),
            _ => ((x0 + a0, x0 + a1), (y0 + b0, y0 + b1)),
        };
        out.push(TextBox { text, x, y });
    }
    out
}

/// The ways the texts of `svg` do not fit: off the canvas, or over one another (by more than
/// `slack` pixels each way, which the font's side bearings and ascents leave).
pub fn misfits(svg: &str, slack: f64) -> Vec<String> {
    let (w, h) = canvas(svg);
    let boxes = texts(svg);
    let mut bad = Vec::new();
    for b in &boxes {
        if b.x.0 < -slack || b.x.1 > w + slack || b.y.0 < -slack || b.y.1 > h + slack {
            bad.push(format!(
                "off the {w} x {h} canvas: {:?} at x {:.0}..{:.0}, y {:.0}..{:.0}",
                b.text, b.x.0, b.x.1, b.y.0, b.y.1
            ));
        }
    }
    for (i, a) in boxes.iter().enumerate() {
        for b in &boxes[i + 1..] {
            let dx = a.x.1.min(b.x.1) - a.x.0.max(b.x.0);
            let dy = a.y.1.min(b.y.1) - a.y.0.max(b.y.0);
            if dx > slack && dy > slack {
                bad.push(format!(
                    "{:?} over {:?} ({dx:.0} x {dy:.0} px)",
                    a.text, b.text
                ));
            }
        }
    }
    bad
}

/// Whether `colour` (`#RRGGBB`) is a colour, not a grey (or black, or white).
fn coloured(colour: &str) -> bool {
    let hex = colour.trim_start_matches('#');
    let c: Vec<u8> = (0..3)
        .filter_map(|k| u8::from_str_radix(hex.get(2 * k..2 * k + 2)?, 16).ok())
        .collect();
    c.len() == 3 && !(c[0] == c[1] && c[1] == c[2])
}

/// Every tag `<name ...>` of `svg`.
fn tags<'a>(svg: &'a str, name: &str) -> Vec<&'a str> {
    let open = format!("<{name} ");
    svg.match_indices(&open)
        .map(|(i, _)| {
            let tag = &svg[i..];
            &tag[..tag.find('>').unwrap_or(tag.len())]
        })
        .collect()
}

/// A straight piece of a line, from one point to the next, pixels.
type Segment = [(f64, f64); 2];
/// A box, as its x and y extents `((x0, x1), (y0, y1))`, pixels.
type Extent = ((f64, f64), (f64, f64));

/// The data of `svg`: the segments of its coloured lines, and its coloured boxes.
fn data(svg: &str) -> (Vec<Segment>, Vec<Extent>) {
    let mut segments = Vec::new();
    for tag in tags(svg, "polyline") {
        if !attr(tag, "stroke").is_some_and(coloured) {
            continue;
        }
        let pts: Vec<(f64, f64)> = attr(tag, "points")
            .unwrap_or("")
            .split_whitespace()
            .filter_map(|p| {
                let (x, y) = p.split_once(',')?;
                Some((x.parse().ok()?, y.parse().ok()?))
            })
            .collect();
        segments.extend(pts.windows(2).map(|w| [w[0], w[1]]));
    }
    let boxes = tags(svg, "rect")
        .into_iter()
        .filter(|tag| attr(tag, "fill").is_some_and(coloured))
        .map(|tag| {
            let (x, y) = (num(tag, "x"), num(tag, "y"));
            ((x, x + num(tag, "width")), (y, y + num(tag, "height")))
        })
        .collect();
    (segments, boxes)
}

/// Whether the segment `a`-`b` passes through the box `(x, y)` (Liang-Barsky clipping).
fn crosses(a: (f64, f64), b: (f64, f64), x: (f64, f64), y: (f64, f64)) -> bool {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [
        (-dx, a.0 - x.0),
        (dx, x.1 - a.0),
        (-dy, a.1 - y.0),
        (dy, y.1 - a.1),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return false;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    t0 <= t1
}

/// The texts of `svg` drawn over its data (coloured lines and boxes), by more than `slack`
/// pixels each way.
pub fn over_data(svg: &str, slack: f64) -> Vec<String> {
    let (segments, boxes) = data(svg);
    let mut bad = Vec::new();
    for t in texts(svg) {
        let (x, y) = (
            (t.x.0 + slack, t.x.1 - slack),
            (t.y.0 + slack, t.y.1 - slack),
        );
        if x.0 >= x.1 || y.0 >= y.1 {
            continue;
        }
        let line = segments.iter().any(|s| crosses(s[0], s[1], x, y));
        let bar = boxes
            .iter()
            .any(|b| b.0 .0 < x.1 && x.0 < b.0 .1 && b.1 .0 < y.1 && y.0 < b.1 .1);
        if line || bar {
            bad.push(format!(
                "{:?} over a {} at x {:.0}..{:.0}, y {:.0}..{:.0}",
                t.text,
                if line { "curve" } else { "bar" },
                t.x.0,
                t.x.1,
                t.y.0,
                t.y.1
            ));
        }
    }
    bad
}

/// Whether `svg` draws a coloured mark (a stroke or a fill whose red, green and blue
/// differ): the grid, the axes, the bounds and the text are grey or black, the data are not.
pub fn has_coloured_mark(svg: &str) -> bool {
    ["stroke=\"", "fill=\""].iter().any(|key| {
        svg.match_indices(key)
            .any(|(i, _)| coloured(svg[i + key.len()..].split('"').next().unwrap_or("")))
    })
}
