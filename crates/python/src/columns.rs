//! A dataset's files as columns: each CSV column a numpy array under its header's name
//! (`docs/data-format.md`), an empty cell a NaN.

use navkf_dynamics::dataset::{
    Dataset, IMU_RATE_COLUMNS, INPUT_COLUMNS, MEASUREMENT_COLUMNS, SPEED_MEASUREMENT_COLUMNS,
};
use navkf_dynamics::model_kind::ModelKind;
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

/// The columns of `rows`, each row `width` values long.
fn transpose<const W: usize>(rows: impl Iterator<Item = [f64; W]>) -> Vec<Vec<f64>> {
    let mut cols: Vec<Vec<f64>> = vec![Vec::new(); W];
    for r in rows {
        for (c, v) in cols.iter_mut().zip(r) {
            c.push(v);
        }
    }
    cols
}

/// The input file's columns: `inputs.csv` (platform) or `imu.csv` as rates (strapdown).
pub fn inputs<'py>(py: Python<'py>, ds: &Dataset) -> PyResult<Bound<'py, PyDict>> {
    match ds.model {
        ModelKind::Platform => dict(
            py,
            &INPUT_COLUMNS,
            transpose(ds.inputs.iter().map(|s| [s.t, s.f[0], s.f[1], s.f[2]])),
        ),
        ModelKind::Strapdown => dict(
            py,
            &IMU_RATE_COLUMNS,
            transpose(ds.inputs.iter().map(|s| {
                let [a, b, c, d, e, f] = s.f;
                [s.t, a, b, c, d, e, f]
            })),
        ),
    }
}

/// `measurements.csv`'s columns, NaN where a sensor gave nothing.
pub fn measurements<'py>(py: Python<'py>, ds: &Dataset) -> PyResult<Bound<'py, PyDict>> {
    let pair = |p: Option<[f64; 2]>| p.unwrap_or([f64::NAN; 2]);
    match ds.model {
        ModelKind::Platform => dict(
            py,
            &MEASUREMENT_COLUMNS,
            transpose(ds.measurements.iter().map(|m| {
                let [ve, vn] = pair(m.velocity);
                let [lat, lon] = pair(m.position_deg);
                [m.t, ve, vn, lat, lon]
            })),
        ),
        ModelKind::Strapdown => dict(
            py,
            &SPEED_MEASUREMENT_COLUMNS,
            transpose(ds.measurements.iter().map(|m| {
                let [lat, lon] = pair(m.position_deg);
                [m.t, m.speed.unwrap_or(f64::NAN), lat, lon]
            })),
        ),
    }
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
