//! Reading a dataset folder, with validation.
//!
//! The files come from users (recorded or simulated elsewhere), so a mistake in them must be
//! fixable without guessing: every error names the file, the 1-based line (the header is
//! line 1), the column and what was expected. Nothing here panics on user input. The checks
//! are the ones of `docs/data-format.md`: exact headers, one cell per column, finite
//! numbers, strictly increasing times, measurements inside the inputs' span, plausible
//! latitude/longitude in degrees, sensor pairs either complete or empty.

use crate::dataset::{
    files_of, Dataset, FamilyFiles, InitialAttitude, InputSample, Measurement, Odometer,
    Provenance, Truth, CONFIG_FILE, IMU_FILE, INPUTS_FILE, INPUT_COLUMNS, MEASUREMENTS_FILE,
    TRUTH_FILE,
};
use crate::earth::{meridian_radius, prime_vertical_radius};
use crate::effects::Registry;
use crate::error::DynamicsError;
use crate::input_file::{
    check_regular, other_encoding, printable, read_text, toml_error, LineLimit, LineTooLong,
    TextFile, CSV_LINE_MAX_BYTES,
};
use crate::model_kind::ModelKind;
use crate::noise::NoiseConfig;
use crate::prior::PlatformPrior;
use crate::state::{BASE_NAMES, NAV_DIM};
use serde::Deserialize;
use std::io::ErrorKind;
use std::path::{Path, PathBuf};

mod config;
mod csv_table;
mod imu;
mod measurements;
mod truth;
mod units;

use config::*;
use csv_table::*;
use measurements::*;
use truth::*;
use units::*;

pub(super) use config::{known_coefficients, strapdown_coefficients};
pub(super) use imu::read_imu;
pub(super) use measurements::read_inputs;
pub(super) use units::{chord_m, odometer_displacement, odometer_east_north};

impl Dataset {
    /// Reads and validates the dataset folder `dir` (`docs/data-format.md`): `inputs.csv` and
    /// `measurements.csv` (required), `dataset.toml` and `truth.csv` (optional). The name is
    /// the folder's final path component. Coefficient names in `[prior.coefficients]` must be
    /// base coefficients or coefficients of the catalogue's effects.
    pub fn read(dir: &Path) -> Result<Dataset, DynamicsError> {
        Self::read_with(dir, &Registry::catalogue())
    }

    /// [`Dataset::read`], knowing the coefficients of `registry`'s effects (a user's own
    /// effects among them) for `[prior.coefficients]`.
    pub fn read_with(dir: &Path, registry: &Registry) -> Result<Dataset, DynamicsError> {
        if !dir.is_dir() {
            return Err(DynamicsError::File {
                path: dir.to_path_buf(),
                message: format!(
                    "not a folder; expected a dataset folder holding {INPUTS_FILE} (or \
                     {IMU_FILE}, a strapdown unit's) and {MEASUREMENTS_FILE}"
                ),
            });
        }
        // dataset.toml first: it says which family's files to read.
        let config_path = dir.join(CONFIG_FILE);
        let (config, known) = if exists(&config_path)? {
            read_config(&config_path, registry)?
        } else {
            let config = ConfigFile::default();
            let known = files_of(config.kind()).declare(&mut registry.clone(), &[])?;
            (config, known)
        };
        let kind = config.kind();
        let files = files_of(kind);
        let state_names: Vec<String> = files
            .navigation_names()
            .iter()
            .map(|s| s.to_string())
            .chain(known)
            .chain(files.other_truth_names().iter().map(|s| s.to_string()))
            .collect();
        let inputs = files.read_inputs(&dir.join(files.inputs_file()))?;
        let measurements = read_measurements(&dir.join(MEASUREMENTS_FILE), &inputs, files)?;
        let truth_path = dir.join(TRUTH_FILE);
        let truth = if exists(&truth_path)? {
            Some(read_truth(
                &truth_path,
                &state_names,
                &inputs,
                files.inputs_file(),
                &measurements,
            )?)
        } else {
            None
        };
        Ok(Dataset {
            name: folder_name(dir),
            inputs,
            measurements,
            noise: config.noise.unwrap_or_default(),
            noise_stated: config.noise.is_some(),
            prior: config.prior,
            provenance: config.simulation,
            truth,
            model: kind,
            initial: config.initial,
            effects: config.effect,
        })
    }
}

/// The folder's final component; for paths like `.` the canonical path's.
fn folder_name(dir: &Path) -> String {
    let named = |p: &Path| p.file_name().map(|n| n.to_string_lossy().into_owned());
    named(dir)
        .or_else(|| dir.canonicalize().ok().and_then(|p| named(&p)))
        .unwrap_or_else(|| "dataset".to_owned())
}

/// Whether an optional file is there (an I/O failure other than "not found" is an error).
fn exists(path: &Path) -> Result<bool, DynamicsError> {
    match std::fs::metadata(path) {
        Ok(_) => Ok(true),
        Err(e) if e.kind() == ErrorKind::NotFound => Ok(false),
        Err(source) => Err(DynamicsError::Io {
            path: path.to_path_buf(),
            source,
        }),
    }
}

fn data_error(path: &Path, line: usize, column: &str, message: String) -> DynamicsError {
    DynamicsError::Data {
        path: path.to_path_buf(),
        line,
        column: printable(column),
        message: printable(&message),
    }
}
