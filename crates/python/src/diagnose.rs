//! `navkf.diagnose`: the command line's `navkf diagnose` on a dataset in memory, the same
//! checks ([`navkf_diagnose::request`]) and the same answer: the diagnosis as the JSON of
//! `diagnosis.json`, the innovation series of the final model's fit (and of the base
//! model's, when effects were added), and, when `out` is given, the results folder with its
//! report and figures.

use crate::background::{run as in_background, Progress};
use crate::dataset::Dataset;
use crate::errors::{to_py, OrNavkfError};
use navkf_diagnose::request::DiagnoseRequest;
use navkf_diagnose::{diagnose as run, report, Fit};
use navkf_dynamics::declared::DeclaredFile;
use navkf_filters::FilterKind;
use navkf_report::{write_atomic, ResultsDir, SettingNames};
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::collections::BTreeMap;
use std::path::PathBuf;

/// See `navkf.diagnose` (python/navkf/__init__.py).
#[pyfunction]
#[pyo3(signature = (dataset, *, with_, priors, level_sigma, azimuth_sigma, fit_noise, filter,
    attitude, window, max_rounds, effects_file, out, progress))]
#[allow(clippy::too_many_arguments)]
pub fn diagnose<'py>(
    py: Python<'py>,
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
    effects_file: Option<PathBuf>,
    out: Option<PathBuf>,
    progress: Option<Bound<'py, PyAny>>,
) -> PyResult<(String, Bound<'py, PyDict>)> {
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
        declared: effects_file
            .as_deref()
            .map(DeclaredFile::read)
            .transpose()
            .or_py()?,
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
    let series = PyDict::new(py);
    series.set_item("model", innovation_series(py, &fits.model)?)?;
    if let Some(before) = &fits.before {
        series.set_item("before", innovation_series(py, before)?)?;
    }
    Ok((json, series))
}

/// A fit's update-by-update series as arrays: `t`, `nis`, `dims`, and per channel (by name)
/// the innovation `z - z_hat` and its predicted one-sigma, NaN where the channel was absent.
fn innovation_series<'py>(py: Python<'py>, fit: &Fit) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("t", PyArray1::from_slice(py, &fit.t))?;
    d.set_item("nis", PyArray1::from_slice(py, &fit.nis))?;
    d.set_item(
        "dims",
        PyArray1::from_vec(py, fit.dims.iter().map(|&k| k as u64).collect()),
    )?;
    let innovation = PyDict::new(py);
    let sigma = PyDict::new(py);
    for (j, c) in fit.channels.iter().enumerate() {
        let nu: Vec<f64> = fit
            .z
            .iter()
            .zip(&fit.z_hat)
            .map(|(z, h)| z[j] - h[j])
            .collect();
        let s: Vec<f64> = fit.s_sigma.iter().map(|s| s[j]).collect();
        innovation.set_item(c.name, PyArray1::from_vec(py, nu))?;
        sigma.set_item(c.name, PyArray1::from_vec(py, s))?;
    }
    d.set_item("innovation", innovation)?;
    d.set_item("innovation_sigma", sigma)?;
    d.set_item("effects", fit.effects.clone())?;
    Ok(d)
}
