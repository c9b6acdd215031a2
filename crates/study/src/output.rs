//! Writing a study's results under `results/<study>/`, every file atomically (written to a
//! temporary name in the same folder, then renamed), and the shard files `merge` reads.

use crate::error::StudyError;
use crate::monte_carlo::{ExampleRun, Study};
use crate::summary::{summarize, Summary};
use crate::tally::Tally;
use navkf_dynamics::state::NAV_DIM;
use navkf_report::provenance::command_line;
use navkf_report::write_atomic;
use serde::{Deserialize, Serialize};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// A shard's output: its blocks' tallies, in order, and the example run if it holds it.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Partial {
    /// The study file, as run (merge checks that every shard ran the same one).
    pub config: crate::config::StudyConfig,
    /// `(i, n)` of `--shard i/n`.
    pub shard: (usize, usize),
    /// Tallies of whole blocks, in block order.
    pub blocks: Vec<Tally>,
    /// The example run, if it fell in this shard.
    pub example: Option<ExampleRun>,
}

/// The blocks of shard `i` of `n` ([`navkf_report::executor::shard_range`] over blocks).
pub fn shard_blocks(blocks: usize, i: usize, n: usize) -> std::ops::Range<usize> {
    navkf_report::executor::shard_range(blocks, i, n)
}

/// Folds block tallies in order into the study's tally.
pub fn fold(blocks: &[Tally]) -> Tally {
    let mut total = Tally::default();
    for b in blocks {
        total.merge(b);
    }
    total
}

/// Writes `summary.json`, the time series, the example run, the figures and `report.md`
/// into `dir`; returns the summary.
pub fn write_results(
    study: &Study,
    tally: &Tally,
    example: Option<&ExampleRun>,
    dir: &Path,
) -> Result<Summary, StudyError> {
    let summary = summarize(study, tally);
    let json =
        serde_json::to_string_pretty(&summary).map_err(|e| StudyError::Other(e.to_string()))?;
    write_atomic(&dir.join("summary.json"), json.as_bytes())?;
    write_atomic(
        &dir.join("rms_over_time.csv"),
        rms_csv(study, tally).as_bytes(),
    )?;
    if let Some(ex) = example {
        write_atomic(&dir.join("example_run.csv"), example_csv(ex).as_bytes())?;
    }
    crate::report::write_report(study, tally, example, dir, &command_line())?;
    Ok(summary)
}

/// `t, filter, then rms_<state>, sigma_<state> for every state, nees, nis, bound_<coef>`.
fn rms_csv(study: &Study, tally: &Tally) -> String {
    use navkf_dynamics::SystemModel;
    let names = &study.names;
    let truth_names = study.sim.model().state_names();
    let mut s = String::from("t,filter");
    for n in names {
        let _ = write!(s, ",rms_{n}");
    }
    for n in names {
        let _ = write!(s, ",sigma_{n}");
    }
    s.push_str(",nees,nis");
    for n in &names[NAV_DIM..] {
        let _ = write!(s, ",bound_{n}");
    }
    s.push('\n');
    for (fname, t) in study.filter_names().iter().zip(&tally.filters) {
        if t.ok == 0 {
            continue;
        }
        let ok = t.ok as f64;
        for (k, time) in study.times.iter().enumerate() {
            let _ = write!(s, "{time},{fname}");
            for v in &t.sum_sq_err[k] {
                let _ = write!(s, ",{}", (v / ok).sqrt());
            }
            for v in &t.sum_var[k] {
                let _ = write!(s, ",{}", (v / ok).sqrt());
            }
            let _ = write!(s, ",{},{}", t.sum_nees[k] / ok, t.sum_nis_window[k] / ok);
            for n in &names[NAV_DIM..] {
                let b = truth_names
                    .iter()
                    .position(|x| x == n)
                    .filter(|_| tally.bound.count > 0)
                    .map(|j| (tally.bound.sum_var[k][j] / tally.bound.count as f64).sqrt());
                match b {
                    Some(v) => {
                        let _ = write!(s, ",{v}");
                    }
                    None => s.push(','),
                }
            }
            s.push('\n');
        }
    }
    s
}

/// `t, filter, then est_<state>, sigma_<state>, true_<state>` at every step of the example run.
fn example_csv(ex: &ExampleRun) -> String {
    let mut s = String::from("t,filter");
    for n in &ex.names {
        let _ = write!(s, ",est_{n},sigma_{n},true_{n}");
    }
    s.push('\n');
    for f in &ex.filters {
        for (k, t) in f.t.iter().enumerate() {
            let _ = write!(s, "{t},{}", f.name);
            let truth =
                ex.t.iter()
                    .position(|x| (x - t).abs() < 1e-9)
                    .map(|j| &ex.truth[j]);
            for i in 0..ex.names.len() {
                let tv = truth.map_or(f64::NAN, |r| r[i]);
                let _ = write!(s, ",{},{},{}", f.estimate[k][i], f.sigma[k][i], tv);
            }
            s.push('\n');
        }
    }
    s
}

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
        crate::shard_check::check(&part, prepared).map_err(|message| StudyError::Config {
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
    crate::shard_check::check_totals(&out).map_err(StudyError::Other)?;
    Ok(out)
}
