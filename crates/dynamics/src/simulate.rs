//! The truth simulator: draws the true coefficients and initial tilt, integrates the truth
//! model with RK4 at a fixed rate (default 100 Hz) under white process noise, and makes
//! odometer and GPS measurements with the noise of docs/model.md eq. (14).
//!
//! Process noise is a constant `w ~ N(0, q / h)` over each RK4 step of length `h`, which gives
//! the white noise's integrated variance `q h` per step (docs/model.md eqs. (15), (16)). The
//! input is the trajectory's exact specific force at each RK4 stage time; the dataset records
//! it sampled at the input rate. Every draw comes from [`crate::rng::stream`], so run `i` of
//! seed `s` is the same bytes on any thread.

use crate::dataset::{Dataset, InputSample, Measurement, Provenance, Truth};
use crate::error::DynamicsError;
use crate::integrate::InputWindow;
use crate::kinematics::{platform_input, Input, SpecificForce, INPUT_WIDTH};
use crate::model::PlatformModel;
use crate::noise::NoiseConfig;
use crate::prior::base_coefficient_sigma;
use crate::rng::{stream, Purpose};
use crate::state::*;
use crate::system::propagate_generic;
use crate::system::SystemModel;
use crate::trajectory::Trajectory;
use rand::Rng;
use rand_distr::StandardNormal;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::sync::Arc;

/// A Gaussian prior `N(mean, sigma^2)`; `sigma = 0` fixes the value. In a study file it is
/// a table, `{ mean = M, sigma = S }` (mean 0 if left out); anything else is refused with
/// that form in the message (a bare number is ambiguous: a fixed value or a sigma?).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Prior {
    /// Mean.
    #[serde(default)]
    pub mean: f64,
    /// Standard deviation (0: the value is given, not drawn).
    pub sigma: f64,
}

/// The table form of [`Prior`], as written in a file.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PriorTable {
    #[serde(default)]
    mean: f64,
    sigma: f64,
}

impl<'de> Deserialize<'de> for Prior {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Table;
        impl<'de> serde::de::Visitor<'de> for Table {
            type Value = Prior;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str(
                    "a prior table `{ mean = M, sigma = S }` (S one standard deviation, 0 to \
                     fix the value at M; M is 0 if left out)",
                )
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(self, map: A) -> Result<Prior, A::Error> {
                let t = PriorTable::deserialize(serde::de::value::MapAccessDeserializer::new(map))?;
                Ok(Prior {
                    mean: t.mean,
                    sigma: t.sigma,
                })
            }
        }
        d.deserialize_map(Table)
    }
}

impl Prior {
    /// A fixed value.
    pub fn fixed(value: f64) -> Self {
        Prior {
            mean: value,
            sigma: 0.0,
        }
    }
    /// Zero-mean with the given sigma.
    pub fn zero_mean(sigma: f64) -> Self {
        Prior { mean: 0.0, sigma }
    }
}

/// How the platform was aligned before the test, which sets how its initial tilt is drawn.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Alignment {
    /// Tilt drawn independently of everything else, `N(0, sigma^2)` per axis.
    #[default]
    Independent,
    /// Levelled and gyrocompassed at rest at the start: the tilt is the one that nulls the
    /// horizontal specific force and the East gyro's apparent drift for this run's own
    /// coefficients (`v_x' = v_y' = phi_x' = 0`: phi_x = -nab_y / g, phi_y = nab_x / g,
    /// phi_z = (eps_x + wie sinL phi_y) / (wie cosL), with every effect's terms), plus a
    /// residual `N(0, sigma^2)` per axis. This is how a real platform starts: its tilt and its
    /// biases are tied together, not independent.
    Gyrocompass,
}

/// The true initial navigation state: the path's start, with the platform tilted.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct InitialTilt {
    /// One-sigma levelling error about East and North, rad (10 arcsec); with
    /// [`Alignment::Gyrocompass`], the residual after levelling.
    pub level_rad: f64,
    /// One-sigma azimuth error about Up, rad (1 arcmin); with [`Alignment::Gyrocompass`],
    /// the residual after gyrocompassing.
    pub azimuth_rad: f64,
    /// How the tilt is drawn.
    pub alignment: Alignment,
}

impl Default for InitialTilt {
    fn default() -> Self {
        InitialTilt {
            level_rad: 4.85e-5,
            azimuth_rad: 2.91e-4,
            alignment: Alignment::Independent,
        }
    }
}

/// Solves the 3 x 3 system `a x = b` by Cramer's rule (the caller guarantees it is regular).
fn solve3(a: [[f64; 3]; 3], b: [f64; 3]) -> [f64; 3] {
    let det3 = |m: [[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let d = det3(a);
    std::array::from_fn(|k| {
        let mut m = a;
        for i in 0..3 {
            m[i][k] = b[i];
        }
        det3(m) / d
    })
}

/// Settings of the truth simulation.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct TruthConfig {
    /// RK4 rate of the truth integration, Hz.
    pub rate_hz: f64,
    /// Rate at which the input is recorded, Hz (the filters' sub-step rate).
    pub input_rate_hz: f64,
    /// Odometer and GPS rate, Hz (the paper's filter period is 1 s).
    pub measurement_rate_hz: f64,
    /// Initial tilt distribution.
    pub initial_tilt: InitialTilt,
    /// Priors of coefficients by state name; any coefficient not named takes
    /// [`base_coefficient_sigma`] or its effect's typical sigma, zero mean.
    pub coefficients: BTreeMap<String, Prior>,
}

impl Default for TruthConfig {
    fn default() -> Self {
        TruthConfig {
            rate_hz: 100.0,
            input_rate_hz: 10.0,
            measurement_rate_hz: 1.0,
            initial_tilt: InitialTilt::default(),
            coefficients: BTreeMap::new(),
        }
    }
}

/// One simulated run: measurements and the true state at t = 0 and at each measurement.
#[derive(Debug, Clone)]
pub struct SimulatedRun {
    /// Run index within the study.
    pub run: u64,
    /// Measurements (both sensors at every measurement time).
    pub measurements: Vec<Measurement>,
    /// True states.
    pub truth: Truth,
    /// The recorded input (the platform's specific force, the same for every run of a
    /// path; a strapdown unit's readings, with this run's sensor errors).
    pub inputs: Arc<Vec<InputSample>>,
}

/// The truth simulator for one model, trajectory and configuration; shared by all runs.
#[derive(Debug)]
pub struct Simulator {
    model: Arc<PlatformModel>,
    trajectory: Arc<Trajectory>,
    config: TruthConfig,
    noise: NoiseConfig,
    priors: Vec<Prior>,
    /// Exact input at every half step of the truth integration.
    half_step_inputs: Vec<Input>,
    steps: usize,
    steps_per_measurement: usize,
    inputs: Arc<Vec<InputSample>>,
}

/// Gyrocompassing needs `cos L` at least this (|latitude| < 85 deg).
const MIN_GYROCOMPASS_COS_LAT: f64 = 0.087;

fn cfg_err(key: &str, message: String) -> DynamicsError {
    DynamicsError::Config {
        key: key.to_string(),
        message,
    }
}

/// `a / b` when it is a whole number (to 1e-9), else `None`.
fn whole_ratio(a: f64, b: f64) -> Option<usize> {
    let r = a / b;
    (r >= 1.0 && (r - r.round()).abs() < 1e-9).then(|| r.round() as usize)
}

impl Simulator {
    /// Prepares a simulator. `model` is the truth's model (base plus the truth's effects).
    pub fn new(
        model: Arc<PlatformModel>,
        trajectory: Arc<Trajectory>,
        config: TruthConfig,
        noise: NoiseConfig,
    ) -> Result<Self, DynamicsError> {
        noise.validate().map_err(|m| cfg_err("noise", m))?;
        for (key, v) in [
            ("truth.rate_hz", config.rate_hz),
            ("truth.input_rate_hz", config.input_rate_hz),
            ("truth.measurement_rate_hz", config.measurement_rate_hz),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(cfg_err(key, format!("{v}: expected a rate > 0 Hz")));
            }
        }
        let steps_per_input =
            whole_ratio(config.rate_hz, config.input_rate_hz).ok_or_else(|| {
                cfg_err(
                    "truth.input_rate_hz",
                    format!(
                        "{} Hz: expected a whole divisor of rate_hz = {} Hz",
                        config.input_rate_hz, config.rate_hz
                    ),
                )
            })?;
        let steps_per_measurement = whole_ratio(config.rate_hz, config.measurement_rate_hz)
            .filter(|s| s % steps_per_input == 0)
            .ok_or_else(|| {
                cfg_err(
                    "truth.measurement_rate_hz",
                    format!(
                        "{} Hz: expected a whole divisor of input_rate_hz = {} Hz",
                        config.measurement_rate_hz, config.input_rate_hz
                    ),
                )
            })?;
        let duration = trajectory.duration();
        let steps = whole_ratio(duration * config.rate_hz, 1.0).ok_or_else(|| {
            cfg_err(
                "trajectory.duration_s",
                format!(
                    "{duration} s: expected a whole number of truth steps at {} Hz",
                    config.rate_hz
                ),
            )
        })?;
        // The recorded inputs, shared by every run, and one run's truth and measurements.
        crate::memory::check(
            "truth.input_rate_hz",
            "the recorded inputs",
            duration * config.input_rate_hz,
            std::mem::size_of::<InputSample>(),
        )?;
        crate::memory::check(
            "truth.measurement_rate_hz",
            "one run's truth",
            duration * config.measurement_rate_hz,
            (model.dim() + 8) * std::mem::size_of::<f64>(),
        )?;
        if config.initial_tilt.alignment == Alignment::Gyrocompass {
            let lat = trajectory.state(0.0).pos[0];
            if lat.cos() < MIN_GYROCOMPASS_COS_LAT {
                return Err(cfg_err(
                    "truth.initial_tilt.alignment",
                    format!(
                        "gyrocompass at latitude {:.2} deg: expected |latitude| < 85 deg \
                         (near the poles the Earth's rate gives no North)",
                        lat.to_degrees()
                    ),
                ));
            }
        }
        for (key, v) in [
            (
                "truth.initial_tilt.level_rad",
                config.initial_tilt.level_rad,
            ),
            (
                "truth.initial_tilt.azimuth_rad",
                config.initial_tilt.azimuth_rad,
            ),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(cfg_err(
                    key,
                    format!("{v}: expected a finite sigma >= 0 rad"),
                ));
            }
        }
        let names = model.state_names();
        for (name, p) in &config.coefficients {
            let Some(i) = model.index_of(name) else {
                return Err(cfg_err(
                    &format!("truth.coefficients.{name}"),
                    format!(
                        "no such coefficient in the truth model (states: {})",
                        names[NAV_DIM..].join(", ")
                    ),
                ));
            };
            if i < NAV_DIM {
                return Err(cfg_err(
                    &format!("truth.coefficients.{name}"),
                    "a navigation state, not a coefficient".to_string(),
                ));
            }
            if !(p.mean.is_finite() && p.sigma.is_finite() && p.sigma >= 0.0) {
                return Err(cfg_err(
                    &format!("truth.coefficients.{name}"),
                    format!(
                        "mean {} sigma {}: expected finite values, sigma >= 0",
                        p.mean, p.sigma
                    ),
                ));
            }
        }
        let mut priors: Vec<Prior> = (0..model.dim())
            .map(|i| Prior::zero_mean(base_coefficient_sigma(i)))
            .collect();
        for (i, s) in model.effect_coefficient_sigmas() {
            priors[i] = Prior::zero_mean(s);
        }
        for (name, p) in &config.coefficients {
            priors[model.index_of(name).expect("checked above")] = *p;
        }
        let h = 1.0 / config.rate_hz;
        let half_step_inputs = (0..=2 * steps)
            .map(|k| platform_input(trajectory.specific_force(k as f64 * 0.5 * h)))
            .collect();
        let input_step = 1.0 / config.input_rate_hz;
        let n_inputs = steps / steps_per_input;
        let inputs = (0..=n_inputs)
            .map(|k| {
                let t = k as f64 * input_step;
                InputSample {
                    t,
                    f: platform_input(trajectory.specific_force(t)),
                }
            })
            .collect();
        Ok(Simulator {
            model,
            trajectory,
            config,
            noise,
            priors,
            half_step_inputs,
            steps,
            steps_per_measurement,
            inputs: Arc::new(inputs),
        })
    }

    /// Adds `error(t)` to the specific force the truth integrates, but not to the recorded
    /// input: an accelerometer error that varies with time and that no coefficient carries
    /// (warm-up, temperature; [`crate::outside::AccelWarmUp`]). Every run of this simulator
    /// then carries it.
    pub fn with_specific_force_error(mut self, error: impl Fn(f64) -> SpecificForce) -> Self {
        let h = 1.0 / self.config.rate_hz;
        for (k, f) in self.half_step_inputs.iter_mut().enumerate() {
            let e = error(k as f64 * 0.5 * h);
            for a in 0..3 {
                f[a] += e[a];
            }
        }
        self
    }

    /// The truth model.
    pub fn model(&self) -> &Arc<PlatformModel> {
        &self.model
    }
    /// The trajectory.
    pub fn trajectory(&self) -> &Arc<Trajectory> {
        &self.trajectory
    }
    /// The settings.
    pub fn config(&self) -> &TruthConfig {
        &self.config
    }
    /// The noise settings.
    pub fn noise(&self) -> &NoiseConfig {
        &self.noise
    }
    /// The recorded input, shared by every run (the path is the same).
    pub fn inputs(&self) -> &Arc<Vec<InputSample>> {
        &self.inputs
    }
    /// The prior of every state (navigation states have sigma 0 here; see
    /// [`Simulator::initial_state`]).
    pub fn priors(&self) -> &[Prior] {
        &self.priors
    }

    /// The true initial state of run `run`: path start, tilted platform, drawn coefficients.
    pub fn initial_state(&self, seed: u64, run: u64) -> Vec<f64> {
        let mut x = vec![0.0; self.model.dim()];
        let start = self.trajectory.state(0.0);
        x[V_X] = start.v[0];
        x[V_Y] = start.v[1];
        x[LAT] = start.pos[0];
        x[LON] = start.pos[1];
        let mut rng = stream(seed, run, Purpose::InitialState);
        let tilt = self.config.initial_tilt;
        let residual = [
            tilt.level_rad * rng.sample::<f64, _>(StandardNormal),
            tilt.level_rad * rng.sample::<f64, _>(StandardNormal),
            tilt.azimuth_rad * rng.sample::<f64, _>(StandardNormal),
        ];
        let mut rng = stream(seed, run, Purpose::Coefficients);
        for (i, p) in self.priors.iter().enumerate().skip(NAV_DIM) {
            // Always draw, so that fixing one coefficient leaves the others' draws unchanged.
            let z: f64 = rng.sample(StandardNormal);
            x[i] = p.mean + p.sigma * z;
        }
        let tilt = match tilt.alignment {
            Alignment::Independent => residual,
            Alignment::Gyrocompass => {
                let aligned = self.aligned_tilt(&x);
                std::array::from_fn(|a| aligned[a] + residual[a])
            }
        };
        x[PHI_X..=PHI_Z].copy_from_slice(&tilt);
        x
    }

    /// The tilt that levelling and gyrocompassing at the start leave for state `x` (its
    /// coefficients and position; its tilt is ignored): the solution of
    /// `phi_x' = v_x' = v_y' = 0` for `phi`. The rates are linear in `phi`, so one Newton
    /// step from zero tilt is exact.
    fn aligned_tilt(&self, x: &[f64]) -> [f64; 3] {
        let model = &*self.model;
        let n = model.dim();
        let f = platform_input(self.trajectory.specific_force(0.0));
        let mut level = x.to_vec();
        level[PHI_X..=PHI_Z].fill(0.0);
        let mut r = vec![0.0; NAV_DIM];
        let mut jac = vec![0.0; NAV_DIM * n];
        model.rates(&level, &f, &mut r);
        model.rate_jacobian(&level, &f, &mut jac);
        let rows = [PHI_X, V_X, V_Y];
        let a: [[f64; 3]; 3] =
            std::array::from_fn(|i| std::array::from_fn(|j| jac[rows[i] * n + j]));
        let b: [f64; 3] = std::array::from_fn(|i| -r[rows[i]]);
        solve3(a, b)
    }

    /// Simulates run `run` of study seed `seed`.
    pub fn run(&self, seed: u64, run: u64) -> SimulatedRun {
        let x0 = self.initial_state(seed, run);
        self.run_from(seed, run, x0)
    }

    /// Simulates from a given true initial state.
    pub fn run_from(&self, seed: u64, run: u64, mut x: Vec<f64>) -> SimulatedRun {
        let model = &*self.model;
        let n = model.dim();
        let channels = model.noise_channels();
        let h = 1.0 / self.config.rate_hz;
        let noise_sd: Vec<f64> = channels.iter().map(|c| (c.psd / h).sqrt()).collect();
        let mut w = vec![0.0; channels.len()];
        let mut scratch = vec![0.0; model.scratch_len(1)];
        let mut window = InputWindow::with_capacity(2);
        let mut proc_rng = stream(seed, run, Purpose::ProcessNoise);
        let mut meas_rng = stream(seed, run, Purpose::MeasurementNoise);
        let n_meas = self.steps / self.steps_per_measurement;
        let mut truth = Truth {
            names: model.state_names(),
            t: Vec::with_capacity(n_meas + 1),
            states: Vec::with_capacity(n_meas + 1),
        };
        let mut measurements = Vec::with_capacity(n_meas);
        truth.t.push(0.0);
        truth.states.push(x.clone());
        let mut z = [0.0; MEAS_DIM];
        for k in 0..self.steps {
            let t0 = k as f64 * h;
            window.clear();
            window.push_with_mid(t0, self.half_step_inputs[2 * k], [0.0; INPUT_WIDTH]);
            window.push_with_mid(
                (k + 1) as f64 * h,
                self.half_step_inputs[2 * k + 2],
                self.half_step_inputs[2 * k + 1],
            );
            for (wi, sd) in w.iter_mut().zip(&noise_sd) {
                *wi = sd * proc_rng.sample::<f64, _>(StandardNormal);
            }
            propagate_generic(model, &mut x, Some(&w), &window, &mut scratch);
            if (k + 1) % self.steps_per_measurement == 0 {
                let t = (k + 1) as f64 * h;
                model.measure(&x, &mut z);
                // The odometer's noise scales with its own reading (which an odometer scale
                // error makes differ from the true speed), as the filters assume.
                let speed = z[0].hypot(z[1]);
                let sig = self.noise.measurement_sigmas(speed, x[LAT]);
                let mut e = [0.0; MEAS_DIM];
                for (ei, s) in e.iter_mut().zip(sig) {
                    *ei = s * meas_rng.sample::<f64, _>(StandardNormal);
                }
                measurements.push(Measurement {
                    t,
                    velocity: Some([z[0] + e[0], z[1] + e[1]]),
                    speed: None,
                    nhc: None,
                    zupt: None,
                    position_deg: Some([(z[2] + e[2]).to_degrees(), (z[3] + e[3]).to_degrees()]),
                });
                truth.t.push(t);
                truth.states.push(x[..n].to_vec());
            }
        }
        SimulatedRun {
            run,
            measurements,
            truth,
            inputs: self.inputs.clone(),
        }
    }

    /// A dataset of one run, named `name`.
    pub fn dataset(&self, name: &str, seed: u64, run: &SimulatedRun) -> Dataset {
        Dataset {
            name: name.to_string(),
            inputs: self.inputs.to_vec(),
            measurements: run.measurements.clone(),
            noise: self.noise,
            noise_stated: true,
            prior: Default::default(),
            provenance: Some(Provenance {
                seed: Some(seed),
                run: Some(run.run),
                effects: self.model.effect_names(),
                note: Some(format!(
                    "navkf truth simulation: RK4 at {} Hz, inputs at {} Hz, measurements at {} Hz",
                    self.config.rate_hz, self.config.input_rate_hz, self.config.measurement_rate_hz
                )),
            }),
            truth: Some(run.truth.clone()),
            model: Default::default(),
            initial: None,
            effects: self.model.declarations(),
        }
    }
}
