//! Figures of a diagnosis, each written as PNG and SVG next to `report.md`:
//!
//! - `measured_vs_predicted`: every measured channel against the filter's prediction of it.
//! - `innovations`: each channel's innovations inside their predicted +-2 sigma band;
//!   `innovations_before` the same for the base model when `--with` added effects.
//! - `path_misfit`: the vehicle's path (the filter's predicted positions) coloured by the
//!   local NIS per degree of freedom of the base model (before any effect was named), so that
//!   the places where the model under test fails show on the map; beside it the final model's
//!   when effects were named.
//! - `nis`: NIS per degree of freedom in sliding windows and per motion phase, against the
//!   95 % chi-square bounds, on linear axes; before and after when effects were named.
//! - `whiteness`: each channel's innovation autocorrelation with its white-noise band.
//! - `coefficient_errors` (when the dataset has `truth.csv`): each coefficient's error divided
//!   by the prior sigma it started from (before any widening), before and after.
//!
//! Positions are shown in metres north and east of the first fix and velocities in m/s, so
//! that a misfit reads in the units a navigation engineer thinks in; axes are named in words
//! with their units. Legends are as wide as their longest label, and notes stand in a strip
//! above the plot, not over its curves (`tests/diagnose_figures.rs` checks that no text runs
//! off the canvas or over other text). A figure that cannot be
//! drawn is reported in its [`FigureOutcome`]; the others are still drawn.

pub mod channels;
pub mod consistency;
pub mod errors;
pub mod path;
pub mod style;

pub use path::PATH_MISFIT_HALF_WINDOW_S;

use crate::diagnosis::{Diagnosis, Fits};
use channels::{innovations, measured_vs_predicted};
use consistency::{nis, whiteness};
use errors::coefficient_errors;
use navkf_report::figure::FigureOutcome;
use navkf_report::figure::{render, Grid};
use path::path_misfit;
use std::path::Path;
use style::{base_label, model_label, Geo};

/// Draws every figure of a diagnosis into `dir`.
pub fn draw(d: &Diagnosis, fits: &Fits, dir: &Path) -> Vec<FigureOutcome> {
    let geo = Geo::of(&fits.model);
    let mut out = Vec::new();
    let mut run = |name: &str, caption: String, question: &str, fig: &dyn Fn() -> Grid| {
        out.push(navkf_report::figure::outcome(
            name,
            caption,
            question,
            || render(dir, name, &fig()),
        ));
    };
    let model_label = model_label(&fits.model.effects);
    let base_name = base_label(d);
    run(
        "measured_vs_predicted",
        "Measured channels against the model's prediction".into(),
        "Does the model predict what was measured, channel by channel?",
        &|| measured_vs_predicted(&fits.model, &geo, &model_label),
    );
    run(
        "innovations",
        format!("Innovations with their +-2 sigma bands ({model_label})"),
        "Do the innovations stay inside the bands the filter predicts, and where do they leave?",
        &|| innovations(&fits.model, &geo, &model_label),
    );
    if let Some(b) = &fits.before {
        run(
            "innovations_before",
            "Innovations with their +-2 sigma bands (base model, before)".into(),
            "Where did the base model's innovations leave their bands, before any effect?",
            &|| innovations(b, &geo, &base_name),
        );
    }
    // Where the model under test fails: the base model's misfit, and the final model's
    // beside it when effects were named.
    let (base, fin) = match &fits.before {
        Some(b) => (b, Some((&fits.model, model_label.as_str()))),
        None => (&fits.model, None),
    };
    run(
        "path_misfit",
        match fin {
            Some(_) => format!(
                "The path coloured by how badly the {base_name} fits there; \
                 beside it the final model ({model_label})"
            ),
            None => format!("The path coloured by how badly the {base_name} fits there"),
        },
        "Where along the path does the model under test fail?",
        &|| path_misfit((base, &base_name), fin, &geo),
    );
    run(
        "nis",
        "NIS in sliding windows and per motion phase, with 95 % bounds".into(),
        "Is the model consistent throughout the test and in every motion phase?",
        &|| nis(d, fits),
    );
    run(
        "whiteness",
        "Autocorrelation of each channel's innovations".into(),
        "Are the innovations white, or is structure left in them that a model could explain?",
        &|| whiteness(d),
    );
    let has_truth = d.model.coefficients.iter().any(|c| c.truth.is_some());
    if has_truth {
        run(
            "coefficient_errors",
            "Coefficient errors against the truth, divided by the prior sigma each started \
             from (before any widening)"
                .into(),
            "How far is each coefficient from the truth, before and after, in its starting sigmas?",
            &|| coefficient_errors(d, fits),
        );
    }
    out
}
