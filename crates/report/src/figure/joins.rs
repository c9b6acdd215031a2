//! Thick lines without miter spikes.
//!
//! plotters' bitmap backend joins the segments of a thick path with miters that have no
//! limit: where a path turns back on itself (an estimate that zigzags step by step, a path
//! that reverses) the miter's point reaches far beyond the line, and the PNG shows spikes
//! through the axes and stray dots above the plot; the SVG, joined by the viewer, is fine.
//! So a thick path is cut wherever it turns by more than a right angle (where a miter would
//! reach further than 0.71 of the width) and each cut is joined with a round dot of the
//! line's width. Points that fall on the pixel of the point before carry no direction and are
//! dropped first: their turn is noise.

/// The pieces of a polyline whose points land on pixels `px`: index lists into `px`, each of
/// at least two points, consecutive pieces sharing their cut point. Within a piece no point
/// repeats the pixel of the one before and no turn exceeds a right angle. A polyline that
/// never leaves its first pixel is one piece of that point alone.
pub(super) fn pieces(px: &[(i32, i32)]) -> Vec<Vec<usize>> {
    let mut kept: Vec<usize> = Vec::with_capacity(px.len());
    for (i, p) in px.iter().enumerate() {
        if kept.last().is_none_or(|&k| px[k] != *p) {
            kept.push(i);
        }
    }
    if kept.len() < 2 {
        return if kept.is_empty() {
            Vec::new()
        } else {
            vec![kept]
        };
    }
    let dir = |a: usize, b: usize| {
        (
            i64::from(px[b].0) - i64::from(px[a].0),
            i64::from(px[b].1) - i64::from(px[a].1),
        )
    };
    let mut out = Vec::new();
    let mut cur = vec![kept[0], kept[1]];
    for w in kept.windows(3) {
        let (a, b) = (dir(w[0], w[1]), dir(w[1], w[2]));
        if a.0 * b.0 + a.1 * b.1 < 0 {
            out.push(std::mem::replace(&mut cur, vec![w[1]]));
        }
        cur.push(w[2]);
    }
    out.push(cur);
    out
}

#[cfg(test)]
mod tests {
    use super::pieces;

    #[test]
    fn a_zigzag_is_cut_at_every_reversal_and_a_gentle_curve_is_not() {
        let zig = [(0, 0), (10, 50), (20, 0), (30, 50)];
        assert_eq!(pieces(&zig), vec![vec![0, 1], vec![1, 2], vec![2, 3]]);
        let gentle = [(0, 0), (10, 2), (20, 6), (30, 12)];
        assert_eq!(pieces(&gentle), vec![vec![0, 1, 2, 3]]);
        // A right angle itself is kept whole: its miter reaches 0.71 of the width.
        assert_eq!(pieces(&[(0, 0), (10, 0), (10, 10)]), vec![vec![0, 1, 2]]);
    }

    #[test]
    fn repeated_pixels_are_dropped_before_turns_are_judged() {
        let px = [(0, 0), (5, 0), (5, 0), (10, 0), (10, 0)];
        assert_eq!(pieces(&px), vec![vec![0, 1, 3]]);
        assert_eq!(pieces(&[(3, 3), (3, 3)]), vec![vec![0]]);
        assert!(pieces(&[]).is_empty());
    }
}
