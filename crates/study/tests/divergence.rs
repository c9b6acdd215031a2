//! Diverged runs are counted with their reason and left out of every statistic.

use crate::common;

use common::short_config;
use navkf_dynamics::state::NAV_DIM;
use navkf_filters::DivergenceCause;
use navkf_study::summary::summarize;
use navkf_study::Study;

const RUNS: usize = 20;

#[test]
fn every_run_beyond_a_tiny_bound_is_counted_and_excluded() {
    let mut c = short_config(RUNS);
    c.divergence.max_error_initial_sigmas = 1e-6;
    let study = Study::new(c).unwrap();
    let tally = common::run_all(&study);
    let s = summarize(&study, &tally);
    for (name, f) in &s.filters {
        assert_eq!(f.diverged, RUNS as u64, "{name}");
        assert_eq!(f.runs_ok, 0, "{name}");
        assert!(f.final_rms.is_empty() && f.final_sigma.is_empty(), "{name}");
        assert!(f.nees_mean.is_nan() && f.nis_mean.is_nan(), "{name}");
        let first = &f.diverged_examples[0].failure;
        assert_eq!(first.cause, DivergenceCause::ErrorBound, "{name}");
        assert!(
            first.reason.contains("initial sigmas"),
            "{name}: {}",
            first.reason
        );
        assert_eq!(
            f.diverged_by_cause.get(&DivergenceCause::ErrorBound),
            Some(&(RUNS as u64)),
            "{name}: counted by cause"
        );
        assert_eq!(f.diverged_by_cause.len(), 1, "{name}: one cause only");
    }
    assert!(s.paired.is_empty(), "no pair of finished runs to compare");
    // The summary still writes (NaN as null) and the time series skips the filters.
    let dir = common::temp_dir("divergence");
    navkf_study::output::write_results(&study, &tally, None, &dir).unwrap();
    let csv = std::fs::read_to_string(dir.join("rms_over_time.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1, "header only");
}

#[test]
fn a_bound_that_splits_the_runs_excludes_exactly_the_runs_beyond_it() {
    // Each run's largest final coefficient error in initial sigmas, for the first filter,
    // with the default (loose) bound.
    let study = Study::new(short_config(RUNS)).unwrap();
    let records: Vec<_> = (0..RUNS).map(|r| study.run_one(r)).collect();
    let ratio = |rec: &navkf_study::monte_carlo::RunRecord| {
        let last = rec.filters[0].err.last().unwrap();
        (NAV_DIM..last.len())
            .map(|i| last[i].abs() / study.initial_sigma[i])
            .fold(0.0, f64::max)
    };
    let mut ratios: Vec<f64> = records.iter().map(ratio).collect();
    assert!(records.iter().all(|r| r.filters[0].outcome.is_ok()));
    ratios.sort_by(f64::total_cmp);
    // Halfway between two middle runs: about half the runs are beyond it.
    let bound = 0.5 * (ratios[RUNS / 2 - 1] + ratios[RUNS / 2]);
    let beyond: Vec<usize> = records
        .iter()
        .filter(|r| ratio(r) > bound)
        .map(|r| r.run)
        .collect();
    assert_eq!(beyond.len(), RUNS / 2, "the bound splits the runs");

    let mut c = short_config(RUNS);
    c.divergence.max_error_initial_sigmas = bound;
    let split = Study::new(c).unwrap();
    let tally = common::run_all(&split);
    let f = &tally.filters[0];
    let diverged: Vec<usize> = f.diverged.iter().map(|d| d.run).collect();
    assert_eq!(diverged, beyond, "exactly the runs beyond the bound");
    assert_eq!(f.ok as usize + diverged.len(), RUNS);

    // The RMS uses the finished runs only.
    let name = split.filter_names()[0].clone();
    let s = summarize(&split, &tally);
    let rms_of = |runs: &mut dyn Iterator<Item = &navkf_study::monte_carlo::RunRecord>,
                  i: usize| {
        let (mut sum, mut n) = (0.0, 0.0);
        for r in runs {
            let e = r.filters[0].err.last().unwrap()[i];
            sum += e * e;
            n += 1.0;
        }
        (sum / n).sqrt()
    };
    let mut differs = false;
    for i in NAV_DIM..split.names.len() {
        let got = s.filters[&name].final_rms[&split.names[i]];
        let ok_only = rms_of(&mut records.iter().filter(|r| !beyond.contains(&r.run)), i);
        let all = rms_of(&mut records.iter(), i);
        assert!(
            (got - ok_only).abs() <= 1e-12 * ok_only,
            "{}: RMS {got} is not the finished runs' {ok_only}",
            split.names[i]
        );
        differs |= (all - ok_only).abs() > 1e-6 * ok_only;
    }
    assert!(differs, "excluding runs changes the RMS");
}
