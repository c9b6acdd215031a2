//! Figures and report.md from a tiny real study (the paper's study file, 2 runs on a 600 s
//! path): every figure is written as PNG and SVG with its title, and degenerate data (every
//! run of a filter diverged, NaN, one stored time, nothing at all) draws without a panic.

use crate::common;

use common::Scratch;
use navkf_filters::{DivergenceCause, RunFailure};
use navkf_report::stats::Consistency;
use navkf_study::monte_carlo::ExampleRun;
use navkf_study::output::{fold, write_results};
use navkf_study::summary::summarize;
use navkf_study::tally::Divergence;
use navkf_study::{plots, report, Study, StudyConfig, Tally};
use std::path::Path;

/// The paper's study, shortened like the filter tests' scenarios: 2 runs, 600 s.
fn tiny(series_every_s: f64) -> (Study, Tally, Option<ExampleRun>) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../studies/paper.toml");
    let mut c = StudyConfig::load(&path).unwrap();
    c.study.runs = 2;
    c.study.example_run = 0;
    c.study.series_every_s = series_every_s;
    c.trajectory.duration_s = 600.0;
    c.trajectory.initial_standstill_s = 30.0;
    c.trajectory.leg_north_m = 1500.0;
    c.trajectory.leg_east_m = 1000.0;
    let study = Study::new(c).unwrap();
    let mut example = None;
    let blocks = study
        .run_blocks(0..study.block_count(), &|_| {}, |rec| {
            example = Some(study.example_of(rec))
        })
        .expect("not interrupted");
    let tally = fold(&blocks);
    (study, tally, example)
}

fn scratch(name: &str) -> Scratch {
    Scratch::new(&format!("plots-{name}"))
}

/// The figure exists as a non-empty PNG and an SVG; returns the SVG's text.
fn figure(dir: &Path, name: &str) -> String {
    let png = std::fs::read(dir.join(format!("{name}.png")))
        .unwrap_or_else(|e| panic!("{name}.png: {e}"));
    assert!(
        png.starts_with(b"\x89PNG\r\n\x1a\n"),
        "{name}.png is not a PNG"
    );
    assert!(png.len() > 5_000, "{name}.png is nearly empty");
    let svg = std::fs::read_to_string(dir.join(format!("{name}.svg")))
        .unwrap_or_else(|e| panic!("{name}.svg: {e}"));
    assert!(svg.contains("<svg") && svg.contains("</svg>"), "{name}.svg");
    assert!(svg.contains("<text"), "{name}.svg has no text");
    svg
}

fn no_temporaries(dir: &Path) {
    for e in std::fs::read_dir(dir).unwrap() {
        let name = e.unwrap().file_name().to_string_lossy().into_owned();
        assert!(!name.contains(".tmp"), "temporary file left behind: {name}");
    }
}

#[test]
fn every_figure_and_the_report_are_written() {
    let (study, tally, example) = tiny(10.0);
    let ex = example.as_ref().expect("run 0 is the example");
    let dir = scratch("all");
    write_results(&study, &tally, Some(ex), &dir).unwrap();

    let svg = figure(&dir, "rms_over_time");
    assert!(svg.contains(plots::RMS_TITLE));
    assert!(svg.contains("Kg0x") && svg.contains("Ka1y"));
    assert!(svg.contains("RMS error / initial sigma"));
    assert!(figure(&dir, "step_cost").contains(plots::STEP_COST_TITLE));
    let svg = figure(&dir, "nees_nis_over_time");
    assert!(svg.contains(plots::NEES_NIS_TITLE));
    assert!(svg.contains("95 % band"));
    assert!(figure(&dir, "estimates_all").contains(plots::ESTIMATES_ALL_TITLE));
    for name in &study.names[7..] {
        let svg = figure(&dir, &format!("estimates_{name}"));
        assert!(svg.contains(&format!("{name}: estimate vs truth, run 0")));
    }
    let svg = figure(&dir, "estimates_Kg0x");
    assert!(svg.contains("deg/h"), "drifts are shown in deg/h");
    assert!(svg.contains("time (s)"));

    let md = std::fs::read_to_string(dir.join("report.md")).unwrap();
    for needle in [
        "# Monte Carlo study `paper`",
        "## Settings",
        "| coefficient |",
        "## Paired differences",
        "95 % interval",
        "## Consistency",
        "](rms_over_time.png)",
        "](nees_nis_over_time.png)",
        "](estimates_all.png)",
        "](step_cost.png)",
        "[Kg0x](estimates_Kg0x.png)",
        "## Diverged runs",
    ] {
        assert!(md.contains(needle), "report.md lacks {needle:?}");
    }
    no_temporaries(&dir);
}

#[test]
fn report_states_the_command_and_verdicts() {
    let (study, tally, example) = tiny(10.0);
    let dir = scratch("command");
    report::write_report(
        &study,
        &tally,
        example.as_ref(),
        &dir,
        "navkf study studies/paper.toml --runs 2",
    )
    .unwrap();
    let md = std::fs::read_to_string(dir.join("report.md")).unwrap();
    assert!(md.contains("navkf study studies/paper.toml --runs 2"));
    let s = summarize(&study, &tally);
    for (name, f) in &s.filters {
        let v = Consistency::of(f.nees_mean, f.nees_bounds).as_str();
        assert!(md.contains(&format!("**{name}**")), "{name}");
        assert!(["consistent", "optimistic", "pessimistic"].contains(&v));
    }
    assert_eq!(Consistency::of(30.0, [10.0, 20.0]).as_str(), "optimistic");
    assert_eq!(Consistency::of(5.0, [10.0, 20.0]).as_str(), "pessimistic");
    assert_eq!(Consistency::of(15.0, [10.0, 20.0]).as_str(), "consistent");
    assert_eq!(
        Consistency::of(f64::NAN, [10.0, 20.0]).as_str(),
        "no verdict"
    );
}

#[test]
fn a_filter_with_every_run_diverged_does_not_panic() {
    let (study, mut tally, example) = tiny(10.0);
    let mut ex = example.unwrap();
    // The first filter: every run diverged, nothing summed, no steps timed; no trace in
    // the example run. The second: NaN in its trace and its sums.
    let f = &mut tally.filters[0];
    let diverged = (0..tally.runs)
        .map(|run| Divergence {
            run,
            failure: RunFailure {
                cause: DivergenceCause::ErrorBound,
                reason: "final Kg0x error is 99.0 initial sigmas (bound 50)".into(),
            },
        })
        .collect();
    *f = navkf_study::tally::FilterTally {
        diverged,
        ..Default::default()
    };
    ex.filters[0].t.clear();
    ex.filters[0].estimate.clear();
    ex.filters[0].sigma.clear();
    for x in &mut ex.filters[1].estimate {
        x[8] = f64::NAN;
    }
    for row in &mut tally.filters[1].sum_sq_err {
        row[9] = f64::NAN;
    }
    tally.filters[1].sum_nees[3] = f64::NAN;
    // No bound either.
    tally.bound = Default::default();

    let dir = scratch("diverged");
    report::write_report(&study, &tally, Some(&ex), &dir, "test").unwrap();
    for name in [
        "rms_over_time",
        "nees_nis_over_time",
        "step_cost",
        "estimates_all",
        "estimates_Kg11x",
    ] {
        let svg = figure(&dir, name);
        if name != "estimates_all" && name != "estimates_Kg11x" {
            assert!(svg.contains("no run finished") || svg.contains("no steps timed"));
        }
    }
    assert!(figure(&dir, "estimates_Kg0x").contains("no estimates in this run"));
    let md = std::fs::read_to_string(dir.join("report.md")).unwrap();
    assert!(md.contains("no run finished, so no verdict"));
    assert!(md
        .contains("run 1 (final error beyond the bound): final Kg0x error is 99.0 initial sigmas"));
    assert!(
        md.contains("diverged (2 final error beyond the bound)"),
        "counted by cause"
    );
}

#[test]
fn one_stored_time_and_an_empty_tally_do_not_panic() {
    // series_every_s beyond the duration: one stored time, the final one.
    let (study, tally, example) = tiny(1000.0);
    assert_eq!(study.times.len(), 1);
    let dir = scratch("single");
    report::write_report(&study, &tally, example.as_ref(), &dir, "test").unwrap();
    figure(&dir, "rms_over_time");
    figure(&dir, "nees_nis_over_time");

    // Nothing at all: no runs, no filters' sums, no example trace.
    let empty = Tally::default();
    let s = summarize(&study, &empty);
    let ex = ExampleRun {
        names: study.names.clone(),
        ..Default::default()
    };
    let dir2 = scratch("empty");
    plots::rms_over_time(&study, &empty, &dir2).unwrap();
    plots::nees_nis_over_time(&study, &empty, &dir2).unwrap();
    plots::step_cost(&study, &empty, &s, &dir2).unwrap();
    plots::estimates_all(&study, &ex, &dir2).unwrap();
    plots::estimates(&study, &ex, 7, &dir2).unwrap();
    assert!(figure(&dir2, "rms_over_time").contains("no data to draw"));
    assert!(figure(&dir2, "estimates_Kg0x").contains("no data to draw"));
    no_temporaries(&dir2);
}

#[test]
fn a_spacing_below_the_measurement_interval_stores_every_measurement() {
    // 0.3 s with 1 Hz measurements: every measurement time once, and no run counted as
    // stopped early (it used to index past the bound's series after all the runs).
    let (study, tally, example) = tiny(0.3);
    let dt = 1.0 / study.config.truth.measurement_rate_hz;
    assert_eq!(study.times.len(), 600);
    for (i, t) in study.times.iter().enumerate() {
        assert!(
            (t - (i + 1) as f64 * dt).abs() < 1e-9,
            "stored time {i} is {t}"
        );
    }
    // However small the spacing, the same times, found in one step per stored time (a loop
    // over the multiples of 1e-9 s would not finish).
    let (finest, _, _) = tiny(1e-9);
    assert_eq!(finest.times, study.times);
    // A spacing off the grid lands on the next measurement: 2.5 s stores 3, 5, 8, 10, ...
    let (coarse, _, _) = tiny(2.5);
    assert_eq!(&coarse.times[..4], &[3.0, 5.0, 8.0, 10.0]);
    let s = summarize(&study, &tally);
    for (name, f) in &s.filters {
        assert_eq!(f.diverged, 0, "{name}: {:?}", f.diverged_examples);
        assert_eq!(f.runs_ok, 2, "{name}");
    }
    let dir = scratch("fine");
    report::write_report(&study, &tally, example.as_ref(), &dir, "test").unwrap();
}
