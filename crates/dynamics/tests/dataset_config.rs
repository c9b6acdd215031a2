//! `dataset.toml`: noise, simulation and prior tables, each refusal naming its key and line.

use crate::dataset_files;

use dataset_files::*;
use navkf_dynamics::dataset::{Dataset, Provenance};
use navkf_dynamics::{NoiseConfig, PlatformPrior, Registry};

#[test]
fn unknown_noise_key_is_refused_with_its_name() {
    let e = read_error(
        "toml-key",
        &[(
            "dataset.toml",
            "[noise]\ngyro_psd = 1e-14\ngyro_pds = 2e-14\n",
        )],
    );
    assert_mentions(&e, &["dataset.toml:3:1:", "gyro_pds", "unknown field"]);
}

#[test]
fn unknown_table_is_refused_with_its_name() {
    let e = read_error(
        "toml-table",
        &[("dataset.toml", "[noise]\ngps_m = 3.0\n\n[sensors]\nx = 1\n")],
    );
    assert_mentions(
        &e,
        &[
            "dataset.toml:4:2:",
            "sensors",
            "expected one of `noise`, `prior`, `simulation`",
        ],
    );
}

#[test]
fn unknown_simulation_key_is_refused_with_its_name() {
    let e = read_error("toml-sim", &[("dataset.toml", "[simulation]\nsead = 3\n")]);
    assert_mentions(&e, &["dataset.toml:2:1:", "sead"]);
}

#[test]
fn the_strapdown_constraint_in_a_platform_dataset_is_refused_not_ignored() {
    let e = read_error(
        "toml-nhc",
        &[("dataset.toml", "[noise]\ngps_m = 3.0\nnhc_m_s = 0.1\n")],
    );
    assert_mentions(&e, &["dataset.toml:3:", "noise.nhc_m_s", "strapdown"]);
}

#[test]
fn toml_syntax_error_gives_line_and_column() {
    let e = read_error("toml-syntax", &[("dataset.toml", "[noise]\ngps_m = = 3\n")]);
    assert_mentions(&e, &["dataset.toml:2:9:", "TOML parse error"]);
}

#[test]
fn invalid_noise_value_is_refused_with_its_line() {
    let e = read_error(
        "toml-value",
        &[(
            "dataset.toml",
            "# noise\n[noise]\ngyro_psd = 1e-14\ngps_m = -3.0\n",
        )],
    );
    assert_mentions(
        &e,
        &[
            "dataset.toml:4:",
            "column `noise.gps_m`",
            "expected a finite number > 0",
        ],
    );
}

#[test]
fn absent_noise_keys_take_defaults_and_simulation_is_read() {
    let inputs = inputs_text(50);
    let dir = folder(
        "toml-defaults",
        &[
            ("inputs.csv", &inputs),
            ("measurements.csv", MEAS_OK),
            (
                "dataset.toml",
                "[noise]\ngps_m = 5\n\n[simulation]\nseed = 9\neffects = [\"ka2\"]\n",
            ),
        ],
    );
    let d = Dataset::read(&dir).unwrap();
    assert_eq!(
        d.noise,
        NoiseConfig {
            gps_m: 5.0,
            ..NoiseConfig::default()
        }
    );
    assert_eq!(
        d.provenance,
        Some(Provenance {
            seed: Some(9),
            effects: vec!["ka2".into()],
            ..Provenance::default()
        })
    );
}

// ---- dataset.toml [prior] ------------------------------------------------------------------

#[test]
fn prior_table_is_read_with_base_and_effect_coefficients() {
    let inputs = inputs_text(50);
    let dir = folder(
        "prior-ok",
        &[
            ("inputs.csv", &inputs),
            ("measurements.csv", MEAS_OK),
            (
                "dataset.toml",
                "[prior]\nazimuth_rad = 2e-3\n\n[prior.coefficients]\nKg0x = 4.8e-7\nKa12x = 1e-3\n",
            ),
        ],
    );
    let d = Dataset::read(&dir).unwrap();
    assert_eq!(d.prior.level_rad, None);
    assert_eq!(d.prior.azimuth_rad, Some(2e-3));
    assert_eq!(d.prior.coefficients["Kg0x"], 4.8e-7);
    assert_eq!(d.prior.coefficients["Ka12x"], 1e-3);
}

#[test]
fn unknown_prior_key_is_refused_with_its_line() {
    let e = read_error(
        "prior-key",
        &[(
            "dataset.toml",
            "[prior]\nlevel_rad = 5e-5\nazimuth_deg = 0.1\n",
        )],
    );
    assert_mentions(&e, &["dataset.toml:3:1:", "azimuth_deg", "unknown field"]);
}

#[test]
fn unknown_prior_coefficient_is_refused_with_its_line_and_the_known_names() {
    let e = read_error(
        "prior-coef",
        &[(
            "dataset.toml",
            "[noise]\ngps_m = 3.0\n\n[prior.coefficients]\nKg0x = 1e-7\nKg0w = 1e-7\n",
        )],
    );
    assert_mentions(
        &e,
        &[
            "dataset.toml:6:",
            "column `prior.coefficients.Kg0w`",
            "unknown coefficient `Kg0w`",
            "Ka12x",
        ],
    );
    // A navigation state is not a coefficient, and the message says where its prior is.
    let e = read_error(
        "prior-nav",
        &[("dataset.toml", "[prior.coefficients]\nphi_z = 1e-3\n")],
    );
    assert_mentions(&e, &["dataset.toml:2:", "phi_z", "azimuth_rad"]);
}

#[test]
fn non_positive_or_malformed_prior_values_are_refused_with_their_line() {
    let e = read_error(
        "prior-neg",
        &[(
            "dataset.toml",
            "[prior]\nlevel_rad = 5e-5\nazimuth_rad = -1e-3\n",
        )],
    );
    assert_mentions(
        &e,
        &[
            "dataset.toml:3:",
            "column `prior.azimuth_rad`",
            "finite and > 0",
        ],
    );
    let e = read_error(
        "prior-zero",
        &[("dataset.toml", "[prior.coefficients]\nkod = 0.0\n")],
    );
    assert_mentions(&e, &["dataset.toml:2:", "prior.coefficients.kod", "> 0"]);
    let e = read_error(
        "prior-type",
        &[("dataset.toml", "[prior]\nlevel_rad = \"small\"\n")],
    );
    assert_mentions(&e, &["dataset.toml:2:13:", "invalid type", "level_rad"]);
}

#[test]
fn a_users_own_effect_coefficient_is_accepted_with_its_registry() {
    #[derive(Debug)]
    struct Drag;
    impl navkf_dynamics::Effect for Drag {
        fn terms(&self) -> navkf_dynamics::Terms {
            navkf_dynamics::Terms {
                rates: false,
                linear_rates: &[],
                measurement: navkf_dynamics::MeasurementTerm::None,
                noise: false,
            }
        }
        fn name(&self) -> &str {
            "drag"
        }
        fn description(&self) -> &str {
            "v' -= kd v"
        }
        fn coefficient_names(&self) -> &[&str] {
            &["kd"]
        }
        fn coefficient_units(&self) -> &[&str] {
            &["1/s"]
        }
        fn coefficient_sigma(&self) -> &[f64] {
            &[1e-5]
        }
    }
    let inputs = inputs_text(50);
    let files = [
        ("inputs.csv", inputs.as_str()),
        ("measurements.csv", MEAS_OK),
        ("dataset.toml", "[prior.coefficients]\nkd = 1e-4\n"),
    ];
    let dir = folder("prior-user", &files);
    assert!(
        Dataset::read(&dir).is_err(),
        "kd is unknown to the catalogue"
    );
    let mut registry = Registry::catalogue();
    registry.register(|| Box::new(Drag));
    let d = Dataset::read_with(&dir, &registry).unwrap();
    assert_eq!(
        d.prior,
        PlatformPrior {
            coefficients: [("kd".to_string(), 1e-4)].into(),
            ..Default::default()
        }
    );
}

// ---- truth.csv -----------------------------------------------------------------------------
