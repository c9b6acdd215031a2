//! A diagnosis study of the strapdown family: the committed file parses and hides what its
//! comments say, what the family does not read is refused by key, and the datasets it makes
//! carry the drawn content (effects at their drawn values, faults in the readings, a noise
//! stated off in the fifth source too).

use navkf_diagnose::diagnosis_study::content::{plan, simulate, Class, Hidden};
use navkf_diagnose::diagnosis_study::DiagnosisStudyConfig;
use navkf_dynamics::strapdown::effects::StrapdownRegistry;
use navkf_dynamics::strapdown::unit_class::UnitClass;
use navkf_dynamics::{ModelKind, Trajectory};
use std::collections::BTreeMap;
use std::sync::Arc;

const HEAD: &str = r#"
[study]
name = "t"
kind = "diagnosis"
seed = 7

[model]
kind = "strapdown"

[noise]
nhc_m_s = 0.1
"#;

fn parse(rest: &str) -> Result<DiagnosisStudyConfig, String> {
    DiagnosisStudyConfig::parse(&format!("{HEAD}{rest}"))
}

/// The committed study file `studies/NAME.toml`.
fn study_file(name: &str) -> DiagnosisStudyConfig {
    let path = format!("{}/../../studies/{name}.toml", env!("CARGO_MANIFEST_DIR"));
    DiagnosisStudyConfig::parse(&std::fs::read_to_string(path).unwrap()).unwrap()
}

fn committed() -> DiagnosisStudyConfig {
    study_file("strapdown-diagnosis")
}

/// A detection study is `base` with its own `[study]` (another seed) and `[[content]]`: the
/// same drives, unit, noise and rules, more of them per effect. Returns its datasets'
/// single-effect count per effect.
fn detection_study_of(base: &str, detection: &str) -> (usize, BTreeMap<String, usize>) {
    let detection = study_file(detection);
    let mut same = study_file(base);
    assert_ne!(detection.study.seed, same.study.seed, "draws of its own");
    same.study = detection.study.clone();
    same.content = detection.content.clone();
    assert_eq!(same, detection, "only [study] and [[content]] differ");
    let planned = plan(&detection).unwrap();
    let mut singles = BTreeMap::new();
    for p in planned.iter().filter(|p| p.class == Class::Single) {
        *singles
            .entry(p.hidden[0].effect().unwrap().to_string())
            .or_insert(0) += 1;
    }
    (planned.len(), singles)
}

#[test]
fn the_manoeuvre_study_drives_its_own_test_and_hides_the_four_effects_it_names() {
    let config = study_file("strapdown-manoeuvres");
    assert_eq!(config.model.kind, ModelKind::Strapdown);
    assert_eq!(
        config.trajectory.segments.len(),
        2,
        "a hold and the repeated cycle"
    );
    Trajectory::build(&config.trajectory).unwrap();
    let planned = plan(&config).unwrap();
    let count = |class: Class, effect: Option<&str>| {
        planned
            .iter()
            .filter(|p| p.class == class && effect.is_none_or(|e| p.hidden[0].effect() == Some(e)))
            .count()
    };
    assert_eq!(count(Class::Nothing, None), 50);
    for effect in [
        "gyro-misalignment",
        "accel-misalignment",
        "gyro-g-sensitivity",
        "accel-bias-instability",
    ] {
        assert_eq!(count(Class::Single, Some(effect)), 30, "{effect}");
    }
    assert_eq!(planned.len(), 170);
}

/// The detection study measures the limits of the error-rate study's drives on more of them:
/// it is that study's file in every section but `[study]` and `[[content]]`, and hides each
/// catalogued effect alone on 100 drives (README's limits are its).
#[test]
fn the_detection_study_is_the_error_rate_study_with_100_drives_per_effect() {
    let (datasets, singles) = detection_study_of("strapdown-diagnosis", "strapdown-detection");
    let registry = StrapdownRegistry::catalogue();
    for name in registry.names() {
        assert_eq!(singles.get(name), Some(&100), "{name}");
    }
    assert_eq!(datasets, 100 * registry.names().len());
}

/// Likewise the stop-and-go drive's detection study: `strapdown-manoeuvres.toml` but for
/// `[study]` and `[[content]]`, and the three effects a stop-and-go drive might reveal, each
/// alone on 100 drives.
#[test]
fn the_stop_and_go_detection_study_is_the_manoeuvre_study_with_100_drives_per_effect() {
    let (datasets, singles) =
        detection_study_of("strapdown-manoeuvres", "strapdown-manoeuvres-detection");
    let expected: BTreeMap<String, usize> = [
        "accel-misalignment",
        "gyro-g-sensitivity",
        "accel-bias-instability",
    ]
    .map(|e| (e.to_string(), 100))
    .into();
    assert_eq!(singles, expected);
    assert_eq!(datasets, 300);
}

#[test]
fn the_committed_study_hides_every_effect_and_300_things_outside_the_catalogue() {
    let config = committed();
    assert_eq!(config.model.kind, ModelKind::Strapdown);
    let planned = plan(&config).unwrap();
    let outside = planned.iter().filter(|p| p.class == Class::Outside).count();
    assert!(outside >= 300, "{outside} outside");
    let registry = StrapdownRegistry::catalogue();
    for name in registry.names() {
        let singles: Vec<_> = planned
            .iter()
            .filter(|p| p.class == Class::Single && p.hidden[0].effect() == Some(name))
            .collect();
        assert!(singles.len() >= 20, "{name}: {}", singles.len());
        let effect = registry.get(name).unwrap();
        for p in singles {
            let Hidden::Effect { values, .. } = &p.hidden[0] else {
                panic!("{name}: not an effect")
            };
            // Every coefficient drawn, each within its bound; an instability's sigma set.
            assert_eq!(
                values.len(),
                effect.coefficients.len() + usize::from(effect.instability.is_some()),
                "{name}: {values:?}"
            );
            for c in effect.coefficients {
                assert!(
                    c.bound.contains(values[c.name]),
                    "{}: {}",
                    c.name,
                    values[c.name]
                );
            }
        }
    }
    for p in planned.iter().filter(|p| p.class == Class::MisstatedNoise) {
        let Hidden::MisstatedNoise { factors } = &p.hidden[0] else {
            panic!("not a noise")
        };
        assert_eq!(factors.len(), 6, "six sources: {factors:?}");
    }
    // The fifth and sixth sources (the constraint's and the standstill's tolerances) are
    // drawn off in some of them.
    for j in [4, 5] {
        assert!(planned.iter().any(|p| matches!(
            p.hidden.first(),
            Some(Hidden::MisstatedNoise { factors }) if factors[j] != 1.0
        )));
    }
}

#[test]
fn what_a_strapdown_study_does_not_read_is_refused_by_key() {
    let cases = [
        (
            "[[content]]\nkind = \"outside\"\neffect = \"drag\"\ncount = 2\nsizes = [1.0, 2.0]\n",
            "content[0].effect",
        ),
        (
            "[[content]]\nkind = \"outside\"\neffect = \"gps-lever-arm\"\ncount = 2\nsizes = [1.0, 2.0]\n",
            "content[0].effect",
        ),
        (
            "[sizes]\ngyro-fz = [0.1, 1.0]\n[[content]]\nkind = \"nothing\"\ncount = 1\n",
            "sizes.gyro-fz",
        ),
        (
            "[truth]\nrate_hz = 50.0\n[[content]]\nkind = \"nothing\"\ncount = 1\n",
            "truth.rate_hz",
        ),
        (
            "[truth.initial_tilt]\nalignment = \"gyrocompass\"\nlevel_rad = 0.01\n[[content]]\nkind = \"nothing\"\ncount = 1\n",
            "truth.initial_tilt.alignment",
        ),
        (
            "[diagnosis]\nattitude = \"exact\"\n[[content]]\nkind = \"nothing\"\ncount = 1\n",
            "diagnosis.attitude",
        ),
    ];
    for (rest, key) in cases {
        let e = parse(rest).unwrap_err();
        assert!(e.contains(key), "{key}: {e}");
    }
    // The noise table: the readings' densities are the unit class's.
    let e = DiagnosisStudyConfig::parse(&format!(
        "{}gyro_psd = 1e-9\n[[content]]\nkind = \"nothing\"\ncount = 1\n",
        HEAD
    ))
    .unwrap_err();
    assert!(e.contains("noise.gyro_psd"), "{e}");
    // And the platform refuses the strapdown's keys.
    let platform = "[study]\nname = \"t\"\nkind = \"diagnosis\"\nseed = 1\n";
    for (extra, key) in [
        ("[model]\nunit = \"mems\"\n", "model.unit"),
        ("[noise]\nnhc_m_s = 0.1\n", "noise.nhc_m_s"),
    ] {
        let e = DiagnosisStudyConfig::parse(&format!(
            "{platform}{extra}[[content]]\nkind = \"nothing\"\ncount = 1\n"
        ))
        .unwrap_err();
        assert!(e.contains(key), "{key}: {e}");
    }
    // A strapdown file with the family's own names parses.
    parse("[sizes]\ngyro-scale = [0.1, 1.0]\n[[content]]\nkind = \"single\"\ncount = 1\n").unwrap();
}

#[test]
fn its_datasets_carry_what_was_drawn() {
    let config = parse(
        "[[content]]\nkind = \"nothing\"\ncount = 1\n\
         [[content]]\nkind = \"pair\"\ncount = 1\neffects = [\"odometer-scale\", \"gps-latency\"]\n\
         [[content]]\nkind = \"outside\"\neffect = \"odometer-slip\"\ncount = 1\nsizes = [5.0, 5.0]\n\
         [[content]]\nkind = \"misstated-noise\"\ncount = 1\nsizes = [4.0, 4.0]\n",
    )
    .unwrap();
    assert_eq!(config.model.unit_class(), UnitClass::Mems);
    let planned = plan(&config).unwrap();
    let trajectory = Arc::new(Trajectory::build(&config.trajectory).unwrap());
    let datasets: Vec<_> = planned
        .iter()
        .map(|p| simulate(&config, &trajectory, p).unwrap())
        .collect();
    let clean = &datasets[0];
    assert_eq!(clean.model, ModelKind::Strapdown);
    assert!(clean.initial.is_some(), "a stated start attitude");
    // The pair's effects are in the truth with their drawn values.
    let truth = datasets[1].truth.as_ref().unwrap();
    let Hidden::Effect { values, .. } = &planned[1].hidden[0] else {
        panic!()
    };
    let (name, value) = values.iter().next().unwrap();
    let i = truth.names.iter().position(|n| n == name).unwrap();
    assert!((truth.states[0][i] - value).abs() <= 1e-12 * value.abs().max(1e-12));
    // Slip: while the vehicle accelerates the odometer reads well above the true speed (the
    // MEMS odometer's own errors are centimetres per second).
    let slip = &datasets[2];
    let t = slip.truth.as_ref().unwrap();
    let over = slip
        .measurements
        .iter()
        .filter_map(|m| {
            let k = t.t.iter().position(|&tt| (tt - m.t).abs() < 1e-9)?;
            let x = &t.states[k];
            Some(m.speed? - x[3].hypot(x[4]))
        })
        .fold(0.0f64, f64::max);
    assert!(over > 0.5, "slip adds at most {over} m/s");
    // Mis-stated noise: the stated noise differs from the truth's in the drawn sources.
    let Hidden::MisstatedNoise { factors } = &planned[3].hidden[0] else {
        panic!()
    };
    let stated = datasets[3].noise;
    let true_noise = clean.noise;
    let off = [
        stated.gyro_psd != true_noise.gyro_psd,
        stated.accel_psd != true_noise.accel_psd,
        stated.odometer_rel != true_noise.odometer_rel,
        stated.gps_m != true_noise.gps_m,
        stated.nhc_m_s != true_noise.nhc_m_s,
        stated.zupt_sigma() != true_noise.zupt_sigma(),
    ];
    for (k, f) in factors.iter().enumerate() {
        assert_eq!(off[k], *f != 1.0, "source {k}: factor {f}");
    }
}

/// A study file's `[[effect]]` joins the family's catalogue: hidden in `single` datasets
/// (here only it, by the class's `effects`) at drawn sizes, drawn in pairs, stated by every dataset (so a clean one is
/// diagnosed with it among the candidates), and refused by key when it is not the family's.
#[test]
fn a_declared_effect_is_hidden_and_a_candidate_everywhere() {
    let declared = r#"
[[effect]]
name = "accel-xy-skew"
coefficients = [{ name = "n_axy", unit = "rad", sigma = 2e-3, bound = 0.05 }]
places = [
    { coefficient = "n_axy", place = "E_a[x][y]" },
    { coefficient = "n_axy", place = "E_a[y][x]" },
]
"#;
    let config = parse(&format!(
        "[sizes]\naccel-xy-skew = [1.0, 10.0]\n\n[[content]]\nkind = \"nothing\"\ncount = 1\n\n\
         [[content]]\nkind = \"single\"\ncount = 2\neffects = [\"accel-xy-skew\"]\n\n[[content]]\nkind = \"pair\"\ncount = 3\n\
         effects = [\"odometer-scale\", \"accel-xy-skew\"]\n{declared}"
    ))
    .unwrap();
    let names = config.effect_names();
    assert_eq!(names.last().map(String::as_str), Some("accel-xy-skew"));
    let planned = plan(&config).unwrap();
    assert_eq!(planned.len(), 1 + 2 + 3);
    let skews: Vec<f64> = planned
        .iter()
        .flat_map(|p| &p.hidden)
        .filter_map(|h| match h {
            Hidden::Effect { name, values, .. } if name == "accel-xy-skew" => Some(values["n_axy"]),
            _ => None,
        })
        .collect();
    // Two singles and every pair (the pool holds two effects).
    assert_eq!(skews.len(), 5, "{skews:?}");
    assert!(
        skews.iter().all(|v| (2e-3..=2e-2).contains(&v.abs())),
        "{skews:?}"
    );
    let trajectory = Arc::new(Trajectory::build(&config.trajectory).unwrap());
    let single = planned
        .iter()
        .find(|p| p.class == Class::Single && p.hidden[0].effect() == Some("accel-xy-skew"))
        .unwrap();
    let clean = &planned[0];
    for p in [single, clean] {
        let ds = simulate(&config, &trajectory, p).unwrap();
        assert_eq!(ds.effects, config.effect, "dataset {}", p.index);
        let catalogue = navkf_diagnose::catalogue::of(&ds).unwrap();
        assert!(catalogue
            .effect_names()
            .iter()
            .any(|n| n == "accel-xy-skew"));
    }
    // The effect is in the truth: its coefficient is a truth column at the drawn value.
    let ds = simulate(&config, &trajectory, single).unwrap();
    let truth = ds.truth.as_ref().unwrap();
    let k = truth.names.iter().position(|n| n == "n_axy").unwrap();
    let Hidden::Effect { values, .. } = &single.hidden[0] else {
        panic!()
    };
    assert_eq!(truth.states[0][k], values["n_axy"]);
    // A platform declaration in a strapdown study is refused by its key.
    let platform = "[[content]]\nkind = \"nothing\"\ncount = 1\n\n[[effect]]\nname = \"drag\"\n\
                    coefficients = [{ name = \"kd\", unit = \"1/s\", sigma = 5e-5 }]\n\
                    rates = [{ to = \"v_x\", coefficient = \"kd\", feature = \"v_x\" }]\n";
    let err = parse(platform).unwrap_err();
    assert!(err.starts_with("effect[0]"), "{err}");
    // A pair that no model holds (both in E_a[x][y]) is refused before any draw, by key.
    let clash = format!(
        "[[content]]\nkind = \"pair\"\ncount = 2\n\
         effects = [\"odometer-scale\", \"accel-misalignment\", \"accel-xy-skew\"]\n{declared}"
    );
    let err = parse(&clash).unwrap_err();
    assert!(
        err.starts_with("content[0].effects: `accel-misalignment` and `accel-xy-skew` cannot be")
            && err.contains("E_a[x][y]"),
        "{err}"
    );
}
