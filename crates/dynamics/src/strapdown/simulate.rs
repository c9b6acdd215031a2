//! The strapdown truth simulator: a unit bolted level to a vehicle that drives a
//! [`Trajectory`], its readings made from the path, its errors drawn per run.
//!
//! **The truth is the path.** The vehicle's attitude (level, heading along its velocity),
//! velocity and position at any time are the trajectory's, exactly; nothing is integrated
//! to make them. The unit's error-free reading (docs/model.md eq. (62)) is what makes the error-free model of
//! docs/model.md eqs. (51)-(58) follow that path: the rate of the body relative to inertial
//! space (the Earth's rate and the transport rate seen in body axes, plus the turn) and the
//! specific force resolved in body axes (the platform's, [`specific_force_for`]). A test
//! holds the model, driven by these readings, to the path. Then each reading gets the run's
//! errors (docs/model.md eq. (50)): the drawn biases and a white noise of the stated
//! densities, `N(0, q / h)` per sample at the sample interval `h` (integrated variance `q h`
//! per sample, the noise the filters' process noise describes).
//!
//! The odometer reads the forward speed, the GPS the position, each with the noise of
//! docs/model.md eq. (14). The path is a rigid vehicle on its road: its lateral and vertical
//! body velocities are zero. A real car's are not quite (sideslip in the turns, bounce), and
//! that is what the constraint's stated sigma `nhc_m_s` describes; the simulator draws them
//! as the constraint's reading ([`Measurement::nhc`], `N(0, nhc_m_s^2)` per axis) so that the
//! filters meet the error they are told of, as they do for every other sensor.
//!
//! Every draw comes from [`crate::rng::stream`]: the biases from `Coefficients`, the reading
//! noise from `ProcessNoise`, the odometer and GPS noise from `MeasurementNoise`.

use super::attitude::{body_to_nav, rotate_back};
use super::model::StrapdownModel;
use super::rates::{input_of, ImuReading};
use super::sensors::StrapdownSensors;
use super::state::*;
use super::unit_class::UnitErrors;
use crate::dataset::{Dataset, InitialAttitude, InputSample, Measurement, Provenance, Truth};
use crate::earth::{meridian_radius, prime_vertical_radius, WIE};
use crate::error::DynamicsError;
use crate::model_kind::ModelKind;
use crate::noise::NoiseConfig;
use crate::prior::PlatformPrior;
use crate::rng::{stream, Purpose};
use crate::simulate::{Prior, SimulatedRun};
use crate::system::SystemModel;
use crate::trajectory::{specific_force_for, PathState, Trajectory};
use rand::Rng;
use rand_distr::StandardNormal;
use std::collections::BTreeMap;
use std::sync::Arc;

/// The true navigation state of the path at `st`: level, heading along the path.
pub fn path_state(st: &PathState) -> [f64; NAV_DIM] {
    [0.0, 0.0, st.heading, st.v[0], st.v[1], st.pos[0], st.pos[1]]
}

/// The error-free reading of a level unit on the path at `st` (module documentation).
pub fn ideal_reading(st: &PathState) -> ImuReading {
    let c = body_to_nav([0.0, 0.0, st.heading]);
    let (sl, cl) = st.pos[0].sin_cos();
    let (rm, rn) = (meridian_radius(sl), prime_vertical_radius(sl));
    let [ve, vn] = st.v;
    let w_in = [-vn / rm, WIE * cl + ve / rn, WIE * sl + ve * sl / cl / rn];
    let w_in_b = rotate_back(&c, w_in);
    // Heading counts clockwise from North: a turn to the right is a negative rate about up.
    ImuReading {
        w: [w_in_b[0], w_in_b[1], w_in_b[2] - st.turn_rate],
        f: rotate_back(&c, specific_force_for(st)),
    }
}

/// The strapdown truth simulator for one model, trajectory and setting; shared by all runs.
#[derive(Debug)]
pub struct StrapdownSimulator {
    model: Arc<StrapdownModel>,
    trajectory: Arc<Trajectory>,
    noise: NoiseConfig,
    sensors: StrapdownSensors,
    priors: Vec<Prior>,
    /// The error-free readings at the sample times, shared by every run.
    ideal: Vec<(f64, ImuReading)>,
    /// Measurement times and the true navigation state there.
    path: Vec<(f64, [f64; NAV_DIM])>,
    imu_rate_hz: f64,
    measurement_rate_hz: f64,
}

fn cfg_err(key: &str, message: String) -> DynamicsError {
    DynamicsError::Config {
        key: key.to_string(),
        message,
    }
}

impl StrapdownSimulator {
    /// Prepares a simulator: readings at `imu_rate_hz`, odometer and GPS at
    /// `measurement_rate_hz` (a whole divisor of it), biases drawn with the sigmas of `unit`
    /// unless `coefficients` gives their prior by name (`bgx` ... `baz`), reading noise with
    /// the densities of `noise`.
    pub fn new(
        model: Arc<StrapdownModel>,
        trajectory: Arc<Trajectory>,
        imu_rate_hz: f64,
        measurement_rate_hz: f64,
        unit: UnitErrors,
        coefficients: &BTreeMap<String, Prior>,
        noise: NoiseConfig,
    ) -> Result<Self, DynamicsError> {
        noise.validate().map_err(|m| cfg_err("noise", m))?;
        for (key, v) in [
            ("truth.input_rate_hz", imu_rate_hz),
            ("truth.measurement_rate_hz", measurement_rate_hz),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(cfg_err(key, format!("{v}: expected a rate > 0 Hz")));
            }
        }
        let per_measurement = whole(imu_rate_hz / measurement_rate_hz).ok_or_else(|| {
            cfg_err(
                "truth.measurement_rate_hz",
                format!(
                    "{measurement_rate_hz} Hz: expected a whole divisor of the IMU rate \
                     {imu_rate_hz} Hz"
                ),
            )
        })?;
        let duration = trajectory.duration();
        let samples = whole(duration * imu_rate_hz).ok_or_else(|| {
            cfg_err(
                "trajectory.duration_s",
                format!("{duration} s: expected a whole number of IMU samples at {imu_rate_hz} Hz"),
            )
        })?;
        crate::memory::check(
            "truth.input_rate_hz",
            "one run's IMU readings",
            duration * imu_rate_hz,
            std::mem::size_of::<InputSample>() * 2,
        )?;
        let names = model.state_names();
        let mut priors: Vec<Prior> = (0..model.dim())
            .map(|i| match i {
                i if (BG_X..BG_X + 3).contains(&i) => Prior::zero_mean(unit.gyro_bias),
                i if (BA_X..BA_X + 3).contains(&i) => Prior::zero_mean(unit.accel_bias),
                _ => Prior::fixed(0.0),
            })
            .collect();
        for (name, p) in coefficients {
            let key = format!("truth.coefficients.{name}");
            let Some(i) = names.iter().position(|n| n == name) else {
                return Err(cfg_err(
                    &key,
                    format!(
                        "no such coefficient in the strapdown truth model (states: {})",
                        names[NAV_DIM..].join(", ")
                    ),
                ));
            };
            if i < NAV_DIM {
                return Err(cfg_err(
                    &key,
                    "a navigation state, not a coefficient".into(),
                ));
            }
            if !(p.mean.is_finite() && p.sigma.is_finite() && p.sigma >= 0.0) {
                return Err(cfg_err(
                    &key,
                    format!(
                        "mean {} sigma {}: expected finite values, sigma >= 0",
                        p.mean, p.sigma
                    ),
                ));
            }
            priors[i] = *p;
        }
        let h = 1.0 / imu_rate_hz;
        let ideal = (0..=samples)
            .map(|k| {
                let t = k as f64 * h;
                (t, ideal_reading(&trajectory.state(t)))
            })
            .collect();
        let path = (0..=samples / per_measurement)
            .map(|j| {
                let t = (j * per_measurement) as f64 * h;
                (t, path_state(&trajectory.state(t)))
            })
            .collect();
        Ok(StrapdownSimulator {
            model,
            trajectory,
            noise,
            sensors: StrapdownSensors { noise },
            priors,
            ideal,
            path,
            imu_rate_hz,
            measurement_rate_hz,
        })
    }

    /// The truth model.
    pub fn model(&self) -> &Arc<StrapdownModel> {
        &self.model
    }
    /// The trajectory.
    pub fn trajectory(&self) -> &Arc<Trajectory> {
        &self.trajectory
    }
    /// The noise settings.
    pub fn noise(&self) -> &NoiseConfig {
        &self.noise
    }
    /// The sensors, with the truth's noise.
    pub fn sensors(&self) -> &StrapdownSensors {
        &self.sensors
    }
    /// The prior of every state (the navigation states are the path's: fixed).
    pub fn priors(&self) -> &[Prior] {
        &self.priors
    }
    /// The IMU's sample rate, Hz.
    pub fn imu_rate_hz(&self) -> f64 {
        self.imu_rate_hz
    }
    /// The odometer's and GPS's rate, Hz.
    pub fn measurement_rate_hz(&self) -> f64 {
        self.measurement_rate_hz
    }

    /// The true biases of run `run`: every prior is drawn, fixed ones too, so that fixing
    /// one leaves the others' draws unchanged.
    pub fn coefficients(&self, seed: u64, run: u64) -> Vec<f64> {
        let mut rng = stream(seed, run, Purpose::Coefficients);
        self.priors
            .iter()
            .skip(NAV_DIM)
            .map(|p| p.mean + p.sigma * rng.sample::<f64, _>(StandardNormal))
            .collect()
    }

    /// Simulates run `run` of study seed `seed`.
    pub fn run(&self, seed: u64, run: u64) -> SimulatedRun {
        let constants = self.coefficients(seed, run);
        let bias = |i: usize| constants[i - NAV_DIM];
        let h = 1.0 / self.imu_rate_hz;
        let sg = (self.noise.gyro_psd / h).sqrt();
        let sa = (self.noise.accel_psd / h).sqrt();
        let mut rng = stream(seed, run, Purpose::ProcessNoise);
        let inputs: Vec<InputSample> = self
            .ideal
            .iter()
            .map(|(t, r)| {
                let mut read = *r;
                for a in 0..3 {
                    let (ng, na): (f64, f64) =
                        (rng.sample(StandardNormal), rng.sample(StandardNormal));
                    read.w[a] += bias(BG_X + a) + sg * ng;
                    read.f[a] += bias(BA_X + a) + sa * na;
                }
                InputSample {
                    t: *t,
                    f: input_of(&read),
                }
            })
            .collect();
        let mut rng = stream(seed, run, Purpose::MeasurementNoise);
        let mut truth = Truth {
            names: self.model.state_names(),
            t: Vec::with_capacity(self.path.len()),
            states: Vec::with_capacity(self.path.len()),
        };
        let mut measurements = Vec::with_capacity(self.path.len());
        for (j, (t, nav)) in self.path.iter().enumerate() {
            let mut x = nav.to_vec();
            x.extend_from_slice(&constants);
            truth.t.push(*t);
            truth.states.push(x);
            if j == 0 {
                continue;
            }
            let speed = self.trajectory.state(*t).speed;
            let sig = self.noise.measurement_sigmas(speed.abs(), nav[LAT]);
            let e: [f64; 5] = std::array::from_fn(|_| rng.sample(StandardNormal));
            // A wheel that does not turn counts nothing: at a standstill the odometer reads
            // exactly zero, and the zero-velocity update's reading gets the floor's noise.
            let still = speed == 0.0;
            let floor = self.noise.odometer_floor;
            let nhc = self
                .noise
                .nhc_m_s
                .filter(|_| !still)
                .map(|s| [s * e[3], s * e[4]]);
            let zupt = still.then(|| [floor * e[3], floor * e[4]]);
            measurements.push(Measurement {
                t: *t,
                velocity: None,
                speed: Some(if still { 0.0 } else { speed + sig[0] * e[0] }),
                nhc,
                zupt,
                position_deg: Some([
                    (nav[LAT] + sig[2] * e[1]).to_degrees(),
                    (nav[LON] + sig[3] * e[2]).to_degrees(),
                ]),
            });
        }
        SimulatedRun {
            run,
            measurements,
            truth,
            inputs: Arc::new(inputs),
        }
    }
}

impl StrapdownSimulator {
    /// Run `run` as a dataset named `name`, with `[initial]` the way a recording states it:
    /// the true first attitude off by the unit's own alignment error, drawn with one-sigma
    /// `level_rad` (roll and pitch) and `heading_rad` (heading), which `[prior]` states.
    ///
    /// The files cannot hold the constraint's and the zero-velocity update's readings that a
    /// study's runs draw ([`Measurement::nhc`]): a recording's are zero, and so are a written
    /// dataset's. Its vehicle then has no sideslip at all, less than its `nhc_m_s` says.
    pub fn dataset(
        &self,
        name: &str,
        seed: u64,
        run: &SimulatedRun,
        level_rad: f64,
        heading_rad: f64,
    ) -> Dataset {
        let mut rng = stream(seed, run.run, Purpose::InitialState);
        let mut draw = |sigma: f64| sigma * rng.sample::<f64, _>(StandardNormal);
        let x0 = &run.truth.states[0];
        let initial = InitialAttitude {
            roll_deg: (x0[ROLL] + draw(level_rad)).to_degrees(),
            pitch_deg: (x0[PITCH] + draw(level_rad)).to_degrees(),
            heading_deg: (x0[HEADING] + draw(heading_rad)).to_degrees(),
        };
        let measurements = run
            .measurements
            .iter()
            .map(|m| Measurement {
                nhc: None,
                zupt: None,
                ..*m
            })
            .collect();
        Dataset {
            name: name.to_string(),
            inputs: run.inputs.to_vec(),
            measurements,
            noise: self.noise,
            noise_stated: true,
            prior: PlatformPrior {
                level_rad: Some(level_rad),
                azimuth_rad: Some(heading_rad),
                coefficients: Default::default(),
            },
            provenance: Some(Provenance {
                seed: Some(seed),
                run: Some(run.run),
                effects: Vec::new(),
                note: Some(format!(
                    "navkf strapdown simulation: the truth is the path; IMU readings at {} Hz, \
                     odometer and GPS at {} Hz",
                    self.imu_rate_hz, self.measurement_rate_hz
                )),
            }),
            truth: Some(run.truth.clone()),
            model: ModelKind::Strapdown,
            initial: Some(initial),
        }
    }
}

/// `r` when it is a whole number >= 1 (to 1e-9).
fn whole(r: f64) -> Option<usize> {
    (r >= 1.0 && (r - r.round()).abs() < 1e-9).then(|| r.round() as usize)
}
