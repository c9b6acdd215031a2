//! What a caller asks [`super::simulate`] for, and what a family makes of it: kept apart
//! from the folder-writing code so that the families (`crate::family`), which build the
//! simulator, depend on the request and not on the code that calls them.

use navkf_dynamics::dataset::Dataset;
use navkf_dynamics::declared::EffectDeclaration;
use navkf_dynamics::model_kind::ModelKind;
use navkf_dynamics::{Attitude, TrajectoryConfig};
/// What a caller asks `simulate` for; `None` takes the family's default.
#[derive(Debug, Clone, Default)]
pub struct SimulationRequest {
    /// The model family.
    pub model: ModelKind,
    /// Seed of the random streams.
    pub seed: u64,
    /// Run index within the seed's family of runs.
    pub run: u64,
    /// Effects the truth carries (`gyro-fz,odometer-scale=0.002,Ka0x=1e-3`).
    pub effects: String,
    /// Effects declared without Rust that `effects` may name (of the request's family).
    pub declarations: Vec<EffectDeclaration>,
    /// The test to drive.
    pub trajectory: TrajectoryConfig,
    /// The truth's attitude equations (the platform's choice; small-angle when `None`).
    pub attitude: Option<Attitude>,
    /// Initial azimuth (platform) or heading (strapdown) error, one sigma, rad.
    pub azimuth_sigma: Option<f64>,
    /// Write the truth file.
    pub truth: bool,
    /// The strapdown unit's class (`navigation`, `tactical`, `mems`).
    pub unit: Option<String>,
    /// The strapdown unit's sample rate, Hz.
    pub imu_rate_hz: Option<f64>,
    /// The non-holonomic constraint's sigma stated in dataset.toml, m/s (strapdown).
    pub nhc_sigma: Option<f64>,
    /// The root-mean-square lateral and vertical body velocity of the vehicle's sideslip
    /// and bounce, m/s (strapdown; `None`: the constraint's sigma; 0: a rigid vehicle).
    pub body_motion_m_s: Option<f64>,
}

/// A simulator with its settings checked, ready to run: given the dataset's name, the seed
/// and the run, the dataset and a line saying what it holds.
pub(crate) type Ready = Box<dyn FnOnce(&str, u64, u64) -> (Dataset, String)>;
