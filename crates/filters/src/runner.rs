//! Drives a filter over recorded inputs and measurements: one prediction across the input
//! samples between consecutive measurements (inputs linearly interpolated at the ends; the
//! window of docs/model.md eq. (15)), one update per measurement. What a record measures, and
//! with which sigmas, is the [`MeasurementModel`]'s business (the platform's is its
//! `NoiseConfig`): the runner does not know the platform.
//!
//! The runner owns its buffers and reuses them, so a run allocates nothing per step. What
//! happens at each step goes to an observer closure (tallies, CSV rows, plots are the
//! caller's business, not the loop's).

use crate::error::FilterError;
use crate::filter::Filter;
use crate::update::{Observation, UpdateReport};
use navkf_dynamics::dataset::InputSample;
use navkf_dynamics::input_cursor::SAME_TIME;
use navkf_dynamics::{InputCursor, InputWindow, MeasurementModel};
use std::time::Instant;

/// A filter failure during a run, with where it happened.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("measurement {index} (t = {t} s): {error}")]
pub struct RunError {
    /// Index of the measurement being processed.
    pub index: usize,
    /// Its time, s.
    pub t: f64,
    /// The filter's error.
    pub error: FilterError,
}

/// What the observer sees after each update.
pub struct StepView<'a, F: ?Sized> {
    /// Index of the measurement.
    pub index: usize,
    /// Its time, s.
    pub t: f64,
    /// The filter after the update.
    pub filter: &'a F,
    /// The update's report.
    pub report: &'a UpdateReport,
    /// The input window the prediction before it integrated over.
    pub window: &'a InputWindow,
    /// Wall time of this predict + update, nanoseconds.
    pub step_ns: u64,
}

/// Reusable driver; see the module documentation.
#[derive(Debug, Default)]
pub struct Runner {
    window: InputWindow,
    /// The observation's buffers, grown to the measurement dimension on the first run.
    z: Vec<f64>,
    sigma: Vec<f64>,
    available: Vec<bool>,
}

/// Measurement channels a new runner has room for (the platform has 4); a model with more
/// grows the buffers once, at the start of its first run.
const OBSERVATION_ROOM: usize = 8;

impl Runner {
    /// A runner with room for `knots` input knots per window (grows if needed, once).
    pub fn new(knots: usize) -> Self {
        Runner {
            window: InputWindow::with_capacity(knots),
            z: Vec::with_capacity(OBSERVATION_ROOM),
            sigma: Vec::with_capacity(OBSERVATION_ROOM),
            available: Vec::with_capacity(OBSERVATION_ROOM),
        }
    }

    /// Runs `filter` from `start` (the time of its initial state) over `measurements`,
    /// calling `observe` after each update. Measurements at or before `start` are skipped.
    /// Stops at the first filter error.
    pub fn run<F, O, S>(
        &mut self,
        filter: &mut F,
        start: f64,
        inputs: &[InputSample],
        measurements: &[S::Record],
        sensors: &S,
        mut observe: O,
    ) -> Result<(), RunError>
    where
        F: Filter + ?Sized,
        O: FnMut(StepView<'_, F>),
        S: MeasurementModel + ?Sized,
    {
        let nz = sensors.dim();
        self.z.resize(nz, 0.0);
        self.sigma.resize(nz, 0.0);
        self.available.resize(nz, false);
        let mut cursor = InputCursor::at(inputs, start);
        for (index, m) in measurements.iter().enumerate() {
            let t_m = sensors.time(m);
            if t_m <= cursor.time() + SAME_TIME {
                continue;
            }
            let t0 = Instant::now();
            cursor.advance(inputs, t_m, &mut self.window);
            let wrap = |error| RunError {
                index,
                t: t_m,
                error,
            };
            filter.predict(&self.window).map_err(wrap)?;
            sensors.observe(
                m,
                filter.state(),
                &mut self.z,
                &mut self.sigma,
                &mut self.available,
            );
            let obs = Observation {
                z: &self.z,
                sigma: &self.sigma,
                available: &self.available,
            };
            let step_ns = {
                // Borrow dance: the report borrows the filter; time before handing it out.
                filter.update(&obs).map_err(wrap)?;
                t0.elapsed().as_nanos() as u64
            };
            let report = filter_report(filter);
            observe(StepView {
                index,
                t: t_m,
                filter: &*filter,
                report,
                window: &self.window,
                step_ns,
            });
        }
        Ok(())
    }
}

fn filter_report<F: Filter + ?Sized>(filter: &F) -> &UpdateReport {
    filter.last_report()
}
