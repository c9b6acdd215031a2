//! `simulate`: one run of a model family's truth simulator written as a dataset folder, as
//! the `navkf simulate` command and the Python package's `navkf.simulate` both ask for it.
//!
//! It writes only what navkf's own reader accepts, from settings a real unit could have: a
//! fixed coefficient beyond what any real sensor has (`Ka0x=1e300`, `gps-latency=1e6`:
//! [`navkf_dynamics::sensor_classes`]) and a tilt sigma beyond what the attitude equations
//! hold are refused before simulating, naming the setting; the folder is checked before
//! simulating (a new folder, an empty one, or a dataset written before: never a user's
//! folder or a results folder); and the dataset is read back through [`Dataset::read`]
//! before it is put in place, so that a truth driven non-finite or off the Earth is refused,
//! not written.

pub(crate) mod request;

use crate::error::StudyError;
use navkf_dynamics::dataset::Dataset;
use navkf_dynamics::TrajectoryConfig;
pub use navkf_report::SettingNames;
use navkf_report::{FolderKind, ResultsDir};
pub use request::SimulationRequest;
use std::path::Path;

/// What `simulate` wrote: the dataset as navkf reads it back, and a line saying what it holds.
#[derive(Debug)]
pub struct Simulated {
    pub dataset: Dataset,
    pub description: String,
}

/// Simulates `req` into the folder `out` (module documentation); errors name the settings
/// as `names` says.
pub fn simulate(
    req: &SimulationRequest,
    out: &Path,
    names: SettingNames,
) -> Result<Simulated, StudyError> {
    let other = |e: String| StudyError::Other(e);
    for (key, value) in [("seed", req.seed), ("run", req.run)] {
        // dataset.toml records both as TOML integers, which are signed 64-bit.
        if value > i64::MAX as u64 {
            return Err(other(format!(
                "{} {value}: expected 0 to {} (dataset.toml records it as a TOML integer)",
                names.of(key),
                i64::MAX
            )));
        }
    }
    let ready = crate::family::of(req.model).prepare(req, names)?;
    // Checked before simulating: a refused folder costs nothing.
    let staged = ResultsDir::begin_kind(out, FolderKind::Dataset, &[])?;
    let (mut ds, description) = ready(&dataset_name(out), req.seed, req.run);
    if !req.truth {
        ds.truth = None;
    }
    Ok(Simulated {
        dataset: put_in_place(&ds, staged, out, &left_real_values(&req.effects, names))?,
        description,
    })
}

/// Writes `ds` into the folder `out` as [`simulate`] does (a new folder, an empty one, or a
/// dataset written before, replaced whole once `ds` reads back; `out` is left as it was
/// otherwise), and returns it as read back: what any later reader sees, bit for bit.
pub fn write_checked(ds: &Dataset, out: &Path) -> Result<Dataset, StudyError> {
    let staged = ResultsDir::begin_kind(out, FolderKind::Dataset, &[])?;
    put_in_place(ds, staged, out, "it holds a value the reader refuses")
}

/// Why a simulated dataset would not read back: its truth left real values (under the
/// effects the caller gave).
fn left_real_values(effects: &str, names: SettingNames) -> String {
    if effects.trim().is_empty() {
        "the truth left real values".into()
    } else {
        format!(
            "the truth left real values under {} {effects}",
            names.of("effects")
        )
    }
}

/// Writes `ds` into `staged`, reads it back and commits it to `out`; messages name `out` and
/// say `why` a refused read-back happened.
fn put_in_place(
    ds: &Dataset,
    staged: ResultsDir,
    out: &Path,
    why: &str,
) -> Result<Dataset, StudyError> {
    ds.write(staged.path())?;
    let back = Dataset::read(staged.path()).map_err(|e| {
        let e = e.to_string().replace(
            &staged.path().display().to_string(),
            &out.display().to_string(),
        );
        StudyError::Other(format!(
            "the dataset is not one navkf reads back ({e}): {why}; nothing was written"
        ))
    })?;
    staged.commit()?;
    Ok(Dataset {
        name: ds.name.clone(),
        ..back
    })
}

/// The dataset's name: the output folder's last component.
pub fn dataset_name(out: &Path) -> String {
    out.file_name()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "dataset".into())
}

/// The `[trajectory]` table of the TOML file at `path` (a study file, or one with only that
/// table), checked. Anything but a regular file of bounded size is refused unread.
pub fn read_trajectory(path: &Path) -> Result<TrajectoryConfig, StudyError> {
    use navkf_dynamics::input_file::{read_text, TextFile};
    let text = read_text(path, &TextFile::TRAJECTORY)?;
    trajectory_from_text(path, &text)
}

/// The `[trajectory]` table of TOML `text` read from `source`, checked; errors name `source`
/// and the line and column (a parse error) or the key (a value the trajectory refuses).
pub fn trajectory_from_text(source: &Path, text: &str) -> Result<TrajectoryConfig, StudyError> {
    /// The file's other tables (a study file's `[study]`, `[noise]`...) are not read here.
    #[derive(serde::Deserialize)]
    struct TrajectoryFile {
        trajectory: Option<TrajectoryConfig>,
    }
    let file: TrajectoryFile = toml::from_str(text)
        .map_err(|e| navkf_dynamics::input_file::toml_error(source, text, &e))?;
    let trajectory = file.trajectory.ok_or_else(|| {
        StudyError::Other(format!(
            "{}: no [trajectory] table; expected the test to drive there",
            source.display()
        ))
    })?;
    trajectory
        .validate()
        .map_err(|e| StudyError::Other(format!("{}: {e}", source.display())))?;
    Ok(trajectory)
}
