//! `docs/study-files.md` held to the code:
//! - every ```` ```toml study ```` block parses with `StudyConfig::parse` and builds with
//!   `Study::new` (a sweep: every point of `sweep::points`);
//! - the ```` ```toml diagnosis-study ```` block loads with `DiagnosisStudyConfig::load`, plans,
//!   and one dataset of each of its classes simulates;
//! - every key the study structs serialise (defaults and examples) and every `kind` the
//!   examples use is named in the page, and every number the page gives as a key's default is
//!   that key's default in the code.

use navkf_diagnose::diagnosis_study::content::{plan, simulate};
use navkf_diagnose::diagnosis_study::{dataset_count, DiagnosisStudyConfig};
use navkf_dynamics::segments::SegmentSpec;
use navkf_dynamics::Trajectory;
use navkf_study::{sweep, Study, StudyConfig};
use std::collections::{BTreeMap, BTreeSet};
use std::sync::Arc;

#[path = "../../dynamics/tests/common/markdown.rs"]
mod markdown;

use markdown::fenced;

fn page() -> String {
    markdown::doc("study-files.md")
}

fn studies(md: &str) -> Vec<StudyConfig> {
    let blocks = fenced(md, "toml study");
    assert!(blocks.len() >= 2, "expected the page's study examples");
    blocks
        .iter()
        .enumerate()
        .map(|(i, b)| StudyConfig::parse(b).unwrap_or_else(|e| panic!("study example {i}: {e}")))
        .collect()
}

fn diagnosis_study(md: &str) -> DiagnosisStudyConfig {
    let blocks = fenced(md, "toml diagnosis-study");
    assert_eq!(blocks.len(), 1, "expected one diagnosis-study example");
    // Parsed from the text: two tests in this process read the example at once, and a
    // shared temporary file raced between them.
    DiagnosisStudyConfig::parse(&blocks[0])
        .unwrap_or_else(|e| panic!("the diagnosis-study example: {e}"))
}

#[test]
fn the_study_examples_build() {
    let md = page();
    let mut swept = 0;
    for (i, config) in studies(&md).into_iter().enumerate() {
        let Some(s) = config.sweep.clone() else {
            Study::new(config).unwrap_or_else(|e| panic!("study example {i}: {e}"));
            continue;
        };
        swept += 1;
        let points = sweep::points(&config).unwrap_or_else(|e| panic!("example {i}: {e}"));
        assert_eq!(points.len(), s.values.len());
        for (point, v) in points.into_iter().zip(&s.values) {
            // The indexed key of the page's sweep reaches the segment it names.
            if s.key == "trajectory.segment[1].to" {
                assert!(
                    matches!(point.trajectory.segments[1], SegmentSpec::Speed { to, .. } if to == *v),
                    "{:?}",
                    point.trajectory.segments[1]
                );
            }
            Study::new(point).unwrap_or_else(|e| panic!("example {i} at {v}: {e}"));
        }
    }
    assert!(swept >= 1, "expected a sweep example");
}

#[test]
fn the_diagnosis_study_example_loads_plans_and_simulates() {
    let config = diagnosis_study(&page());
    let planned = plan(&config).unwrap();
    assert_eq!(planned.len(), dataset_count(&config));
    let trajectory = Arc::new(Trajectory::build(&config.trajectory).unwrap());
    let mut seen = BTreeSet::new();
    for p in planned.iter().filter(|p| seen.insert(p.class)) {
        simulate(&config, &trajectory, p)
            .unwrap_or_else(|e| panic!("dataset {} ({:?}): {e}", p.index, p.class));
    }
    assert_eq!(seen.len(), 5, "one dataset of each content kind: {seen:?}");
}

/// Tables whose keys are names the user chooses (coefficients, labels, effects), not settings.
const NAMED: [&str; 5] = [
    "truth.coefficients",
    "filter.initial.coefficient_sigma",
    "filter.variants",
    "sizes",
    "content[].sizes",
];

/// Every setting key under `value` (at `path`) into `keys`, with the `kind` values into
/// `kinds`, and every numeric leaf's value into `numbers` by key.
fn walk(
    value: &toml::Value,
    path: &str,
    keys: &mut BTreeSet<String>,
    kinds: &mut BTreeSet<String>,
    numbers: &mut BTreeMap<String, Vec<f64>>,
) {
    match value {
        toml::Value::Table(t) => {
            let named = NAMED.contains(&path);
            for (k, v) in t {
                let here = if named {
                    format!("{path}.*")
                } else {
                    keys.insert(k.clone());
                    if path.is_empty() {
                        k.clone()
                    } else {
                        format!("{path}.{k}")
                    }
                };
                if let (false, "kind", Some(s)) = (named, k.as_str(), v.as_str()) {
                    kinds.insert(s.to_string());
                }
                match v {
                    toml::Value::Float(x) => numbers.entry(k.clone()).or_default().push(*x),
                    toml::Value::Integer(x) => {
                        numbers.entry(k.clone()).or_default().push(*x as f64)
                    }
                    _ => {}
                }
                walk(v, &here, keys, kinds, numbers);
            }
        }
        toml::Value::Array(a) => {
            for v in a {
                walk(v, &format!("{path}[]"), keys, kinds, numbers);
            }
        }
        _ => {}
    }
}

const MINIMAL: &str = "[study]\nname = \"m\"\nruns = 1\nseed = 0\nfilters = [\"ekf\"]\n";
const MINIMAL_DIAGNOSIS: &str =
    "[study]\nname = \"m\"\nkind = \"diagnosis\"\nseed = 0\n[[content]]\nkind = \"nothing\"\ncount = 1\n";

/// The keys, kinds and default numbers of the minimal files (what the code fills in), and
/// the keys and kinds of the page's examples.
fn settings(
    md: &str,
) -> (
    BTreeSet<String>,
    BTreeSet<String>,
    BTreeMap<String, Vec<f64>>,
) {
    let (mut keys, mut kinds, mut defaults) = Default::default();
    let mut example_numbers = BTreeMap::new();
    let minimal = StudyConfig::parse(MINIMAL).unwrap();
    let minimal_diagnosis = DiagnosisStudyConfig::parse(MINIMAL_DIAGNOSIS).unwrap();
    walk(
        &toml::Value::try_from(&minimal).unwrap(),
        "",
        &mut keys,
        &mut kinds,
        &mut defaults,
    );
    walk(
        &toml::Value::try_from(&minimal_diagnosis).unwrap(),
        "",
        &mut keys,
        &mut kinds,
        &mut defaults,
    );
    for config in studies(md) {
        let v = toml::Value::try_from(&config).unwrap();
        walk(&v, "", &mut keys, &mut kinds, &mut example_numbers);
    }
    let v = toml::Value::try_from(diagnosis_study(md)).unwrap();
    walk(&v, "", &mut keys, &mut kinds, &mut example_numbers);
    (keys, kinds, defaults)
}

#[test]
fn every_key_and_kind_is_named_and_every_default_is_the_codes() {
    let md = page();
    let (keys, kinds, defaults) = settings(&md);
    // Words inside the page's code spans: `[truth.initial_tilt]` names `initial_tilt`.
    let named: BTreeSet<&str> = md
        .split('`')
        .skip(1)
        .step_by(2)
        .flat_map(|span| span.split(|c: char| !(c.is_ascii_alphanumeric() || c == '_' || c == '-')))
        .collect();
    for k in keys.iter().chain(&kinds) {
        assert!(
            named.contains(k.as_str()),
            "docs/study-files.md never names `{k}` in code"
        );
    }
    // Rows `| `key` | float | unit | DEFAULT | ...` and `| `key` | integer | ...`.
    let mut checked = 0;
    for line in md.lines().filter(|l| l.starts_with("| `")) {
        let cells: Vec<&str> = line.trim_matches('|').split('|').map(str::trim).collect();
        let key = cells[0].trim_matches('`');
        let default = match cells.get(1) {
            Some(&"float") | Some(&"integer") => cells.get(3).and_then(|c| c.parse::<f64>().ok()),
            _ => None,
        };
        let Some(default) = default else { continue };
        let code = defaults.get(key).unwrap_or_else(|| {
            panic!("`{key}` has a documented default but no default in the code")
        });
        assert!(
            code.contains(&default),
            "`{key}`: the page gives the default {default}, the code {code:?}"
        );
        checked += 1;
    }
    assert!(
        checked >= 25,
        "only {checked} defaults found in the page's tables"
    );
}
