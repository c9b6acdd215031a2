//! Effects declared in TOML (`navkf_dynamics::declared`): a declaration of a catalogued
//! effect's terms behaves as the catalogued effect (rates, measurement and both Jacobians, at
//! random states), the public partials check passes on every catalogued and declared effect
//! and fails on a broken one, a simulated dataset with a declared effect reads back with the
//! effect known, and each malformed declaration is refused by its key.

use crate::common;

use crate::common::markdown;
use crate::common::scratch;
use common::*;
use navkf_dynamics::dataset::Dataset;
use navkf_dynamics::declared::{parse_declarations, TermFeature, TermSide};
use navkf_dynamics::partials_check::check_effect;
use navkf_dynamics::simulate::Prior;
use navkf_dynamics::{
    DynamicsError, NoiseConfig, PlatformModel, Registry, Simulator, SystemModel, Trajectory,
    TruthConfig,
};
use scratch::Scratch;
use std::sync::Arc;

/// Declared twins of four catalogued effects, under new names and coefficient names.
const TWINS: &str = r#"
[[effect]]
name = "my-accel-cross-axis"
coefficients = [
    { name = "m12x", unit = "1", sigma = 1e-4 },
    { name = "m12y", unit = "1", sigma = 1e-4 },
]
rates = [
    { to = "v_x", coefficient = "m12x", feature = "f_y" },
    { to = "v_y", coefficient = "m12y", feature = "f_x" },
]

[[effect]]
name = "my-torquer-scale"
coefficients = [
    { name = "tx", unit = "1", sigma = 1e-3 },
    { name = "ty", unit = "1", sigma = 1e-3 },
    { name = "tz", unit = "1", sigma = 1e-3 },
]
rates = [
    { to = "phi_x", coefficient = "tx", feature = "w_x" },
    { to = "phi_y", coefficient = "ty", feature = "w_y" },
    { to = "phi_z", coefficient = "tz", feature = "w_z" },
]

[[effect]]
name = "my-odometer-scale"
coefficients = [{ name = "k_odo", unit = "1", sigma = 2e-3, bound = 0.2, bound_reason = "tyres" }]
measurement = [
    { to = "v_x", coefficient = "k_odo", feature = "v_x" },
    { to = "v_y", coefficient = "k_odo", feature = "v_y" },
]

[[effect]]
name = "my-gps-latency"
coefficients = [{ name = "lag", unit = "s", sigma = 0.1 }]
measurement = [
    { to = "L", coefficient = "lag", feature = "L_dot", factor = -1 },
    { to = "lambda", coefficient = "lag", feature = "lambda_dot", factor = -1.0 },
]
"#;

const PAIRS: [(&str, &str); 4] = [
    ("accel-cross-axis", "my-accel-cross-axis"),
    ("torquer-scale", "my-torquer-scale"),
    ("odometer-scale", "my-odometer-scale"),
    ("gps-latency", "my-gps-latency"),
];

fn registry() -> Registry {
    let mut r = Registry::catalogue();
    r.declare(&parse_declarations(TWINS).unwrap()).unwrap();
    r
}

fn model(registry: &Registry, name: &str) -> PlatformModel {
    PlatformModel::new(
        registry.build_all(&[name]).unwrap(),
        &NoiseConfig::default(),
    )
    .unwrap()
}

/// `a` and `b` agree to a few ulp of the larger of their entries' sizes.
fn assert_close(a: &[f64], b: &[f64], what: &str) {
    for (i, (x, y)) in a.iter().zip(b).enumerate() {
        let scale = x.abs().max(y.abs()).max(1e-300);
        assert!(
            (x - y).abs() <= 4.0 * f64::EPSILON * scale,
            "{what}[{i}]: {x:e} vs {y:e}"
        );
    }
}

#[test]
fn a_declared_twin_behaves_as_the_catalogued_effect() {
    let registry = registry();
    for (catalogued, declared) in PAIRS {
        let (a, b) = (model(&registry, catalogued), model(&registry, declared));
        assert_eq!(a.dim(), b.dim());
        assert_eq!(
            a.measurement_is_linear(),
            b.measurement_is_linear(),
            "{declared}"
        );
        let mut rng = rng(11);
        for _ in 0..16 {
            let x = random_state(&a, &mut rng);
            let u = random_input(&mut rng);
            let (n, d) = (a.dim(), a.dynamic_dim());
            let (mut ra, mut rb) = (vec![0.0; d], vec![0.0; d]);
            a.rates(&x, &u, &mut ra);
            b.rates(&x, &u, &mut rb);
            assert_close(&ra, &rb, &format!("{declared} rates"));
            let (mut ja, mut jb) = (vec![0.0; d * n], vec![0.0; d * n]);
            a.rate_jacobian(&x, &u, &mut ja);
            b.rate_jacobian(&x, &u, &mut jb);
            assert_close(&ja, &jb, &format!("{declared} rate Jacobian"));
            let (mut za, mut zb) = (vec![0.0; 4], vec![0.0; 4]);
            a.measure(&x, &mut za);
            b.measure(&x, &mut zb);
            assert_close(&za, &zb, &format!("{declared} measurement"));
            let (mut ha, mut hb) = (vec![0.0; 4 * n], vec![0.0; 4 * n]);
            a.measurement_jacobian(&x, &mut ha);
            b.measurement_jacobian(&x, &mut hb);
            assert_close(&ha, &hb, &format!("{declared} measurement Jacobian"));
        }
    }
}

#[test]
fn the_public_partials_check_passes_every_catalogued_and_declared_effect() {
    let registry = registry();
    for name in registry.names() {
        let report = check_effect(
            registry.build(&name).unwrap(),
            &NoiseConfig::default(),
            12,
            5,
        )
        .unwrap();
        assert!(report.passes(), "{report}");
        assert!(
            report.worst.is_some() || name == "gyro-bias-walk",
            "{report}"
        );
    }
}

/// A declared effect's bound reaches the model: the simulator refuses a value beyond it, by
/// the coefficient's name.
#[test]
fn a_declared_bound_reaches_the_model_and_an_undeclared_one_is_absent() {
    let registry = registry();
    let effect = registry.build("my-odometer-scale").unwrap();
    assert_eq!(effect.coefficient_bounds()[0].limit, 0.2);
    assert_eq!(effect.coefficient_bounds()[0].reason, "tyres");
    assert!(registry
        .build("my-gps-latency")
        .unwrap()
        .coefficient_bounds()
        .is_empty());
    // The bound the simulator and the diagnosis read from the model.
    let model = PlatformModel::new(vec![effect], &NoiseConfig::default()).unwrap();
    let bound = model
        .coefficient_bound(model.index_of("k_odo").unwrap())
        .unwrap();
    assert!(bound.contains(0.19) && !bound.contains(0.5));
}

/// A simulated dataset with a declared effect in its truth writes the declaration into
/// `dataset.toml`, and reads back, with the catalogue alone, knowing the effect and its
/// coefficient's true value.
#[test]
fn a_simulated_dataset_carries_its_declared_effects() {
    let registry = registry();
    let noise = NoiseConfig::default();
    let truth = Arc::new(
        PlatformModel::new(registry.build_all(&["my-gps-latency"]).unwrap(), &noise).unwrap(),
    );
    let trajectory = Arc::new(Trajectory::build(&datasets::short()).unwrap());
    let mut config = TruthConfig::default();
    config.coefficients.insert("lag".into(), Prior::fixed(0.15));
    let sim = Simulator::new(truth, trajectory, config, noise).unwrap();
    let ds = sim.dataset("declared", 3, &sim.run(3, 0));
    assert_eq!(ds.effects.len(), 1);
    assert_eq!(ds.effects[0].name, "my-gps-latency");
    let dir = Scratch::new("declared");
    ds.write(&dir).unwrap();
    let text = std::fs::read_to_string(dir.join("dataset.toml")).unwrap();
    assert!(text.contains("[[effect]]"), "{text}");
    let back = Dataset::read(&dir).unwrap();
    assert_eq!(back.effects, ds.effects);
    let truth = back.truth.unwrap();
    let column = truth.names.iter().position(|n| n == "lag").unwrap();
    assert_eq!(truth.states[0][column], 0.15);
}

/// Each malformed declaration is refused, naming the key at fault.
#[test]
fn malformed_declarations_are_refused_by_key() {
    let base = |coefficients: &str, terms: &str| {
        format!("[[effect]]\nname = \"x-effect\"\ncoefficients = [{coefficients}]\n{terms}\n")
    };
    let good_c = r#"{ name = "q", unit = "1", sigma = 1e-3 }"#;
    let good_t = r#"rates = [{ to = "v_x", coefficient = "q", feature = "f_x" }]"#;
    let cases: Vec<(String, &str)> = vec![
        (
            base(
                good_c,
                r#"rates = [{ to = "v_x", coefficient = "q", feature = "f_w" }]"#,
            ),
            "effect[0].rates[0].feature",
        ),
        (
            base(
                good_c,
                r#"measurement = [{ to = "v_x", coefficient = "q", feature = "f_x" }]"#,
            ),
            "effect[0].measurement[0].feature",
        ),
        (
            base(
                good_c,
                r#"rates = [{ to = "L", coefficient = "q", feature = "f_x" }]"#,
            ),
            "effect[0].rates[0].to",
        ),
        (
            base(
                good_c,
                r#"rates = [{ to = "v_x", coefficient = "p", feature = "f_x" }]"#,
            ),
            "effect[0].rates[0].coefficient",
        ),
        (
            base(
                good_c,
                r#"rates = [{ to = "v_x", coefficient = "q", feature = "f_x", factor = 0 }]"#,
            ),
            "effect[0].rates[0].factor",
        ),
        (
            base(
                r#"{ name = "kod", unit = "1", sigma = 1e-3 }"#,
                &good_t.replace('q', "kod"),
            ),
            "effect[0].coefficients[0].name",
        ),
        (
            base(
                r#"{ name = "Ka0x", unit = "1", sigma = 1e-3 }"#,
                &good_t.replace('q', "Ka0x"),
            ),
            "effect[0].coefficients[0].name",
        ),
        (
            base(r#"{ name = "q", unit = "1", sigma = 0 }"#, good_t),
            "effect[0].coefficients[0].sigma",
        ),
        (
            base(
                r#"{ name = "q", unit = "1", sigma = 1e-3, bound = 1e-4 }"#,
                good_t,
            ),
            "effect[0].coefficients[0].bound",
        ),
        (
            base(
                &format!("{good_c}, {}", good_c.replace("\"q\"", "\"r\"")),
                good_t,
            ),
            "effect[0].coefficients[1].name",
        ),
        (base(good_c, ""), "effect[0].rates"),
        (
            format!(
                "{}\n{}",
                base(good_c, good_t),
                base(good_c, good_t).replace("\"q\"", "\"s\"")
            ),
            "effect[1].name",
        ),
        (
            base(good_c, good_t).replace("x-effect", "gyro-fz"),
            "effect[0].name",
        ),
    ];
    for (text, key) in cases {
        let declarations = parse_declarations(&text).unwrap_or_else(|e| panic!("{text}: {e}"));
        let mut registry = Registry::catalogue();
        match registry.declare(&declarations) {
            Err(DynamicsError::Config { key: k, message }) => {
                assert_eq!(k, key, "{text}: {message}");
                assert!(message.contains("expected"), "{key}: {message}");
            }
            other => panic!("{text}: expected an error at {key}, got {other:?}"),
        }
        // Nothing is half declared.
        assert_eq!(registry.names(), Registry::catalogue().names());
    }
    // An unknown key is the parser's, located.
    let typo = base(good_c, good_t).replace("sigma", "sigmaa");
    assert!(parse_declarations(&typo).is_err());
}

/// Declaring what is declared already, word for word, is no conflict (a dataset simulated
/// with an effects file, read with the same file); the same name declared otherwise is.
#[test]
fn the_same_declaration_twice_is_one_effect_and_a_different_one_a_conflict() {
    let declarations = parse_declarations(TWINS).unwrap();
    let mut registry = registry();
    registry.declare(&declarations).unwrap();
    assert_eq!(
        registry.names().len(),
        Registry::catalogue().names().len() + 4
    );
    let mut changed = declarations[3].clone();
    changed.coefficients[0].sigma = 0.2;
    let err = registry.declare(&[changed]).unwrap_err().to_string();
    assert!(err.contains("effect[0].name"), "{err}");
}

/// docs/declared-effects.md held to the code: its example and the committed effects file
/// declare, and its feature table names every feature the code knows, with its unit.
#[test]
fn the_page_and_the_example_file_agree_with_the_code() {
    let md = markdown::doc("declared-effects.md");
    let blocks = markdown::fenced(&md, "toml effects");
    assert_eq!(blocks.len(), 1, "one example on the page");
    let file = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../studies/effects/examples.toml"
    ))
    .unwrap();
    let page = parse_declarations(&blocks[0]).unwrap();
    assert_eq!(
        page,
        parse_declarations(&file).unwrap(),
        "the page shows the file"
    );
    Registry::catalogue().declare(&page).unwrap();
    let table = md
        .split("## Features")
        .nth(1)
        .and_then(|s| s.split("\n## ").next())
        .unwrap();
    for (feature, name, unit, _) in TermFeature::ALL {
        let row = table
            .lines()
            .find(|l| l.starts_with('|') && l.contains(&format!("`{name}`")))
            .unwrap_or_else(|| panic!("feature `{name}` is not in the page's table"));
        assert!(row.contains(&format!("| {unit} |")), "{name}: {row}");
        let cells: Vec<&str> = row.split('|').map(str::trim).collect();
        let n = cells.len();
        let (rates, measurement) = (cells[n - 3], cells[n - 2]);
        assert_eq!(rates == "yes", feature.allowed_on(TermSide::Rate), "{row}");
        assert_eq!(
            measurement == "yes",
            feature.allowed_on(TermSide::Measurement),
            "{row}"
        );
    }
}

/// The example file's effects (the speed features among them) pass the partials check, and at
/// a standstill, where `|v|` has no derivative, their Jacobians stay finite.
#[test]
fn the_example_effects_pass_the_check_and_stay_finite_at_a_standstill() {
    let file = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../studies/effects/examples.toml"
    ))
    .unwrap();
    let mut registry = Registry::catalogue();
    let declarations = parse_declarations(&file).unwrap();
    registry.declare(&declarations).unwrap();
    let noise = NoiseConfig::default();
    for d in &declarations {
        let report = check_effect(registry.build(&d.name).unwrap(), &noise, 16, 9).unwrap();
        assert!(report.passes(), "{report}");
        let model = model(&registry, &d.name);
        let mut x = random_state(&model, &mut rng(3));
        x[navkf_dynamics::state::V_X] = 0.0;
        x[navkf_dynamics::state::V_Y] = 0.0;
        let n = model.dim();
        let mut h = vec![0.0; 4 * n];
        model.measurement_jacobian(&x, &mut h);
        let mut j = vec![0.0; model.dynamic_dim() * n];
        model.rate_jacobian(&x, &random_input(&mut rng(4)), &mut j);
        assert!(h.iter().chain(&j).all(|v| v.is_finite()), "{}", d.name);
    }
}
