//! A sweep spread over machines: `navkf study sweep.toml --shard i/n` runs shard `i` of
//! every point's blocks (the split a point's own study would use, [`shard_blocks`]) and
//! writes one file holding each point's [`Partial`]; `navkf merge` checks every point's set
//! of partials as it checks a study's ([`check_partials`]), folds them in block order and
//! writes the sweep a single machine writes, bit for bit.

use super::points;
use crate::config::StudyConfig;
use crate::error::StudyError;
use crate::merge::{check_partials, read_shard_file};
use crate::partial::{shard_blocks, Partial};
use serde::{Deserialize, Serialize};
use std::path::PathBuf;

/// What one shard of a sweep wrote.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SweepShard {
    /// The sweep's study file, as run (with its `[sweep]`).
    pub config: StudyConfig,
    /// `(i, n)`: shard `i` of `n` of every point.
    pub shard: (usize, usize),
    /// Each point's share, in the order of the values.
    pub points: Vec<Partial>,
}

/// The most shards a sweep takes: one per block of its smallest point (a point with fewer
/// blocks than shards would leave some shards nothing to run).
pub fn max_shards(config: &StudyConfig) -> Result<usize, StudyError> {
    let configs = points(config).map_err(StudyError::Other)?;
    Ok(configs
        .iter()
        .map(|c| c.study.runs.div_ceil(crate::tally::BLOCK))
        .min()
        .unwrap_or(0))
}

/// The blocks shard `(i, n)` runs of a point with `blocks` blocks.
pub fn point_blocks(blocks: usize, (i, n): (usize, usize)) -> std::ops::Range<usize> {
    shard_blocks(blocks, i, n)
}

/// Reads the shard files of one sweep and checks them: one sweep, split one way, every
/// point's partials consistent with the point's study and tiling its runs. Returns the
/// sweep's study file and each point's partials in run order.
pub fn read(paths: &[PathBuf]) -> Result<(StudyConfig, Vec<Vec<Partial>>), StudyError> {
    let bad = |path: &PathBuf, message: String| StudyError::Config {
        path: path.clone(),
        message,
    };
    let mut shards: Vec<(PathBuf, SweepShard)> = Vec::with_capacity(paths.len());
    for path in paths {
        let shard: SweepShard = read_shard_file(path)?;
        shard
            .config
            .validate()
            .map_err(|m| bad(path, format!("config.{m}")))?;
        let expected = points(&shard.config).map_err(|m| bad(path, format!("config.{m}")))?;
        if shard.points.len() != expected.len() {
            return Err(bad(
                path,
                format!(
                    "points: {} of them; the sweep has {}",
                    shard.points.len(),
                    expected.len()
                ),
            ));
        }
        for (j, (part, config)) in shard.points.iter().zip(&expected).enumerate() {
            if &part.config != config {
                return Err(bad(
                    path,
                    format!("points[{j}].config: not the sweep's point {j}"),
                ));
            }
            if part.shard != shard.shard {
                return Err(bad(
                    path,
                    format!(
                        "points[{j}].shard = {:?}: the file is shard {:?}",
                        part.shard, shard.shard
                    ),
                ));
            }
        }
        if let Some((_, first)) = shards.first() {
            if first.config != shard.config {
                return Err(bad(
                    path,
                    "this shard ran a different sweep than the first shard".into(),
                ));
            }
        }
        shards.push((path.clone(), shard));
    }
    let Some((_, first)) = shards.first() else {
        return Err(StudyError::Other(
            "merge needs at least one shard file".into(),
        ));
    };
    let config = first.config.clone();
    let count = first.points.len();
    let mut per_point: Vec<Vec<(PathBuf, Partial)>> = vec![Vec::new(); count];
    for (path, shard) in shards {
        for (j, part) in shard.points.into_iter().enumerate() {
            per_point[j].push((path.clone(), part));
        }
    }
    let checked = per_point
        .into_iter()
        .enumerate()
        .map(|(j, parts)| {
            check_partials(parts).map_err(|e| StudyError::Other(format!("sweep point {j}: {e}")))
        })
        .collect::<Result<Vec<_>, _>>()?;
    Ok((config, checked))
}
