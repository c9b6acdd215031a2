//! `navkf.simulate`: the command line's `navkf simulate`, the same checks and the same
//! dataset bit for bit ([`navkf_study::simulation`]), returned in memory and, when `out` is
//! given, written there.

use crate::dataset::Dataset;
use crate::errors::OrNavkfError;
use navkf_dynamics::declared::DeclaredFile;
use navkf_dynamics::model_kind::ModelKind;
use navkf_dynamics::TrajectoryConfig;
use navkf_study::simulation::{
    simulate as run, trajectory_from_text, SettingNames, SimulationRequest,
};
use pyo3::prelude::*;
use std::path::PathBuf;

/// See `navkf.simulate` (python/navkf/__init__.py) for the arguments.
#[pyfunction]
#[pyo3(signature = (*, out, seed, run_index, effects, model, trajectory_toml, duration,
    attitude, azimuth_sigma, truth, unit, imu_rate, nhc_sigma, body_motion, effects_file))]
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
    body_motion: Option<f64>,
    effects_file: Option<PathBuf>,
) -> PyResult<Dataset> {
    let model: ModelKind = model.parse().map_err(|_| {
        crate::errors::to_py(&format!(
            "model {model:?}: expected {}",
            ModelKind::expected("\"")
        ))
    })?;
    let declarations = match effects_file {
        Some(path) => {
            let file = DeclaredFile::read(&path).or_py()?;
            file.expect_family(model, "the model simulated (model=)")
                .or_py()?;
            file.declarations().to_vec()
        }
        None => Vec::new(),
    };
    let mut trajectory = match trajectory_toml {
        Some(text) => trajectory_from_text(std::path::Path::new("trajectory"), &text).or_py()?,
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
        declarations,
        trajectory,
        attitude,
        azimuth_sigma,
        truth,
        unit,
        imu_rate_hz: imu_rate,
        nhc_sigma,
        body_motion_m_s: body_motion,
    };
    let written = py
        .detach(|| run(&request, &out, SettingNames::Keywords))
        .or_py()?;
    Ok(Dataset {
        inner: written.dataset,
    })
}
