//! What `navkf simulate` does for every model family around its simulator: reading the
//! test to drive from a TOML file, and reading the written dataset back before it is put in
//! place.

use navkf_dynamics::dataset::Dataset;
use std::path::Path;

/// The dataset's name: the output folder's last component.
pub fn dataset_name(out: &Path) -> String {
    out.file_name()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "dataset".into())
}
use navkf_dynamics::TrajectoryConfig;

/// The `[trajectory]` table of the TOML file at `path`, checked; errors name the file and
/// the line and column (a parse error) or the key (a value the trajectory refuses).
/// Anything but a regular file of bounded size is refused unread (`read_text`).
pub fn read_trajectory(
    path: &std::path::Path,
) -> Result<TrajectoryConfig, Box<dyn std::error::Error>> {
    /// The file's other tables (a study file's `[study]`, `[noise]`...) are not read here.
    #[derive(serde::Deserialize)]
    struct TrajectoryFile {
        trajectory: Option<TrajectoryConfig>,
    }
    use navkf_dynamics::input_file::{read_text, toml_error, TextFile};
    let text = read_text(path, &TextFile::TRAJECTORY)?;
    let file: TrajectoryFile = toml::from_str(&text).map_err(|e| toml_error(path, &text, &e))?;
    let trajectory = file.trajectory.ok_or_else(|| {
        format!(
            "{}: no [trajectory] table; expected the test to drive there",
            path.display()
        )
    })?;
    trajectory
        .validate()
        .map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(trajectory)
}

/// Checks that the dataset written in the staging folder `written` reads back through
/// [`Dataset::read`] (every value finite, positions on the Earth, every rule of the data
/// format) before it is put in place at `out`: a truth the settings drove off the Earth is
/// refused, and `out` is left as it was. Messages name `out`, not the staging folder.
pub fn readable(
    written: &std::path::Path,
    out: &std::path::Path,
    effects: &str,
) -> Result<(), String> {
    let checked = Dataset::read(written)
        .map(|_| ())
        .map_err(|e| e.to_string());
    checked.map_err(|e| {
        let e = e.replace(&written.display().to_string(), &out.display().to_string());
        format!(
            "the simulated dataset is not one navkf reads back ({e}): the truth left real \
             values{}; nothing was written",
            if effects.trim().is_empty() {
                String::new()
            } else {
                format!(" under --effects {effects}")
            }
        )
    })
}
