//! The strapdown family (docs/model.md, "The strapdown family", "Strapdown effects") as the
//! diagnosis sees it: the catalogue of [`StrapdownRegistry`] at a MEMS unit's sizes, the
//! odometer's speed, the GPS fix, the non-holonomic constraint and the zero-velocity update
//! as channels, and a filter that starts from the dataset's `[initial]` attitude or, without
//! one, from the attitude the data give ([`Dataset::align_from_data`]).
//!
//! A bias instability is the family's noise-only term: its one parameter, as the diagnosis
//! fits it, is the density `q = 2 sigma^2 / T` of its white noise, at the correlation time
//! `T` of its declaration (docs/model.md eq. (69)).

use super::{first_full_measurement, Catalogue, Channel, ChannelKind, EffectInfo, Start};
use crate::error::DiagnoseError;
use crate::start_attitude::{AttitudeSource, StartAttitude};
use navkf_dynamics::dataset::{Dataset, Measurement};
use navkf_dynamics::earth::WIE;
use navkf_dynamics::strapdown::effect_list::StrapdownEffectList;
use navkf_dynamics::strapdown::effects::{StrapdownEffect, StrapdownRegistry};
use navkf_dynamics::strapdown::errors::ErrorLayout;
use navkf_dynamics::strapdown::model::{StrapdownModel, MEAS_DIM};
use navkf_dynamics::strapdown::sensors::StrapdownSensors;
use navkf_dynamics::strapdown::state::*;
use navkf_dynamics::strapdown::unit_class::UnitClass;
use navkf_dynamics::trajectory::{phase_thresholds as thresholds, Phase};
use navkf_dynamics::{
    Attitude, FamilyModel, InputWindow, MeasurementModel, ModelKind, NoiseConfig,
};
use std::collections::BTreeMap;
use std::sync::Arc;

/// A heading's one-sigma when `[initial]` states the heading but `[prior]` not its sigma, rad:
/// 2 deg, a heading taken from a GPS track.
pub const STATED_HEADING_SIGMA: f64 = 0.035;

/// A level's one-sigma when `[prior]` does not state it, rad: the tilt that levelling on the
/// accelerometers leaves, the unit class's accelerometer bias over g.
pub fn stated_level_sigma(class: UnitClass) -> f64 {
    class.errors().accel_bias / navkf_dynamics::earth::STANDARD_GRAVITY
}

/// The span, centred on an update, whose mean rate about up and whose odometer speeds
/// ([`speed_slope`]) file the update under a motion phase, s. The body's sway about its path
/// (sideslip and bounce, at most a degree or so, with content below about 1.5 Hz) averages
/// out over it: a sideslip of 0.6 deg that reverses within it yaws the body at 0.3 deg/s on
/// average, below the 1 deg/s of a turn. A real turn of the path lasts longer.
pub const PHASE_WINDOW_S: f64 = 4.0;

/// The along-track acceleration about `t`, m/s^2: the least-squares slope of the odometer's
/// speeds within `half` seconds either side; `None` with fewer than two readings there, or
/// readings less than `half` apart.
///
/// Not the forward specific force: the body's bounce pitches it by `theta`, which puts
/// `g theta` into that force (0.18 m/s^2 rms at a bounce of 0.3 m/s, still 0.07 averaged over
/// [`PHASE_WINDOW_S`], against the 0.1 m/s^2 of an acceleration), while the speed along the
/// body hardly changes with it. The odometer's noise (centimetres a second) leaves the slope
/// of a few readings within millimetres a second squared.
fn speed_slope(measurements: &[Measurement], t: f64, half: f64) -> Option<f64> {
    let from = measurements.partition_point(|m| m.t < t - half);
    let to = measurements.partition_point(|m| m.t <= t + half);
    let near = || {
        measurements[from..to.max(from)]
            .iter()
            .filter_map(|m| m.speed.filter(|v| v.is_finite()).map(|v| (m.t, v)))
    };
    let (n, st, sv) = near().fold((0.0, 0.0, 0.0), |(n, st, sv), (t, v)| {
        (n + 1.0, st + t, sv + v)
    });
    if n < 2.0 {
        return None;
    }
    let (tm, vm) = (st / n, sv / n);
    let (stt, stv) = near().fold((0.0, 0.0), |(stt, stv), (t, v)| {
        (stt + (t - tm) * (t - tm), stv + (t - tm) * (v - vm))
    });
    // Spread below a quarter of the window: the readings are too close to tell a slope.
    (stt >= n * (0.25 * half) * (0.25 * half)).then(|| stv / stt)
}

/// The strapdown catalogue at the sizes of a unit class (MEMS unless set).
#[derive(Debug, Clone, Default)]
pub struct StrapdownCatalogue {
    /// The effects by name.
    pub registry: StrapdownRegistry,
    /// The unit's class: the typical sizes of its biases and effects.
    pub class: UnitClass,
    /// The attitude at the first IMU row with its tilt sigmas, found once for the dataset
    /// the catalogue was made for ([`StrapdownCatalogue::for_dataset`]): the alignment from
    /// the data scans every reading, and every fit of a diagnosis starts from it.
    aligned: Option<([f64; 3], [f64; 2])>,
}

const CHANNELS: [Channel; MEAS_DIM] = [
    Channel {
        name: "speed",
        title: "odometer speed",
        kind: ChannelKind::Velocity,
    },
    Channel {
        name: "L",
        title: "latitude L, as metres north of the first fix",
        kind: ChannelKind::Latitude,
    },
    Channel {
        name: "lambda",
        title: "longitude lambda, as metres east of the first fix",
        kind: ChannelKind::Longitude,
    },
    Channel {
        name: "nhc_lateral",
        title: "constraint: lateral velocity (zero)",
        kind: ChannelKind::Constraint,
    },
    Channel {
        name: "nhc_vertical",
        title: "constraint: vertical velocity (zero)",
        kind: ChannelKind::Constraint,
    },
    Channel {
        name: "zupt_east",
        title: "at a standstill: east velocity (zero)",
        kind: ChannelKind::Constraint,
    },
    Channel {
        name: "zupt_north",
        title: "at a standstill: north velocity (zero)",
        kind: ChannelKind::Constraint,
    },
];

impl StrapdownCatalogue {
    /// The MEMS catalogue for `ds`, its start attitude found once (a catalogue made with
    /// `default()` finds it at every fit, for whatever dataset it is given).
    pub fn for_dataset(ds: &Dataset) -> Self {
        let mut c = StrapdownCatalogue::default();
        c.aligned = c.initial(ds).ok();
        c
    }

    /// The attitude at the first IMU row and the tilt sigmas that go with it: `[initial]`
    /// with `[prior]`'s sigmas, or the alignment from the data.
    fn initial(&self, ds: &Dataset) -> Result<([f64; 3], [f64; 2]), DiagnoseError> {
        if let Some(a) = self.aligned {
            return Ok(a);
        }
        let start = StartAttitude::try_of(ds)?;
        let sigmas = match start.source {
            AttitudeSource::Stated => [
                ds.prior
                    .level_rad
                    .unwrap_or_else(|| stated_level_sigma(self.class)),
                ds.prior.azimuth_rad.unwrap_or(STATED_HEADING_SIGMA),
            ],
            AttitudeSource::Aligned {
                level_sigma_rad,
                heading_sigma_rad,
                ..
            } => [level_sigma_rad, heading_sigma_rad],
        };
        Ok((start.angles_rad(), sigmas))
    }
}

/// The family's channels.
pub fn channels() -> &'static [Channel] {
    &CHANNELS
}

impl Catalogue for StrapdownCatalogue {
    fn kind(&self) -> ModelKind {
        ModelKind::Strapdown
    }
    fn effect_names(&self) -> Vec<String> {
        self.registry
            .names()
            .into_iter()
            .map(String::from)
            .collect()
    }
    fn effect(&self, name: &str) -> Result<EffectInfo, DiagnoseError> {
        let e = self.registry.get(name)?;
        Ok(EffectInfo {
            description: e.description.to_string(),
            coefficients: e.coefficients.iter().map(|c| c.name.to_string()).collect(),
            units: e.coefficients.iter().map(|c| c.unit.to_string()).collect(),
            bounds: e.coefficients.iter().map(|c| c.bound).collect(),
            noise_density: e.instability.map(|law| {
                let sigma = law.sigma_for(self.class);
                2.0 * sigma * sigma / law.time_s
            }),
        })
    }
    fn model(
        &self,
        effects: &[String],
        parameters: &BTreeMap<String, f64>,
        noise: &NoiseConfig,
        attitude: Attitude,
    ) -> Result<Arc<dyn FamilyModel>, DiagnoseError> {
        if attitude != Attitude::SmallAngle {
            return Err(DiagnoseError::Data(
                "--attitude: the platform's choice; the strapdown family's attitude equations \
                 are exact Euler angles (docs/model.md eqs. (53)-(55)), expected no --attitude"
                    .into(),
            ));
        }
        let mut list = StrapdownEffectList::default();
        for name in effects {
            let effect = self.registry.get(name)?.clone();
            if let (Some(law), Some(&density)) = (effect.instability, parameters.get(name)) {
                // q = 2 sigma^2 / T at the declared T.
                let sigma = (density * law.time_s / 2.0).sqrt();
                list.parameters
                    .insert(law.parameter_names[1].to_string(), sigma);
            }
            list.effects.push(effect);
        }
        Ok(Arc::new(
            StrapdownModel::base(noise)
                .with_unit(self.class.errors())
                .with_effects(&list, self.class, 1.0)?,
        ))
    }
    fn sensors(
        &self,
        noise: NoiseConfig,
    ) -> Box<dyn MeasurementModel<Record = Measurement> + Sync> {
        Box::new(StrapdownSensors { noise })
    }
    fn channels(&self) -> &'static [Channel] {
        &CHANNELS
    }
    fn nav_dim(&self) -> usize {
        NAV_DIM
    }
    fn tilt_names(&self) -> [&'static str; 2] {
        ["level_rad", "heading_rad"]
    }
    fn start_attitude(&self, ds: &Dataset) -> Option<StartAttitude> {
        StartAttitude::of(ds)
    }
    fn default_tilt(&self, ds: &Dataset, _start_lat: f64) -> [f64; 2] {
        let level = stated_level_sigma(self.class);
        self.initial(ds)
            .map_or([level, STATED_HEADING_SIGMA], |(_, sigma)| sigma)
    }
    /// Level to 3 deg, ten times a MEMS unit's levelling on its accelerometer bias; heading to
    /// 45 deg, where `studies/strapdown-heading.toml` finds every filter leaving its bound (a
    /// widened heading of 200 deg, which the platform's factors gave, made a hidden odometer
    /// scale look partly explained).
    fn widest_tilt(&self) -> [f64; 2] {
        [3f64.to_radians(), 45f64.to_radians()]
    }
    fn base_coefficients(&self) -> Vec<(String, f64)> {
        let unit = self.class.errors();
        (NAV_DIM..BASE_DIM)
            .map(|i| {
                let sigma = if i < BA_X {
                    unit.gyro_bias
                } else {
                    unit.accel_bias
                };
                (STATE_NAMES[i].to_string(), sigma)
            })
            .collect()
    }
    /// At the first row with both odometer and GPS: the initial attitude, its heading turned
    /// by what the z gyro read since the first IMU row (a level unit's `psi' = -w_z`; the bias
    /// over that time is within the heading's prior for the usual second or two), the
    /// velocity along the heading at the odometer's speed, and the fix.
    fn start(
        &self,
        ds: &Dataset,
        noise: &NoiseConfig,
        [level, azimuth]: [f64; 2],
    ) -> Result<Start, DiagnoseError> {
        let (m0, p0) = first_full_measurement(ds)?;
        let ([roll, pitch, heading0], _) = self.initial(ds)?;
        // The heading at the start: the initial one turned by what the z gyro read less the
        // Earth's rate about the vertical (a level unit's psi' = -(w_z - wie sinL)), its
        // sigma grown by the gyro bias over that time: a record whose first full fix comes
        // minutes after its first reading would otherwise claim its heading to the
        // alignment's sigma (a MEMS unit's 50 deg/h turns it 17 deg in twenty minutes). The
        // stand-in tests never start a filter mid-record here: they restart coefficients
        // mid-pass, or resume a second half from the first half's navigation state.
        let first = ds.inputs.first().map_or(m0.t, |s| s.t);
        let up_rate = WIE * p0[0].sin();
        let mut turned = 0.0;
        for pair in ds.inputs.windows(2).take_while(|p| p[1].t <= m0.t) {
            let w_z = 0.5 * (pair[0].f[2] + pair[1].f[2]);
            turned -= (w_z - up_rate) * (pair[1].t - pair[0].t);
        }
        let heading = heading0 + turned;
        let gyro_bias = ds
            .prior
            .coefficients
            .get("bgz")
            .copied()
            .unwrap_or(self.class.errors().gyro_bias);
        let azimuth = azimuth.hypot(gyro_bias * (m0.t - first));
        let speed = m0.speed.unwrap_or(0.0);
        let sig = noise.measurement_sigmas(speed.abs(), p0[0]);
        let v_sigma = sig[0].hypot(speed.abs() * azimuth);
        let x = vec![
            roll,
            pitch,
            heading,
            speed * heading.sin(),
            speed * heading.cos(),
            p0[0],
            p0[1],
        ];
        let sigma = vec![level, level, azimuth, v_sigma, v_sigma, sig[2], sig[3]];
        Ok(Start { t: m0.t, x, sigma })
    }
    /// The sensors' four and the tolerances of the constraint and of the zero-velocity update,
    /// each its own: what the moving vehicle's sideways and vertical velocities and the
    /// standing vehicle's velocity really are, which a stated `nhc_m_s` and `zupt_m_s` only
    /// guess (a recording's zeros left pessimistic make the likelihood reward whatever shrinks
    /// the predicted variance).
    fn noise_sources(&self) -> usize {
        6
    }
    /// What the horizontal model cannot inform, whose estimates a filter's own linearisation
    /// drifts whatever the truth, so that the likelihood rewards them for the drift (see
    /// docs/model.md, "What the horizontal model cannot see: the vertical accelerometer bias"): `baz`
    /// and the z accelerometer's scale and cross-axis terms, which act on the vertical force
    /// the model does not integrate, and the x and y gyros' scales, which a drive about the
    /// vertical never exercises. The widening followed `baz`'s drift to 4.8 m/s^2; on clean MEMS drives
    /// `accel-scale` was decisive at s_az = 1.3 and `gyro-scale` at s_gy = 0.4, never naming
    /// (no real sensor's), but outranking what a run did hold; `accel-misalignment` at
    /// m_azx = 3.1 beside a hidden x accelerometer scale.
    fn pinned(&self) -> &'static [&'static str] {
        &["baz", "s_az", "m_azx", "m_azy", "s_gx", "s_gy"]
    }
    /// From the odometer's speed and the readings over [`PHASE_WINDOW_S`] about the update:
    /// the forward force (accelerating, decelerating) and the rate about up (turning). Over
    /// the step's own readings (a tenth of a second at 10 Hz), the body's sway is what they
    /// measure: its sideslip yaws it at degrees a second and its bounce pitches gravity into
    /// the forward force, so 13 % of the updates a drive's path took straight at a steady
    /// speed were filed as turning or accelerating, picked for the sway that also makes their
    /// constraint rows large (test `a_bodys_sway_is_not_filed_as_turning`).
    fn phase(&self, ds: &Dataset, window: &InputWindow, m: &Measurement) -> Phase {
        let Some(speed) = m.speed else {
            return Phase::Cruising;
        };
        if speed.abs() < thresholds::STILL_SPEED {
            return Phase::Standstill;
        }
        let half = 0.5 * PHASE_WINDOW_S;
        let inputs = &ds.inputs;
        let from = inputs.partition_point(|s| s.t < m.t - half);
        let to = inputs.partition_point(|s| s.t <= m.t + half);
        // Readings sparser than the window: the step's own.
        let (turn, force, count) = if to > from + 1 {
            inputs[from..to]
                .iter()
                .fold((0.0, 0.0, 0.0), |(w, a, n), s| {
                    (w + s.f[2], a + s.f[3], n + 1.0)
                })
        } else {
            window.f.iter().fold((0.0, 0.0, 0.0), |(w, a, n), f| {
                (w + f[2], a + f[3], n + 1.0)
            })
        };
        let count = f64::max(count, 1.0);
        let along = speed_slope(&ds.measurements, m.t, half).unwrap_or(force / count);
        crate::consistency::moving_phase(turn / count, along)
    }
    fn cannot_join(&self, effects: &[String], candidate: &str) -> Option<String> {
        let list: Vec<StrapdownEffect> = effects
            .iter()
            .chain(std::iter::once(&candidate.to_string()))
            .filter_map(|e| self.registry.get(e).ok().cloned())
            .collect();
        ErrorLayout::new(&list, |_| 1.0).err()
    }
    fn with_rival(&self) -> Option<(Box<dyn Catalogue>, &'static str, f64)> {
        None
    }
    /// The strapdown catalogue holds its look-alikes itself (`gps-lever-arm` beside
    /// `gps-latency`): the contest of the round weighs them.
    fn with_structured_rival(&self, _effect: &str) -> Option<(Box<dyn Catalogue>, &'static str)> {
        None
    }
}
