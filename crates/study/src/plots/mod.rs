//! Figures of a study, each written as PNG and SVG into the results folder:
//!
//! - `estimates_<coefficient>`: the example run's estimate of one coefficient by every filter,
//!   with its +-1 sigma band, against the true value (the paper's Figures 2 and 3);
//!   `estimates_all` puts every coefficient in one grid.
//! - `rms_over_time`: RMS error over runs of every coefficient against time, divided by the
//!   coefficient's initial sigma so all share one log axis, with the truth-linearised bound.
//! - `step_cost`: median and 90th percentile of one predict + update, and the distribution.
//! - `nees_nis_over_time`: average NEES and NIS against time with their 95 % chi-square bands.
//!
//! They are drawn with the figure kit of `navkf-report` (bundled font, panels, grids).
//! Degenerate data (a filter with every run diverged, NaN, a zero range, a single stored time)
//! gives an empty or partial panel with a note, never a panic.

mod consistency;
mod curve_labels;
mod estimates;
mod layout;
pub mod plan;
mod rms;
mod step_cost;
pub mod sweep;
mod units;

use layout::Fig;
pub use units::display_unit;

use crate::monte_carlo::{ExampleRun, Study};
use crate::summary::Summary;
use crate::tally::Tally;
use navkf_dynamics::state::NAV_DIM;
use navkf_report::figure::*;
pub use navkf_report::figure::{register_font, FigureOutcome};
use navkf_report::ReportError;
use std::path::Path;

/// Title of `rms_over_time`.
pub const RMS_TITLE: &str = "RMS error over time, divided by the initial sigma";
/// Title of `step_cost`.
pub const STEP_COST_TITLE: &str = "Cost of one filter step (predict + update)";
/// Title of `nees_nis_over_time`.
pub const NEES_NIS_TITLE: &str = "Average NEES and NIS over time, with 95 % bands";
/// Title of `estimates_all` (followed by the run index).
pub const ESTIMATES_ALL_TITLE: &str = "Coefficient estimates against the truth";

/// What `estimates_all` and each `estimates_<coefficient>` answer.
pub const ESTIMATES_QUESTION: &str =
    "Does each filter's estimate reach the truth, and does its +-1 sigma band cover it?";
/// What `rms_over_time` answers.
pub const RMS_QUESTION: &str =
    "How fast does each filter's error fall, and does it reach the truth-linearised bound?";
/// What `nees_nis_over_time` answers.
pub const NEES_NIS_QUESTION: &str =
    "Do the filters know their own error: do NEES and NIS stay inside the 95 % band?";
/// What `step_cost` answers.
pub const STEP_COST_QUESTION: &str = "What does one predict + update cost with each filter?";

/// Draws every figure into `dir`. A figure that fails (or panics) is reported in its outcome;
/// the others are still drawn.
pub fn write_all(
    study: &Study,
    tally: &Tally,
    summary: &Summary,
    example: Option<&ExampleRun>,
    dir: &Path,
) -> Vec<FigureOutcome> {
    let mut out = Vec::new();
    let mut run =
        |name: String, caption: String, question: &str, f: &dyn Fn() -> Result<(), ReportError>| {
            out.push(outcome(name, caption, question, f));
        };
    if let Some(ex) = example {
        run(
            "estimates_all".into(),
            format!(
                "Estimates of every coefficient against the truth, run {}",
                ex.run
            ),
            ESTIMATES_QUESTION,
            &|| estimates_all(study, ex, dir),
        );
        for i in NAV_DIM..ex.names.len() {
            run(
                format!("estimates_{}", ex.names[i]),
                format!("{} in run {}", ex.names[i], ex.run),
                ESTIMATES_QUESTION,
                &|| estimates(study, ex, i, dir),
            );
        }
    }
    run(
        "rms_over_time".into(),
        "RMS error over time / initial sigma, with the bound".into(),
        RMS_QUESTION,
        &|| rms_over_time(study, tally, dir),
    );
    run(
        "nees_nis_over_time".into(),
        "Average NEES and NIS over time with 95 % bands".into(),
        NEES_NIS_QUESTION,
        &|| nees_nis_over_time(study, tally, dir),
    );
    run(
        "step_cost".into(),
        "Cost of one filter step".into(),
        STEP_COST_QUESTION,
        &|| step_cost(study, tally, summary, dir),
    );
    out
}

/// `estimates_<name>`: the example run's estimates of coefficient `i` (a filter state index)
/// by every filter, with +-1 sigma bands, against the true value.
pub fn estimates(study: &Study, ex: &ExampleRun, i: usize, dir: &Path) -> Result<(), ReportError> {
    let name = ex
        .names
        .get(i)
        .ok_or_else(|| ReportError::Figure(format!("estimates: no state {i}")))?;
    render(
        dir,
        &format!("estimates_{name}"),
        &Fig::Estimates { study, ex, i },
    )
}

/// `estimates_all`: one small panel per coefficient.
pub fn estimates_all(study: &Study, ex: &ExampleRun, dir: &Path) -> Result<(), ReportError> {
    render(dir, "estimates_all", &Fig::EstimatesAll { study, ex })
}

/// `rms_over_time`: one log panel per coefficient.
pub fn rms_over_time(study: &Study, tally: &Tally, dir: &Path) -> Result<(), ReportError> {
    render(dir, "rms_over_time", &Fig::Rms { study, tally })
}

/// `step_cost`: median and p90 per filter (from the summary), and the distributions.
pub fn step_cost(
    study: &Study,
    tally: &Tally,
    summary: &Summary,
    dir: &Path,
) -> Result<(), ReportError> {
    render(
        dir,
        "step_cost",
        &Fig::StepCost {
            study,
            tally,
            summary,
        },
    )
}

/// `nees_nis_over_time`: average NEES and NIS per filter with their 95 % bands.
pub fn nees_nis_over_time(study: &Study, tally: &Tally, dir: &Path) -> Result<(), ReportError> {
    render(dir, "nees_nis_over_time", &Fig::NeesNis { study, tally })
}

// ---------------------------------------------------------------------------------------------
// Units

// ---------------------------------------------------------------------------------------------
// The figures' data

// ---------------------------------------------------------------------------------------------
// Figures and rendering
