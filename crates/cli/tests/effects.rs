//! `navkf effects`: exits 0 and lists every catalogued effect with each of its coefficients
//! (unit and typical size on the coefficient's line), and the 13 base coefficients.

use crate::common;

use common::{navkf, text};
use navkf_dynamics::prior::base_coefficient_sigma;
use navkf_dynamics::state::{BASE_DIM, BASE_NAMES, BASE_UNITS, NAV_DIM};
use navkf_dynamics::Registry;

/// The line of `out` listing coefficient `name` (first word), with its other words.
fn coefficient_line<'a>(out: &'a str, name: &str) -> Vec<&'a str> {
    out.lines()
        .map(|l| l.split_whitespace().collect::<Vec<_>>())
        .find(|w| w.first() == Some(&name))
        .unwrap_or_else(|| panic!("no line for `{name}` in:\n{out}"))
}

/// `words` hold `unit`, then a number within 0.1 % of `sigma`.
fn check(words: &[&str], name: &str, unit: &str, sigma: f64) {
    assert_eq!(words.get(1), Some(&unit), "{name}: {words:?}");
    let shown: f64 = words
        .get(2)
        .and_then(|w| w.parse().ok())
        .unwrap_or_else(|| panic!("{name}: no typical size in {words:?}"));
    assert!(
        ((shown - sigma) / sigma).abs() < 1e-3,
        "{name}: shows {shown}, the code's typical sigma is {sigma}"
    );
}

#[test]
fn effects_lists_the_catalogue_and_the_base_coefficients() {
    let o = navkf(["effects"]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let out = text(&o.stdout);
    for i in NAV_DIM..BASE_DIM {
        let words = coefficient_line(&out, BASE_NAMES[i]);
        check(
            &words,
            BASE_NAMES[i],
            BASE_UNITS[i],
            base_coefficient_sigma(i),
        );
    }
    let registry = Registry::catalogue();
    for name in registry.names() {
        let effect = registry.build(&name).unwrap();
        let header = format!("{name}: {}", effect.description());
        assert!(
            out.lines().any(|l| l == header),
            "no line `{header}` in:\n{out}"
        );
        for (k, c) in effect.coefficient_names().iter().enumerate() {
            let words = coefficient_line(&out, c);
            check(
                &words,
                c,
                effect.coefficient_units()[k],
                effect.coefficient_sigma()[k],
            );
        }
    }
}

#[test]
fn effects_lists_the_strapdown_catalogue_at_a_units_sizes() {
    use navkf_dynamics::strapdown::effects::StrapdownRegistry;
    use navkf_dynamics::strapdown::unit_class::UnitClass;
    for class in UnitClass::ALL {
        let o = navkf(["effects", "--model", "strapdown", "--unit", class.name()]);
        assert!(o.status.success(), "{}", text(&o.stderr));
        let out = text(&o.stdout);
        let unit = class.errors();
        check(
            &coefficient_line(&out, "bgz"),
            "bgz",
            "rad/s",
            unit.gyro_bias,
        );
        check(
            &coefficient_line(&out, "bax"),
            "bax",
            "m/s^2",
            unit.accel_bias,
        );
        let registry = StrapdownRegistry::catalogue();
        for name in registry.names() {
            let effect = registry.get(name).unwrap();
            let header = format!("{name}: {}", effect.description);
            assert!(out.lines().any(|l| l == header), "no `{header}` in:\n{out}");
            for c in effect.coefficients {
                let words = coefficient_line(&out, c.name);
                check(&words, c.name, c.unit, c.sigma_for(class));
            }
        }
    }
    let o = navkf(["effects", "--unit", "mems"]);
    assert!(!o.status.success());
    assert!(text(&o.stderr).contains("--model strapdown"));
    let o = navkf(["effects", "--model", "gimbal"]);
    assert!(!o.status.success());
    assert!(text(&o.stderr).contains("[possible values: platform, strapdown]"));
    let o = navkf(["effects", "--model", "strapdown", "--unit", "consumer"]);
    assert!(!o.status.success());
    assert!(text(&o.stderr).contains("navigation, tactical or mems"));
}

/// `NAVKF_SIMD` set to a value it ignores is said once on stderr, not passed over in silence;
/// `baseline` and an empty value are understood and say nothing.
#[test]
fn an_ignored_instruction_set_setting_is_warned_about() {
    let run = |value: &str| {
        std::process::Command::new(env!("CARGO_BIN_EXE_navkf"))
            .arg("effects")
            .env("NAVKF_SIMD", value)
            .output()
            .unwrap()
    };
    let o = run("plain");
    assert!(o.status.success());
    let err = text(&o.stderr);
    assert!(
        err.contains("NAVKF_SIMD=\"plain\" is ignored") && err.contains("baseline"),
        "{err}"
    );
    for understood in ["baseline", ""] {
        let o = run(understood);
        assert!(o.status.success());
        assert!(!text(&o.stderr).contains("warning"), "{}", text(&o.stderr));
    }
}
