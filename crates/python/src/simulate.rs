//! `navkf.simulate`: the command line's `navkf simulate`, the same checks and the same
//! dataset bit for bit ([`navkf_study::simulation`]), returned in memory and, when `out` is
//! given, written there.

use crate::dataset::Dataset;
use crate::errors::OrNavkfError;
use navkf_dynamics::model_kind::ModelKind;
use navkf_dynamics::TrajectoryConfig;
use navkf_study::simulation::{simulate as run, SettingNames, SimulationRequest};
use pyo3::prelude::*;
use std::path::PathBuf;

/// See `navkf.simulate` (python/navkf/__init__.py) for the arguments.
#[pyfunction]
#[pyo3(signature = (*, out, seed, run_index, effects, model, trajectory_toml, duration,
    attitude, azimuth_sigma, truth, unit, imu_rate, nhc_sigma))]
#[allow(clippy::too_many_arguments)]
pub fn simulate(
    py: Python<'_>,
    out: PathBuf,
    seed: u64,
    run_index: u64,
    effects: String,
    model: &str,
    trajectory_toml: Option<String>,
    duration: Option<f64>,
    attitude: Option<String>,
    azimuth_sigma: Option<f64>,
    truth: bool,
    unit: Option<String>,
    imu_rate: Option<f64>,
    nhc_sigma: Option<f64>,
) -> PyResult<Dataset> {
    let model = match model {
        "platform" => ModelKind::Platform,
        "strapdown" => ModelKind::Strapdown,
        other => {
            return Err(crate::errors::to_py(&format!(
                "model {other:?}: expected \"platform\" or \"strapdown\""
            )))
        }
    };
    let mut trajectory = match trajectory_toml {
        Some(text) => trajectory_from_toml(&text)?,
        None => TrajectoryConfig::default(),
    };
    if let Some(d) = duration {
        trajectory.duration_s = d;
    }
    let attitude = attitude
        .map(|a| a.parse::<navkf_dynamics::Attitude>())
        .transpose()
        .map_err(|e| crate::errors::to_py(&format!("attitude: {e}")))?;
    let request = SimulationRequest {
        model,
        seed,
        run: run_index,
        effects,
        declarations: Vec::new(),
        trajectory,
        attitude,
        azimuth_sigma,
        truth,
        unit,
        imu_rate_hz: imu_rate,
        nhc_sigma,
    };
    let written = py
        .detach(|| run(&request, &out, SettingNames::Keywords))
        .or_py()?;
    Ok(Dataset {
        inner: written.dataset,
    })
}

/// The `[trajectory]` table of TOML `text` (a study file's, or one with only that table),
/// checked; errors name the key.
fn trajectory_from_toml(text: &str) -> PyResult<TrajectoryConfig> {
    #[derive(serde::Deserialize)]
    struct TrajectoryFile {
        trajectory: Option<TrajectoryConfig>,
    }
    let file: TrajectoryFile =
        toml::from_str(text).map_err(|e| crate::errors::to_py(&format!("trajectory: {e}")))?;
    let trajectory = file
        .trajectory
        .ok_or_else(|| crate::errors::to_py("trajectory: no [trajectory] table"))?;
    trajectory
        .validate()
        .map_err(|e| crate::errors::to_py(&format!("trajectory: {e}")))?;
    Ok(trajectory)
}
