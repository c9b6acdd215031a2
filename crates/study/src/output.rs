//! Writing a study's results under `results/<study>/`, every file atomically (written to a
//! temporary name in the same folder, then renamed).

use crate::error::StudyError;
use crate::monte_carlo::{ExampleRun, Study};
use crate::summary::{summarize, Summary};
use crate::tally::Tally;
use navkf_dynamics::state::NAV_DIM;
use navkf_report::provenance::command_line;
use navkf_report::write_atomic;
use std::fmt::Write as _;
use std::path::Path;

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
pub fn rms_csv(study: &Study, tally: &Tally) -> String {
    let names = &study.names;
    let truth_names = study.sim.truth_model().state_names();
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
