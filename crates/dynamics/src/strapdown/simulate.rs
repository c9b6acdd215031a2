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
//! filters meet the error they are told of, as they do for every other sensor. A file has no
//! column for those readings, so a simulator whose runs are written to files moves the body
//! itself instead ([`StrapdownSimulator::with_body_motion`], [`super::body_motion`]): the
//! heading and pitch of the truth and the readings are then the turned body's
//! ([`body_state`], [`body_reading`], docs/model.md, "A written dataset's body moves").
//!
//! Every draw comes from [`crate::rng::stream`]: the biases from `Coefficients`, the reading
//! noise from `ProcessNoise`, the odometer and GPS noise from `MeasurementNoise`.

use super::attitude::{body_to_nav, euler_of, rotate_back};
use super::body_motion::{BodyMotion, BodyOffsets, MAX_SIGMA_M_S};
use super::errors::{measurement_with, reading_with_errors, vehicle_axes, ErrorLayout, Wander};
use super::model::{StrapdownModel, MEAS_DIM};
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

/// The true navigation state of the rigid vehicle at `st`: level, heading along the path.
pub fn path_state(st: &PathState) -> [f64; NAV_DIM] {
    body_state(st, &BodyOffsets::default())
}

/// The true navigation state of a body turned by `off` from the rigid vehicle on the path
/// at `st` ([`super::body_motion`]): the path's velocity and position, the body's attitude.
pub fn body_state(st: &PathState, off: &BodyOffsets) -> [f64; NAV_DIM] {
    let heading = st.heading + off.heading;
    [
        0.0, off.pitch, heading, st.v[0], st.v[1], st.pos[0], st.pos[1],
    ]
}

/// The error-free reading of a level unit on the path at `st` (module documentation).
pub fn ideal_reading(st: &PathState) -> ImuReading {
    body_reading(st, &BodyOffsets::default())
}

/// The error-free reading of the unit on a body turned by `off` from the rigid vehicle on
/// the path at `st` ([`super::body_motion`]); [`ideal_reading`] when `off` is zero.
pub fn body_reading(st: &PathState, off: &BodyOffsets) -> ImuReading {
    let c = body_to_nav([0.0, off.pitch, st.heading + off.heading]);
    let (sl, cl) = st.pos[0].sin_cos();
    let (rm, rn) = (meridian_radius(sl), prime_vertical_radius(sl));
    let [ve, vn] = st.v;
    let w_in = [-vn / rm, WIE * cl + ve / rn, WIE * sl + ve * sl / cl / rn];
    let w_in_b = rotate_back(&c, w_in);
    // The body's rate relative to n at roll 0, from its pitch and heading rates (eqs.
    // (53)-(55) solved for the rate): forward -psi' sin(theta), left -theta', up
    // -psi' cos(theta). Heading counts clockwise from North: a turn to the right is a
    // negative rate about up.
    let turn = st.turn_rate + off.heading_rate;
    let (sp, cp) = off.pitch.sin_cos();
    ImuReading {
        w: [
            w_in_b[0] - turn * sp,
            w_in_b[1] - off.pitch_rate,
            w_in_b[2] - turn * cp,
        ],
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
    /// Measurement times and the true navigation state there (the vehicle's: its unit's
    /// when no mounting effect turns the two apart).
    path: Vec<(f64, [f64; NAV_DIM])>,
    /// IMU samples per measurement.
    per_measurement: usize,
    imu_rate_hz: f64,
    measurement_rate_hz: f64,
    /// The root-mean-square body velocity of each run's sideslip and bounce, m/s
    /// ([`StrapdownSimulator::with_body_motion`]); `None`: a rigid vehicle.
    body_motion: Option<f64>,
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
                i => model
                    .coefficient_sigma(i)
                    .map_or(Prior::fixed(0.0), Prior::zero_mean),
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
            // The biases' bounds (and their departures') are the platform's drift and
            // accelerometer bias; an effect's, its own.
            let bound = match i {
                i if i < BA_X || GYRO_DEPARTURE_NAMES.contains(&name.as_str()) => {
                    Some(crate::sensor_classes::GYRO_DRIFT)
                }
                i if i < BASE_DIM || ACCEL_DEPARTURE_NAMES.contains(&name.as_str()) => {
                    Some(crate::sensor_classes::ACCEL_BIAS)
                }
                _ => model
                    .effects()
                    .iter()
                    .flat_map(|e| e.coefficients.iter())
                    .find(|c| c.name == name)
                    .map(|c| c.bound),
            };
            if let Some(b) = bound.filter(|b| !(b.contains(p.mean) && b.contains(p.sigma))) {
                return Err(cfg_err(
                    &key,
                    format!(
                        "mean {} sigma {}: beyond what a real instrument gives ({})",
                        p.mean, p.sigma, b.reason
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
            per_measurement,
            imu_rate_hz,
            measurement_rate_hz,
            body_motion: None,
        })
    }

    /// The simulator with each run's vehicle body sliding and pitching about its path
    /// ([`super::body_motion`]), its lateral and vertical body velocities of root-mean-square
    /// `sigma_m_s` when cruising, drawn per run. The runs then carry no drawn constraint
    /// readings ([`Measurement::nhc`]): the truth carries the motion, as a recording's does.
    /// A rigid vehicle's constraint holds exactly, which no car's does; a dataset meant for
    /// files wants this, with the sigma its `nhc_m_s` states. `sigma_m_s` must be in
    /// `(0, MAX_SIGMA_M_S]` ([`super::body_motion::MAX_SIGMA_M_S`]): a rigid vehicle is the
    /// simulator without this call.
    pub fn with_body_motion(mut self, sigma_m_s: f64) -> Result<Self, DynamicsError> {
        if !(sigma_m_s > 0.0 && sigma_m_s <= MAX_SIGMA_M_S) {
            return Err(cfg_err(
                "truth.body_motion_m_s",
                format!(
                    "{sigma_m_s}: expected a velocity > 0 and at most {MAX_SIGMA_M_S} m/s rms \
                     (a car's sideslip is centimetres a second)"
                ),
            ));
        }
        self.body_motion = Some(sigma_m_s);
        Ok(self)
    }

    /// Run `run`'s body motion, if any.
    fn motion_of(&self, seed: u64, run: u64) -> Option<BodyMotion> {
        self.body_motion.map(|sigma| {
            let mut rng = stream(seed, run, Purpose::Other(BODY_MOTION));
            BodyMotion::draw(sigma, self.trajectory.duration(), &mut rng)
        })
    }

    /// The vehicle's navigation state at `t` under `motion`.
    fn vehicle_at(&self, motion: Option<&BodyMotion>, t: f64) -> [f64; NAV_DIM] {
        let st = self.trajectory.state(t);
        match motion {
            None => path_state(&st),
            Some(m) => body_state(&st, &m.offsets(t, &st)),
        }
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
        let layout = self.model.layout();
        // The state's constant part, the biases' departures updated as they wander (drawn at
        // the start from their steady law).
        let mut x = vec![0.0; NAV_DIM];
        x.extend_from_slice(&constants);
        let dynamic_end = BASE_DIM + layout.departures();
        let mount = vehicle_axes(layout, &x);
        let h = 1.0 / self.imu_rate_hz;
        let sg = (self.noise.gyro_psd / h).sqrt();
        let sa = (self.noise.accel_psd / h).sqrt();
        let wander = self.bias_laws(h);
        let mut rng = stream(seed, run, Purpose::ProcessNoise);
        let mut walk = stream(seed, run, Purpose::Other(BIAS_WALK));
        let motion = self.motion_of(seed, run);
        let mut biases = Vec::with_capacity(self.path.len());
        let mut inputs: Vec<InputSample> = Vec::with_capacity(self.ideal.len());
        for (k, (t, ideal)) in self.ideal.iter().enumerate() {
            if k % self.per_measurement == 0 {
                biases.push(x[BG_X..dynamic_end].to_vec());
            }
            let mut truth = match &motion {
                None => *ideal,
                Some(m) => {
                    let st = self.trajectory.state(*t);
                    body_reading(&st, &m.offsets(*t, &st))
                }
            };
            if let Some(m) = &mount {
                truth.w = rotate_back(m, truth.w);
                truth.f = rotate_back(m, truth.f);
            }
            let mut read = if layout.has_reading_errors() {
                reading_with_errors(layout, &truth, &x)
            } else {
                truth
            };
            let departure = |w: Option<Wander>, a: usize| w.map_or(0.0, |w| x[w.first + a]);
            for a in 0..3 {
                let (ng, na): (f64, f64) = (rng.sample(StandardNormal), rng.sample(StandardNormal));
                read.w[a] += x[BG_X + a] + departure(layout.gyro_wander, a) + sg * ng;
                read.f[a] += x[BA_X + a] + departure(layout.accel_wander, a) + sa * na;
            }
            inputs.push(InputSample {
                t: *t,
                f: input_of(&read),
            });
            // docs/model.md eq. (69), exact over the sample interval.
            for &(first, decay, step_sigma) in &wander {
                for d in &mut x[first..first + 3] {
                    *d = decay * *d + step_sigma * walk.sample::<f64, _>(StandardNormal);
                }
            }
        }
        let mut rng = stream(seed, run, Purpose::MeasurementNoise);
        let mut truth = Truth {
            names: self.model.state_names(),
            t: Vec::with_capacity(self.path.len()),
            states: Vec::with_capacity(self.path.len()),
        };
        let mut measurements = Vec::with_capacity(self.path.len());
        let effects = &constants[dynamic_end - NAV_DIM..];
        let unit_state = |nav: &[f64; NAV_DIM], bias: &[f64]| {
            self.unit_state(nav, mount.as_ref(), bias, effects)
        };
        for (j, (t, path_nav)) in self.path.iter().enumerate() {
            let moved;
            let nav = match &motion {
                None => path_nav,
                Some(m) => {
                    moved = self.vehicle_at(Some(m), *t);
                    &moved
                }
            };
            let state = unit_state(nav, &biases[j]);
            truth.t.push(*t);
            truth.states.push(state.clone());
            if j == 0 {
                continue;
            }
            let speed = self.trajectory.state(*t).speed;
            let sig = self.noise.measurement_sigmas(speed.abs(), nav[LAT]);
            let e: [f64; 5] = std::array::from_fn(|_| rng.sample(StandardNormal));
            // A wheel that does not turn counts nothing: at a standstill the odometer reads
            // exactly zero, and the zero-velocity update's reading gets its stated noise (the
            // odometer's floor unless `zupt_m_s` says otherwise).
            let still = speed == 0.0;
            let floor = self.noise.zupt_sigma();
            // A moving body carries its sideslip and bounce itself and stands exactly still:
            // its readings are zero, as a recording's.
            let nhc = self
                .noise
                .nhc_m_s
                .filter(|_| !still && motion.is_none())
                .map(|s| [s * e[3], s * e[4]]);
            let zupt = (still && motion.is_none()).then(|| [floor * e[3], floor * e[4]]);
            // The odometer reads the forward speed: the path's, unless the body is turned.
            let (odometer, position) = if layout.has_measurement_errors() || motion.is_some() {
                let earlier = |t: f64| unit_state(&self.vehicle_at(motion.as_ref(), t), &biases[j]);
                self.read_aids(layout, *t, &state, earlier)
            } else {
                (speed, [nav[LAT], nav[LON]])
            };
            measurements.push(Measurement {
                t: *t,
                velocity: None,
                speed: Some(if still { 0.0 } else { odometer + sig[0] * e[0] }),
                nhc,
                zupt,
                position_deg: Some([
                    (position[0] + sig[2] * e[1]).to_degrees(),
                    (position[1] + sig[3] * e[2]).to_degrees(),
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

    /// For each triad (gyro, accelerometer) whose biases wander: the first of its departure
    /// states, the decay over one sample interval `h` and the sigma of the step's draw,
    /// `exp(-h/T)` and `sigma sqrt(1 - exp(-2h/T))` (the discrete form of
    /// docs/model.md eq. (69)).
    fn bias_laws(&self, h: f64) -> Vec<(usize, f64, f64)> {
        let steady = |first: usize| {
            self.model
                .noise_channels()
                .iter()
                .find(|c| c.state == first)
                .map_or(0.0, |c| c.psd)
        };
        self.model
            .layout()
            .wanders()
            .map(|w| {
                // psd = 2 sigma^2 / T.
                let sigma = (steady(w.first) / (2.0 * w.decay)).sqrt();
                let phi = (-h * w.decay).exp();
                (w.first, phi, sigma * (1.0 - phi * phi).sqrt())
            })
            .collect()
    }

    /// The unit's full true state where the vehicle's navigation state is `nav`, its biases
    /// `bias` and its effects' coefficients `effects`.
    fn unit_state(
        &self,
        nav: &[f64; NAV_DIM],
        mount: Option<&[[f64; 3]; 3]>,
        bias: &[f64],
        effects: &[f64],
    ) -> Vec<f64> {
        let mut state = self.unit_navigation(nav, mount).to_vec();
        state.extend_from_slice(bias);
        state.extend_from_slice(effects);
        state
    }

    /// The unit's navigation state where the vehicle's is `nav`: the same but for the
    /// attitude, turned by the mounting (`C_b^n = C_v^n A`, `A` the rows of
    /// [`vehicle_axes`]).
    fn unit_navigation(
        &self,
        nav: &[f64; NAV_DIM],
        mount: Option<&[[f64; 3]; 3]>,
    ) -> [f64; NAV_DIM] {
        let Some(a) = mount else { return *nav };
        let c_vn = body_to_nav([nav[ROLL], nav[PITCH], nav[HEADING]]);
        let c_bn: [[f64; 3]; 3] = std::array::from_fn(|i| {
            std::array::from_fn(|j| (0..3).map(|k| c_vn[i][k] * a[k][j]).sum())
        });
        let [roll, pitch, heading] = euler_of(&c_bn);
        [roll, pitch, heading, nav[V_E], nav[V_N], nav[LAT], nav[LON]]
    }

    /// The odometer's and the GPS's error-free readings at `t` with the effects of `layout`:
    /// the model's measurement of the true state, but for the latency, which the truth takes
    /// exactly (the position `tau` seconds before, with the lever arm of that time) where the
    /// model takes it to first order.
    fn read_aids(
        &self,
        layout: &ErrorLayout,
        t: f64,
        state: &[f64],
        earlier: impl Fn(f64) -> Vec<f64>,
    ) -> (f64, [f64; 2]) {
        let mut z = [0.0; MEAS_DIM];
        measurement_with(layout, state, &mut z);
        let speed = z[0];
        if let Some((i, factor)) = layout.latency_entry() {
            let before = (t - factor * state[i]).max(0.0);
            let mut then = earlier(before);
            then[i] = 0.0;
            measurement_with(layout, &then, &mut z);
        }
        (speed, [z[1], z[2]])
    }
}

/// The [`Purpose::Other`] stream of the biases' Gauss-Markov draws.
const BIAS_WALK: u32 = 69;
/// The [`Purpose::Other`] stream of the body's sideslip and bounce.
const BODY_MOTION: u32 = 70;

impl StrapdownSimulator {
    /// Run `run` as a dataset named `name`, with `[initial]` the way a recording states it:
    /// the true first attitude off by the unit's own alignment error, drawn with one-sigma
    /// `level_rad` (roll and pitch) and `heading_rad` (heading), which `[prior]` states.
    ///
    /// The files cannot hold the constraint's and the zero-velocity update's readings that a
    /// study's runs draw ([`Measurement::nhc`]): a recording's are zero, and so are a written
    /// dataset's. A rigid vehicle then has no sideslip at all, less than its `nhc_m_s` says;
    /// a simulator [`StrapdownSimulator::with_body_motion`] gives its vehicle the motion that
    /// sigma stands for.
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
                effects: self
                    .model
                    .effects()
                    .iter()
                    .map(|e| e.name.to_string())
                    .collect(),
                note: Some(format!(
                    "navkf strapdown simulation: the truth is the path; IMU readings at {} Hz, \
                     odometer and GPS at {} Hz",
                    self.imu_rate_hz, self.measurement_rate_hz
                )),
            }),
            truth: Some(run.truth.clone()),
            model: ModelKind::Strapdown,
            initial: Some(initial),
            // The declarations of the user's effects in the truth: the folder reads back
            // with them known.
            effects: self.model.declarations(),
        }
    }
}

impl StrapdownSimulator {
    /// [`StrapdownSimulator::dataset`] with the run's constraint and zero-velocity readings
    /// kept ([`Measurement::nhc`], [`Measurement::zupt`]): the dataset as the study's filters
    /// meet it, which no file holds. A diagnosis measured on it meets the vehicle its stated
    /// `nhc_m_s` describes.
    pub fn dataset_with_readings(
        &self,
        name: &str,
        seed: u64,
        run: &SimulatedRun,
        level_rad: f64,
        heading_rad: f64,
    ) -> Dataset {
        let mut ds = self.dataset(name, seed, run, level_rad, heading_rad);
        for (m, r) in ds.measurements.iter_mut().zip(&run.measurements) {
            m.nhc = r.nhc;
            m.zupt = r.zupt;
        }
        ds
    }
}

/// `r` when it is a whole number >= 1 (to 1e-9).
fn whole(r: f64) -> Option<usize> {
    (r >= 1.0 && (r - r.round()).abs() < 1e-9).then(|| r.round() as usize)
}
