//! `navkf diagnose`: compare a model with a dataset: does the noise fit, where does the model
//! fail, and which catalogued effects are missing.
//!
//! Data that cannot be what they claim (a GPS jump beyond what the speed allows, an input
//! gap, free fall, noise beyond any real sensor, a fix at the pole...) get the verdict
//! `implausible data` with where, and nothing named: an answer, so the exit code is 0.
//! Data that cannot start a filter at all (no row with both sensors, too few updates) are an
//! error (exit 1), as are options that make no sense (`--max-rounds 0`, a tilt sigma beyond
//! what the attitude equations hold).

use navkf_diagnose::{diagnose, report, Options, RoundKind};
use navkf_dynamics::dataset::{Dataset, CONFIG_FILE};
use navkf_dynamics::PlatformPrior;
use navkf_report::write_atomic;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    /// The dataset folder.
    dataset: PathBuf,
    /// Effects to switch on in the model under test, comma-separated
    /// (`odometer-scale,gps-latency`): a manual first round.
    #[arg(long, default_value = "")]
    with: String,
    /// Output folder (default results/diagnose/<dataset name>).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Width of the sliding NIS windows, s.
    #[arg(long, default_value_t = 300.0)]
    window: f64,
    /// Initial level error, one sigma, rad (over dataset.toml's [prior] level_rad; default:
    /// the accelerometer bias over gravity, 5e-5).
    #[arg(long, value_name = "RAD")]
    level_sigma: Option<f64>,
    /// Initial azimuth error, one sigma, rad (over [prior] azimuth_rad; default: what
    /// gyrocompassing leaves, drift / (wie cos L), 1.9e-3 at 45.8 deg).
    #[arg(long, value_name = "RAD")]
    azimuth_sigma: Option<f64>,
    /// Coefficient priors, one sigma each, comma-separated `NAME=SIGMA` (`Kg0x=1e-6,kod=0.01`),
    /// over [prior.coefficients].
    #[arg(long, value_name = "LIST", default_value = "")]
    prior: String,
    /// `fit`: check the stated noise and fit the levels that are off; `stated`: take the
    /// stated noise as it is.
    #[arg(long, value_enum, default_value_t = NoiseMode::Fit)]
    noise: NoiseMode,
    /// The filter of every fit.
    #[arg(long, default_value = "ekf", value_parser = filter_names())]
    filter: navkf_filters::FilterKind,
    /// The attitude equations of the fits' model: `small-angle` (the paper's) or `exact`
    /// (Euler angles; for a platform that may be misaligned by degrees).
    #[arg(long, default_value = "small-angle", value_parser = crate::attitude_names())]
    attitude: String,
    /// A TOML file of `[[effect]]` tables: effects declared without Rust
    /// (docs/declared-effects.md), candidates and `--with` names beside the catalogue's.
    #[arg(long, value_name = "FILE")]
    effects_file: Option<PathBuf>,
    /// Most automatic rounds of the forward selection (at least 1).
    #[arg(long, default_value_t = Options::default().max_rounds)]
    max_rounds: usize,
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum NoiseMode {
    Fit,
    Stated,
}

/// Parses `--prior`: `NAME=SIGMA` items.
fn parse_priors(list: &str) -> Result<PlatformPrior, String> {
    let mut p = PlatformPrior::default();
    for item in list.split(',').map(str::trim).filter(|s| !s.is_empty()) {
        let Some((name, value)) = item.split_once('=') else {
            return Err(format!(
                "--prior `{item}`: expected NAME=SIGMA, e.g. Kg0x=1e-6"
            ));
        };
        let v: f64 = value.trim().parse().map_err(|_| {
            format!(
                "--prior `{item}`: `{}` is not a number; expected a one-sigma > 0",
                value.trim()
            )
        })?;
        let name = name.trim().to_string();
        if p.coefficients.insert(name.clone(), v).is_some() {
            return Err(format!("--prior: `{name}` is given twice"));
        }
    }
    Ok(p)
}

pub fn run(a: Args) -> Result<(), Box<dyn std::error::Error>> {
    let with: Vec<String> = a
        .with
        .split(',')
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .map(String::from)
        .collect();
    for (i, w) in with.iter().enumerate() {
        if with[..i].contains(w) {
            return Err(format!("--with: `{w}` is given twice").into());
        }
    }
    if !(a.window.is_finite() && a.window > 0.0) {
        return Err(format!("--window {}: expected a duration > 0 s", a.window).into());
    }
    if a.max_rounds == 0 {
        return Err(
            "--max-rounds 0: expected at least 1 (with no automatic round nothing is tested)"
                .into(),
        );
    }
    let attitude: navkf_dynamics::Attitude = a.attitude.parse()?;
    let mut flags = parse_priors(&a.prior)?;
    flags.level_rad = a.level_sigma;
    flags.azimuth_rad = a.azimuth_sigma;
    // A large recording takes seconds to read and minutes to diagnose: a spinner with the
    // elapsed time says it is working (drawn only on a terminal).
    let spinner = navkf_report::progress::spinner(format!("reading {}", a.dataset.display()));
    let (registry, declared) = crate::effects::registry_with_file(a.effects_file.as_deref())?;
    let ds = Dataset::read_with(&a.dataset, &registry)?;
    // The settings that depend on the dataset's family, checked before anything is fitted.
    let catalogue = navkf_diagnose::catalogue::with_declared(&ds, &declared)?;
    let effects = catalogue.effect_names();
    for w in &with {
        if !effects.contains(w) {
            return Err(format!(
                "--with: unknown {} effect `{w}`; known effects: {}",
                ds.model.name(),
                effects.join(", ")
            )
            .into());
        }
    }
    let known = navkf_diagnose::catalogue::coefficient_names(&*catalogue);
    flags.validate(&known).map_err(|(key, message)| {
        let flag = match key.as_str() {
            "prior.level_rad" => "--level-sigma".to_string(),
            "prior.azimuth_rad" => "--azimuth-sigma".to_string(),
            k => format!("--prior {}", k.trim_start_matches("prior.coefficients.")),
        };
        format!("{flag}: {message}")
    })?;
    let strapdown = !ds.model.is_platform();
    if strapdown && attitude != navkf_dynamics::Attitude::SmallAngle {
        return Err(
            "--attitude: the platform's choice; the strapdown family's attitude equations are \
             exact Euler angles, expected no --attitude"
                .into(),
        );
    }
    // The tilt priors, flags first, then the dataset's own where no flag overrides them: the
    // platform's within what its attitude equations hold, a strapdown heading up to half a
    // turn.
    let check_tilt = |what: &str, v: f64| -> Result<(), String> {
        if strapdown {
            if v.is_finite() && v > 0.0 && v <= std::f64::consts::PI {
                Ok(())
            } else {
                Err(format!("{what} {v}: expected a one-sigma in (0, pi] rad"))
            }
        } else {
            attitude
                .check_tilt_sigma(what, v)
                .map_err(|e| e.to_string())
        }
    };
    for (flag, v) in [
        ("--level-sigma", a.level_sigma),
        ("--azimuth-sigma", a.azimuth_sigma),
    ] {
        if let Some(v) = v {
            check_tilt(flag, v)?;
        }
    }
    for (key, stated, flag) in [
        ("level_rad", ds.prior.level_rad, a.level_sigma),
        ("azimuth_rad", ds.prior.azimuth_rad, a.azimuth_sigma),
    ] {
        if let (Some(v), None) = (stated, flag) {
            check_tilt(&format!("{CONFIG_FILE} [prior] {key} ="), v)?;
        }
    }
    let opts = Options {
        with,
        window_s: a.window,
        prior: flags,
        fit_noise: matches!(a.noise, NoiseMode::Fit),
        filter: navkf_filters::FilterSpec {
            attitude,
            ..navkf_filters::FilterSpec::new(a.filter)
        },
        max_rounds: a.max_rounds,
        ..Default::default()
    };
    let out = match a.out {
        Some(out) => out,
        None => {
            navkf_report::names::plain_name("the dataset's name", &ds.name)?;
            PathBuf::from("results/diagnose").join(&ds.name)
        }
    };
    spinner.suspend(|| {
        for w in ds.warnings() {
            eprintln!("warning: {w}");
        }
    });
    let staged = navkf_report::ResultsDir::begin(&out)?;
    let started = std::time::Instant::now();
    spinner.set_message(format!(
        "diagnosing {} ({} input rows, {} measurement rows)",
        ds.name,
        ds.inputs.len(),
        ds.measurements.len()
    ));
    let diagnosed = diagnose(&ds, &*catalogue, &opts);
    drop(spinner);
    let (d, fits) = diagnosed?;
    let figures = navkf_diagnose::plots::draw(&d, &fits, staged.path());
    crate::warn_undrawn(&figures);
    let command = navkf_report::provenance::command_line();
    write_atomic(
        &staged.path().join("diagnosis.json"),
        serde_json::to_string_pretty(&d)?.as_bytes(),
    )?;
    write_atomic(
        &staged.path().join("report.md"),
        report::markdown(&d, &command, &figures).as_bytes(),
    )?;
    staged.commit()?;
    eprintln!(
        "diagnosed {} in {:.1} s ({} rounds), wrote {}",
        ds.name,
        started.elapsed().as_secs_f64(),
        d.rounds.len(),
        out.display()
    );
    println!(
        "verdict: {}{}",
        d.verdict,
        if !d.effects.is_empty() {
            format!(" (missing: {})", d.effects.join(", "))
        } else if !d.suggested.is_empty() {
            format!(" (suggested, not named: {})", d.suggested.join(", "))
        } else {
            String::new()
        }
    );
    for f in &d.findings {
        println!("- {f}");
    }
    for (k, r) in d.rounds.iter().enumerate() {
        println!(
            "\nround {} ({}): model {}",
            k + 1,
            match r.kind {
                RoundKind::Manual => "manual",
                RoundKind::Automatic => "automatic",
            },
            if r.model.is_empty() {
                "base".to_string()
            } else {
                format!("base + {}", r.model.join(", "))
            }
        );
        // The widest candidate's name sets the first column (`accel-bias-instability`).
        let width = r
            .candidates
            .iter()
            .map(|c| c.effect.chars().count())
            .max()
            .unwrap_or(0)
            .max("candidate".len());
        println!(
            "{:<width$} {:>12} {:>10} {:>9}  outcome",
            "candidate", "dLL", "BIC gain", "removed"
        );
        for c in &r.candidates {
            println!(
                "{:<width$} {:>12.1} {:>10.1} {:>8.0}%  {}",
                c.effect,
                c.delta_loglik,
                c.bic_gain,
                100.0 * c.excess_removed,
                c.outcome
            );
        }
    }
    Ok(())
}

/// The filters' names with their one-line documentation, for `--filter` (from the one list,
/// [`navkf_filters::FilterKind`]), parsed into the kind at the edge.
fn filter_names() -> impl clap::builder::TypedValueParser<Value = navkf_filters::FilterKind> {
    use clap::builder::TypedValueParser;
    clap::builder::PossibleValuesParser::new(
        navkf_filters::FilterKind::ALL
            .map(|k| clap::builder::PossibleValue::new(k.name()).help(k.doc())),
    )
    .try_map(|name| name.parse::<navkf_filters::FilterKind>())
}
