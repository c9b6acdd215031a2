//! Attitude equations and filter variants in study files: the exact-attitude truth at small
//! angles gives the base model's results, and `[filter.variants]` are parsed, checked and run
//! under their labels.

use crate::common;

use common::{run_all, short_config, PAPER};
use navkf_dynamics::Attitude;
use navkf_study::summary::summarize;
use navkf_study::{Study, StudyConfig};

const RUNS: usize = 40;

/// The paper's filters plus the EKF on the exact model, under the label `ekf_exact`.
fn with_exact_ekf(truth: Attitude) -> StudyConfig {
    let mut c = short_config(RUNS);
    c.truth.attitude = truth;
    c.study.filters = vec!["ekf".into(), "simplified_ukf".into(), "ekf_exact".into()];
    c.filter.variants.insert(
        "ekf_exact".into(),
        navkf_study::config::FilterVariant {
            kind: navkf_filters::FilterKind::Ekf,
            attitude: Some(Attitude::Exact),
            alpha: None,
            beta: None,
            kappa: None,
        },
    );
    c.validate().unwrap();
    c
}

#[test]
fn an_exact_truth_at_small_angles_gives_the_base_models_results() {
    let summaries: Vec<_> = [Attitude::SmallAngle, Attitude::Exact]
        .into_iter()
        .map(|a| {
            let study = Study::new(with_exact_ekf(a)).unwrap();
            summarize(&study, &run_all(&study))
        })
        .collect();
    let (base, exact) = (&summaries[0], &summaries[1]);
    // The Monte Carlo standard error of an RMS over RUNS runs is RMS / sqrt(2 RUNS); the two
    // truths share every seed, so they differ by far less. Both are held to a tenth of it.
    let tolerance = 0.1 / (2.0 * RUNS as f64).sqrt();
    let mut compared = 0;
    for (name, fb) in &base.filters {
        let fe = &exact.filters[name];
        assert_eq!(fb.diverged + fe.diverged, 0, "{name}");
        for (coef, rb) in &fb.final_rms {
            let re = fe.final_rms[coef];
            assert!(
                (re - rb).abs() <= tolerance * rb,
                "{name} {coef}: final RMS {re:e} (exact truth) vs {rb:e} (base truth)"
            );
            compared += 1;
        }
        assert!(
            (fe.nees_mean - fb.nees_mean).abs() < 0.05,
            "{name}: NEES {} vs {}",
            fe.nees_mean,
            fb.nees_mean
        );
        // Consistent as well: mean NEES within its 95 % bounds on either truth.
        for s in [fb, fe] {
            assert!(
                s.nees_mean > s.nees_bounds[0] && s.nees_mean < s.nees_bounds[1],
                "{name}: NEES {} outside {:?}",
                s.nees_mean,
                s.nees_bounds
            );
        }
    }
    assert_eq!(compared, 3 * 13);
    // And the filter on the exact model equals the one on the small-angle model there.
    for (coef, r) in &exact.filters["ekf"].final_rms {
        let re = exact.filters["ekf_exact"].final_rms[coef];
        assert!((re - r).abs() <= tolerance * r, "{coef}: {re:e} vs {r:e}");
    }
}

fn parse_error(extra_filters: &str, tables: &str) -> String {
    let text = PAPER.replace(
        r#"filters = ["ekf", "standard_ukf", "simplified_ukf"]"#,
        &format!(r#"filters = ["ekf", "standard_ukf", "simplified_ukf"{extra_filters}]"#),
    );
    assert!(
        PAPER.contains(r#"filters = ["ekf", "standard_ukf", "simplified_ukf"]"#),
        "the filters line of studies/paper.toml changed"
    );
    match StudyConfig::parse(&format!("{text}\n{tables}")) {
        Ok(_) => panic!("accepted: {extra_filters} / {tables}"),
        Err(e) => e,
    }
}

#[test]
fn filter_variants_are_checked_with_their_key() {
    let ok = PAPER.replace(
        r#"filters = ["ekf", "standard_ukf", "simplified_ukf"]"#,
        r#"filters = ["ekf", "cubature"]"#,
    ) + "\n[filter.variants.cubature]\nkind = \"simplified_ukf\"\nalpha = 1.0\nbeta = 0.0\nkappa = 0.0\nattitude = \"exact\"\n";
    let c = StudyConfig::parse(&ok).unwrap();
    let plan = c.filter.plan("cubature").unwrap();
    assert_eq!(plan.kind.name(), "simplified_ukf");
    assert_eq!(plan.attitude, Attitude::Exact);
    assert_eq!(
        (plan.scaling.alpha, plan.scaling.beta, plan.scaling.kappa),
        (1.0, 0.0, 0.0)
    );
    // What the variant leaves out comes from [filter].
    assert_eq!(c.filter.plan("ekf").unwrap().attitude, Attitude::SmallAngle);

    let e = parse_error(r#", "nope""#, "");
    assert!(
        e.contains("study.filters[3]") && e.contains("unknown filter `nope`"),
        "{e}"
    );
    let e = parse_error(r#", "v""#, "[filter.variants.v]\nkind = \"ukf\"\n");
    // Refused where it is read, by line and column, with the list of filters.
    assert!(
        e.contains("column 8") && e.contains("unknown filter `ukf`; expected one of ekf"),
        "{e}"
    );
    let e = parse_error("", "[filter.variants.unused]\nkind = \"ekf\"\n");
    assert!(
        e.contains("filter.variants.unused is defined but not listed"),
        "{e}"
    );
    let e = parse_error("", "[filter.variants.ekf]\nkind = \"simplified_ukf\"\n");
    assert!(e.contains("cannot take a filter kind's name"), "{e}");
    let e = parse_error(
        r#", "v""#,
        "[filter.variants.v]\nkind = \"ekf\"\nalpah = 1.0\n",
    );
    assert!(e.contains("alpah"), "{e}");
    let e = parse_error(
        r#", "v""#,
        "[filter.variants.v]\nkind = \"ekf\"\nattitude = \"big\"\n",
    );
    assert!(e.contains("big"), "{e}");
    let text = PAPER.replace("[truth]\n", "[truth]\nattitude = \"sideways\"\n");
    let e = StudyConfig::parse(&text).unwrap_err();
    assert!(e.contains("sideways"), "{e}");
}
