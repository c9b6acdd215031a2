//! A dataset's files as columns: each CSV column a numpy array under its header's name
//! (`docs/data-format.md`), an empty cell a NaN.

use navkf_dynamics::dataset::{files_of, Dataset, Odometer, MEASUREMENTS_FILE};
use navkf_dynamics::ModelKind;
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// `columns[k]` under `names[k]`, as a dict of 1-D float arrays.
fn dict<'py>(
    py: Python<'py>,
    names: &[&str],
    columns: Vec<Vec<f64>>,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for (name, col) in names.iter().zip(columns) {
        d.set_item(*name, PyArray1::from_vec(py, col))?;
    }
    Ok(d)
}

/// The columns of `rows`, as many as `names`.
fn transpose(names: &[&str], rows: impl Iterator<Item = Vec<f64>>) -> Vec<Vec<f64>> {
    let mut cols: Vec<Vec<f64>> = vec![Vec::new(); names.len()];
    for r in rows {
        for (c, v) in cols.iter_mut().zip(r) {
            c.push(v);
        }
    }
    cols
}

/// The input file's columns, as the dataset's family writes them: `inputs.csv` (platform)
/// or `imu.csv` as rates (strapdown).
pub fn inputs<'py>(py: Python<'py>, ds: &Dataset) -> PyResult<Bound<'py, PyDict>> {
    let names = files_of(ds.model).input_columns();
    let rows = ds.inputs.iter().map(|s| {
        std::iter::once(s.t)
            .chain(s.f[..names.len() - 1].iter().copied())
            .collect()
    });
    dict(py, names, transpose(names, rows))
}

/// `measurements.csv`'s columns, NaN where a sensor gave nothing.
pub fn measurements<'py>(py: Python<'py>, ds: &Dataset) -> PyResult<Bound<'py, PyDict>> {
    let files = files_of(ds.model);
    let names = files.measurement_columns();
    let pair = |p: Option<[f64; 2]>| p.unwrap_or([f64::NAN; 2]);
    let rows = ds.measurements.iter().map(|m| {
        let [lat, lon] = pair(m.position_deg);
        match files.odometer() {
            Odometer::VelocityEastNorth => {
                let [ve, vn] = pair(m.velocity);
                vec![m.t, ve, vn, lat, lon]
            }
            Odometer::ForwardSpeed => vec![m.t, m.speed.unwrap_or(f64::NAN), lat, lon],
        }
    });
    dict(py, names, transpose(names, rows))
}

/// `truth.csv`'s columns (`t`, then the states by name), when the dataset has truth.
pub fn truth<'py>(py: Python<'py>, ds: &Dataset) -> PyResult<Option<Bound<'py, PyDict>>> {
    let Some(truth) = &ds.truth else {
        return Ok(None);
    };
    let d = PyDict::new(py);
    d.set_item("t", PyArray1::from_vec(py, truth.t.clone()))?;
    for (k, name) in truth.names.iter().enumerate() {
        let col: Vec<f64> = truth.states.iter().map(|s| s[k]).collect();
        d.set_item(name, PyArray1::from_vec(py, col))?;
    }
    Ok(Some(d))
}

/// Every model family's files, in `ModelKind::ALL`'s order: its name, whether it is the
/// default (which `dataset.toml` need not name), and the inputs and measurements files with
/// their columns. The package's `from_arrays` writes a dataset from them, so it holds no list
/// of families or columns of its own.
#[pyfunction]
pub fn families(py: Python<'_>) -> PyResult<Vec<Bound<'_, PyDict>>> {
    ModelKind::ALL
        .iter()
        .map(|&kind| {
            let files = files_of(kind);
            let d = PyDict::new(py);
            d.set_item("name", kind.name())?;
            d.set_item("default", kind == ModelKind::default())?;
            d.set_item(
                "inputs",
                (files.inputs_file(), files.input_columns().to_vec()),
            )?;
            d.set_item(
                "measurements",
                (MEASUREMENTS_FILE, files.measurement_columns().to_vec()),
            )?;
            Ok(d)
        })
        .collect()
}
