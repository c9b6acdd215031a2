//! The marker that makes a folder navkf's: which command made it, with which version, and
//! every file it wrote.
//!
//! navkf replaces its output folders whole (see [`super::ResultsDir`]), so it must never
//! mistake a user's folder for its own. A folder's name or its files prove nothing: a thesis
//! folder may hold some other tool's `summary.json`, a recorder may leave one beside a
//! dataset. Only the marker does, and only navkf writes it: into the staging folder before
//! any output, then again with the list of files when the folder is committed. A folder is
//! replaced only if it holds the marker of the right kind and nothing the marker does not
//! list, so a file a user drops into a results folder is never deleted with it.

use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// What a navkf folder holds; each kind has a marker file of its own name.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum FolderKind {
    /// A command's results (`study`, `diagnose`, `plan`, `merge`), replaced whole by a rerun.
    Results,
    /// A dataset that `simulate` wrote, replaced whole by a rerun of `simulate`.
    Dataset,
    /// The shard files of `study --shard`: each shard adds its file, none is removed.
    Shards,
}

impl FolderKind {
    /// Every kind.
    pub const ALL: [FolderKind; 3] = [FolderKind::Results, FolderKind::Dataset, FolderKind::Shards];

    /// The marker file's name inside the folder.
    pub fn marker_name(self) -> &'static str {
        match self {
            FolderKind::Results => ".navkf-results",
            FolderKind::Dataset => ".navkf-dataset",
            FolderKind::Shards => ".navkf-shards",
        }
    }

    /// The kind in words, for messages.
    pub fn describe(self) -> &'static str {
        match self {
            FolderKind::Results => "a navkf results folder",
            FolderKind::Dataset => "a dataset folder navkf simulated",
            FolderKind::Shards => "a folder of navkf shard files",
        }
    }
}

/// The marker's content.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Marker {
    /// The kind of folder.
    pub kind: FolderKind,
    /// `navkf <version>` that wrote it.
    pub made_by: String,
    /// The command line that made the folder.
    pub command: String,
    /// Every file written, as `/`-separated paths relative to the folder, sorted; empty
    /// while the folder is being written. Shard folders list none: each shard adds its own.
    pub files: Vec<String>,
}

impl Marker {
    /// A marker of `kind` for this process, listing no files yet.
    pub fn new(kind: FolderKind) -> Self {
        Marker {
            kind,
            made_by: format!("navkf {}", env!("CARGO_PKG_VERSION")),
            command: crate::provenance::command_line(),
            files: Vec::new(),
        }
    }

    /// The marker as written to disk.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).expect("a marker serialises") + "\n"
    }

    /// Reads the marker of `kind` in `dir`: `Ok(None)` if there is none, `Err` with the
    /// reason if there is one this version cannot read.
    pub fn read(dir: &Path, kind: FolderKind) -> Result<Option<Marker>, String> {
        let path = dir.join(kind.marker_name());
        let meta = match std::fs::symlink_metadata(&path) {
            Ok(m) => m,
            Err(_) => return Ok(None),
        };
        let unreadable = |why: String| {
            format!(
                "{}: {why}; navkf cannot tell its own files from yours there, so it replaces \
                 nothing: remove the folder yourself, or choose another output folder",
                path.display()
            )
        };
        // A marker is small; anything else (a link, a device, a huge file) is not one of ours.
        if !meta.is_file() || meta.len() > 16 << 20 {
            return Err(unreadable("not a marker navkf wrote".into()));
        }
        let text = std::fs::read_to_string(&path).map_err(|e| unreadable(e.to_string()))?;
        let marker: Marker = serde_json::from_str(&text).map_err(|_| {
            unreadable("a marker this version cannot read (written by an earlier navkf?)".into())
        })?;
        if marker.kind != kind {
            return Err(unreadable(format!(
                "says {}, not {}",
                marker.kind.describe(),
                kind.describe()
            )));
        }
        Ok(Some(marker))
    }
}

/// The name of the files navkf creates and removes at once to test that it can write in a
/// folder.
pub const PROBE_PREFIX: &str = ".navkf-probe-";

/// Every entry below `dir` (files, links, other non-folders, and empty folders), as sorted
/// `/`-separated relative paths, not following links; the markers and write probes left out.
pub fn entries_below(dir: &Path) -> std::io::Result<Vec<String>> {
    let mut out = Vec::new();
    walk(dir, "", &mut out)?;
    out.sort();
    Ok(out)
}

fn walk(dir: &Path, prefix: &str, out: &mut Vec<String>) -> std::io::Result<()> {
    let mut any = false;
    for e in std::fs::read_dir(dir)? {
        let e = e?;
        any = true;
        let name = e.file_name().to_string_lossy().into_owned();
        if prefix.is_empty() && FolderKind::ALL.iter().any(|k| k.marker_name() == name) {
            continue;
        }
        // A write probe (`super::probe_deletable`) that a killed process left is navkf's own,
        // and must not make its folder look like the user's.
        if name.starts_with(PROBE_PREFIX) {
            continue;
        }
        let rel = format!("{prefix}{name}");
        if e.file_type()?.is_dir() {
            walk(&e.path(), &format!("{rel}/"), out)?;
        } else {
            out.push(rel);
        }
    }
    if !any && !prefix.is_empty() {
        out.push(prefix.to_string());
    }
    Ok(())
}

/// Who a folder belongs to, as far as replacing it goes.
#[derive(Debug, Clone, PartialEq)]
pub enum Ownership {
    /// Nothing there, or an empty folder: safe to write.
    Free,
    /// navkf's, of the asked kind, holding nothing its marker does not list.
    Ours(Marker),
}

/// Decides whether the folder `dir` (which exists and is a folder) may be replaced by a
/// folder of `kind`; the refusal says why and names what is not navkf's. `also` lists other
/// kinds that may be replaced too (`merge` replaces its shard folder).
pub fn ownership(dir: &Path, kind: FolderKind, also: &[FolderKind]) -> Result<Ownership, String> {
    let failed = |e: std::io::Error| format!("{}: {e}", dir.display());
    let mut found = None;
    for k in std::iter::once(kind).chain(also.iter().copied()) {
        if let Some(m) = Marker::read(dir, k)? {
            found = Some(m);
            break;
        }
    }
    let Some(marker) = found else {
        // Not navkf's: its top level is enough to refuse it (a `--out ~` is not walked).
        let entries = top_level(dir).map_err(failed)?;
        let other = FolderKind::ALL
            .into_iter()
            .find(|k| std::fs::symlink_metadata(dir.join(k.marker_name())).is_ok());
        if entries.is_empty() && other.is_none() {
            return Ok(Ownership::Free);
        }
        return Err(match other {
            Some(k) => format!(
                "{}: {}, not {}; expected a new folder or {}",
                dir.display(),
                k.describe(),
                kind.describe(),
                kind.describe()
            ),
            None => format!(
                "{}: a folder navkf did not make (no {} marker; it holds {}); {}",
                dir.display(),
                kind.marker_name(),
                listed(&entries),
                match kind {
                    FolderKind::Shards => "shards write only into a new folder, an empty one, \
                                           or one that earlier shards made"
                        .to_string(),
                    _ => format!(
                        "navkf replaces its output folder whole, so it writes only into a new \
                         folder, an empty one, or {} it made before",
                        kind.describe()
                    ),
                }
            ),
        });
    };
    let foreign: Vec<String> = entries_below(dir)
        .map_err(failed)?
        .into_iter()
        .filter(|e| !owned(&marker, e))
        .collect();
    if !foreign.is_empty() {
        return Err(format!(
            "{}: navkf made this folder ({}), but it also holds {}, which navkf did not \
             write; replacing the folder would delete {}: move {} out, or choose another \
             output folder",
            dir.display(),
            marker.kind.describe(),
            listed(&foreign),
            if foreign.len() == 1 { "it" } else { "them" },
            if foreign.len() == 1 { "it" } else { "them" },
        ));
    }
    Ok(Ownership::Ours(marker))
}

/// Whether the marker accounts for the entry `rel`: a listed file, or for a shard folder a
/// shard file (each shard adds its own without listing it).
fn owned(marker: &Marker, rel: &str) -> bool {
    match marker.kind {
        FolderKind::Shards => is_shard_file(rel),
        _ => marker
            .files
            .binary_search_by(|f| f.as_str().cmp(rel))
            .is_ok(),
    }
}

/// Whether `name` is a shard file's name (`partial-I-of-N.json`).
pub fn is_shard_file(name: &str) -> bool {
    name.strip_prefix("partial-")
        .and_then(|s| s.strip_suffix(".json"))
        .and_then(|s| s.split_once("-of-"))
        .is_some_and(|(i, n)| {
            [i, n]
                .iter()
                .all(|x| !x.is_empty() && x.bytes().all(|b| b.is_ascii_digit()))
        })
}

/// The entries directly in `dir` (folders with a trailing `/`), sorted, markers and write
/// probes left out.
fn top_level(dir: &Path) -> std::io::Result<Vec<String>> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir)? {
        let e = e?;
        let name = e.file_name().to_string_lossy().into_owned();
        let ours = FolderKind::ALL.iter().any(|k| k.marker_name() == name)
            || name.starts_with(PROBE_PREFIX);
        if !ours {
            let folder = e.file_type().is_ok_and(|t| t.is_dir());
            out.push(if folder { format!("{name}/") } else { name });
        }
    }
    out.sort();
    Ok(out)
}

/// Up to three names, quoted, and how many more.
fn listed(names: &[String]) -> String {
    let shown: Vec<String> = names
        .iter()
        .take(3)
        .map(|n| format!("`{}`", crate::names::shown(n).trim_matches('"')))
        .collect();
    let more = names.len().saturating_sub(3);
    if more > 0 {
        format!("{} and {more} more", shown.join(", "))
    } else {
        shown.join(", ")
    }
}

/// `path` with a symbolic link at its end resolved (once, to the folder it names), so the
/// staging folder goes beside the real folder and the link keeps pointing at the results.
/// A link to nothing, or a loop, is refused: where the results would go is not known.
pub fn resolve_link(path: &Path) -> Result<PathBuf, String> {
    match std::fs::symlink_metadata(path) {
        Ok(m) if m.file_type().is_symlink() => std::fs::canonicalize(path).map_err(|e| {
            let to = std::fs::read_link(path)
                .map(|t| format!(" to `{}`", t.display()))
                .unwrap_or_default();
            format!(
                "{}: a symbolic link{to}, which cannot be followed ({e}); expected a folder, \
                 or a path that does not exist yet",
                path.display()
            )
        }),
        _ => Ok(path.to_path_buf()),
    }
}
