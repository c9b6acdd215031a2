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
//! (`navkf_dynamics::partials_check`), reporting each one's worst entry.

use navkf_dynamics::declared::{read_declarations, EffectDeclaration};
use navkf_dynamics::model_kind::ModelKind;
use navkf_dynamics::partials_check::check_effect;
use navkf_dynamics::prior::base_coefficient_sigma;
use navkf_dynamics::state::{BASE_DIM, BASE_MEANINGS, BASE_NAMES, BASE_UNITS, NAV_DIM};
use navkf_dynamics::strapdown::effects::StrapdownRegistry;
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
    #[arg(long, default_value = "platform")]
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
    /// each one's worst entry; exit 1 if any disagrees.
    #[arg(long)]
    check: bool,
}

/// The catalogue with the effects declared in `file` (`--effects-file`), and the
/// declarations; errors name the file and the key.
pub fn registry_with_file(
    file: Option<&Path>,
) -> Result<(Registry, Vec<EffectDeclaration>), Box<dyn std::error::Error>> {
    let Some(path) = file else {
        return Ok((Registry::catalogue(), Vec::new()));
    };
    let declarations = read_declarations(path)?;
    Ok((platform_registry(path, &declarations)?, declarations))
}

/// For a command that reads a dataset of either family (`diagnose`): the platform catalogue
/// the dataset is read with (with `file`'s effects when they are platform ones), `file`'s
/// declarations, and the family they belong to (the strapdown's when any states `places`).
pub fn registry_for_either(
    file: Option<&Path>,
) -> Result<(Registry, Vec<EffectDeclaration>, ModelKind), Box<dyn std::error::Error>> {
    let Some(path) = file else {
        return Ok((Registry::catalogue(), Vec::new(), ModelKind::Platform));
    };
    let declarations = read_declarations(path)?;
    if declarations.iter().any(|d| !d.places.is_empty()) {
        strapdown_registry(path, &declarations)?;
        Ok((Registry::catalogue(), declarations, ModelKind::Strapdown))
    } else {
        let registry = platform_registry(path, &declarations)?;
        Ok((registry, declarations, ModelKind::Platform))
    }
}

/// The effects declared in `file` for the strapdown family, checked against its catalogue;
/// errors name the file and the key.
pub fn strapdown_declarations(
    file: &Path,
) -> Result<Vec<EffectDeclaration>, Box<dyn std::error::Error>> {
    let declarations = read_declarations(file)?;
    strapdown_registry(file, &declarations)?;
    Ok(declarations)
}

/// The platform catalogue with `declarations` (read from `path`) declared.
fn platform_registry(
    path: &Path,
    declarations: &[EffectDeclaration],
) -> Result<Registry, Box<dyn std::error::Error>> {
    let mut registry = Registry::catalogue();
    registry
        .declare(declarations)
        .map_err(|e| located(path, e))?;
    Ok(registry)
}

/// The strapdown catalogue with `declarations` (read from `path`) declared.
fn strapdown_registry(
    path: &Path,
    declarations: &[EffectDeclaration],
) -> Result<StrapdownRegistry, Box<dyn std::error::Error>> {
    let mut registry = StrapdownRegistry::catalogue();
    registry
        .declare(declarations)
        .map_err(|e| located(path, e))?;
    Ok(registry)
}

/// A declaration's error with the file it came from.
fn located(path: &Path, e: DynamicsError) -> String {
    match e {
        DynamicsError::Config { key, message } => {
            format!("{}: {key}: {message}", path.display())
        }
        other => format!("{}: {other}", path.display()),
    }
}

pub fn run(a: Args) -> Result<(), Box<dyn std::error::Error>> {
    let text = match a.model.as_str() {
        "platform" => {
            if let Some(unit) = a.unit {
                return Err(format!(
                    "--unit {unit}: a strapdown unit's class; expected --model strapdown or \
                     no --unit"
                )
                .into());
            }
            let (registry, _) = registry_with_file(a.effects_file.as_deref())?;
            let mut text = listing(&registry)?;
            if a.check {
                let (report, failed) = checks(&registry)?;
                text.push_str(&report);
                if failed > 0 {
                    say!("{}", text.trim_end());
                    return Err(format!(
                        "{failed} effect(s) have partial derivatives that disagree with finite \
                         differences; the EKF would linearise them wrongly"
                    )
                    .into());
                }
            }
            text
        }
        "strapdown" => {
            if a.check {
                return Err(
                    "--check: the partials check of declared terms is the platform \
                     family's; a strapdown effect's partials are the model's own chain rule \
                     through each place (crates/dynamics/tests/strapdown_effects.rs checks it \
                     on declared effects); expected --model platform"
                        .into(),
                );
            }
            let registry = match &a.effects_file {
                Some(file) => strapdown_registry(file, &read_declarations(file)?)?,
                None => StrapdownRegistry::catalogue(),
            };
            strapdown_listing(a.unit.as_deref().unwrap_or("mems").parse()?, &registry)
        }
        other => {
            return Err(format!("--model {other}: expected platform or strapdown").into());
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

/// The partials check of every effect of `registry`, one line each, and how many failed.
fn checks(registry: &Registry) -> Result<(String, usize), Box<dyn std::error::Error>> {
    let mut out = String::from(
        "\n\nPartial derivatives against central finite differences (16 random states each; \
         an entry passes within its tolerance, 1.000):\n",
    );
    let mut failed = 0;
    for name in registry.names() {
        let report = check_effect(registry.build(&name)?, &NoiseConfig::default(), 16, 1)?;
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
