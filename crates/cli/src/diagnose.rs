//! `navkf diagnose`: compare a model with a dataset: does the noise fit, where does the model
//! fail, and which catalogued effects are missing.
//!
//! Data that cannot be what they claim (a GPS jump beyond what the speed allows, an input
//! gap, free fall, noise beyond any real sensor, a fix at the pole...) get the verdict
//! `implausible data` with where, and nothing named: an answer, so the exit code is 0.
//! Data that cannot start a filter at all (no row with both sensors, too few updates) are an
//! error (exit 1), as are options that make no sense (`--max-rounds 0`, a tilt sigma beyond
//! what the attitude equations hold).

use navkf_diagnose::request::DiagnoseRequest;
use navkf_diagnose::{diagnose, report, Options, RoundKind};
use navkf_dynamics::declared::DeclaredFile;
use navkf_report::{write_atomic, SettingNames};
use std::collections::BTreeMap;
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
    /// the accelerometer bias over gravity, 5e-5 on the platform; a strapdown unit's
    /// [initial] or alignment from the data states its own).
    #[arg(long, value_name = "RAD")]
    level_sigma: Option<f64>,
    /// Initial azimuth (platform) or heading (strapdown) error, one sigma, rad (over [prior]
    /// azimuth_rad or heading_rad; default on the platform: what gyrocompassing leaves,
    /// drift / (wie cos L), 1.9e-3 at 45.8 deg; on a strapdown unit: 2 deg after a stated
    /// [initial], or the alignment's own sigma).
    #[arg(long, value_name = "RAD")]
    azimuth_sigma: Option<f64>,
    /// Coefficient priors, one sigma each, comma-separated `NAME=SIGMA` (`Kg0x=1e-6,kod=0.01`
    /// on the platform, `bgx=2e-4` on a strapdown unit), over [prior.coefficients].
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
fn parse_priors(list: &str) -> Result<BTreeMap<String, f64>, String> {
    let mut p = BTreeMap::new();
    for item in list.split(',').map(str::trim).filter(|s| !s.is_empty()) {
        let Some((name, value)) = item.split_once('=') else {
            return Err(format!(
                "--prior `{item}`: expected NAME=SIGMA, e.g. Kg0x=1e-6 or bgx=2e-4"
            ));
        };
        let v: f64 = value.trim().parse().map_err(|_| {
            format!(
                "--prior `{item}`: `{}` is not a number; expected a one-sigma > 0",
                value.trim()
            )
        })?;
        let name = name.trim().to_string();
        if p.insert(name.clone(), v).is_some() {
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
    let attitude: navkf_dynamics::Attitude = a.attitude.parse()?;
    let priors = parse_priors(&a.prior)?;
    // A large recording takes seconds to read and minutes to diagnose: a spinner with the
    // elapsed time says it is working (drawn only on a terminal).
    let spinner = navkf_report::progress::spinner(format!("reading {}", a.dataset.display()));
    let declared = a
        .effects_file
        .as_deref()
        .map(DeclaredFile::read)
        .transpose()?;
    let request = DiagnoseRequest {
        with,
        window_s: a.window,
        level_sigma: a.level_sigma,
        azimuth_sigma: a.azimuth_sigma,
        priors,
        fit_noise: matches!(a.noise, NoiseMode::Fit),
        filter: a.filter,
        // `--attitude small-angle` is the default: only another choice is a choice.
        attitude: (attitude != navkf_dynamics::Attitude::SmallAngle).then_some(attitude),
        declared,
        max_rounds: a.max_rounds,
    };
    let ds = DeclaredFile::read_dataset(request.declared.as_ref(), &a.dataset)?;
    // The settings that depend on the dataset's family, checked before anything is fitted.
    let (catalogue, opts) = request.check(&ds, SettingNames::CommandLine)?;
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
    say!(
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
        say!("- {f}");
    }
    for (k, r) in d.rounds.iter().enumerate() {
        say!(
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
        say!(
            "{:<width$} {:>12} {:>10} {:>9}  outcome",
            "candidate",
            "dLL",
            "BIC gain",
            "removed"
        );
        for c in &r.candidates {
            say!(
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
