//! `navkf plan` on a strapdown study with the installation's and the unit's effects in the
//! filters' model: its predicted final sigma of every coefficient agrees with the Monte Carlo
//! RMS of the same study, and it says what a level drive cannot identify.

use crate::common;

use common::run_all;
use navkf_study::plan::plan;
use navkf_study::summary::summarize;
use navkf_study::{Study, StudyConfig};

const STRAPDOWN: &str = include_str!("../../../studies/strapdown.toml");
const RUNS: usize = 150;

#[test]
fn the_strapdown_plan_agrees_with_a_monte_carlo_and_names_what_a_level_drive_hides() {
    let mut c = StudyConfig::parse(STRAPDOWN).expect("studies/strapdown.toml parses");
    let effects: Vec<String> = [
        "gyro-scale",
        "odometer-scale",
        "odometer-misalignment",
        "gps-lever-arm",
        "gps-latency",
    ]
    .map(String::from)
    .to_vec();
    c.truth.effects = effects.clone();
    c.filter.effects = effects;
    c.study.runs = RUNS;
    c.study.filters = vec!["ekf".into()];
    let study = Study::new(c).unwrap();
    let p = plan(&study).unwrap();
    assert_eq!(p.coefficients.len(), 6 + 3 + 1 + 2 + 3 + 1);
    let s = summarize(&study, &run_all(&study));
    let ekf = &s.filters["ekf"];
    assert_eq!(ekf.diverged, 0);
    // The RMS over N runs has a standard error of RMS / sqrt(2 N). baz is left out: the
    // filter's estimate of it drifts, which no bound predicts; see
    // docs/model.md, "What the horizontal model cannot see: the vertical accelerometer bias".
    let mut z2 = 0.0;
    let mut count = 0.0;
    for c in p.coefficients.iter().filter(|c| c.name != "baz") {
        let rms = ekf.final_rms[&c.name];
        let se = rms / (2.0 * RUNS as f64).sqrt();
        let z = (c.final_sigma - rms) / se;
        assert!(
            z.abs() < 3.5,
            "{}: plan {:e}, Monte Carlo {rms:e} ({z:+.2} SE)",
            c.name,
            c.final_sigma
        );
        z2 += z * z;
        count += 1.0;
    }
    assert!(z2 / count < 2.0, "mean z^2 = {}", z2 / count);
    // What a level drive with turns about the vertical identifies, and what it cannot: the
    // z gyro's scale (the turns), the odometer's scale and yaw, the latency; not the x and y
    // gyros' scales (no rotation about them) nor the antenna's height (never off level).
    let identified = p.identified();
    for name in ["s_gz", "kod", "a_y", "tau", "bgx", "bgy"] {
        assert!(
            identified.contains(&name),
            "{name} not identified: {identified:?}"
        );
    }
    for name in ["s_gx", "s_gy", "l_z", "baz"] {
        assert!(
            !identified.contains(&name),
            "{name} identified: {identified:?}"
        );
    }
}
