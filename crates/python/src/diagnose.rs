//! `navkf.diagnose`: the command line's `navkf diagnose` on a dataset in memory, the same
//! checks ([`navkf_diagnose::request`]) and the same answer: the diagnosis as the JSON of
//! `diagnosis.json`, and, when `out` is given, the results folder with its report and figures.

use crate::background::{run as in_background, Progress};
use crate::dataset::Dataset;
use crate::errors::{to_py, OrNavkfError};
use navkf_diagnose::request::DiagnoseRequest;
use navkf_diagnose::{diagnose as run, report};
use navkf_filters::FilterKind;
use navkf_report::{write_atomic, ResultsDir, SettingNames};
use pyo3::prelude::*;
use std::collections::BTreeMap;
use std::path::PathBuf;

/// See `navkf.diagnose` (python/navkf/__init__.py).
#[pyfunction]
#[pyo3(signature = (dataset, *, with_, priors, level_sigma, azimuth_sigma, fit_noise, filter,
    attitude, window, max_rounds, out, progress))]
#[allow(clippy::too_many_arguments)]
pub fn diagnose(
    py: Python<'_>,
    dataset: &Dataset,
    with_: Vec<String>,
    priors: BTreeMap<String, f64>,
    level_sigma: Option<f64>,
    azimuth_sigma: Option<f64>,
    fit_noise: bool,
    filter: &str,
    attitude: Option<String>,
    window: f64,
    max_rounds: usize,
    out: Option<PathBuf>,
    progress: Option<Bound<'_, PyAny>>,
) -> PyResult<String> {
    let filter: FilterKind = filter.parse().map_err(|e| to_py(&format!("filter: {e}")))?;
    let attitude = attitude
        .map(|a| a.parse::<navkf_dynamics::Attitude>())
        .transpose()
        .map_err(|e| to_py(&format!("attitude: {e}")))?;
    let request = DiagnoseRequest {
        with: with_,
        window_s: window,
        level_sigma,
        azimuth_sigma,
        priors,
        fit_noise,
        filter,
        attitude,
        declared: Vec::new(),
        max_rounds,
    };
    let ds = &dataset.inner;
    let (catalogue, opts) = request.check(ds, SettingNames::Keywords).or_py()?;
    let staged = out.as_deref().map(ResultsDir::begin).transpose().or_py()?;
    let tracker = Progress::default();
    let (d, fits) = in_background(py, progress.as_ref(), &tracker, || {
        run(ds, &*catalogue, &opts)
    })?
    .or_py()?;
    let json = serde_json::to_string(&d).or_py()?;
    if let Some(staged) = staged {
        py.detach(|| -> Result<(), Box<dyn std::error::Error + Send + Sync>> {
            let figures = navkf_diagnose::plots::draw(&d, &fits, staged.path());
            let command = navkf_report::provenance::command_line();
            write_atomic(&staged.path().join("diagnosis.json"), json.as_bytes())?;
            write_atomic(
                &staged.path().join("report.md"),
                report::markdown(&d, &command, &figures).as_bytes(),
            )?;
            staged.commit()?;
            Ok(())
        })
        .map_err(|e| to_py(&e))?;
    }
    Ok(json)
}
