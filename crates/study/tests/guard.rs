//! The accuracy guard on a short study: the baseline passes against itself and against a
//! rerun (bit for bit, same seed), and deliberately mis-tuned filters fail with a table that
//! names the filter and the coefficient.

use crate::common;

use common::short_config;
use navkf_study::guard::{compare, settings_differences, DEFAULT_K};
use navkf_study::summary::{summarize, Summary};
use navkf_study::Study;

const RUNS: usize = 20;

fn summary_of(config: navkf_study::StudyConfig) -> Summary {
    let study = Study::new(config).unwrap();
    summarize(&study, &common::run_all(&study))
}

#[test]
fn the_baseline_passes_against_itself_and_a_rerun() {
    let base = summary_of(short_config(RUNS));
    let r = compare(&base, &base, DEFAULT_K);
    assert!(r.passed(), "{}", r.table());
    // 3 filters: 13 coefficients, NEES, NIS and the divergence count each.
    assert_eq!(r.checks, 3 * 16);
    assert_eq!(r.identical, r.checks);

    // A rerun, and the baseline read back from its JSON file: identical bit for bit.
    let again = summary_of(short_config(RUNS));
    let dir = common::temp_dir("guard");
    let path = dir.join("summary.json");
    std::fs::write(&path, serde_json::to_string_pretty(&base).unwrap()).unwrap();
    let stored = navkf_study::guard::load_baseline(&path).unwrap();
    let r = compare(&stored, &again, DEFAULT_K);
    assert!(r.passed(), "{}", r.table());
    assert_eq!(r.identical, r.checks, "same seed and code: identical");
    assert!(r.table().contains("accuracy guard passed"), "{}", r.table());
    assert!(settings_differences(&stored, &again.settings).is_empty());
}

#[test]
fn mistuned_filters_fail_with_a_table_naming_filter_and_coefficient() {
    let base = summary_of(short_config(RUNS));
    // Process noise 100 times the truth's: the filters forget what they learnt of the gyro
    // drifts. On this study Kg0x's and Kg0y's RMS errors grow about 3.2 to 3.5 times, against
    // a tolerance of +89 % (4 * sqrt(1/40 + 1/40) for 20 runs each).
    let mut c = short_config(RUNS);
    c.filter.process_noise_scale = 100.0;
    let worse = summary_of(c);
    for (name, f) in &worse.filters {
        let (b, w) = (base.filters[name].final_rms["Kg0x"], f.final_rms["Kg0x"]);
        assert!(w > 2.5 * b, "{name}: Kg0x RMS {b:e} -> {w:e}: not degraded");
    }
    let r = compare(&base, &worse, DEFAULT_K);
    let table = r.table();
    println!("{table}");
    assert!(!r.passed());
    assert!(table.contains("accuracy guard FAILED"), "{table}");
    for filter in ["ekf", "standard_ukf", "simplified_ukf"] {
        for coef in ["Kg0x", "Kg0y"] {
            assert!(
                table.contains(&format!("| {filter} | RMS {coef} |")),
                "{filter} {coef} not flagged:\n{table}"
            );
        }
    }
    // Coefficients the trajectory cannot separate stay at their prior and are not flagged.
    assert!(!table.contains("RMS Kg11x"), "{table}");
    // The settings check tells what differs.
    let diffs = settings_differences(&base, &worse.settings);
    assert_eq!(diffs.len(), 1, "{diffs:?}");
    assert!(
        diffs[0].starts_with("filter.process_noise_scale: 1.0 in the baseline, 100.0 now"),
        "{diffs:?}"
    );
}
