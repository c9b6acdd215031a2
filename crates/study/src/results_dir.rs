//! A results folder written all-or-nothing.
//!
//! A command's outputs go into a fresh sibling folder, `.<name>.navkf-partial-<pid>`, and
//! [`ResultsDir::commit`] swaps it into place once every file is written: the old folder, if
//! any, is renamed to `.<name>.navkf-old-<pid>`, the new one takes its name, and the old one
//! is removed. So a run that fails, panics or is interrupted leaves the old complete folder
//! (or none) and never a mix of new and old files. An error or a panic removes the partial
//! folder (see `Drop`); a killed process leaves it, clearly named, and the next run into the
//! same place removes it when its process is gone.
//!
//! An existing folder is replaced only if it holds results: the marker file
//! [`MARKER`] (written into every committed folder), or a results file of a version that
//! wrote none (`summary.json`, `diagnosis.json`, `plan.json`, `designs.json`, `sweep.json`).
//! Anything else (`--out .`, `--out ~/data`) is refused before the work starts.

use crate::error::StudyError;
use std::path::{Path, PathBuf};

/// The file that marks a folder as a navkf results folder, safe to replace.
pub const MARKER: &str = ".navkf-results";

/// Results files of versions that wrote no marker.
const RESULTS_FILES: [&str; 5] = [
    "summary.json",
    "diagnosis.json",
    "plan.json",
    "designs.json",
    "sweep.json",
];

/// A results folder being written: write into [`ResultsDir::path`], then
/// [`ResultsDir::commit`].
///
/// ```
/// use navkf_study::output::ResultsDir;
/// let out = std::env::temp_dir().join(format!("navkf-doc-results-{}", std::process::id()));
/// let staged = ResultsDir::begin(&out).unwrap();
/// std::fs::write(staged.path().join("report.md"), "new").unwrap();
/// assert!(!out.exists(), "nothing is in place before the commit");
/// staged.commit().unwrap();
/// assert_eq!(std::fs::read_to_string(out.join("report.md")).unwrap(), "new");
/// # std::fs::remove_dir_all(&out).unwrap();
/// ```
#[derive(Debug)]
pub struct ResultsDir {
    target: PathBuf,
    staging: PathBuf,
    committed: bool,
}

impl ResultsDir {
    /// Checks `target` and opens a fresh staging folder beside it: refused if `target` is a
    /// file, a folder that holds something other than results, or a place where no folder
    /// can be written.
    pub fn begin(target: &Path) -> Result<Self, StudyError> {
        let other = |message: String| StudyError::Other(message);
        let name = target
            .file_name()
            .filter(|n| *n != "." && *n != "..")
            .ok_or_else(|| {
                other(format!(
                    "{}: expected a folder name for the results, not `.` or `..`",
                    target.display()
                ))
            })?
            .to_string_lossy()
            .into_owned();
        if target.exists() {
            if !target.is_dir() {
                return Err(other(format!(
                    "{}: exists and is not a folder; expected a folder for the results (or a path that does not exist yet)",
                    target.display()
                )));
            }
            if !holds_results(target) {
                return Err(other(format!(
                    "{}: a folder that holds something other than navkf results (no {MARKER} file); the results replace the whole folder, so expected a new path or an earlier results folder",
                    target.display()
                )));
            }
        }
        let parent = match target.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        };
        let io = |path: &Path| {
            let path = path.to_path_buf();
            move |source| StudyError::Io { path, source }
        };
        std::fs::create_dir_all(&parent).map_err(io(&parent))?;
        remove_abandoned(&parent, &name);
        let staging = parent.join(format!(".{name}.navkf-partial-{}", std::process::id()));
        if staging.exists() {
            std::fs::remove_dir_all(&staging).map_err(io(&staging))?;
        }
        std::fs::create_dir(&staging).map_err(io(&staging))?;
        Ok(ResultsDir {
            target: target.to_path_buf(),
            staging,
            committed: false,
        })
    }

    /// Where to write the outputs until the commit.
    pub fn path(&self) -> &Path {
        &self.staging
    }

    /// The folder the results will have once committed.
    pub fn target(&self) -> &Path {
        &self.target
    }

    /// Moves the files of the folder in place whose names `keep` accepts into the new one
    /// (`merge` keeps the shard files it read), unless the new one has the same name.
    pub fn carry_over(&self, keep: impl Fn(&str) -> bool) -> Result<(), StudyError> {
        let Ok(entries) = std::fs::read_dir(&self.target) else {
            return Ok(());
        };
        for e in entries.flatten() {
            let name = e.file_name().to_string_lossy().into_owned();
            let to = self.staging.join(&name);
            if keep(&name) && !to.exists() && e.path().is_file() {
                std::fs::copy(e.path(), &to).map_err(|source| StudyError::Io {
                    path: e.path(),
                    source,
                })?;
            }
        }
        Ok(())
    }

    /// Swaps the new folder into place and removes the old one.
    pub fn commit(mut self) -> Result<(), StudyError> {
        let io = |path: &Path| {
            let path = path.to_path_buf();
            move |source| StudyError::Io { path, source }
        };
        std::fs::write(self.staging.join(MARKER), b"").map_err(io(&self.staging))?;
        let old = self.target.with_file_name(format!(
            ".{}.navkf-old-{}",
            self.target
                .file_name()
                .expect("checked in begin")
                .to_string_lossy(),
            std::process::id()
        ));
        let had_old = self.target.exists();
        if had_old {
            if old.exists() {
                std::fs::remove_dir_all(&old).map_err(io(&old))?;
            }
            std::fs::rename(&self.target, &old).map_err(io(&self.target))?;
        }
        if let Err(source) = std::fs::rename(&self.staging, &self.target) {
            if had_old {
                // Put the old folder back: the run leaves what it found.
                let _ = std::fs::rename(&old, &self.target);
            }
            return Err(StudyError::Io {
                path: self.target.clone(),
                source,
            });
        }
        self.committed = true;
        if had_old {
            std::fs::remove_dir_all(&old).map_err(io(&old))?;
        }
        Ok(())
    }
}

impl Drop for ResultsDir {
    fn drop(&mut self) {
        if !self.committed {
            let _ = std::fs::remove_dir_all(&self.staging);
        }
    }
}

/// Whether `dir` holds navkf results (or nothing): its marker, a results file of an earlier
/// version, or shard files.
fn holds_results(dir: &Path) -> bool {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return false;
    };
    let mut empty = true;
    for e in entries.flatten() {
        empty = false;
        let name = e.file_name().to_string_lossy().into_owned();
        let shard = name.starts_with("partial-") && name.ends_with(".json");
        if name == MARKER || RESULTS_FILES.contains(&name.as_str()) || shard {
            return true;
        }
    }
    empty
}

/// Removes the staging and old folders of `name` left by processes that no longer run
/// (killed before they could clean up). Where it cannot tell (no `/proc`), it leaves them.
fn remove_abandoned(parent: &Path, name: &str) {
    if !Path::new("/proc/self").exists() {
        return;
    }
    let Ok(entries) = std::fs::read_dir(parent) else {
        return;
    };
    for e in entries.flatten() {
        let file = e.file_name().to_string_lossy().into_owned();
        let pid = [".navkf-partial-", ".navkf-old-"].iter().find_map(|kind| {
            file.strip_prefix(&format!(".{name}{kind}"))
                .and_then(|p| p.parse::<u32>().ok())
        });
        if let Some(pid) = pid {
            if pid != std::process::id() && !Path::new(&format!("/proc/{pid}")).exists() {
                let _ = std::fs::remove_dir_all(e.path());
            }
        }
    }
}
