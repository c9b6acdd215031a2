//! `plan` predicts, from one bound recursion, what the Monte Carlo RMS of the same study is.

mod common;

use common::{run_all, short_config};
use navkf_study::plan::plan;
use navkf_study::summary::summarize;
use navkf_study::Study;

const RUNS: usize = 200;

#[test]
fn the_plan_agrees_with_a_200_run_monte_carlo() {
    let mut c = short_config(RUNS);
    c.study.filters = vec!["ekf".into()];
    let study = Study::new(c).unwrap();
    let p = plan(&study).unwrap();
    let s = summarize(&study, &run_all(&study));
    let ekf = &s.filters["ekf"];
    assert_eq!(ekf.diverged, 0);
    assert_eq!(p.coefficients.len(), 13);
    // The RMS over N runs has a standard error of RMS / sqrt(2 N). Each coefficient within
    // 3 of them, and on average (z^2) no further than chance allows.
    let mut z2 = 0.0;
    for c in &p.coefficients {
        let rms = ekf.final_rms[&c.name];
        let se = rms / (2.0 * RUNS as f64).sqrt();
        let z = (c.final_sigma - rms) / se;
        assert!(
            z.abs() < 3.0,
            "{}: plan {:e}, Monte Carlo {rms:e} ({z:+.2} SE)",
            c.name,
            c.final_sigma
        );
        z2 += z * z;
    }
    assert!(z2 / 13.0 < 2.0, "mean z^2 = {}", z2 / 13.0);
    // On this test the constant drifts are learnt and the level-platform confusions show.
    let ka0x = p.coefficients.iter().find(|c| c.name == "Ka0x").unwrap();
    assert!(!ka0x.identified);
    assert!(
        ka0x.confounded
            .iter()
            .any(|k| k.with == "phi_y" && k.correlation > 0.99),
        "{:?}",
        ka0x.confounded
    );
    assert!(p.identified().contains(&"Kg0x"));
    // The series start at the prior and end at the final sigma.
    for (c, series) in p.coefficients.iter().zip(&p.sigma_over_prior) {
        assert_eq!(series.len(), p.t.len());
        assert!((series.last().unwrap() - c.ratio).abs() < 1e-12);
    }
}
