//! `navkf effects`: what a model can carry, from the code itself. The 13 base coefficients
//! (names, units and typical sizes of `navkf_dynamics::state` and
//! `navkf_dynamics::prior::base_coefficient_sigma`), then every catalogued effect with its
//! one line of meaning and its coefficients, each read from the effect's own methods
//! (`description`, `coefficient_names`, `coefficient_units`, `coefficient_sigma`,
//! `process_noise`): a new effect is listed the moment it is in `Registry::catalogue`, and no
//! second table can go stale. `docs/glossary.md` says the same in prose. `--model strapdown`
//! lists the strapdown family's six biases and its declared effects the same way.
//!
//! `--effects-file FILE` adds the effects a user declared in TOML (docs/declared-effects.md),
//! and `--check` compares every listed effect's partial derivatives with finite differences
//! (`navkf_dynamics::partials_check`, `navkf_dynamics::strapdown::partials_check`), reporting
//! each one's worst entry.

use navkf_dynamics::declared::DeclaredFile;
use navkf_dynamics::model_kind::ModelKind;
use navkf_dynamics::partials_check::check_effect;
use navkf_dynamics::prior::base_coefficient_sigma;
use navkf_dynamics::state::{BASE_DIM, BASE_MEANINGS, BASE_NAMES, BASE_UNITS, NAV_DIM};
use navkf_dynamics::strapdown::effects::StrapdownRegistry;
use navkf_dynamics::strapdown::partials_check::check_effect as strapdown_check_effect;
use navkf_dynamics::strapdown::state::{
    BASE_DIM as SD_BASE_DIM, BA_X as SD_BA_X, NAV_DIM as SD_NAV_DIM, STATE_NAMES as SD_NAMES,
    STATE_UNITS as SD_UNITS,
};
use navkf_dynamics::strapdown::unit_class::UnitClass;
use navkf_dynamics::{DynamicsError, NoiseConfig, Registry};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

#[derive(clap::Args)]
pub struct Args {
    /// The model family whose catalogue to list: `platform` or `strapdown` (its sizes those of
    /// `--unit`)
    #[arg(long, default_value = "platform", value_parser = crate::model_names())]
    model: String,
    /// The strapdown unit's class whose typical sizes to show: navigation, tactical or mems
    /// (MEMS if left out)
    #[arg(long)]
    unit: Option<String>,
    /// A TOML file of `[[effect]]` tables: effects declared without Rust
    /// (docs/declared-effects.md), listed after the catalogue's (either family).
    #[arg(long, value_name = "FILE")]
    effects_file: Option<PathBuf>,
    /// Check every listed effect's partial derivatives against finite differences and report
    /// each one's worst entry; exit 1 if any disagrees (either family).
    #[arg(long)]
    check: bool,
}

/// The effects file `file` (`--effects-file`), read and checked, when one is given, refused
/// unless its effects are of `family` (the family of `what`, e.g. `--model platform`).
pub fn effects_file_of(
    file: Option<&Path>,
    family: ModelKind,
    what: &str,
) -> Result<Option<DeclaredFile>, DynamicsError> {
    let Some(path) = file else {
        return Ok(None);
    };
    let file = DeclaredFile::read(path)?;
    file.expect_family(family, what)?;
    Ok(Some(file))
}

pub fn run(a: Args) -> Result<(), Box<dyn std::error::Error>> {
    let model: ModelKind = a.model.parse().map_err(|e| format!("--model {e}"))?;
    let text = match model {
        ModelKind::Platform => {
            if let Some(unit) = a.unit {
                return Err(format!(
                    "--unit {unit}: a strapdown unit's class; expected --model strapdown or \
                     no --unit"
                )
                .into());
            }
            let registry = match effects_file_of(
                a.effects_file.as_deref(),
                ModelKind::Platform,
                "the model listed (--model)",
            )? {
                Some(file) => file.registry()?,
                None => Registry::catalogue(),
            };
            let mut text = listing(&registry)?;
            if a.check {
                let (report, failed) = checks(&registry)?;
                text.push_str(&report);
                if failed > 0 {
                    say!("{}", text.trim_end());
                    return Err(disagree(failed));
                }
            }
            text
        }
        ModelKind::Strapdown => {
            let registry = match effects_file_of(
                a.effects_file.as_deref(),
                ModelKind::Strapdown,
                "the model listed (--model)",
            )? {
                Some(file) => file.registry()?,
                None => StrapdownRegistry::catalogue(),
            };
            let class: UnitClass = a.unit.as_deref().unwrap_or("mems").parse()?;
            let mut text = strapdown_listing(class, &registry);
            if a.check {
                let (report, failed) = strapdown_checks(&registry, class)?;
                text.push_str(&report);
                if failed > 0 {
                    say!("{}", text.trim_end());
                    return Err(disagree(failed));
                }
            }
            text
        }
    };
    say!("{}", text.trim_end());
    Ok(())
}

/// The strapdown family's effects in `registry` (its catalogue and any declared ones) at the
/// sizes of `class`, after its six biases.
fn strapdown_listing(class: UnitClass, registry: &StrapdownRegistry) -> String {
    let mut out = String::new();
    let unit = class.errors();
    let _ = writeln!(
        out,
        "Base coefficients (6, always in the model; typical one-sigma of a {} unit):",
        class.name()
    );
    let _ = writeln!(
        out,
        "  {:<9} {:<15} {:<10} meaning",
        "name", "unit", "typical"
    );
    for i in SD_NAV_DIM..SD_BASE_DIM {
        let (sigma, meaning) = if i < SD_BA_X {
            (unit.gyro_bias, "gyro bias, body axis")
        } else {
            (unit.accel_bias, "accelerometer bias, body axis")
        };
        row(&mut out, SD_NAMES[i], SD_UNITS[i], sigma, meaning);
    }
    let names = registry.names();
    let _ = writeln!(
        out,
        "\nEffects ({}; switch on with `--effects NAME` or a strapdown study file's `effects = \
         [\"NAME\"]`; `NAME=VALUE` fixes every coefficient, `COEFFICIENT=VALUE` one, \
         `PARAMETER=VALUE` a bias instability's):",
        names.len()
    );
    for name in names {
        let Ok(effect) = registry.get(name) else {
            continue;
        };
        let _ = writeln!(out, "\n{name}: {}", effect.description);
        for c in effect.coefficients {
            row(&mut out, c.name, c.unit, c.sigma_for(class), "");
        }
        if let Some(law) = effect.instability {
            let [t, sigma] = law.parameter_names;
            let _ = writeln!(
                out,
                "  no coefficients: {t} = {} s and {sigma} = {:.3e} by default",
                law.time_s,
                law.sigma_for(class)
            );
        }
    }
    out.lines()
        .map(str::trim_end)
        .collect::<Vec<_>>()
        .join("\n")
}

/// One coefficient's row: name, unit, typical one-sigma, meaning.
fn row(out: &mut String, name: &str, unit: &str, sigma: f64, meaning: &str) {
    let _ = writeln!(out, "  {name:<9} {unit:<15} {sigma:<10.3e} {meaning}");
}

/// The heading of the partials check's lines.
const CHECK_HEADING: &str =
    "\n\nPartial derivatives against central finite differences (16 random \
     states each; an entry passes within its tolerance, 1.000):\n";

/// The refusal when `failed` effects' partials disagree.
fn disagree(failed: usize) -> Box<dyn std::error::Error> {
    format!(
        "{failed} effect(s) have partial derivatives that disagree with finite differences; \
         the EKF would linearise them wrongly"
    )
    .into()
}

/// The partials check of every effect of `registry`, one line each, and how many failed.
fn checks(registry: &Registry) -> Result<(String, usize), Box<dyn std::error::Error>> {
    let mut out = String::from(CHECK_HEADING);
    let mut failed = 0;
    for name in registry.names() {
        let report = check_effect(registry.build(&name)?, &NoiseConfig::default(), 16, 1)?;
        failed += usize::from(!report.passes());
        let _ = writeln!(out, "  {report}");
    }
    Ok((out, failed))
}

/// The same for the strapdown family: each effect alone in a model of `class`, through the
/// chain rule of its places ([`navkf_dynamics::strapdown::partials_check`]).
fn strapdown_checks(
    registry: &StrapdownRegistry,
    class: UnitClass,
) -> Result<(String, usize), Box<dyn std::error::Error>> {
    let mut out = String::from(CHECK_HEADING);
    let mut failed = 0;
    for name in registry.names() {
        let report = strapdown_check_effect(registry, name, class, 16, 1)?;
        failed += usize::from(!report.passes());
        let _ = writeln!(out, "  {report}");
    }
    Ok((out, failed))
}

/// The listing of `registry`'s effects, after the base coefficients.
pub fn listing(registry: &Registry) -> Result<String, Box<dyn std::error::Error>> {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "Base coefficients ({}, always in the model; typical one-sigma of a navigation-grade \
         platform):",
        BASE_DIM - NAV_DIM
    );
    let _ = writeln!(
        out,
        "  {:<9} {:<15} {:<10} meaning",
        "name", "unit", "typical"
    );
    for i in NAV_DIM..BASE_DIM {
        row(
            &mut out,
            BASE_NAMES[i],
            BASE_UNITS[i],
            base_coefficient_sigma(i),
            BASE_MEANINGS[i],
        );
    }
    let names = registry.names();
    let _ = writeln!(
        out,
        "\nEffects ({}; switch on with `--effects NAME` or a study file's `effects = \
         [\"NAME\"]`; `NAME=VALUE` fixes every coefficient, `COEFFICIENT=VALUE` one):",
        names.len()
    );
    for name in &names {
        let effect = registry.build(name)?;
        let _ = writeln!(out, "\n{name}: {}", effect.description());
        let (coefficients, units, sigmas) = (
            effect.coefficient_names(),
            effect.coefficient_units(),
            effect.coefficient_sigma(),
        );
        for (k, c) in coefficients.iter().enumerate() {
            let unit = units.get(k).copied().unwrap_or("?");
            let sigma = sigmas.get(k).copied().unwrap_or(f64::NAN);
            row(&mut out, c, unit, sigma, "");
        }
        if coefficients.is_empty() {
            let channels = effect.process_noise();
            if channels.is_empty() {
                let _ = writeln!(out, "  no coefficients");
            } else {
                let list: Vec<&str> = channels.iter().map(|c| c.name.as_str()).collect();
                let _ = writeln!(
                    out,
                    "  no coefficients: white noise {} of density {:.3e} by default \
                     (`{name}=VALUE` sets it)",
                    list.join(", "),
                    channels[0].psd
                );
            }
        }
    }
    // Rows of effects' coefficients have no meaning column: trim the padding it leaves.
    Ok(out
        .lines()
        .map(str::trim_end)
        .collect::<Vec<_>>()
        .join("\n"))
}
