//! Figures of a diagnosis, each written as PNG and SVG next to `report.md`:
//!
//! - `measured_vs_predicted`: every measured channel against the filter's prediction of it.
//! - `innovations`: each channel's innovations inside their predicted +-2 sigma band;
//!   `innovations_before` the same for the base model when `--with` added effects.
//! - `path_misfit`: the vehicle's path (from the GPS fixes) coloured by the local NIS per
//!   degree of freedom, so that the places where the model fails show on the map.
//! - `nis`: NIS per degree of freedom in sliding windows and per motion phase, against the
//!   95 % chi-square bounds; before and after when `--with` is given.
//! - `whiteness`: each channel's innovation autocorrelation with its white-noise band.
//! - `coefficient_errors` (when the dataset has `truth.csv`): each coefficient's error divided
//!   by its initial sigma, before and after.
//!
//! Positions are shown in metres north and east of the first fix and velocities in m/s, so
//! that a misfit reads in the units a navigation engineer thinks in. A figure that cannot be
//! drawn is reported in its [`FigureOutcome`]; the others are still drawn.

pub mod channels;
pub mod consistency;
pub mod path;
pub mod style;

pub use path::PATH_MISFIT_HALF_WINDOW_S;

use crate::diagnosis::{Diagnosis, Fits};
use channels::{innovations, measured_vs_predicted};
use consistency::{coefficient_errors, nis, whiteness};
use navkf_report::figure::FigureOutcome;
use navkf_report::figure::{render, Grid};
use path::path_misfit;
use std::path::Path;
use style::{model_label, Geo};

/// Draws every figure of a diagnosis into `dir`.
pub fn draw(d: &Diagnosis, fits: &Fits, dir: &Path) -> Vec<FigureOutcome> {
    let geo = Geo::of(&fits.model);
    let mut out = Vec::new();
    let mut run = |name: &str, caption: String, fig: &dyn Fn() -> Grid| {
        out.push(navkf_report::figure::outcome(name, caption, || {
            render(dir, name, &fig())
        }));
    };
    let model_label = model_label(&fits.model.effects);
    run(
        "measured_vs_predicted",
        "Measured channels against the model's prediction".into(),
        &|| measured_vs_predicted(&fits.model, &geo, &model_label),
    );
    run(
        "innovations",
        format!("Innovations with their +-2 sigma bands ({model_label})"),
        &|| innovations(&fits.model, &geo, &model_label),
    );
    if let Some(b) = &fits.before {
        run(
            "innovations_before",
            "Innovations with their +-2 sigma bands (base model, before)".into(),
            &|| innovations(b, &geo, "base model"),
        );
    }
    run(
        "path_misfit",
        "The path coloured by how badly the model fits there".into(),
        &|| path_misfit(&fits.model, &geo, &model_label),
    );
    run(
        "nis",
        "NIS in sliding windows and per motion phase, with 95 % bounds".into(),
        &|| nis(d, fits),
    );
    run(
        "whiteness",
        "Autocorrelation of each channel's innovations".into(),
        &|| whiteness(d),
    );
    let has_truth = d.model.coefficients.iter().any(|c| c.truth.is_some());
    if has_truth {
        run(
            "coefficient_errors",
            "Coefficient errors against the truth, divided by the initial sigma".into(),
            &|| coefficient_errors(d),
        );
    }
    out
}
