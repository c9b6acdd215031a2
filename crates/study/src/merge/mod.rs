//! `merge`: shard files read back, checked against the study they ran ([`shard_check`]) and
//! against each other (one study, complete, not overlapping), in run order, ready to fold.

pub mod shard_check;

use crate::error::StudyError;
use crate::monte_carlo::Study;
use crate::partial::Partial;
use std::path::{Path, PathBuf};

/// Reads shard files and checks they are one study, complete and not overlapping.
pub fn read_partials(paths: &[PathBuf]) -> Result<Vec<Partial>, StudyError> {
    let parts = paths
        .iter()
        .map(|p| Ok((p.clone(), read_shard_file::<Partial>(p)?)))
        .collect::<Result<Vec<_>, StudyError>>()?;
    check_partials(parts)
}

/// Reads a shard file as `T` (a regular file of bounded size; a message naming the file if
/// it is not one).
pub fn read_shard_file<T: serde::de::DeserializeOwned>(path: &Path) -> Result<T, StudyError> {
    let text =
        navkf_dynamics::input_file::read_text(path, &navkf_dynamics::input_file::TextFile::SHARD)?;
    serde_json::from_str(&text).map_err(|e| StudyError::Config {
        path: path.to_path_buf(),
        // serde_json quotes a bad string whole: cut it.
        message: navkf_dynamics::input_file::printable(&format!("not a shard file: {e}")),
    })
}

/// Checks that the shards (each with the file it came from) are one study, each consistent
/// with it, complete and not overlapping; returns them in run order.
pub fn check_partials(parts: Vec<(PathBuf, Partial)>) -> Result<Vec<Partial>, StudyError> {
    let mut out: Vec<Partial> = Vec::new();
    let mut study: Option<Study> = None;
    for (p, part) in parts {
        // A shard file is data: its settings are checked as a study file's are (an edited
        // `name` must not send the results outside results/).
        part.config
            .validate()
            .map_err(|message| StudyError::Config {
                path: p.clone(),
                message: format!("config.{message}"),
            })?;
        if let Some(first) = out.first() {
            if first.config != part.config {
                return Err(StudyError::Config {
                    path: p.clone(),
                    message: "this shard ran a different study file than the first shard".into(),
                });
            }
            if first.shard.1 != part.shard.1 {
                return Err(StudyError::Config {
                    path: p.clone(),
                    message: format!(
                        "shard = ({}, {}): the first shard is one of {}; a set of shards splits the study one way",
                        part.shard.0, part.shard.1, first.shard.1
                    ),
                });
            }
        }
        // Its counts and arrays against the study, built once (every shard ran the same one).
        let prepared = match study.take() {
            Some(s) => s,
            None => Study::new(part.config.clone()).map_err(|e| StudyError::Config {
                path: p.clone(),
                message: format!("config: {e}"),
            })?,
        };
        let prepared = study.insert(prepared);
        shard_check::check(&part, prepared).map_err(|message| StudyError::Config {
            path: p.clone(),
            message,
        })?;
        out.push(part);
    }
    if out.is_empty() {
        return Err(StudyError::Other(
            "merge needs at least one shard file".into(),
        ));
    }
    out.sort_by_key(|p| p.blocks.first().map_or(usize::MAX, |b| b.first_run));
    let runs = out[0].config.study.runs;
    let mut expect = 0;
    for p in &out {
        for b in &p.blocks {
            if b.first_run != expect {
                return Err(StudyError::Other(format!(
                    "shards do not fit together: expected the block starting at run {expect}, found one starting at run {} (a shard missing or given twice?)",
                    b.first_run
                )));
            }
            expect += b.runs;
        }
    }
    if expect != runs {
        return Err(StudyError::Other(format!(
            "shards cover runs 0..{expect} of {runs}: some shards are missing"
        )));
    }
    shard_check::check_totals(&out).map_err(StudyError::Other)?;
    Ok(out)
}
