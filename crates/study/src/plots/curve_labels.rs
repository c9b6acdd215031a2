//! Names written on curves (the plan's panels): each just above or just below its own curve,
//! where it crosses no line of the panel and no other name and stays inside the plot, as
//! near as it can to where the names would spread evenly along the time axis. Where curves
//! run together and leave no clear place beside a curve, its name stands a row or more of
//! text off it, clear of the bundle, in the curve's colour. Placed blindly (at
//! evenly spread times), a name sat across its own curve where it fell steeply, or across a
//! neighbour's.
//!
//! Places are found in the plot's own units (0..1 across, 0..1 up), from its size in pixels
//! estimated as the figure kit lays a panel out; a few pixels of margin absorb the estimate's
//! error (the estimate errs small, which only widens the margin).

use navkf_report::figure::{text_width, Sizes};

/// Pixels between a name and its curve.
const LIFT: f64 = 4.0;
/// Pixels kept clear around a name's box.
const MARGIN: f64 = 3.0;
/// Names tried along a curve, at most.
const TRIES: usize = 150;
/// The most rows of text a name may stand off its curve, to clear a bundle of curves that run
/// together (a dozen misalignments all near their priors): a name across a line is not read.
const MOST_ROWS_OFF: usize = 3;

/// The plot of a panel: its x range, its log y range and its size in pixels.
pub(super) struct Plot {
    pub x: (f64, f64),
    pub y_log: (f64, f64),
    pub px: (f64, f64),
}

impl Plot {
    /// The plot of a panel drawn in a cell of `cell` pixels with type `sizes`: as the figure
    /// kit draws it (margins of 8 pixels, 18 on the right; the caption; the axes' numbers
    /// and names), spanning `x` and, on a log axis, `y`.
    pub fn in_cell(cell: (u32, u32), sizes: Sizes, x: (f64, f64), y: (f64, f64)) -> Self {
        let left = (sizes.tick * 4 + sizes.desc + 12) as f64;
        let below = (sizes.tick * 2 + sizes.desc + 8) as f64;
        let caption = sizes.caption as f64 + 8.0;
        Plot {
            x,
            y_log: (y.0.log10(), y.1.log10()),
            px: (
                cell.0 as f64 - 27.0 - left,
                cell.1 as f64 - 16.0 - caption - below,
            ),
        }
    }

    /// `(x, y)` in the plot's units; `None` if it cannot be drawn.
    fn at(&self, x: f64, y: f64) -> Option<(f64, f64)> {
        let u = (x - self.x.0) / (self.x.1 - self.x.0);
        let v = (y.log10() - self.y_log.0) / (self.y_log.1 - self.y_log.0);
        (u.is_finite() && v.is_finite()).then_some((u, v))
    }

    /// The y of the plot's height `v`.
    fn y_of(&self, v: f64) -> f64 {
        10f64.powf(self.y_log.0 + v * (self.y_log.1 - self.y_log.0))
    }
}

/// A box `((u0, u1), (v0, v1))` in the plot's units.
type Box2 = ((f64, f64), (f64, f64));

/// A place for a name: how many lines its box crosses, how many rows of text it stands off
/// its curve, how far it is from where the names would spread evenly, its box, and its
/// bottom centre, in the plot's units.
struct Place {
    crossed: usize,
    row: usize,
    off: f64,
    b: Box2,
    at: (f64, f64),
}

/// Whether the segment `a`-`b` passes through the box `(u, v)` (Liang-Barsky clipping).
fn crosses(a: (f64, f64), b: (f64, f64), (u, v): Box2) -> bool {
    let (du, dv) = (b.0 - a.0, b.1 - a.1);
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [
        (-du, a.0 - u.0),
        (du, u.1 - a.0),
        (-dv, a.1 - v.0),
        (dv, v.1 - a.1),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return false;
            }
        } else if p < 0.0 {
            t0 = t0.max(q / p);
        } else {
            t1 = t1.min(q / p);
        }
    }
    t0 <= t1
}

/// The points of `line` (in increasing u) from the one before `u.0` to the one after `u.1`.
fn window(line: &[(f64, f64)], u: (f64, f64)) -> &[(f64, f64)] {
    let first = line.partition_point(|p| p.0 < u.0).saturating_sub(1);
    let last = line.partition_point(|p| p.0 <= u.1).min(line.len() - 1);
    &line[first..=last]
}

/// The lowest and highest v of `line` over `u`.
fn extent(line: &[(f64, f64)], u: (f64, f64)) -> (f64, f64) {
    window(line, u)
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(p.1), hi.max(p.1))
        })
}

/// How many of `lines` (polylines in the plot's units, their points in increasing u) pass
/// through `b`.
fn crossings(lines: &[Vec<(f64, f64)>], b: Box2) -> usize {
    lines
        .iter()
        .filter(|l| window(l, b.0).windows(2).any(|s| crosses(s[0], s[1], b)))
        .count()
}

/// Where to write the name of each of `curves` (its name and its points, in increasing x;
/// with `others`, lines that no name may cross) in `plot` at text size `size`: the point of
/// the name's bottom centre, as the figure kit anchors a panel's labels; `None` for a curve
/// with no point to name.
pub(super) fn place(
    plot: &Plot,
    curves: &[(&str, Vec<(f64, f64)>)],
    others: &[Vec<(f64, f64)>],
    size: u32,
) -> Vec<Option<(f64, f64)>> {
    let (w, h) = plot.px;
    let to_plot = |pts: &[(f64, f64)]| -> Vec<(f64, f64)> {
        pts.iter().filter_map(|&(x, y)| plot.at(x, y)).collect()
    };
    let lines: Vec<Vec<(f64, f64)>> = curves
        .iter()
        .map(|c| to_plot(&c.1))
        .chain(others.iter().map(|l| to_plot(l)))
        .filter(|l| !l.is_empty())
        .collect();
    let mut taken: Vec<Box2> = Vec::new();
    let n = curves.len();
    let mut out = Vec::with_capacity(n);
    for (k, (name, pts)) in curves.iter().enumerate() {
        let half = (text_width(name, size) as f64 / 2.0 + MARGIN) / w;
        let tall = (size as f64 + MARGIN) / h;
        let target = (k + 1) as f64 / (n + 1) as f64;
        let own = to_plot(pts);
        let step = own.len().div_ceil(TRIES).max(1);
        // The best place so far: the fewest lines crossed, then the nearest its curve, then
        // the nearest the target; above the curve on a tie (it is tried first).
        let mut best: Option<Place> = None;
        for &(u, _) in own.iter().step_by(step) {
            // The curve's lowest and highest under the name: the name clears its own curve
            // however steep it is there.
            let (v_lo, v_hi) = extent(&own, (u - half, u + half));
            for row in 0..=MOST_ROWS_OFF {
                let stand_off = row as f64 * (size as f64 + MARGIN) / h;
                for below in [false, true] {
                    // The name's bottom edge, in the plot's units.
                    let bottom = if below {
                        v_lo - (LIFT + size as f64) / h - stand_off
                    } else {
                        v_hi + LIFT / h + stand_off
                    };
                    let b = ((u - half, u + half), (bottom - MARGIN / h, bottom + tall));
                    if b.0 .0 < 0.0 || b.0 .1 > 1.0 || b.1 .0 < 0.0 || b.1 .1 > 1.0 {
                        continue;
                    }
                    let overlaps = taken.iter().any(|t| {
                        t.0 .0 < b.0 .1 && b.0 .0 < t.0 .1 && t.1 .0 < b.1 .1 && b.1 .0 < t.1 .1
                    });
                    if overlaps {
                        continue;
                    }
                    let here = Place {
                        crossed: crossings(&lines, b),
                        row,
                        off: (u - target).abs(),
                        b,
                        at: (u, bottom),
                    };
                    if best.as_ref().is_none_or(|p| {
                        (here.crossed, here.row, here.off) < (p.crossed, p.row, p.off)
                    }) {
                        best = Some(here);
                    }
                }
            }
        }
        out.push(best.map(|p| {
            taken.push(p.b);
            (plot.x.0 + p.at.0 * (plot.x.1 - plot.x.0), plot.y_of(p.at.1))
        }));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use navkf_report::figure::BIG;

    /// Eight curves within 7 % of each other, flat at their priors (the strapdown plan's
    /// misalignments): no name may sit across a line, as it did when names had to touch their
    /// own curve.
    #[test]
    fn names_clear_a_bundle_of_curves() {
        let x = (0.0, 100.0);
        let y = (0.1 / 1.15, 1.15);
        let plot = Plot::in_cell((560, 400), BIG, x, y);
        let names: Vec<String> = (0..8).map(|k| format!("m_g{k}z")).collect();
        let curves: Vec<(&str, Vec<(f64, f64)>)> = names
            .iter()
            .enumerate()
            .map(|(k, n)| {
                let level = 1.0 - 0.01 * k as f64;
                (n.as_str(), (0..=100).map(|t| (t as f64, level)).collect())
            })
            .collect();
        let places = place(&plot, &curves, &[], BIG.note);
        let lines: Vec<Vec<(f64, f64)>> = curves
            .iter()
            .map(|c| c.1.iter().filter_map(|&(t, r)| plot.at(t, r)).collect())
            .collect();
        let (w, h) = plot.px;
        let size = BIG.note as f64;
        for ((name, _), at) in curves.iter().zip(&places) {
            let (t, r) = at.expect("every curve has points");
            let (u, v) = plot.at(t, r).unwrap();
            let half = (text_width(name, BIG.note) as f64 / 2.0 + MARGIN) / w;
            let b = (
                (u - half, u + half),
                (v - MARGIN / h, v + (size + MARGIN) / h),
            );
            assert_eq!(
                crossings(&lines, b),
                0,
                "{name} at ({t}, {r}) crosses a line"
            );
        }
    }
}
