//! `navkf.study` and `navkf.plan`: a Monte Carlo study file (or its text) run as
//! `navkf study` runs it, and the planner's prediction for it, as `navkf plan` makes it.
//! The summary and the plan come back as the JSON the command line writes; the series as
//! the CSV text of `rms_over_time.csv`; the per-run results as JSON, one entry per run.

use crate::background::{run as in_background, Progress};
use crate::errors::{to_py, OrNavkfError};
use navkf_report::ResultsDir;
use navkf_study::monte_carlo::RunRecord;
use navkf_study::output::{rms_csv, write_results};
use navkf_study::summary::summarize;
use navkf_study::{Study, StudyConfig};
use pyo3::prelude::*;
use std::collections::BTreeMap;
use std::path::PathBuf;
use std::sync::Mutex;

/// A study's configuration from its file at `path` (read as `navkf study` reads it: a regular
/// file of bounded size) or from `json`, a dict's tables turned into a study file's text by
/// the `toml` crate and named `<dict>` in errors.
fn config(path: Option<PathBuf>, json: Option<String>) -> PyResult<(PathBuf, StudyConfig)> {
    use navkf_dynamics::input_file::{read_text, TextFile};
    let (path, text) = match (path, json) {
        (Some(path), None) => {
            let text = read_text(&path, &TextFile::STUDY).or_py()?;
            (path, text)
        }
        (None, Some(json)) => {
            let tables: toml::Value = serde_json::from_str(&json).map_err(|e| {
                to_py(&format!(
                    "study: {e}; expected tables of numbers, text and lists"
                ))
            })?;
            (PathBuf::from("<dict>"), toml::to_string(&tables).or_py()?)
        }
        _ => {
            return Err(to_py(
                "study: expected a study file's path or its tables as a dict",
            ))
        }
    };
    let kind = navkf_report::StudyKind::declared(&text).map_err(|e| to_py(&e))?;
    if kind != navkf_report::StudyKind::MonteCarlo {
        return Err(to_py(&format!(
            "{}: a diagnosis study ([study] kind = \"diagnosis\"); navkf.study runs Monte Carlo \
             studies from Python (the command line's `navkf study` runs this one)",
            path.display()
        )));
    }
    let config = StudyConfig::from_file_text(&path, &text).or_py()?;
    Ok((path, config))
}

/// One run's results, per filter: how it ended, its final errors and claimed sigmas, its
/// mean NEES, its NIS over the run and its mean step cost.
fn per_run(names: &[String], filters: &[String], rec: &RunRecord) -> serde_json::Value {
    let each: Vec<serde_json::Value> = rec
        .filters
        .iter()
        .zip(filters)
        .map(|(f, name)| {
            let last_err = f.err.last().cloned().unwrap_or_default();
            let last_sigma: Vec<f64> = f
                .var
                .last()
                .map(|v| v.iter().map(|v| v.sqrt()).collect())
                .unwrap_or_default();
            let finite = |v: f64| if v.is_finite() { Some(v) } else { None };
            // Keyed by state, NaN (a diverged run's) as null.
            let by_name = |v: &[f64]| -> BTreeMap<String, Option<f64>> {
                names
                    .iter()
                    .cloned()
                    .zip(v.iter().map(|v| finite(*v)))
                    .collect()
            };
            let mean = |v: &[f64]| finite(v.iter().sum::<f64>() / v.len() as f64);
            let cost = f.step_ns.iter().sum::<u64>() as f64 / f.step_ns.len().max(1) as f64 / 1e3;
            serde_json::json!({
                "filter": name,
                "diverged": f.outcome.as_ref().err().map(|e| e.to_string()),
                "final_error": by_name(&last_err),
                "final_sigma": by_name(&last_sigma),
                "mean_nees": mean(&f.nees),
                "nis_sum": finite(f.nis.sum),
                "nis_dof": f.nis.dof,
                "step_us": cost,
            })
        })
        .collect();
    serde_json::json!({ "run": rec.run, "filters": each })
}

/// See `navkf.study` (python/navkf/__init__.py): returns the summary, the series and the
/// per-run results as JSON, CSV and JSON text.
#[pyfunction]
#[pyo3(signature = (*, path, json, runs, out, progress))]
pub fn study(
    py: Python<'_>,
    path: Option<PathBuf>,
    json: Option<String>,
    runs: Option<usize>,
    out: Option<PathBuf>,
    progress: Option<Bound<'_, PyAny>>,
) -> PyResult<(String, String, String)> {
    let (path, mut config) = config(path, json)?;
    if let Some(r) = runs {
        if r == 0 {
            return Err(to_py("runs 0: expected at least one run"));
        }
        config.study.runs = r;
        config.study.example_run = config.study.example_run.min(r - 1);
    }
    if let Some(s) = &config.sweep {
        return Err(to_py(&format!(
            "{}: sweeps `{}`; navkf.study runs one study from Python (the command line's \
             `navkf study` runs the sweep)",
            path.display(),
            s.key
        )));
    }
    let study = Study::new(config).or_py()?;
    // Checked before any run: a refused folder costs nothing.
    let staged = out.as_deref().map(ResultsDir::begin).transpose().or_py()?;
    let tracker = Progress::default();
    tracker.total.store(
        study.config.study.runs,
        std::sync::atomic::Ordering::Relaxed,
    );
    let example = Mutex::new(None);
    let runs = Mutex::new(Vec::new());
    let names = study.names.clone();
    let filters = study.filter_names().to_vec();
    let tally = in_background(py, progress.as_ref(), &tracker, || {
        study.run_folded_each(0..study.block_count(), &|done| tracker.set(done), |rec| {
            if rec.run == study.config.study.example_run {
                *example.lock().expect("not poisoned") = Some(study.example_of(rec));
            }
            runs.lock()
                .expect("not poisoned")
                .push(per_run(&names, &filters, rec));
        })
    })?
    .map_err(|e| crate::errors::interrupted(e.to_string()))?;
    let example = example.into_inner().expect("not poisoned");
    let summary = match staged {
        Some(staged) => {
            let s = py
                .detach(|| write_results(&study, &tally, example.as_ref(), staged.path()))
                .or_py()?;
            staged.commit().or_py()?;
            s
        }
        None => summarize(&study, &tally),
    };
    let runs = runs.into_inner().expect("not poisoned");
    Ok((
        serde_json::to_string(&summary).or_py()?,
        rms_csv(&study, &tally),
        serde_json::to_string(&runs).or_py()?,
    ))
}

/// See `navkf.plan` (python/navkf/__init__.py): the plan as JSON text.
#[pyfunction]
#[pyo3(signature = (*, path, json, out))]
pub fn plan(
    py: Python<'_>,
    path: Option<PathBuf>,
    json: Option<String>,
    out: Option<PathBuf>,
) -> PyResult<String> {
    let (path, config) = config(path, json)?;
    if let Some(s) = &config.sweep {
        return Err(to_py(&format!(
            "{}: sweeps `{}`; navkf.plan plans one design from Python (the command line's \
             `navkf plan` compares a sweep's points)",
            path.display(),
            s.key
        )));
    }
    let staged = out.as_deref().map(ResultsDir::begin).transpose().or_py()?;
    let p = py
        .detach(|| Study::new(config).and_then(|s| navkf_study::plan::plan(&s)))
        .or_py()?;
    if let Some(staged) = staged {
        let command = navkf_report::provenance::command_line();
        py.detach(|| navkf_study::plan_output::write_plan(&p, staged.path(), &command, true))
            .or_py()?;
        staged.commit().or_py()?;
    }
    serde_json::to_string(&p).or_py()
}
