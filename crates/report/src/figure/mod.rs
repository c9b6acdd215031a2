//! The figure kit every figure shares: the bundled font, panels (lines, bands, bars, labels
//! and notes on linear or log axes), legends, grids, and atomic PNG + SVG rendering.
//!
//! A figure is data first ([`Panel`]s), then one drawing routine that copes with empty and
//! degenerate data: non-finite points break a line, an empty panel says so in a note. A
//! figure that cannot be drawn, or whose code panics, is reported in its [`FigureOutcome`]
//! and never costs the results it illustrates.
//!
//! Text is drawn with DejaVu Sans, compiled in from `assets/fonts/` (see the LICENSE there)
//! and registered with plotters once, so figures render the same on a machine without fonts.

mod grid;
mod joins;
mod panel;
mod section;
mod style;

pub use grid::{draw_legend, text_width, Grid};
pub use panel::{draw_notes, draw_panel, entry, Band, Entry, Line, Mark, Panel, Scale};
pub use section::{embeds_without_question, ANSWERS};
pub use style::{color, filter_line, text_color, text_style, tick, Msg, Sizes, BIG, GREY, SMALL};

use crate::atomic_write::write_atomic;
use crate::error::ReportError;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::FontStyle;
use std::path::Path;
use std::sync::OnceLock;

/// The bundled font (DejaVu Sans; license in `assets/fonts/LICENSE`).
static FONT_BYTES: &[u8] = include_bytes!("../../../../assets/fonts/DejaVuSans.ttf");
/// The family every figure asks for; the bundled font is registered under it.
pub const FONT: &str = "sans-serif";

/// Registers the bundled font with plotters (once per process; later calls return the first
/// call's outcome).
pub fn register_font() -> Result<(), ReportError> {
    static REGISTERED: OnceLock<Result<(), String>> = OnceLock::new();
    REGISTERED
        .get_or_init(|| {
            plotters::style::register_font(FONT, FontStyle::Normal, FONT_BYTES)
                .map_err(|_| "the bundled font assets/fonts/DejaVuSans.ttf is not a font".into())
        })
        .clone()
        .map_err(ReportError::Figure)
}

/// A figure written (or not): its name, caption, the question it answers, and why it failed
/// if it did. [`FigureOutcome::markdown`] writes its section of a report.
#[derive(Debug, Clone)]
pub struct FigureOutcome {
    /// File stem: the figure is `<name>.png` and `<name>.svg`.
    pub name: String,
    /// What it shows, in words.
    pub caption: String,
    /// The one question it answers, ending in `?`.
    pub question: String,
    /// `Err(reason)` when it could not be drawn.
    pub result: Result<(), String>,
}

/// Draws one figure with `draw`, catching its failure, or its panic, into the outcome: a
/// figure that cannot be drawn never costs the results it illustrates.
pub fn outcome<E: std::fmt::Display>(
    name: impl Into<String>,
    caption: impl Into<String>,
    question: impl Into<String>,
    draw: impl FnOnce() -> Result<(), E>,
) -> FigureOutcome {
    let result = match std::panic::catch_unwind(std::panic::AssertUnwindSafe(draw)) {
        Ok(drawn) => drawn.map_err(|e| e.to_string()),
        Err(_) => Err("the figure code panicked".to_string()),
    };
    FigureOutcome {
        name: name.into(),
        caption: caption.into(),
        question: question.into(),
        result,
    }
}

/// A figure: its size in pixels and how to draw it on any backend.
pub trait Figure {
    /// Width and height in pixels.
    fn size(&self) -> (u32, u32);
    /// Draws the figure on `root`.
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String>;
}

/// Draws `fig` as `<name>.svg` and `<name>.png` in `dir`, each written atomically.
pub fn render<F: Figure>(dir: &Path, name: &str, fig: &F) -> Result<(), ReportError> {
    register_font()?;
    let size = fig.size();
    let err = |e: String| ReportError::Figure(format!("figure {name}: {e}"));
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        root.fill(&WHITE).m().map_err(err)?;
        fig.draw(&root).map_err(err)?;
        root.present().m().map_err(err)?;
    }
    write_atomic(&dir.join(format!("{name}.svg")), svg.as_bytes())?;
    std::fs::create_dir_all(dir).map_err(|source| ReportError::Io {
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
    std::fs::rename(&tmp, &path).map_err(|source| ReportError::Io { path, source })
}
