//! What `navkf simulate` reads around the simulator: the test to drive, from a TOML file.

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
