//! A diagnosis study spread over machines: `navkf study studies/diagnosis.toml --shard i/n`
//! diagnoses the contiguous range of datasets of shard `i`
//! ([`navkf_report::executor::shard_range`]) and writes its records; `navkf merge` checks
//! that the shards ran the same study and tile its datasets, and writes the report from the
//! records in dataset order. Each dataset depends only on its index and the seed, so the
//! merged report is the one a single machine writes, byte for byte (the run's wall time
//! aside, which a merge does not know).

use super::{DiagnosisStudyConfig, Record};
use crate::DiagnoseError;
use navkf_dynamics::input_file::{printable, read_text, TextFile};
use navkf_report::executor::shard_range;
use navkf_report::StudyKind;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// What one shard of a diagnosis study wrote.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DiagnosisShard {
    /// Always [`StudyKind::Diagnosis`]: what tells `merge` which kind of shard this is.
    pub kind: StudyKind,
    /// The study file, as run.
    pub config: DiagnosisStudyConfig,
    /// `(i, n)`: shard `i` of `n`.
    pub shard: (usize, usize),
    /// Datasets the whole run diagnoses (all of the study's, or `--runs`' first ones).
    pub datasets: usize,
    /// The records of this shard's datasets, in order.
    pub records: Vec<Record>,
}

impl DiagnosisShard {
    /// The shard `shard = (i, n)` of a run of `datasets` datasets, with its records.
    pub fn new(
        config: &DiagnosisStudyConfig,
        shard: (usize, usize),
        datasets: usize,
        records: Vec<Record>,
    ) -> Self {
        DiagnosisShard {
            kind: StudyKind::Diagnosis,
            config: config.clone(),
            shard,
            datasets,
            records,
        }
    }

    /// The datasets of this shard.
    pub fn range(&self) -> std::ops::Range<usize> {
        shard_range(self.datasets, self.shard.0, self.shard.1)
    }

    /// What is wrong with this shard on its own (the message names the field).
    fn check(&self) -> Result<(), String> {
        if self.kind != StudyKind::Diagnosis {
            return Err("kind: expected \"diagnosis\"".into());
        }
        self.config.validate().map_err(|m| format!("config.{m}"))?;
        let (i, n) = self.shard;
        let total = super::dataset_count(&self.config);
        if self.datasets == 0 || self.datasets > total {
            return Err(format!(
                "datasets = {}: the study makes {total}; expected 1 to {total}",
                self.datasets
            ));
        }
        if n == 0 || i >= n || n > self.datasets {
            return Err(format!(
                "shard = ({i}, {n}): expected 0 <= i < n <= datasets ({})",
                self.datasets
            ));
        }
        let range = self.range();
        if self.records.len() != range.len() {
            return Err(format!(
                "records: {} of them; shard {i} of {n} diagnoses datasets {}..{} ({})",
                self.records.len(),
                range.start,
                range.end,
                range.len()
            ));
        }
        for (k, (r, expected)) in self.records.iter().zip(range).enumerate() {
            if r.index != expected {
                return Err(format!(
                    "records[{k}].index = {}: expected {expected}",
                    r.index
                ));
            }
        }
        Ok(())
    }
}

/// Reads the shard files `paths` of one diagnosis study, checks each and that together they
/// are every shard of one run once, and returns the study and its records in dataset order.
pub fn merge(paths: &[PathBuf]) -> Result<(DiagnosisStudyConfig, Vec<Record>), DiagnoseError> {
    let bad = |path: &Path, message: String| DiagnoseError::Config {
        path: path.to_path_buf(),
        message: printable(&message),
    };
    let mut shards: Vec<DiagnosisShard> = Vec::with_capacity(paths.len());
    for path in paths {
        let text = read_text(path, &TextFile::SHARD)?;
        let shard: DiagnosisShard = serde_json::from_str(&text)
            .map_err(|e| bad(path, format!("not a diagnosis-study shard file: {e}")))?;
        shard.check().map_err(|m| bad(path, m))?;
        if let Some(first) = shards.first() {
            if first.config != shard.config || first.datasets != shard.datasets {
                return Err(bad(
                    path,
                    "this shard ran a different study (or --runs) than the first shard".into(),
                ));
            }
            if first.shard.1 != shard.shard.1 {
                return Err(bad(
                    path,
                    format!(
                        "shard = ({}, {}): the first shard is one of {}; a set of shards \
                         splits the study one way",
                        shard.shard.0, shard.shard.1, first.shard.1
                    ),
                ));
            }
            if let Some(twin) = shards.iter().find(|s| s.shard.0 == shard.shard.0) {
                return Err(bad(
                    path,
                    format!(
                        "shard {} of {} is given twice (datasets {}..{})",
                        shard.shard.0,
                        shard.shard.1,
                        twin.range().start,
                        twin.range().end
                    ),
                ));
            }
        }
        shards.push(shard);
    }
    let Some(first) = shards.first() else {
        return Err(DiagnoseError::Content(
            "merge needs at least one shard file".into(),
        ));
    };
    let n = first.shard.1;
    if shards.len() != n {
        let mut missing: Vec<usize> = (0..n).collect();
        missing.retain(|i| shards.iter().all(|s| s.shard.0 != *i));
        return Err(DiagnoseError::Content(format!(
            "shards {missing:?} of {n} are missing: every shard of the run is needed"
        )));
    }
    shards.sort_by_key(|s| s.shard.0);
    let config = shards[0].config.clone();
    let records = shards.into_iter().flat_map(|s| s.records).collect();
    Ok((config, records))
}
