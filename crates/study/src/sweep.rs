//! Sweeps: one setting of a study file varied over a list of values, every other setting
//! fixed, each value a full Monte Carlo with the same seeds for every filter.
//!
//! ```toml
//! [sweep]
//! key = "truth.initial_tilt.azimuth_rad"
//! values = [2.9e-4, 1.7e-3, 1.7e-2]
//! ```
//!
//! Any numeric key works, written in the file or left at its default (noise levels,
//! trajectory parameters, sigma-point scaling, a variant's setting), including one inside a
//! list, indexed as located errors write it (`trajectory.segment[1].to`, the speed of the
//! second segment; `trajectory.segment[3].segments[0].duration_s`): [`points`] writes the
//! value into the study's settings as TOML and reads them back, so each point is checked
//! exactly as a study file would be, and a misspelt key is refused with its name. The
//! results of a sweep are one ordinary results folder per point plus a summary across
//! points ([`SweepSummary`], `sweep.json`, `sweep.md` and the figures of
//! [`crate::plots::sweep`]).

use crate::config::StudyConfig;
use crate::error::StudyError;
use crate::monte_carlo::{ExampleRun, Study};
use crate::output::write_results;
use crate::summary::{paired_difference, PairedDifference, Summary};
use crate::tally::Tally;
use navkf_dynamics::state::PHI_Z;
use navkf_filters::DivergenceCause;
use navkf_report::figure::FigureOutcome;
use navkf_report::stats::mean_chi2_bounds;
use navkf_report::write_atomic;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::fmt::Write;
use std::path::Path;

/// The study of every point of `config`'s sweep, in order (each without the `[sweep]`
/// table and checked); the message names the key and the value's index.
pub fn points(config: &StudyConfig) -> Result<Vec<StudyConfig>, String> {
    let Some(sweep) = &config.sweep else {
        return Ok(vec![config.clone()]);
    };
    if sweep.values.is_empty() {
        return Err("sweep.values is empty: expected at least one value".into());
    }
    for (i, v) in sweep.values.iter().enumerate() {
        if !v.is_finite() {
            return Err(format!("sweep.values[{i}] = {v}: expected a finite number"));
        }
        if sweep.values[..i].contains(v) {
            return Err(format!(
                "sweep.values[{i}] = {v} is listed twice; expected each value once"
            ));
        }
    }
    let path: Vec<&str> = sweep.key.split('.').collect();
    if path.iter().any(|p| p.is_empty()) || path[0] == "sweep" {
        return Err(format!(
            "sweep.key = `{}`: expected the dotted path of a numeric setting, e.g. \
             `truth.initial_tilt.azimuth_rad`",
            sweep.key
        ));
    }
    let mut base = config.clone();
    base.sweep = None;
    let value = toml::Value::try_from(&base).map_err(|e| e.to_string())?;
    sweep
        .values
        .iter()
        .enumerate()
        .map(|(i, &v)| {
            let mut value = value.clone();
            set(&mut value, &path, v).map_err(|e| format!("sweep.key = `{}`: {e}", sweep.key))?;
            let point: StudyConfig = value.try_into().map_err(|e: toml::de::Error| {
                format!(
                    "sweep.values[{i}] = {v} for `{}`: {}",
                    sweep.key,
                    e.message()
                )
            })?;
            point
                .validate()
                .map_err(|e| format!("sweep.values[{i}] = {v} for `{}`: {e}", sweep.key))?;
            Ok(point)
        })
        .collect()
}

/// Writes `v` at `path` in `value`: over a number (an integer setting takes integral values
/// only), or as a new key of an existing table (a setting left at no value, such as a
/// variant's alpha; reading the result back refuses a name the study does not know). A
/// component may index a list, as located errors write it: `trajectory.segment[1].to`,
/// `trajectory.segment[3].segments[0].duration_s`.
fn set(value: &mut toml::Value, path: &[&str], v: f64) -> Result<(), String> {
    let (last, parents) = path.split_last().expect("a non-empty path");
    let mut table = value;
    for (depth, p) in parents.iter().enumerate() {
        let here = || path[..=depth].join(".");
        table = component(table, p, &here)?;
        if !table.is_table() {
            return Err(format!("`{}` is not a table of settings", here()));
        }
    }
    // The last component: a key of `table`, or an element of a list under it.
    let (name, indices) = split_indices(last).map_err(|e| format!("`{last}`: {e}"))?;
    let (container, key): (&mut toml::Value, Slot) = match indices.split_last() {
        None => (table, Slot::Key(name.to_string())),
        Some((&i, outer)) => {
            let mut list = table
                .get_mut(name)
                .ok_or_else(|| format!("no setting `{}` in the study", path.join(".")))?;
            for &j in outer {
                list = element(list, j, &|| path.join("."))?;
            }
            (list, Slot::Index(i))
        }
    };
    let current = match (&*container, &key) {
        (toml::Value::Table(t), Slot::Key(k)) => t.get(k),
        (toml::Value::Array(a), Slot::Index(i)) => Some(a.get(*i).ok_or_else(|| {
            format!(
                "`{}` has {} entries, not {}",
                path.join("."),
                a.len(),
                i + 1
            )
        })?),
        _ => return Err(format!("`{}` is not a list", path.join("."))),
    };
    let new = match current {
        Some(toml::Value::Integer(_)) => {
            if v.fract() != 0.0 || v.abs() > 9.0e15 {
                return Err(format!(
                    "{v} is not a whole number, which this setting takes"
                ));
            }
            toml::Value::Integer(v as i64)
        }
        Some(toml::Value::Float(_)) | None => toml::Value::Float(v),
        Some(other) => {
            return Err(format!(
                "the setting is a {}, not a number",
                other.type_str()
            ))
        }
    };
    match (container, key) {
        (toml::Value::Table(t), Slot::Key(k)) => {
            t.insert(k, new);
        }
        (toml::Value::Array(a), Slot::Index(i)) => a[i] = new,
        _ => unreachable!("matched above"),
    }
    Ok(())
}

/// Where the swept number goes: a table's key or a list's element.
enum Slot {
    Key(String),
    Index(usize),
}

/// `value`'s entry `comp` (`name` or `name[i][j]`); `here` names the path so far.
fn component<'v>(
    value: &'v mut toml::Value,
    comp: &str,
    here: &dyn Fn() -> String,
) -> Result<&'v mut toml::Value, String> {
    let (name, indices) = split_indices(comp).map_err(|e| format!("`{}`: {e}", here()))?;
    let mut v = value
        .get_mut(name)
        .ok_or_else(|| format!("no table `{}` in the study", here()))?;
    for i in indices {
        v = element(v, i, here)?;
    }
    Ok(v)
}

/// Element `i` of the list `value`.
fn element<'v>(
    value: &'v mut toml::Value,
    i: usize,
    here: &dyn Fn() -> String,
) -> Result<&'v mut toml::Value, String> {
    let toml::Value::Array(a) = value else {
        return Err(format!("`{}` is not a list", here()));
    };
    let n = a.len();
    a.get_mut(i)
        .ok_or_else(|| format!("`{}` has {n} entries, not {}", here(), i + 1))
}

/// `name[1][2]` -> (`name`, [1, 2]).
fn split_indices(comp: &str) -> Result<(&str, Vec<usize>), String> {
    let Some(open) = comp.find('[') else {
        return Ok((comp, Vec::new()));
    };
    let (name, mut rest) = comp.split_at(open);
    let mut indices = Vec::new();
    while !rest.is_empty() {
        let inner = rest
            .strip_prefix('[')
            .and_then(|r| r.split_once(']'))
            .ok_or("expected an index in brackets, e.g. `segment[1]`")?;
        indices.push(
            inner
                .0
                .parse::<usize>()
                .map_err(|_| format!("`[{}]`: expected an index 0, 1, 2, ...", inner.0))?,
        );
        rest = inner.1;
    }
    if name.is_empty() {
        return Err("expected a name before the index".into());
    }
    Ok((name, indices))
}

/// The folder of point `i` inside a sweep's results folder.
pub fn point_folder(i: usize) -> String {
    format!("point-{i:02}")
}

/// One filter at one point of a sweep.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PointFilter {
    /// RMS over runs of the final heading error (`phi_z`), rad.
    pub heading_rms: f64,
    /// The truth-linearised bound of the final heading error, rad.
    pub heading_bound: f64,
    /// Final RMS / bound of each coefficient.
    pub rms_over_bound: BTreeMap<String, f64>,
    /// Their geometric mean.
    pub rms_over_bound_mean: f64,
    /// Average NEES at the first stored time, when the initial error is largest.
    pub nees_early: f64,
    /// Its 95 % bounds for a consistent filter.
    pub nees_early_bounds: [f64; 2],
    /// Average NEES at the final time.
    pub nees_final: f64,
    /// Its 95 % bounds.
    pub nees_final_bounds: [f64; 2],
    /// The largest average NEES over the stored times, and when.
    pub nees_peak: f64,
    /// Time of `nees_peak`, s.
    pub nees_peak_t: f64,
    /// Runs excluded as diverged, and by cause.
    pub diverged: u64,
    /// Those runs by cause.
    pub diverged_by_cause: BTreeMap<DivergenceCause, u64>,
    /// Runs included.
    pub runs_ok: u64,
    /// Median cost of one predict + update, ns.
    pub step_ns_median: f64,
}

/// One point of a sweep.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SweepPoint {
    /// The swept setting's value.
    pub value: f64,
    /// Its results folder, relative to the sweep's.
    pub folder: String,
    /// Per filter, by label.
    pub filters: BTreeMap<String, PointFilter>,
    /// Paired differences of the final heading error, per pair of filters.
    pub paired_heading: Vec<PairedDifference>,
    /// Paired differences of the coefficients (as in the point's `summary.json`).
    pub paired: Vec<PairedDifference>,
}

/// `sweep.json`: every point's results, side by side.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SweepSummary {
    /// Study name.
    pub study: String,
    /// The swept key.
    pub key: String,
    /// Runs per point.
    pub runs: usize,
    /// Filters, in the study's order.
    pub filters: Vec<String>,
    /// The points, in the order of the values.
    pub points: Vec<SweepPoint>,
}

/// The summary of point `index` (value `value`) from its study, tally and summary.
pub fn point(
    index: usize,
    value: f64,
    study: &Study,
    tally: &Tally,
    summary: &Summary,
) -> SweepPoint {
    let last = study.times.len() - 1;
    let n = study.names.len();
    let truth_phi_z = study.to_truth[PHI_Z];
    let bound_of = |s: usize, j: usize| {
        if tally.bound.count > 0 {
            (tally.bound.sum_var[s][j] / tally.bound.count as f64).sqrt()
        } else {
            f64::NAN
        }
    };
    let mut filters = BTreeMap::new();
    for (name, ft) in study.filter_names().iter().zip(&tally.filters) {
        let s = &summary.filters[name];
        let ok = ft.ok as f64;
        let mean_nees = |k: usize| {
            if ft.ok > 0 {
                ft.sum_nees[k] / ok
            } else {
                f64::NAN
            }
        };
        let (mut peak, mut peak_t) = (f64::NAN, f64::NAN);
        for (k, t) in study.times.iter().enumerate() {
            let v = mean_nees(k);
            if !(v <= peak) && v.is_finite() {
                (peak, peak_t) = (v, *t);
            }
        }
        let rms_over_bound: BTreeMap<String, f64> = s
            .final_rms
            .iter()
            .filter_map(|(c, r)| s.final_bound.get(c).map(|b| (c.clone(), r / b)))
            .collect();
        let logs: Vec<f64> = rms_over_bound.values().map(|v| v.ln()).collect();
        let bounds = if ft.ok > 0 {
            mean_chi2_bounds(ok * n as f64, ok)
        } else {
            [f64::NAN; 2]
        };
        filters.insert(
            name.clone(),
            PointFilter {
                heading_rms: s
                    .final_rms_nav
                    .get(&study.names[PHI_Z])
                    .copied()
                    .unwrap_or(f64::NAN),
                heading_bound: truth_phi_z.map_or(f64::NAN, |j| bound_of(last, j)),
                rms_over_bound_mean: if logs.is_empty() {
                    f64::NAN
                } else {
                    (logs.iter().sum::<f64>() / logs.len() as f64).exp()
                },
                rms_over_bound,
                nees_early: mean_nees(0),
                nees_early_bounds: bounds,
                nees_final: mean_nees(last),
                nees_final_bounds: bounds,
                nees_peak: peak,
                nees_peak_t: peak_t,
                diverged: s.diverged,
                diverged_by_cause: s.diverged_by_cause.clone(),
                runs_ok: s.runs_ok,
                step_ns_median: s.step_ns_median,
            },
        );
    }
    let paired_heading = tally
        .pairs
        .iter()
        .filter(|p| p.n >= 2)
        .map(|p| paired_difference(study, tally, p, PHI_Z))
        .collect();
    SweepPoint {
        value,
        folder: point_folder(index),
        filters,
        paired_heading,
        paired: summary.paired.clone(),
    }
}

/// The swept key as a figure's axis: its path in words, in the unit engineers quote, and
/// the factor from the key's unit to it. Angles (`_rad`) are shown in degrees, as the study
/// files' comments and README speak of them; a list index counts from 1.
///
/// ```
/// use navkf_study::sweep::axis;
/// let (words, factor) = axis("truth.initial_tilt.azimuth_rad");
/// assert_eq!(words, "truth: initial tilt: azimuth (deg)");
/// assert!((factor - 57.29577951308232).abs() < 1e-12);
/// assert_eq!(axis("trajectory.segment[1].to").0, "trajectory: segment 2: to");
/// assert_eq!(axis("noise.gps_m"), ("noise: gps (m)".to_string(), 1.0));
/// ```
pub fn axis(key: &str) -> (String, f64) {
    const UNITS: [(&str, &str, f64); 7] = [
        ("_rad", "deg", 180.0 / std::f64::consts::PI),
        ("_deg", "deg", 1.0),
        ("_m_s", "m/s", 1.0),
        ("_hz", "Hz", 1.0),
        ("_m", "m", 1.0),
        ("_s", "s", 1.0),
        ("_psd", "PSD, SI", 1.0),
    ];
    let mut parts: Vec<String> = Vec::new();
    for comp in key.split('.') {
        let (name, indices) = match comp.split_once('[') {
            Some((n, rest)) => (n, Some(rest)),
            None => (comp, None),
        };
        parts.push(name.replace('_', " "));
        for index in indices.into_iter().flat_map(|r| r.split('[')) {
            let n = index
                .trim_end_matches(']')
                .parse::<usize>()
                .map_or(0, |n| n + 1);
            if let Some(last) = parts.last_mut() {
                *last = format!("{last} {n}");
            }
        }
    }
    let leaf = key.rsplit('.').next().unwrap_or(key);
    let (unit, factor) = UNITS
        .iter()
        .find(|(suffix, _, _)| leaf.ends_with(suffix))
        .map_or((None, 1.0), |(suffix, unit, factor)| {
            if let Some(last) = parts.last_mut() {
                let words = suffix.trim_start_matches('_').replace('_', " ");
                *last = last.trim_end_matches(&format!(" {words}")).to_string();
            }
            (Some(*unit), *factor)
        });
    let words = parts.join(": ");
    match unit {
        Some(u) => (format!("{words} ({u})"), factor),
        None => (words, factor),
    }
}

/// Writes point `index` (value `value`) of a sweep: its results folder, `point-NN/` of
/// `dir` (as any study's), and returns its row of the sweep's summary.
pub fn write_point(
    index: usize,
    value: f64,
    study: &Study,
    tally: &Tally,
    example: Option<&ExampleRun>,
    dir: &Path,
) -> Result<SweepPoint, StudyError> {
    let summary = write_results(study, tally, example, &dir.join(point_folder(index)))?;
    Ok(point(index, value, study, tally, &summary))
}

/// Writes the sweep's own files into `dir`: its figures, `sweep.json` and `sweep.md` (with
/// `command`); returns the figures' outcomes.
pub fn write_sweep(
    summary: &SweepSummary,
    state_count: usize,
    dir: &Path,
    command: &str,
) -> Result<Vec<FigureOutcome>, StudyError> {
    let figures = crate::plots::sweep::draw(summary, state_count, dir);
    let json =
        serde_json::to_string_pretty(summary).map_err(|e| StudyError::Other(e.to_string()))?;
    write_atomic(&dir.join("sweep.json"), json.as_bytes())?;
    write_atomic(
        &dir.join("sweep.md"),
        markdown(summary, command, &figures).as_bytes(),
    )?;
    Ok(figures)
}

fn cell(v: f64, digits: usize) -> String {
    if v.is_finite() {
        format!("{v:.digits$}")
    } else {
        "-".into()
    }
}

/// `sweep.md`: the points side by side, one table per quantity, then the paired tests of the
/// heading error. `figures` are the sweep's figures; those not drawn are said so.
pub fn markdown(s: &SweepSummary, command: &str, figures: &[FigureOutcome]) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "# Sweep `{}` over `{}`\n", s.study, s.key);
    let _ = writeln!(out, "Command: `{command}`\n");
    let _ = writeln!(
        out,
        "{} points, {} runs each, the same seeds at every point and for every filter. Each \
         point's full results are in its folder (`point-NN/`).\n",
        s.points.len(),
        s.runs
    );
    for f in figures {
        match &f.result {
            Ok(()) => {
                let _ = writeln!(out, "![{}]({}.png)\n", f.caption, f.name);
            }
            Err(e) => {
                let _ = writeln!(out, "Figure `{}` could not be drawn: {e}\n", f.name);
            }
        }
    }
    type Column = fn(&PointFilter) -> String;
    let tables: [(&str, Column); 8] = [
        ("Final heading error, RMS / bound", |f| {
            cell(f.heading_rms / f.heading_bound, 3)
        }),
        ("Final heading error, RMS (deg)", |f| {
            cell(f.heading_rms.to_degrees(), 4)
        }),
        (
            "Coefficients: geometric mean over them of final RMS / bound",
            |f| cell(f.rms_over_bound_mean, 3),
        ),
        ("Average NEES at the first stored time [95 % bounds]", |f| {
            format!(
                "{} [{}, {}]",
                cell(f.nees_early, 2),
                cell(f.nees_early_bounds[0], 1),
                cell(f.nees_early_bounds[1], 1)
            )
        }),
        ("Largest average NEES over the run, and when", |f| {
            format!("{} at {} s", cell(f.nees_peak, 2), cell(f.nees_peak_t, 0))
        }),
        ("Average NEES at the end [95 % bounds]", |f| {
            format!(
                "{} [{}, {}]",
                cell(f.nees_final, 2),
                cell(f.nees_final_bounds[0], 1),
                cell(f.nees_final_bounds[1], 1)
            )
        }),
        ("Diverged runs", |f| format!("{}", f.diverged)),
        ("Median cost of one step (us)", |f| {
            cell(f.step_ns_median / 1e3, 1)
        }),
    ];
    for (title, column) in tables {
        let _ = writeln!(out, "## {title}\n");
        let _ = writeln!(out, "| {} | {} |", s.key, s.filters.join(" | "));
        let _ = writeln!(out, "|---|{}", "---|".repeat(s.filters.len()));
        for p in &s.points {
            let cells: Vec<String> = s
                .filters
                .iter()
                .map(|f| p.filters.get(f).map_or("-".into(), column))
                .collect();
            let _ = writeln!(out, "| {:e} | {} |", p.value, cells.join(" | "));
        }
        out.push('\n');
    }
    let _ = writeln!(
        out,
        "## Paired differences of the final heading error\n\nMean over runs of \
         `e_a^2 - e_b^2` (rad^2) with its 95 % confidence interval, and relative to `b`'s mean \
         squared error; significant where the interval excludes zero.\n"
    );
    let _ = writeln!(
        out,
        "| {} | a | b | mean difference | 95 % CI | relative | significant |",
        s.key
    );
    let _ = writeln!(out, "|---|---|---|---|---|---|---|");
    for p in &s.points {
        for d in &p.paired_heading {
            let _ = writeln!(
                out,
                "| {:e} | {} | {} | {:.3e} | [{:.3e}, {:.3e}] | {:+.2} % | {} |",
                p.value,
                d.a,
                d.b,
                d.mean_sq_err_diff,
                d.ci95[0],
                d.ci95[1],
                100.0 * d.relative,
                if d.significant() { "yes" } else { "no" }
            );
        }
    }
    let _ = writeln!(
        out,
        "\n## Paired differences of the coefficients\n\nPer point, how many of the paired \
         tests (pairs of filters x coefficients) find a significant difference, and the \
         largest relative one.\n"
    );
    let _ = writeln!(
        out,
        "| {} | significant / tests | largest relative |",
        s.key
    );
    let _ = writeln!(out, "|---|---|---|");
    for p in &s.points {
        let sig: Vec<&PairedDifference> = p.paired.iter().filter(|d| d.significant()).collect();
        let largest = sig
            .iter()
            .max_by(|a, b| a.relative.abs().total_cmp(&b.relative.abs()))
            .map_or("-".to_string(), |d| {
                format!(
                    "{} vs {} on {}: {:+.2} %",
                    d.a,
                    d.b,
                    d.coefficient,
                    100.0 * d.relative
                )
            });
        let _ = writeln!(
            out,
            "| {:e} | {} / {} | {} |",
            p.value,
            sig.len(),
            p.paired.len(),
            largest
        );
    }
    out
}
