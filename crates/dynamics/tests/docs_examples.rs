//! The documentation of the dataset format and of the coefficients, held to the code:
//! - `docs/data-format.md`'s example dataset (its fenced blocks ```` ```toml dataset.toml ````,
//!   ```` ```csv inputs.csv ````, ...) is written to a folder and read by `Dataset::read`, and it
//!   writes every key of `dataset.toml`; every column and `[noise]` key has a row, with the
//!   code's default;
//! - `docs/glossary.md` has a row for every navigation state, base coefficient and coefficient
//!   of every catalogued effect, with the code's unit and typical size, and a section per
//!   effect: a new effect, or a changed unit or size, fails here until the glossary says so.

use navkf_dynamics::dataset::{
    Dataset, Provenance, CONFIG_FILE, INPUTS_FILE, INPUT_COLUMNS, MEASUREMENTS_FILE,
    MEASUREMENT_COLUMNS, TRUTH_FILE,
};
use navkf_dynamics::prior::base_coefficient_sigma;
use navkf_dynamics::state::{BASE_DIM, BASE_NAMES, BASE_UNITS, NAV_DIM};
use navkf_dynamics::{NoiseConfig, PlatformPrior, Registry};

use crate::common::markdown;
use crate::common::scratch;

use markdown::{doc, fenced};
use scratch::Scratch;

/// The one block of `md` marked `info`.
fn one_block(md: &str, info: &str) -> String {
    let mut blocks = fenced(md, info);
    assert_eq!(blocks.len(), 1, "expected one ```{info} block");
    blocks.remove(0)
}

/// The cells of the table row of `md` whose first cell is `` `name` ``, trimmed.
fn row<'a>(md: &'a str, name: &str) -> Option<Vec<&'a str>> {
    let first = format!("`{name}`");
    md.lines()
        .filter(|l| l.starts_with('|'))
        .map(|l| {
            l.trim_matches('|')
                .split('|')
                .map(str::trim)
                .collect::<Vec<_>>()
        })
        .find(|cells| cells.first() == Some(&first.as_str()))
}

/// The top-level keys `value` serialises with, as TOML.
fn keys<T: serde::Serialize>(value: &T) -> Vec<String> {
    match toml::Value::try_from(value).expect("serialises") {
        toml::Value::Table(t) => t.keys().cloned().collect(),
        other => panic!("not a table: {other:?}"),
    }
}

#[test]
fn the_example_dataset_reads_as_documented() {
    let md = doc("data-format.md");
    let dir = Scratch::new("docs-dataset");
    let config = one_block(&md, "toml dataset.toml");
    for (file, info) in [
        (CONFIG_FILE, "toml dataset.toml"),
        (INPUTS_FILE, "csv inputs.csv"),
        (MEASUREMENTS_FILE, "csv measurements.csv"),
        (TRUTH_FILE, "csv truth.csv"),
    ] {
        std::fs::write(dir.join(file), one_block(&md, info)).unwrap();
    }
    let ds = Dataset::read(&dir).unwrap_or_else(|e| panic!("the doc's example: {e}"));
    assert!(ds.warnings().is_empty(), "{:?}", ds.warnings());
    // What the prose around the example says of it.
    assert_eq!(ds.inputs.len(), 7);
    assert_eq!(ds.measurements.len(), 3);
    assert!(ds.measurements[1].position_deg.is_none() && ds.measurements[1].velocity.is_some());
    assert_eq!(ds.noise, NoiseConfig::default());
    assert!(ds.prior.coefficients.contains_key("kod"));
    assert!(ds
        .truth
        .as_ref()
        .unwrap()
        .names
        .contains(&"kod".to_string()));

    // The example writes every key dataset.toml takes.
    let prior = PlatformPrior {
        level_rad: Some(1.0),
        azimuth_rad: Some(1.0),
        coefficients: [("Kg0x".to_string(), 1.0)].into(),
    };
    let provenance = Provenance {
        seed: Some(1),
        run: Some(1),
        effects: vec!["gyro-fz".into()],
        note: Some("n".into()),
    };
    let tables = [
        ("noise", keys(&NoiseConfig::default())),
        ("prior", keys(&prior)),
        ("simulation", keys(&provenance)),
    ];
    for (table, keys) in tables {
        assert!(config.contains(&format!("[{table}]")), "[{table}] missing");
        for key in keys {
            let written = key == "coefficients" && config.contains("[prior.coefficients]")
                || config.lines().any(|l| l.starts_with(&format!("{key} = ")));
            assert!(written, "the example dataset.toml lacks {table}.{key}");
        }
    }
}

#[test]
fn every_column_and_noise_key_has_a_row_with_the_codes_default() {
    let md = doc("data-format.md");
    for column in INPUT_COLUMNS.iter().chain(&MEASUREMENT_COLUMNS) {
        assert!(row(&md, column).is_some(), "no row for column `{column}`");
    }
    let defaults = toml::Value::try_from(NoiseConfig::default()).unwrap();
    for (key, value) in defaults.as_table().unwrap() {
        let cells = row(&md, key).unwrap_or_else(|| panic!("no row for noise key `{key}`"));
        let shown: f64 = cells[3]
            .parse()
            .unwrap_or_else(|_| panic!("{key}: {cells:?}"));
        assert_eq!(Some(shown), value.as_float(), "noise.{key}'s default");
    }
    let level = row(&md, "level_rad").expect("a row for level_rad");
    let shown: f64 = level[3].parse().expect("level_rad's default");
    let code = navkf_dynamics::prior::default_level_rad();
    assert!(
        ((shown - code) / code).abs() < 0.01,
        "level_rad: {shown} vs {code}"
    );
    for key in keys(&PlatformPrior {
        level_rad: Some(1.0),
        azimuth_rad: Some(1.0),
        ..Default::default()
    }) {
        assert!(row(&md, &key).is_some(), "no row for prior key `{key}`");
    }
}

/// `cells` (name, unit, typical size, ...) show `unit` and a size within 1 % of `sigma`.
fn check_row(md: &str, name: &str, unit: &str, sigma: Option<f64>) {
    let cells = row(md, name).unwrap_or_else(|| panic!("glossary: no row for `{name}`"));
    assert_eq!(
        cells.get(1),
        Some(&format!("`{unit}`").as_str()),
        "{name}'s unit"
    );
    if let Some(sigma) = sigma {
        let shown: f64 = cells
            .get(2)
            .and_then(|c| c.parse().ok())
            .unwrap_or_else(|| panic!("{name}: no typical size in {cells:?}"));
        assert!(
            ((shown - sigma) / sigma).abs() < 0.01,
            "{name}: the glossary says {shown}, the code {sigma}"
        );
    }
}

#[test]
fn the_glossary_has_the_strapdown_states_with_the_mems_sizes() {
    use navkf_dynamics::strapdown::model::StrapdownModel;
    use navkf_dynamics::strapdown::state::{BASE_DIM, STATE_NAMES, STATE_UNITS};
    use navkf_dynamics::FamilyModel;
    let md = doc("glossary.md");
    let model = StrapdownModel::base(&NoiseConfig::default());
    for i in 0..BASE_DIM {
        let sigma = Some(model.typical_sigma(i)).filter(|s| *s > 0.0);
        check_row(&md, STATE_NAMES[i], STATE_UNITS[i], sigma);
    }
}

/// The glossary's strapdown effects: a row for each effect and one for each coefficient, with
/// its unit and MEMS size, in its own section (some names are the platform's too).
#[test]
fn the_glossary_has_every_strapdown_effect_and_coefficient() {
    use navkf_dynamics::strapdown::effects::StrapdownRegistry;
    use navkf_dynamics::strapdown::unit_class::UnitClass;
    let md = doc("glossary.md");
    let start = md
        .find("\n## Strapdown effects\n")
        .expect("a section `## Strapdown effects`");
    let rest = &md[start + 1..];
    let section = &rest[..rest[3..].find("\n## ").map_or(rest.len(), |e| e + 3)];
    let registry = StrapdownRegistry::catalogue();
    for name in registry.names() {
        assert!(
            row(section, name).is_some(),
            "glossary: no row for `{name}`"
        );
        for c in registry.get(name).unwrap().coefficients {
            check_row(section, c.name, c.unit, Some(c.sigma_for(UnitClass::Mems)));
        }
    }
}

#[test]
fn the_glossary_has_every_state_coefficient_and_effect() {
    let md = doc("glossary.md");
    for i in 0..BASE_DIM {
        let sigma = (i >= NAV_DIM).then(|| base_coefficient_sigma(i));
        check_row(&md, BASE_NAMES[i], BASE_UNITS[i], sigma);
    }
    let registry = Registry::catalogue();
    for name in registry.names() {
        let heading = format!("### `{name}`");
        assert!(
            md.lines().any(|l| l == heading),
            "glossary: no section `{heading}` for the catalogued effect"
        );
        let effect = registry.build(&name).unwrap();
        for (k, c) in effect.coefficient_names().iter().enumerate() {
            let unit = effect.coefficient_units()[k];
            check_row(&md, c, unit, Some(effect.coefficient_sigma()[k]));
        }
    }
}
