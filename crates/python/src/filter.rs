//! `navkf.Filter`: one of navkf's filters, stepped by hand on a dataset, as filterpy's are.
//!
//! The model, the sensors and the start are those a diagnosis fit uses on the same dataset
//! (the family's catalogue: [`navkf_diagnose::catalogue`]; the start:
//! [`navkf_diagnose::fit::pass::initial`]), so a hand-stepped filter reproduces the command
//! line's numbers. After each update it exposes the estimate, its covariance, the
//! innovation, its covariance `S`, the NIS and the log-likelihood (docs/model.md eqs. (17),
//! (18)).

use crate::dataset::Dataset;
use crate::errors::{to_py, OrNavkfError};
use navkf_diagnose::fit::pass::initial;
use navkf_diagnose::request::DiagnoseRequest;
use navkf_diagnose::FitSetup;
use navkf_dynamics::dataset::{Dataset as Inner, Measurement};
use navkf_dynamics::input_cursor::SAME_TIME;
use navkf_dynamics::kinematics::INPUT_WIDTH;
use navkf_dynamics::{InputCursor, InputWindow, MeasurementModel};
use navkf_filters::{FilterKind, FilterSpec, Observation};
use navkf_report::SettingNames;
use numpy::{PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;

type Sensors = Box<dyn MeasurementModel<Record = Measurement> + Sync>;

/// A filter on a dataset (module documentation).
#[pyclass(module = "navkf._navkf", unsendable)]
pub struct Filter {
    filter: Box<dyn navkf_filters::Filter>,
    dataset: Inner,
    sensors: Sensors,
    state_names: Vec<String>,
    channel_names: Vec<&'static str>,
    input_width: usize,
    start_t: f64,
    x0: Vec<f64>,
    p0: Vec<f64>,
    cursor: InputCursor,
    window: InputWindow,
    /// Whether an update has been made since the last reset (the report is meaningful).
    updated: bool,
    /// The observation `step` reads into: values, one-sigmas, presence (no allocation per
    /// step).
    read: (Vec<f64>, Vec<f64>, Vec<bool>),
}

#[pymethods]
impl Filter {
    /// See `navkf.Filter` (python/navkf/__init__.py).
    #[new]
    #[pyo3(signature = (kind, dataset, effects, attitude=None))]
    fn new(
        kind: &str,
        dataset: &Dataset,
        effects: Vec<String>,
        attitude: Option<String>,
    ) -> PyResult<Self> {
        let kind: FilterKind = kind.parse().or_py()?;
        let ds = dataset.inner.clone();
        let attitude = attitude
            .map(|a| a.parse::<navkf_dynamics::Attitude>())
            .transpose()
            .map_err(|e| to_py(&format!("attitude: {e}")))?;
        // The effects and the attitude are checked as a diagnosis's `with_` and `attitude`.
        let request = DiagnoseRequest {
            with: effects,
            attitude,
            ..DiagnoseRequest::default()
        };
        let (catalogue, opts) = request
            .check(&ds, SettingNames::Keywords)
            .map_err(|e| to_py(&e.to_string().replacen("with:", "effects:", 1)))?;
        let attitude = opts.filter.attitude;
        let (_, start) = navkf_diagnose::catalogue::first_full_measurement(&ds).or_py()?;
        let (priors, _) = navkf_diagnose::priors::resolve(&ds, &opts.prior, start[0], &*catalogue);
        let setup = FitSetup::new(opts.with, ds.noise, priors);
        let model = catalogue
            .model(&setup.effects, &setup.parameters, &setup.noise, attitude)
            .or_py()?;
        let start = initial(&ds, &setup, &*catalogue, &*model).or_py()?;
        let spec = FilterSpec {
            attitude,
            ..FilterSpec::new(kind)
        };
        let mut filter = spec.build(model.clone()).or_py()?;
        filter.reset(&start.x, &start.p).or_py()?;
        let cursor = InputCursor::at(&ds.inputs, start.t);
        let sensors = catalogue.sensors(ds.noise);
        let nz = sensors.dim();
        Ok(Filter {
            filter,
            sensors,
            state_names: model.state_names(),
            channel_names: catalogue.channels().iter().map(|c| c.name).collect(),
            input_width: navkf_dynamics::dataset::files_of(ds.model)
                .input_columns()
                .len()
                - 1,
            start_t: start.t,
            x0: start.x,
            p0: start.p,
            cursor,
            window: InputWindow::with_capacity(64),
            dataset: ds,
            updated: false,
            read: (vec![0.0; nz], vec![0.0; nz], vec![false; nz]),
        })
    }

    /// The filter's name: `ekf`, `standard_ukf`, `simplified_ukf` or `square_root_ukf`.
    #[getter]
    fn kind(&self) -> String {
        self.filter.name().to_string()
    }

    /// The states' names, in the order of `x`.
    #[getter]
    fn state_names(&self) -> Vec<String> {
        self.state_names.clone()
    }

    /// The measurement channels' names, in the order of `observation`'s arrays.
    #[getter]
    fn channel_names(&self) -> Vec<&'static str> {
        self.channel_names.clone()
    }

    /// The time the estimate is at, s.
    #[getter]
    fn t(&self) -> f64 {
        self.cursor.time()
    }

    /// Predictions made since the last reset.
    #[getter]
    fn step_index(&self) -> usize {
        self.filter.step_index()
    }

    /// The estimate.
    #[getter]
    fn x<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, self.filter.state())
    }

    /// The estimate's covariance, n x n.
    #[getter(P)]
    fn covariance<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let n = self.filter.dim();
        // Column-major and symmetric: read row-major, it is the same matrix.
        PyArray1::from_slice(py, self.filter.covariance()).reshape([n, n])
    }

    /// The channels the last update used (indices into `channel_names`).
    #[getter]
    fn channels(&self) -> PyResult<Vec<usize>> {
        Ok(self.report()?.channels.clone())
    }

    /// The last update's innovation `z - z_hat` on the channels it used.
    #[getter]
    fn innovation<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        Ok(PyArray1::from_slice(py, &self.report()?.innovation))
    }

    /// The last update's innovation covariance `S`, k x k.
    #[getter(S)]
    fn innovation_cov<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let r = self.report()?;
        let k = r.channels.len();
        PyArray1::from_slice(py, &r.innovation_cov).reshape([k, k])
    }

    /// The last update's normalised innovation squared.
    #[getter]
    fn nis(&self) -> PyResult<f64> {
        Ok(self.report()?.nis)
    }

    /// The last update's log-likelihood of the measurement under the prediction.
    #[getter]
    fn log_likelihood(&self) -> PyResult<f64> {
        Ok(self.report()?.log_likelihood)
    }

    /// Restarts at the dataset's start, or from `x0` and `P0` at that time.
    #[pyo3(signature = (x0=None, P0=None))]
    #[allow(non_snake_case)]
    fn reset(
        &mut self,
        x0: Option<PyReadonlyArray1<'_, f64>>,
        P0: Option<PyReadonlyArray2<'_, f64>>,
    ) -> PyResult<()> {
        let n = self.filter.dim();
        let x = match &x0 {
            Some(a) => a.as_array().iter().copied().collect(),
            None => self.x0.clone(),
        };
        let p: Vec<f64> = match &P0 {
            Some(a) => {
                let a = a.as_array();
                if a.shape() != [n, n] {
                    return Err(to_py(&format!(
                        "P0: shape {:?}; expected ({n}, {n})",
                        a.shape()
                    )));
                }
                // Column-major, as the filters keep it.
                (0..n * n).map(|k| a[[k % n, k / n]]).collect()
            }
            None => self.p0.clone(),
        };
        if x.len() != n {
            return Err(to_py(&format!(
                "x0: {} values; expected {n} (state_names)",
                x.len()
            )));
        }
        self.filter.reset(&x, &p).or_py()?;
        self.cursor = InputCursor::at(&self.dataset.inputs, self.start_t);
        self.updated = false;
        Ok(())
    }

    /// Propagates the estimate to time `t` across the dataset's inputs (interpolated at the
    /// ends), as a run does between two measurements.
    fn predict_to(&mut self, t: f64) -> PyResult<()> {
        if !(t.is_finite() && t > self.cursor.time() + SAME_TIME) {
            return Err(to_py(&format!(
                "t {t}: expected a time after the estimate's, {} s",
                self.cursor.time()
            )));
        }
        self.cursor
            .advance(&self.dataset.inputs, t, &mut self.window);
        self.filter.predict(&self.window).or_py()
    }

    /// Propagates the estimate across input knots `t` (k times, the first the estimate's)
    /// with inputs `u` (k x 3 specific forces for the platform; k x 6 body rates then
    /// specific forces for a strapdown unit); each sub-step's midpoint input is the mean of
    /// its ends.
    fn predict(
        &mut self,
        t: PyReadonlyArray1<'_, f64>,
        u: PyReadonlyArray2<'_, f64>,
    ) -> PyResult<()> {
        let (t, u) = (t.as_array(), u.as_array());
        let w = self.input_width;
        if u.shape() != [t.len(), w] {
            return Err(to_py(&format!(
                "u: shape {:?}; expected ({}, {w}): one row per knot of t, {w} inputs each",
                u.shape(),
                t.len()
            )));
        }
        if t.len() < 2 || (t[0] - self.cursor.time()).abs() > SAME_TIME {
            return Err(to_py(&format!(
                "t: expected at least 2 knots, the first at the estimate's time {} s",
                self.cursor.time()
            )));
        }
        self.window.clear();
        for (k, tk) in t.iter().enumerate() {
            let mut f = [0.0; INPUT_WIDTH];
            for j in 0..w {
                f[j] = u[[k, j]];
            }
            self.window.push_linear(*tk, f);
        }
        self.filter.predict(&self.window).or_py()?;
        let end = t[t.len() - 1];
        self.cursor = InputCursor::at(&self.dataset.inputs, end);
        Ok(())
    }

    /// The observation of the dataset's measurement `index` at the current estimate: the
    /// measured values `z`, their one-sigmas and which channels are present.
    #[allow(clippy::type_complexity)]
    fn observation<'py>(
        &self,
        py: Python<'py>,
        index: usize,
    ) -> PyResult<(
        Bound<'py, PyArray1<f64>>,
        Bound<'py, PyArray1<f64>>,
        Bound<'py, PyArray1<bool>>,
    )> {
        let m = self.dataset.measurements.get(index).ok_or_else(|| {
            to_py(&format!(
                "index {index}: the dataset has {} measurements",
                self.dataset.measurements.len()
            ))
        })?;
        let (z, sigma, available) = self.observe(m);
        Ok((
            PyArray1::from_vec(py, z),
            PyArray1::from_vec(py, sigma),
            PyArray1::from_vec(py, available),
        ))
    }

    /// Corrects the estimate with measured values `z`, their one-sigmas `sigma` and which
    /// channels are present (all when None). Values of absent channels are not read.
    #[pyo3(signature = (z, sigma, available=None))]
    fn update(
        &mut self,
        z: PyReadonlyArray1<'_, f64>,
        sigma: PyReadonlyArray1<'_, f64>,
        available: Option<PyReadonlyArray1<'_, bool>>,
    ) -> PyResult<()> {
        let nz = self.sensors.dim();
        let z: Vec<f64> = z.as_array().iter().copied().collect();
        let sigma: Vec<f64> = sigma.as_array().iter().copied().collect();
        let available: Vec<bool> = match &available {
            Some(a) => a.as_array().iter().copied().collect(),
            None => vec![true; nz],
        };
        for (name, len) in [
            ("z", z.len()),
            ("sigma", sigma.len()),
            ("available", available.len()),
        ] {
            if len != nz {
                return Err(to_py(&format!(
                    "{name}: {len} values; expected {nz} (channel_names)"
                )));
            }
        }
        for k in 0..nz {
            if available[k] && !(z[k].is_finite() && sigma[k].is_finite() && sigma[k] > 0.0) {
                return Err(to_py(&format!(
                    "channel {} ({}): z = {}, sigma = {}; expected a finite value and a \
                     one-sigma > 0 (or the channel marked absent)",
                    k, self.channel_names[k], z[k], sigma[k]
                )));
            }
        }
        self.correct(&z, &sigma, &available)
    }

    /// Predicts to the dataset's next measurement after the estimate's time and updates with
    /// it, as a run does; returns that measurement's index, or None at the end.
    fn step(&mut self) -> PyResult<Option<usize>> {
        let now = self.cursor.time();
        // Measurements are in time order: the first after the estimate's time, found in
        // log time (a scan from the start made stepping a long recording quadratic).
        let measurements = &self.dataset.measurements;
        let index = measurements.partition_point(|m| m.t <= now + SAME_TIME);
        let Some(&m) = measurements.get(index) else {
            return Ok(None);
        };
        self.predict_to(m.t)?;
        let (mut z, mut sigma, mut available) = std::mem::take(&mut self.read);
        self.sensors
            .observe(&m, self.filter.state(), &mut z, &mut sigma, &mut available);
        let corrected = self.correct(&z, &sigma, &available);
        self.read = (z, sigma, available);
        corrected?;
        Ok(Some(index))
    }

    fn __repr__(&self) -> String {
        format!(
            "<navkf.Filter {} on {:?}: {} states, t = {} s>",
            self.filter.name(),
            self.dataset.name,
            self.filter.dim(),
            self.cursor.time()
        )
    }
}

impl Filter {
    /// The dataset's sensors' reading of `m` at the current estimate: values, one-sigmas
    /// and which channels are present.
    fn observe(&self, m: &Measurement) -> (Vec<f64>, Vec<f64>, Vec<bool>) {
        let nz = self.sensors.dim();
        let (mut z, mut sigma, mut available) = (vec![0.0; nz], vec![0.0; nz], vec![false; nz]);
        self.sensors
            .observe(m, self.filter.state(), &mut z, &mut sigma, &mut available);
        (z, sigma, available)
    }

    /// The update with an observation already checked.
    fn correct(&mut self, z: &[f64], sigma: &[f64], available: &[bool]) -> PyResult<()> {
        let obs = Observation {
            z,
            sigma,
            available,
        };
        self.filter.update(&obs).or_py()?;
        self.updated = true;
        Ok(())
    }

    fn report(&self) -> PyResult<&navkf_filters::UpdateReport> {
        if !self.updated {
            return Err(to_py(
                "no update since the filter started: call update or step first",
            ));
        }
        Ok(self.filter.last_report())
    }
}
