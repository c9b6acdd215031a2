//! Panels in a grid under a title, with a legend strip on the right.

use super::panel::{draw_panel, Entry, Mark, Panel};
use super::style::{text_style, Msg};
use super::{Figure, FONT};
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// Draws a legend in `area`, one row per entry, from its top-left corner.
pub fn draw_legend<DB: DrawingBackend>(
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

/// A figure of panels in a grid under a title, with a legend strip on the right.
pub struct Grid {
    pub title: String,
    pub panels: Vec<Panel>,
    pub cols: usize,
    pub cell: (u32, u32),
    pub legend: Vec<Entry>,
}

const TITLE_H: u32 = 50;
/// The legend strip's width at least; wider when a label needs it.
const LEGEND_W: u32 = 290;
/// Size of the legend's text.
const LEGEND_TEXT: u32 = 15;

/// Width of `text` at `size` in the bundled font, pixels (an estimate of 0.6 em a character
/// if the font cannot measure it).
pub fn text_width(text: &str, size: u32) -> u32 {
    (FONT, size)
        .into_font()
        .box_size(text)
        .map(|(w, _)| w)
        .unwrap_or((0.6 * size as f64 * text.chars().count() as f64) as u32)
}

impl Grid {
    /// The legend strip's width: [`LEGEND_W`], or what the widest label needs (its mark is
    /// 52 pixels, and 16 are left at the right edge).
    fn legend_width(&self) -> u32 {
        if self.legend.is_empty() {
            return 0;
        }
        let widest = self
            .legend
            .iter()
            .map(|e| text_width(&e.label, LEGEND_TEXT));
        LEGEND_W.max(52 + 16 + widest.max().unwrap_or(0))
    }
}

impl Figure for Grid {
    fn size(&self) -> (u32, u32) {
        let rows = self.panels.len().div_ceil(self.cols).max(1) as u32;
        let legend = self.legend_width();
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
            draw_legend(&side, &self.legend, LEGEND_TEXT, 40)?;
        }
        Ok(())
    }
}
