//! The diagnosis study's file and plan: the committed study file parses, a malformed content
//! table is refused naming its key, and the plan draws what the file says, the same every time.

use navkf_diagnose::diagnosis_study::content::{plan, Class, Hidden};
use navkf_diagnose::diagnosis_study::DiagnosisStudyConfig;

const HEAD: &str = r#"
[study]
name = "t"
kind = "diagnosis"
seed = 7
"#;

fn parse(content: &str) -> Result<DiagnosisStudyConfig, String> {
    DiagnosisStudyConfig::parse(&format!("{HEAD}{content}"))
}

#[test]
fn the_committed_study_file_parses() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../studies/diagnosis.toml");
    let text = std::fs::read_to_string(path).unwrap();
    DiagnosisStudyConfig::parse(&text).unwrap();
}

#[test]
fn a_pair_table_with_a_bad_effect_or_size_is_refused_by_key() {
    let e = parse("[[content]]\nkind = \"pair\"\ncount = 3\neffects = [\"gyro-fz\", \"nope\"]\n")
        .unwrap_err();
    assert!(
        e.contains("content[0].effects") && e.contains("nope"),
        "{e}"
    );
    let e =
        parse("[[content]]\nkind = \"pair\"\ncount = 3\neffects = [\"gyro-fz\"]\n").unwrap_err();
    assert!(e.contains("content[0].effects") && e.contains("two"), "{e}");
    let e = parse(
        "[[content]]\nkind = \"pair\"\ncount = 3\neffects = [\"gyro-fz\", \"gps-latency\", \"gyro-fz\"]\n",
    )
    .unwrap_err();
    assert!(
        e.contains("content[0].effects") && e.contains("listed twice"),
        "{e}"
    );
    let e =
        parse("[[content]]\nkind = \"pair\"\ncount = 3\nsizes = { gps-latency = [2.0, 1.0] }\n")
            .unwrap_err();
    assert!(e.contains("content[0].sizes.gps-latency"), "{e}");
    let e = parse("[[content]]\nkind = \"pair\"\ncount = 3\ncolour = 1\n").unwrap_err();
    assert!(e.contains("colour"), "{e}");
}

#[test]
fn a_restricted_pair_table_draws_only_its_effects_within_its_sizes() {
    let cfg = parse(
        r#"
[[content]]
kind = "pair"
count = 40
effects = ["gps-latency", "torquer-scale", "odometer-scale"]
sizes = { torquer-scale = [40.0, 100.0] }
"#,
    )
    .unwrap();
    let planned = plan(&cfg).unwrap();
    assert_eq!(planned.len(), 40);
    let mut torquer = 0;
    for p in &planned {
        assert_eq!(p.class, Class::Pair);
        assert_eq!(p.hidden.len(), 2);
        let names: Vec<&str> = p
            .hidden
            .iter()
            .map(|h| match h {
                Hidden::Effect { name, multiple, .. } => {
                    if name == "torquer-scale" {
                        torquer += 1;
                        assert!((40.0..=100.0).contains(multiple), "{multiple}");
                    } else {
                        assert!((0.1..=100.0).contains(multiple), "{multiple}");
                    }
                    name.as_str()
                }
                other => panic!("a pair hid {other:?}"),
            })
            .collect();
        assert_ne!(names[0], names[1]);
        for n in names {
            assert!(["gps-latency", "torquer-scale", "odometer-scale"].contains(&n));
        }
    }
    // Two of the three possible pairs hold the torquer: about 27 of 40.
    assert!((15..=38).contains(&torquer), "{torquer}");
    let again = plan(&cfg).unwrap();
    assert_eq!(format!("{planned:?}"), format!("{again:?}"));
}

#[test]
fn the_committed_study_hides_at_least_300_things_outside_the_catalogue_of_five_kinds() {
    use navkf_dynamics::sensor_faults::SensorFault as Fault;
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../studies/diagnosis.toml");
    let config = DiagnosisStudyConfig::parse(&std::fs::read_to_string(path).unwrap()).unwrap();
    let planned = plan(&config).unwrap();
    let outside: Vec<&Hidden> = planned
        .iter()
        .filter(|p| p.class == Class::Outside)
        .flat_map(|p| &p.hidden)
        .collect();
    assert!(outside.len() >= 300, "{} outside", outside.len());
    let mut kinds = std::collections::BTreeMap::new();
    for h in &outside {
        *kinds.entry(h.label()).or_insert(0) += 1;
        if let Hidden::Fault { multiple, fault } = h {
            match *fault {
                Fault::GpsStep {
                    offset_m,
                    start_s,
                    duration_s,
                } => {
                    // `multiple` typical offsets (3 m) per axis, in any direction.
                    let size = offset_m[0].hypot(offset_m[1]);
                    assert!((size - multiple * 3.0 * 2f64.sqrt()).abs() < 1e-9);
                    assert!((120.0..=600.0).contains(&duration_s));
                    assert!(start_s >= 0.0 && start_s + duration_s <= 2400.0);
                }
                Fault::OdometerSlip { gain_s2_m } => {
                    assert!((gain_s2_m - multiple * 0.02).abs() < 1e-12)
                }
                Fault::GpsLeverArm { forward_m, right_m } => {
                    assert!((forward_m.abs() - multiple * 1.5).abs() < 1e-12);
                    assert!(right_m.abs() <= 0.25 * forward_m.abs() + 1e-12);
                }
            }
        }
    }
    assert_eq!(kinds.len(), 5, "{kinds:?}");
    assert!(kinds.values().all(|&n| n == 60), "{kinds:?}");
}
