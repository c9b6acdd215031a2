//! Markdown tables, one writer and one number formatter for every report: a cell that has no
//! value (no run finished, a NaN) is a dash, never `NaN`, and a table's rows always have its
//! header's columns.
//!
//! ```
//! use navkf_report::markdown::{number, Number, Table};
//! let mut t = Table::new(["filter", "NIS", "share"]);
//! t.row(["ekf".to_string(), number(4.0123, Number::Fixed(3)), number(0.25, Number::Percent(1))]);
//! t.row(["ukf".to_string(), number(f64::NAN, Number::Fixed(3)), number(1e-3, Number::Sci(2))]);
//! assert_eq!(
//!     t.render(),
//!     "| filter | NIS | share |\n|---|---|---|\n| ekf | 4.012 | 25.0 % |\n| ukf | - | 1.00e-3 |\n"
//! );
//! ```

/// How a number is written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Number {
    /// Scientific with this many decimals: `1.234e-3`.
    Sci(usize),
    /// Fixed with this many decimals: `20.46`.
    Fixed(usize),
    /// Fixed with a sign, with this many decimals: `+0.125`, `-2.000`.
    SignedFixed(usize),
    /// A share as per cent with this many decimals: `0.25` -> `25.0 %`.
    Percent(usize),
    /// A signed share as per cent: `-0.012` -> `-1.2 %`.
    SignedPercent(usize),
    /// Nanoseconds as microseconds with one decimal: `8812.0` -> `8.8 us`.
    Micros,
}

/// `v` written as `format` says; a dash where `v` is not finite.
pub fn number(v: f64, format: Number) -> String {
    if !v.is_finite() {
        return "-".into();
    }
    match format {
        Number::Sci(d) => format!("{v:.d$e}"),
        Number::Fixed(d) => format!("{v:.d$}"),
        Number::SignedFixed(d) => format!("{v:+.d$}"),
        Number::Percent(d) => format!("{:.d$} %", 100.0 * v),
        Number::SignedPercent(d) => format!("{:+.d$} %", 100.0 * v),
        Number::Micros => format!("{:.1} us", v / 1e3),
    }
}

/// Text made safe for a cell: a `|` would end the cell, a line break the row.
pub fn cell(text: &str) -> String {
    text.replace('|', "\\|").replace('\n', " ")
}

/// A Markdown table: a header and rows of cells, rendered `| a | b |`.
#[derive(Debug, Clone, Default)]
pub struct Table {
    header: Vec<String>,
    rows: Vec<Vec<String>>,
}

impl Table {
    /// A table with these column headers.
    pub fn new<S: Into<String>>(header: impl IntoIterator<Item = S>) -> Self {
        Table {
            header: header.into_iter().map(Into::into).collect(),
            rows: Vec::new(),
        }
    }

    /// Appends a row; missing cells are left empty, extra ones are an error of the caller's
    /// and are dropped in release builds (checked in debug builds).
    pub fn row<S: Into<String>>(&mut self, cells: impl IntoIterator<Item = S>) {
        let mut cells: Vec<String> = cells.into_iter().map(Into::into).collect();
        debug_assert!(
            cells.len() <= self.header.len(),
            "a row of {} cells in a table of {} columns",
            cells.len(),
            self.header.len()
        );
        cells.resize(self.header.len(), String::new());
        self.rows.push(cells);
    }

    /// Whether it has no rows.
    pub fn is_empty(&self) -> bool {
        self.rows.is_empty()
    }

    /// The table as Markdown, each line ending in a newline.
    pub fn render(&self) -> String {
        let line = |cells: &[String]| format!("| {} |\n", cells.join(" | "));
        let mut out = line(&self.header);
        out.push('|');
        out.push_str(&"---|".repeat(self.header.len()));
        out.push('\n');
        for r in &self.rows {
            out.push_str(&line(r));
        }
        out
    }
}
