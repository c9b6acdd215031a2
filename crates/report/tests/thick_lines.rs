//! A thick line that zigzags stays within its width of its data in the PNG.
//!
//! plotters' bitmap backend joins thick segments with unlimited miters; where a path turns
//! back on itself the miter's point used to draw spikes far past the data (through the x axis
//! of `estimates_*.png`). The panel now cuts such a path and joins the cuts round
//! (`figure/joins.rs`). The test draws the same zigzag thin (exact: Bresenham, no joins) and
//! thick, into memory, and compares the rows each covers.

use navkf_report::figure::{draw_panel, register_font, Panel, Scale, BIG};
use plotters::prelude::*;

const W: u32 = 700;
const H: u32 = 500;
const RED: RGBColor = RGBColor(230, 0, 0);

/// The rows holding the line's colour after drawing a zigzag of `width` pixels.
fn rows_covered(width: u32) -> (usize, usize) {
    register_font().unwrap();
    let mut buf = vec![255u8; (W * H * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (W, H)).into_drawing_area();
        let mut p = Panel::new(
            "zigzag".into(),
            "time (s)",
            "value".into(),
            Scale::Linear,
            BIG,
        );
        // Steep reversals every 4-5 pixels: the worst case of an estimate that chatters.
        let pts = (0..120)
            .map(|i| (i as f64, if i % 2 == 0 { 0.0 } else { 1.0 }))
            .collect();
        p.line(RED.stroke_width(width), false, pts);
        draw_panel(&root, &p).unwrap();
        root.present().unwrap();
    }
    let red = |px: &[u8]| px[0] > 200 && px[1] < 60 && px[2] < 60;
    let rows: Vec<usize> = (0..H as usize)
        .filter(|&r| (0..W as usize).any(|c| red(&buf[(r * W as usize + c) * 3..][..3])))
        .collect();
    assert!(!rows.is_empty(), "nothing drawn at width {width}");
    (rows[0], *rows.last().unwrap())
}

#[test]
fn a_thick_zigzag_stays_within_its_width_of_the_data() {
    let (top, bottom) = rows_covered(1);
    for width in [3u32, 6, 13] {
        let (t, b) = rows_covered(width);
        let reach = width as usize;
        assert!(
            t + reach >= top && b <= bottom + reach,
            "width {width}: rows {t}-{b}, the data span rows {top}-{bottom}"
        );
    }
}
