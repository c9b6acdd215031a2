//! Preparing a study: the truth and filter models from the study file, the truth
//! simulator with its coefficient priors, every compared filter's [`FilterSpec`] and model,
//! the stored times and each filter state's initial sigma.

use super::{FilterSetup, Study};
use crate::config::StudyConfig;
use crate::error::StudyError;
use crate::family::{self, FamilyParts};
use navkf_dynamics::rng::{stream, Purpose};
use navkf_dynamics::state::*;
use navkf_dynamics::Trajectory;
use rand::Rng;
use rand_distr::StandardNormal;
use std::sync::Arc;

/// The stored times: the first measurement time at or after each multiple of `every` below
/// `duration`, then the last measurement time, without repeats (measurements fall at
/// multiples of `dt_meas` from `dt_meas` on; a run stores at most one value per measurement).
fn stored_times(every: f64, duration: f64, dt_meas: f64) -> Vec<f64> {
    // Work in measurement indices: multiple j of `every` lands on index ceil(j every / dt).
    let last = (duration / dt_meas).floor();
    let index_of = |j: f64| (j * every / dt_meas - 1e-9).ceil();
    let mut times: Vec<f64> = Vec::new();
    // Measurements start one interval in: index 1 at the earliest.
    let mut m = index_of(1.0).max(1.0);
    while m < last && m * dt_meas < duration - 1e-9 {
        times.push(m * dt_meas);
        // The first multiple beyond index m, and at least the next index: one step per
        // stored time however small `every` is.
        let j = ((m + 1e-9) * dt_meas / every).floor() + 1.0;
        m = index_of(j).max(m + 1.0);
    }
    times.push(last * dt_meas);
    times
}

impl Study {
    /// Prepares a study from its configuration.
    pub fn new(config: StudyConfig) -> Result<Self, StudyError> {
        if let Some(sweep) = &config.sweep {
            return Err(StudyError::Other(format!(
                "the study sweeps `{}`: each of its points is a study of its own \
                 (navkf_study::sweep::points)",
                sweep.key
            )));
        }
        let trajectory = Arc::new(Trajectory::build(&config.trajectory)?);
        let FamilyParts {
            sim,
            filter_model,
            filter_model_in,
        } = family::of(config.model.kind).parts(&config, trajectory)?;
        let mut filters = Vec::new();
        for label in &config.study.filters {
            let spec = config.filter.plan(label).map_err(StudyError::Other)?;
            let model = if spec.attitude == config.filter.attitude {
                filter_model.clone()
            } else {
                filter_model_in(spec.attitude)?
            };
            navkf_filters::SigmaPoints::new(model.dim(), spec.scaling).map_err(|e| {
                StudyError::Other(format!("the sigma-point scaling of `{label}`: {e}"))
            })?;
            filters.push(FilterSetup { spec, model });
        }
        let truth_model = sim.truth_model();
        let scale = config.truth.coefficient_scale;
        let names = filter_model.state_names();
        let truth_names = truth_model.state_names();
        let to_truth = names
            .iter()
            .map(|n| truth_names.iter().position(|t| t == n))
            .collect();
        let init = &config.filter.initial;
        for name in init.coefficient_sigma.keys() {
            if !names.iter().skip(NAV_DIM).any(|n| n == name) {
                return Err(StudyError::Other(format!(
                    "filter.initial.coefficient_sigma.{name}: no such coefficient in the filters' model"
                )));
            }
        }
        let tilt = config.truth.initial_tilt;
        let initial_sigma: Vec<f64> = (0..filter_model.dim())
            .map(|i| {
                let s = match i {
                    PHI_X | PHI_Y => tilt.level_rad,
                    PHI_Z => tilt.azimuth_rad,
                    V_X | V_Y => init.velocity_sigma,
                    LAT => init.position_sigma_m / navkf_dynamics::earth::meridian_radius(0.0),
                    LON => init.position_sigma_m / navkf_dynamics::earth::RE,
                    _ => init
                        .coefficient_sigma
                        .get(&names[i])
                        .copied()
                        .unwrap_or(filter_model.typical_sigma(i) * scale),
                };
                s * init.sigma_scale
            })
            .collect();
        // A sigma whose square overflows (or a NaN) would stop every run at its first step;
        // say which setting made it instead.
        if let Some(i) = initial_sigma.iter().position(|s| !(s * s).is_finite()) {
            let key = match i {
                PHI_X | PHI_Y => "truth.initial_tilt.level_rad".to_string(),
                PHI_Z => "truth.initial_tilt.azimuth_rad".to_string(),
                V_X | V_Y => "filter.initial.velocity_sigma".to_string(),
                LAT | LON => "filter.initial.position_sigma_m".to_string(),
                _ => format!("filter.initial.coefficient_sigma.{}", names[i]),
            };
            return Err(StudyError::Other(format!(
                "the initial sigma of {} is {:e} ({key}, times filter.initial.sigma_scale = \
                 {:e}): its variance is not a finite number; expected a sigma below 1e150",
                names[i], initial_sigma[i], init.sigma_scale
            )));
        }
        let every = config.study.series_every_s;
        let duration = config.trajectory.duration_s;
        let dt_meas = 1.0 / config.truth.measurement_rate_hz;
        let times = stored_times(every, duration, dt_meas);
        Ok(Study {
            config,
            sim,
            filter_model,
            to_truth,
            initial_sigma,
            names,
            times,
            filters,
        })
    }

    /// Filter names, in order.
    pub fn filter_names(&self) -> &[String] {
        &self.config.study.filters
    }

    /// The initial estimate of run `run`: the truth's start perturbed by the initial sigmas of
    /// the navigation states (so that the filters' initial covariance is honest), zero tilt
    /// and zero coefficients.
    pub(super) fn initial_estimate(&self, run: usize, truth0: &[f64]) -> Vec<f64> {
        let mut rng = stream(self.config.study.seed, run as u64, Purpose::Other(1));
        let mut x = vec![0.0; self.filter_model.dim()];
        for i in (0..NAV_DIM).filter(|&i| self.filter_model.estimate_starts_at_truth(i)) {
            let z: f64 = rng.sample(StandardNormal);
            x[i] = truth0[i] + self.initial_sigma[i] * z;
        }
        x
    }
}
