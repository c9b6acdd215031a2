//! `navkf.Dataset`: a dataset folder in memory (`docs/data-format.md`), read and written by
//! the same code as the command line's, its files' columns as numpy arrays.

use crate::columns;
use crate::errors::OrNavkfError;
use navkf_dynamics::dataset::Dataset as Inner;
use navkf_dynamics::declared::DeclaredFile;
use navkf_study::simulation::write_checked;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;

/// A dataset: inputs, measurements, the stated noise and priors, and truth when simulated.
#[pyclass(module = "navkf._navkf", frozen)]
pub struct Dataset {
    pub inner: Inner,
}

#[pymethods]
impl Dataset {
    /// Reads and validates the dataset folder `path`; errors name the file, line and column.
    /// With `effects_file` (effects declared in TOML, of the dataset's family),
    /// `[prior.coefficients]` and `truth.csv` may name its coefficients.
    #[staticmethod]
    #[pyo3(signature = (path, effects_file=None))]
    fn read(py: Python<'_>, path: PathBuf, effects_file: Option<PathBuf>) -> PyResult<Self> {
        let inner = py
            .detach(|| -> Result<Inner, navkf_dynamics::DynamicsError> {
                let file = effects_file
                    .as_deref()
                    .map(DeclaredFile::read)
                    .transpose()?;
                DeclaredFile::read_dataset(file.as_ref(), &path)
            })
            .or_py()?;
        Ok(Dataset { inner })
    }

    /// A dataset built from columns in memory, checked as a folder on disk is: see
    /// `navkf._from_arrays` (python/navkf/__init__.py), which writes the columns as the
    /// family's files and reads them back through [`Inner::read`].
    #[staticmethod]
    #[pyo3(signature = (*args, **kwargs))]
    fn from_arrays<'py>(
        py: Python<'py>,
        args: &Bound<'py, pyo3::types::PyTuple>,
        kwargs: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        py.import("navkf")?
            .getattr("_from_arrays")?
            .call(args, kwargs)
    }

    /// Writes the dataset into the folder `path`: a new folder, an empty one, or a dataset
    /// navkf wrote before (replaced whole); never a folder holding anything else. The files
    /// are read back before they are put in place, so what is written reads.
    fn write(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        py.detach(|| write_checked(&self.inner, &path)).or_py()?;
        Ok(())
    }

    /// The dataset's name (its folder's).
    #[getter]
    fn name(&self) -> &str {
        &self.inner.name
    }

    /// The model family: `"platform"` or `"strapdown"`.
    #[getter]
    fn model(&self) -> &'static str {
        self.inner.model.name()
    }

    /// The input file's columns by header name (`inputs.csv`, or a strapdown unit's `imu.csv`
    /// as rates).
    #[getter]
    fn inputs<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        columns::inputs(py, &self.inner)
    }

    /// `measurements.csv`'s columns by header name; NaN where a sensor gave nothing.
    #[getter]
    fn measurements<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        columns::measurements(py, &self.inner)
    }

    /// `truth.csv`'s columns (`t`, then the states by name), or None.
    #[getter]
    fn truth<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        columns::truth(py, &self.inner)
    }

    /// Whether `dataset.toml` states the noise (otherwise the noise is navkf's default).
    #[getter]
    fn noise_stated(&self) -> bool {
        self.inner.noise_stated
    }

    /// The noise: `dataset.toml`'s `[noise]` keys.
    #[getter]
    fn noise<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        json_loads(py, &serde_json::to_string(&self.inner.noise).or_py()?)
    }

    /// `navkf inspect --json`'s summary.
    fn summary<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        json_loads(py, &serde_json::to_string(&self.inner.summary()).or_py()?)
    }

    /// The plausibility warnings `navkf inspect` prints (units, wrapped longitude...).
    fn warnings(&self) -> Vec<String> {
        self.inner
            .warnings()
            .iter()
            .map(|w| w.to_string())
            .collect()
    }

    fn __len__(&self) -> usize {
        self.inner.measurements.len()
    }

    fn __repr__(&self) -> String {
        format!(
            "<navkf.Dataset {:?}: {} model, {} input rows, {} measurement rows{}>",
            self.inner.name,
            self.inner.model.name(),
            self.inner.inputs.len(),
            self.inner.measurements.len(),
            if self.inner.truth.is_some() {
                ", truth"
            } else {
                ""
            }
        )
    }
}

/// `text` as Python data, through the standard library's `json`.
fn json_loads<'py>(py: Python<'py>, text: &str) -> PyResult<Bound<'py, PyAny>> {
    py.import("json")?.call_method1("loads", (text,))
}
