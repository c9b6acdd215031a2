//! An output folder written all-or-nothing, and never over a user's files.
//!
//! A command's outputs go into a fresh sibling folder, `.<name>.navkf-partial-<pid>`, whose
//! first file is its marker ([`marker`]: the kind of folder, the command and navkf's
//! version). [`ResultsDir::commit`] lists every file written in the marker and swaps the
//! folder into place: the old folder, if any, is renamed to `.<name>.navkf-old-<pid>`, the
//! new one takes its name, and the old one is removed. So a run that fails, panics or is
//! interrupted leaves the old complete folder (or none) and never a mix of new and old
//! files. An error or a panic removes the staging folder (`Drop`), Ctrl-C too
//! ([`live::abandon_all`]); a killed process leaves it, clearly named, and the next run into
//! the same place removes it when its process is gone.
//!
//! What may be replaced is decided before the work starts, in [`ResultsDir::begin`]: a new
//! path, an empty folder, or a folder of the same kind that navkf made and that holds nothing
//! its marker does not list. Anything else is refused, whatever files it holds: a user's
//! folder, the dataset being diagnosed, a folder holding a file the user added. A symbolic
//! link is followed to the folder it names (the link stays, and points at the new results);
//! a link to nothing is refused. The old folder must also be one this process can delete,
//! which is probed up front, so a run does not compute for an hour and then fail to put its
//! results in place.

pub mod live;
pub mod marker;

use crate::error::ReportError;
use marker::{FolderKind, Marker, Ownership};
use std::path::{Path, PathBuf};

/// The marker of a results folder.
pub const MARKER: &str = ".navkf-results";

/// An output folder being written: write into [`ResultsDir::path`], then
/// [`ResultsDir::commit`].
///
/// ```
/// use navkf_report::ResultsDir;
/// let out = std::env::temp_dir().join(format!("navkf-doc-results-{}", std::process::id()));
/// # // Removed however the example ends: it must not litter /tmp.
/// # struct Cleanup(std::path::PathBuf);
/// # impl Drop for Cleanup {
/// #     fn drop(&mut self) {
/// #         let _ = std::fs::remove_dir_all(&self.0);
/// #     }
/// # }
/// # let _cleanup = Cleanup(out.clone());
/// let staged = ResultsDir::begin(&out).unwrap();
/// std::fs::write(staged.path().join("report.md"), "new").unwrap();
/// assert!(!out.exists(), "nothing is in place before the commit");
/// staged.commit().unwrap();
/// assert_eq!(std::fs::read_to_string(out.join("report.md")).unwrap(), "new");
/// // The user adds a file: the folder is no longer navkf's alone, and is not replaced.
/// std::fs::write(out.join("notes.txt"), "mine").unwrap();
/// let refused = ResultsDir::begin(&out).unwrap_err().to_string();
/// assert!(refused.contains("`notes.txt`, which navkf did not write"), "{refused}");
/// ```
#[derive(Debug)]
pub struct ResultsDir {
    /// The folder as the user named it (for messages).
    target: PathBuf,
    /// The folder it resolves to (a link at its end followed).
    resolved: PathBuf,
    staging: PathBuf,
    marker: Marker,
    /// Other kinds of folder it may replace.
    also: Vec<FolderKind>,
    committed: bool,
}

impl ResultsDir {
    /// A results folder at `target`: see [`ResultsDir::begin_kind`].
    pub fn begin(target: &Path) -> Result<Self, ReportError> {
        Self::begin_kind(target, FolderKind::Results, &[])
    }

    /// Checks `target` and opens a fresh staging folder beside it, its marker written first.
    /// Refused before any work: a file, `.` or `..`, a link to nothing, a folder that is not
    /// navkf's folder of `kind` (or of one of `also`) or holds anything its marker does not
    /// list, an old folder this process could not delete, or a place where no folder can be
    /// written.
    pub fn begin_kind(
        target: &Path,
        kind: FolderKind,
        also: &[FolderKind],
    ) -> Result<Self, ReportError> {
        let other = ReportError::Folder;
        folder_name(target).map_err(other)?;
        let resolved = marker::resolve_link(target).map_err(other)?;
        check_replaceable(&resolved, kind, also).map_err(other)?;
        let parent = parent_of(&resolved);
        std::fs::create_dir_all(&parent).map_err(io(&parent))?;
        let real_name = folder_name(&resolved).map_err(other)?;
        remove_abandoned(&parent, &real_name);
        let staging = parent.join(format!(".{real_name}.navkf-partial-{}", std::process::id()));
        if staging.exists() {
            std::fs::remove_dir_all(&staging).map_err(io(&staging))?;
        }
        std::fs::create_dir(&staging).map_err(io(&staging))?;
        live::register(&staging, &resolved);
        let staged = ResultsDir {
            target: target.to_path_buf(),
            resolved,
            staging,
            marker: Marker::new(kind),
            also: also.to_vec(),
            committed: false,
        };
        staged.write_marker(&staged.staging)?;
        Ok(staged)
    }

    /// Where to write the outputs until the commit.
    pub fn path(&self) -> &Path {
        &self.staging
    }

    /// The folder the results will have once committed, as the user named it.
    pub fn target(&self) -> &Path {
        &self.target
    }

    /// Moves the files of the folder in place whose names `keep` accepts into the new one
    /// (`merge` keeps the shard files it read), unless the new one has the same name.
    pub fn carry_over(&self, keep: impl Fn(&str) -> bool) -> Result<(), ReportError> {
        let Ok(entries) = std::fs::read_dir(&self.resolved) else {
            return Ok(());
        };
        for e in entries.flatten() {
            let name = e.file_name().to_string_lossy().into_owned();
            let to = self.staging.join(&name);
            if keep(&name) && !to.exists() && e.file_type().is_ok_and(|t| t.is_file()) {
                std::fs::copy(e.path(), &to).map_err(io(&e.path()))?;
            }
        }
        Ok(())
    }

    /// Lists the files written in the marker, swaps the new folder into place and removes
    /// the old one. If the folder in place changed during the run so that it is no longer
    /// navkf's alone, nothing is replaced and the error says so.
    pub fn commit(mut self) -> Result<(), ReportError> {
        self.marker.files = marker::entries_below(&self.staging).map_err(io(&self.staging))?;
        self.write_marker(&self.staging)?;
        let old = self.resolved.with_file_name(format!(
            ".{}.navkf-old-{}",
            folder_name(&self.resolved).map_err(ReportError::Folder)?,
            std::process::id()
        ));
        let mut live = live::lock();
        // A user may have written into the old folder while the run computed.
        check_replaceable(&self.resolved, self.marker.kind, &self.also).map_err(|e| {
            ReportError::Folder(format!(
                "{e} (it changed during the run; the new results were not put in place)"
            ))
        })?;
        let had_old = self.resolved.exists();
        if had_old {
            if old.exists() {
                std::fs::remove_dir_all(&old).map_err(io(&old))?;
            }
            std::fs::rename(&self.resolved, &old).map_err(io(&self.resolved))?;
        }
        if let Err(source) = std::fs::rename(&self.staging, &self.resolved) {
            if had_old {
                // Put the old folder back: the run leaves what it found.
                let _ = std::fs::rename(&old, &self.resolved);
            }
            return Err(ReportError::Io {
                path: self.target.clone(),
                source,
            });
        }
        self.committed = true;
        live::forget_locked(&mut live, &self.staging);
        drop(live);
        if had_old {
            std::fs::remove_dir_all(&old).map_err(|source| {
                ReportError::Folder(format!(
                    "{}: the new results are in place, but the old ones, moved to {}, could \
                     not be removed ({source}); remove that folder by hand",
                    self.target.display(),
                    old.display()
                ))
            })?;
        }
        Ok(())
    }

    fn write_marker(&self, dir: &Path) -> Result<(), ReportError> {
        let path = dir.join(self.marker.kind.marker_name());
        std::fs::write(&path, self.marker.to_json()).map_err(io(&path))
    }
}

impl Drop for ResultsDir {
    fn drop(&mut self) {
        if !self.committed {
            let mut live = live::lock();
            let _ = std::fs::remove_dir_all(&self.staging);
            live::forget_locked(&mut live, &self.staging);
        }
    }
}

/// The last component of `path`, which names the folder: not `.` or `..`.
fn folder_name(path: &Path) -> Result<String, String> {
    path.file_name()
        .filter(|n| *n != "." && *n != "..")
        .map(|n| n.to_string_lossy().into_owned())
        .ok_or_else(|| {
            format!(
                "{}: expected a folder name for the output, not `.` or `..`",
                path.display()
            )
        })
}

fn parent_of(path: &Path) -> PathBuf {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

fn io(path: &Path) -> impl FnOnce(std::io::Error) -> ReportError {
    let path = path.to_path_buf();
    move |source| ReportError::Io { path, source }
}

/// Whether a folder of `kind` may be written at `dir` (a link already resolved): nothing
/// there, or a folder [`marker::ownership`] gives to navkf, which this process can delete.
pub fn check_replaceable(dir: &Path, kind: FolderKind, also: &[FolderKind]) -> Result<(), String> {
    let meta = match std::fs::symlink_metadata(dir) {
        Ok(m) => m,
        Err(_) => return Ok(()),
    };
    if !meta.is_dir() {
        return Err(format!(
            "{}: exists and is not a folder; expected a folder for the output (or a path that \
             does not exist yet)",
            dir.display()
        ));
    }
    if let Ownership::Ours(_) = marker::ownership(dir, kind, also)? {
        probe_deletable(dir)?;
    }
    Ok(())
}

/// Checks that every folder in `dir` (itself included) lets this process remove its
/// entries, by creating and removing a file in each: the permission bits alone do not say
/// (root ignores them; ACLs and read-only mounts add to them).
fn probe_deletable(dir: &Path) -> Result<(), String> {
    let probe = dir.join(format!("{}{}", marker::PROBE_PREFIX, std::process::id()));
    if let Err(e) = std::fs::write(&probe, b"") {
        return Err(format!(
            "{}: navkf made this folder, but cannot replace it ({e}); the new results could \
             not be put in place: make it writable, or choose another output folder",
            dir.display()
        ));
    }
    let _ = std::fs::remove_file(&probe);
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Ok(());
    };
    for e in entries.flatten() {
        if e.file_type().is_ok_and(|t| t.is_dir()) {
            probe_deletable(&e.path())?;
        }
    }
    Ok(())
}

/// Checks, without creating anything, that a folder can be made at `dir` (a link at its end
/// already resolved): its nearest existing ancestor is a folder this process can write in.
pub fn check_creatable(dir: &Path) -> Result<(), String> {
    let mut at = dir.to_path_buf();
    loop {
        match std::fs::metadata(&at) {
            Ok(m) if m.is_dir() => break,
            Ok(_) => {
                return Err(format!(
                    "{}: {} is not a folder; expected a path where a folder can be made",
                    dir.display(),
                    at.display()
                ))
            }
            Err(_) => match at.parent() {
                Some(p) if !p.as_os_str().is_empty() => at = p.to_path_buf(),
                _ => {
                    at = PathBuf::from(".");
                    break;
                }
            },
        }
    }
    let probe = at.join(format!("{}{}", marker::PROBE_PREFIX, std::process::id()));
    std::fs::write(&probe, b"").map_err(|e| {
        format!(
            "{}: cannot write in {} ({e}); expected a place where a folder can be made",
            dir.display(),
            at.display()
        )
    })?;
    let _ = std::fs::remove_file(&probe);
    Ok(())
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

/// The folder the shards of a study write into. Several shards share it (on a cluster,
/// at once), each adding its `partial-I-of-N.json` and removing nothing, so it is not
/// staged; it must be new, empty, or a shard folder navkf made.
#[derive(Debug)]
pub struct ShardFolder {
    dir: PathBuf,
}

impl ShardFolder {
    /// Checks `dir` before the work starts, creating nothing: a refused run leaves no
    /// folder behind.
    pub fn check(dir: &Path) -> Result<Self, ReportError> {
        let other = ReportError::Folder;
        folder_name(dir).map_err(other)?;
        let resolved = marker::resolve_link(dir).map_err(other)?;
        match std::fs::symlink_metadata(&resolved) {
            Err(_) => check_creatable(&resolved).map_err(other)?,
            Ok(m) if !m.is_dir() => {
                return Err(other(format!(
                    "{}: exists and is not a folder; expected a folder for the shard files (or \
                     a path that does not exist yet)",
                    dir.display()
                )))
            }
            Ok(_) => {
                // Shards add files and remove none: a user's file beside them is safe, but
                // the folder must be one navkf made for shards (or empty).
                if Marker::read(&resolved, FolderKind::Shards)
                    .map_err(other)?
                    .is_none()
                {
                    marker::ownership(&resolved, FolderKind::Shards, &[]).map_err(other)?;
                }
                check_creatable(&resolved.join("x")).map_err(other)?;
            }
        }
        Ok(ShardFolder { dir: resolved })
    }

    /// Writes the shard file `name` (atomically), creating the folder and its marker if
    /// they are not there yet; returns its path.
    pub fn write(&self, name: &str, bytes: &[u8]) -> Result<PathBuf, ReportError> {
        std::fs::create_dir_all(&self.dir).map_err(io(&self.dir))?;
        let kind = FolderKind::Shards;
        if Marker::read(&self.dir, kind)
            .map_err(ReportError::Folder)?
            .is_none()
        {
            crate::atomic_write::write_atomic(
                &self.dir.join(kind.marker_name()),
                Marker::new(kind).to_json().as_bytes(),
            )?;
        }
        let path = self.dir.join(name);
        crate::atomic_write::write_atomic(&path, bytes)?;
        Ok(path)
    }
}
