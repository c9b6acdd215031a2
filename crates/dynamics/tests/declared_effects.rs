//! Effects declared in TOML (`navkf_dynamics::declared`): a declaration of a catalogued
//! effect's terms behaves as the catalogued effect (rates, measurement and both Jacobians, at
//! random states), the public partials check passes on every catalogued and declared effect
//! and fails on a broken one, a simulated dataset with a declared effect reads back with the
//! effect known, and each malformed declaration is refused by its key.

mod common;

use common::*;
use navkf_dynamics::dataset::Dataset;
use navkf_dynamics::declared::parse_declarations;
use navkf_dynamics::partials_check::check_effect;
use navkf_dynamics::simulate::Prior;
use navkf_dynamics::{
    DynamicsError, NoiseConfig, PlatformModel, Registry, Simulator, SystemModel, Trajectory,
    TruthConfig,
};
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
    let dir = std::env::temp_dir().join(format!("navkf-declared-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    ds.write(&dir).unwrap();
    let text = std::fs::read_to_string(dir.join("dataset.toml")).unwrap();
    assert!(text.contains("[[effect]]"), "{text}");
    let back = Dataset::read(&dir).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
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
