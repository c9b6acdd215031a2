//! Datasets: the folder layout of `docs/data-format.md` (inputs.csv, measurements.csv,
//! optional dataset.toml with its `[noise]`, `[prior]` and `[simulation]` tables, and
//! truth.csv), read with validation and written atomically.
//!
//! Positions are kept in degrees, exactly as in the file (except that a track crossing the
//! antimeridian is made continuous), so that a dataset written and read back is
//! bit-identical; [`Measurement::gps_rad`] converts for the filters.

pub mod alignment;
mod family;
mod implausibility;
mod implausible;
pub mod kitti;
mod limits;
mod plausibility;
mod read;
mod series;
mod strapdown_plausibility;
mod summary;
mod write;

pub use family::{files_of, FamilyFiles, Odometer};
pub use implausibility::{Implausibility, JumpShape};
pub use implausible::noise_beyond_sensors;
pub use limits::{
    latitude_limit_deg, FALL_FRACTION, GNSS_FLOOR_M, OVERLOAD_G, POLE_DISTANCE_M, SCATTER_SIGMAS,
    SPEED_MARGIN, SUSTAINED_S,
};
pub use plausibility::{DataWarning, Doubt};
pub use summary::{
    DatasetSummary, Extent, Gap, Gaps, IntervalStats, Span, SpeedProfile, Stream, TruthSummary,
    TurnProfile, GAP_FACTOR, MIN_HEADING_SPEED, STILL_SPEED, TURN_RATE_DEG_S,
};

use crate::kinematics::Input;
use crate::noise::NoiseConfig;
use crate::prior::PlatformPrior;
use serde::{Deserialize, Serialize};

/// The file of input samples (required).
pub const INPUTS_FILE: &str = "inputs.csv";
/// The file of measurements (required).
pub const MEASUREMENTS_FILE: &str = "measurements.csv";
/// The file of noise and provenance (optional).
pub const CONFIG_FILE: &str = "dataset.toml";
/// The file of true states (optional).
pub const TRUTH_FILE: &str = "truth.csv";
/// The header of `inputs.csv`, exactly.
pub const INPUT_COLUMNS: [&str; 4] = ["t", "f_e", "f_n", "f_u"];
/// The header of `measurements.csv`, exactly.
pub const MEASUREMENT_COLUMNS: [&str; 5] = ["t", "v_e", "v_n", "lat_deg", "lon_deg"];
/// The strapdown family's file of IMU readings (required there, instead of `inputs.csv`).
pub const IMU_FILE: &str = "imu.csv";
/// The header of `imu.csv` holding rates: body rate (rad/s) and specific force (m/s^2),
/// forward-left-up axes, each the reading at `t`.
pub const IMU_RATE_COLUMNS: [&str; 7] = ["t", "w_x", "w_y", "w_z", "f_x", "f_y", "f_z"];
/// The header of `imu.csv` holding increments: angle (rad) and velocity (m/s) over the
/// interval that ends at `t`.
pub const IMU_INCREMENT_COLUMNS: [&str; 7] = [
    "t", "dtheta_x", "dtheta_y", "dtheta_z", "dv_x", "dv_y", "dv_z",
];
/// The header of a strapdown dataset's `measurements.csv`: odometer speed and GPS.
pub const SPEED_MEASUREMENT_COLUMNS: [&str; 4] = ["t", "speed", "lat_deg", "lon_deg"];

/// `[initial]` of a strapdown dataset: the unit's attitude at the first IMU row's time, from
/// the recording's own alignment, degrees (any heading; reports use (-180, 180]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InitialAttitude {
    /// Roll, right side down positive, deg.
    pub roll_deg: f64,
    /// Pitch, nose up positive, deg.
    pub pitch_deg: f64,
    /// Heading from North, clockwise, deg.
    pub heading_deg: f64,
}

/// One row of `inputs.csv`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InputSample {
    /// Time, s.
    pub t: f64,
    /// Specific force `[f_e, f_n, f_u]`, m/s^2.
    pub f: Input,
}

/// One row of `measurements.csv`; a sensor that gave nothing is `None`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Measurement {
    /// Time, s.
    pub t: f64,
    /// Odometer velocity `[v_e, v_n]`, m/s (the platform family's odometer).
    pub velocity: Option<[f64; 2]>,
    /// Odometer speed along the vehicle's forward axis, signed, m/s (the strapdown family's
    /// odometer, docs/model.md eq. (59)).
    pub speed: Option<f64>,
    /// The vehicle's lateral and vertical velocity that the non-holonomic constraint reads
    /// as its measurement, m/s (docs/model.md eq. (60)): zero in a recording, where the
    /// constraint asserts them; the strapdown simulator draws them with the stated
    /// `nhc_m_s`, the sideslip and bounce that sigma stands for, which its path (a rigid
    /// vehicle on its road) does not have. `None`: zero.
    pub nhc: Option<[f64; 2]>,
    /// The vehicle's East and North velocity that the zero-velocity update reads at a
    /// standstill (a speed of exactly zero), m/s: zero in a recording; drawn by the simulator
    /// with the odometer's floor sigma, as `nhc`. `None`: zero.
    pub zupt: Option<[f64; 2]>,
    /// GPS `[lat_deg, lon_deg]`, degrees.
    pub position_deg: Option<[f64; 2]>,
}

impl Measurement {
    /// The odometer's speed, m/s, unsigned: the East-North velocity's magnitude (platform) or
    /// the forward speed (strapdown); `None` without an odometer reading.
    pub fn odometer_speed(&self) -> Option<f64> {
        self.velocity
            .map(|v| v[0].hypot(v[1]))
            .or(self.speed.map(f64::abs))
    }

    /// GPS position in radians.
    pub fn gps_rad(&self) -> Option<[f64; 2]> {
        self.position_deg
            .map(|[a, b]| [a.to_radians(), b.to_radians()])
    }
}

impl Dataset {
    /// The specific force of input sample `s`, m/s^2, in the frame of the family's inputs
    /// ([`FamilyFiles::specific_force`]): the platform's navigation-frame `[f_e, f_n, f_u]`,
    /// the strapdown unit's body-frame `[f_x, f_y, f_z]`.
    pub fn specific_force(&self, s: &InputSample) -> [f64; 3] {
        files_of(self.model).specific_force(s)
    }
}

/// `truth.csv`: the true state at some times (only a simulation knows it).
#[derive(Debug, Clone, PartialEq)]
pub struct Truth {
    /// State names, the columns after `t` (docs/model.md's names, then effect coefficients).
    pub names: Vec<String>,
    /// Times, s.
    pub t: Vec<f64>,
    /// One state vector per time, `names.len()` long.
    pub states: Vec<Vec<f64>>,
}

/// What `dataset.toml` records besides noise: how a simulated dataset was made.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Provenance {
    /// The seed of the study / simulation.
    #[serde(default)]
    pub seed: Option<u64>,
    /// The run index within the study.
    #[serde(default)]
    pub run: Option<u64>,
    /// The effects the truth carried.
    #[serde(default)]
    pub effects: Vec<String>,
    /// Free text.
    #[serde(default)]
    pub note: Option<String>,
}

/// A dataset in memory.
#[derive(Debug, Clone, PartialEq)]
pub struct Dataset {
    /// The folder's name (used for default output paths).
    pub name: String,
    /// Input samples, strictly increasing in time.
    pub inputs: Vec<InputSample>,
    /// Measurements, strictly increasing in time, inside the inputs' span.
    pub measurements: Vec<Measurement>,
    /// Noise (defaults where `dataset.toml` is absent or silent).
    pub noise: NoiseConfig,
    /// Whether `dataset.toml` has a `[noise]` table: without one, `noise` is navkf's default
    /// (navigation grade), which reports must not call the user's statement.
    pub noise_stated: bool,
    /// `[prior]` table of dataset.toml: what the user states of the platform before the
    /// record (empty when absent; [`crate::prior`] gives the defaults).
    pub prior: PlatformPrior,
    /// `[simulation]` table of dataset.toml, when present.
    pub provenance: Option<Provenance>,
    /// `truth.csv`, when present.
    pub truth: Option<Truth>,
    /// The model family (`[model] kind`; the platform when absent). A strapdown dataset's
    /// inputs are the unit's readings (body rate, then specific force) and its odometer
    /// measures the forward speed ([`Measurement::speed`]).
    pub model: crate::model_kind::ModelKind,
    /// `[initial]`: the strapdown unit's first attitude, when the dataset states it.
    pub initial: Option<InitialAttitude>,
    /// `[[effect]]` tables of dataset.toml: effects the user declared
    /// ([`crate::declared`]), known to every command that reads the folder.
    pub effects: Vec<crate::declared::EffectDeclaration>,
}
