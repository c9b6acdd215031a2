//! `navkf`: the harness's command line.
//!
//! - `simulate`: write a simulated vehicle-test dataset (data-format.md);
//! - `inspect`: validate a dataset and summarise it;
//! - `study`: run a Monte Carlo study, or a shard of one;
//! - `diagnose`: compare a model with a dataset and find the missing effect;
//! - `plan`: predict which coefficients a study's test identifies, without Monte Carlo;
//! - `merge`: combine shards;
//! - `effects`: list the catalogued effects and the base coefficients.

use clap::{Parser, Subcommand};
use std::io::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;

/// `println!` for the results a command prints: a reader that has gone (`navkf inspect d |
/// head -1`) ends the output quietly instead of panicking with "Broken pipe".
macro_rules! say {
    ($($arg:tt)*) => {
        $crate::write_stdout(&format!($($arg)*))
    };
}

mod convert;
mod diagnose;
mod effects;
mod plan;
mod simulate;
mod study;
mod study_file;

#[derive(Parser)]
#[command(
    name = "navkf",
    version,
    about = "Nonlinear Kalman filtering on inertial-platform error models"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Simulate the paper's vehicle test and write a dataset folder.
    Simulate(simulate::Args),
    /// Run a Monte Carlo study (the paper's: studies/paper.toml).
    Study(study::Args),
    /// Compare a model with a dataset: where it fails, and which effect is missing.
    Diagnose(diagnose::Args),
    /// Predict which coefficients a study file's test identifies, in seconds.
    Plan(plan::Args),
    /// Combine the shard files of `study --shard` into the study's results.
    Merge(study::MergeArgs),
    /// List the base coefficients and every catalogued effect: coefficients, units, sizes.
    Effects(effects::Args),
    /// Write a recording in another format (KITTI raw OXTS) as a dataset folder.
    Convert(convert::Args),
    /// Validate a dataset folder and print a summary of it.
    Inspect {
        /// The dataset folder (inputs.csv or a strapdown unit's imu.csv, measurements.csv,
        /// optional dataset.toml, truth.csv).
        dir: PathBuf,
        /// Print the summary as JSON instead of text.
        #[arg(long)]
        json: bool,
    },
}

/// The attitude variants' names, for `--attitude` (see [`navkf_dynamics::Attitude`]).
fn attitude_names() -> clap::builder::PossibleValuesParser {
    use navkf_dynamics::Attitude;
    clap::builder::PossibleValuesParser::new(Attitude::ALL.map(Attitude::name))
}

/// The model families' names, for `--model` (see [`navkf_dynamics::ModelKind`]).
fn model_names() -> clap::builder::PossibleValuesParser {
    use navkf_dynamics::ModelKind;
    clap::builder::PossibleValuesParser::new(ModelKind::ALL.map(ModelKind::name))
}

/// Warns on stderr of every figure that could not be drawn (the results stand without it).
fn warn_undrawn(figures: &[navkf_report::figure::FigureOutcome]) {
    for f in figures {
        if let Err(e) = &f.result {
            eprintln!("warning: figure {} not drawn: {e}", f.name);
        }
    }
}

/// How long a cooperative stop (a study finishing the runs in flight) may take before the
/// process stops at once: Ctrl-C always ends navkf within about a second.
const COOPERATIVE_GRACE: std::time::Duration = std::time::Duration::from_millis(800);

/// Ctrl-C. A Monte Carlo or diagnosis study first stops after the runs in flight, writes
/// nothing and says what it kept (`navkf_report::interrupt`), exiting 130 from `main`. If it
/// has not done so within [`COOPERATIVE_GRACE`], on a second Ctrl-C, and at once during any
/// other command, the handler removes the output folders being written, says that the ones
/// in place are as they were, and exits 130 itself.
fn handle_ctrl_c(cooperative: bool) {
    let presses = std::sync::atomic::AtomicUsize::new(0);
    let installed = ctrlc::set_handler(move || {
        let n = presses.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
        if cooperative && n == 0 {
            navkf_report::interrupt::request();
            eprintln!("\ninterrupt: stopping after the runs in flight");
            std::thread::sleep(COOPERATIVE_GRACE);
        }
        let targets = navkf_report::results_dir::live::abandon_all();
        eprintln!("\n{}", interrupted_message(&targets));
        std::process::exit(130);
    });
    if let Err(e) = installed {
        eprintln!("warning: Ctrl-C will stop the process without cleaning up: {e}");
    }
}

/// What an interrupt leaves: each output folder as it was (or not created).
fn interrupted_message(targets: &[PathBuf]) -> String {
    if targets.is_empty() {
        return "interrupted: nothing was written".into();
    }
    let each: Vec<String> = targets
        .iter()
        .map(|t| {
            if t.exists() {
                format!("{} is as it was", t.display())
            } else {
                format!("{} was not created", t.display())
            }
        })
        .collect();
    format!(
        "interrupted: the partial output was removed; {}",
        each.join(", ")
    )
}

/// Writes `text` and a line break to stdout; see [`say!`].
fn write_stdout(text: &str) {
    let mut out = std::io::stdout().lock();
    if let Err(e) = writeln!(out, "{text}").and_then(|()| out.flush()) {
        if e.kind() != std::io::ErrorKind::BrokenPipe {
            eprintln!("warning: could not write the output: {e}");
        }
    }
}

/// `message` safe to print on a terminal: control characters other than line breaks (a
/// terminal escape sequence echoed from a user's file by a parser) escaped as `\u{1b}`.
fn terminal_safe(message: &str) -> String {
    message
        .chars()
        .flat_map(|c| {
            let escape = c.is_control() && c != '\n';
            let shown: Vec<char> = if escape {
                c.escape_unicode().collect()
            } else {
                vec![c]
            };
            shown
        })
        .collect()
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    if let Some(w) = navkf_dynamics::instruction_set::ignored_setting() {
        eprintln!("warning: {}", terminal_safe(&w));
    }
    handle_ctrl_c(matches!(cli.command, Command::Study(_)));
    let result = match cli.command {
        Command::Simulate(args) => simulate::run(args),
        Command::Convert(args) => convert::run(args),
        Command::Inspect { dir, json } => inspect(&dir, json),
        Command::Study(args) => study::run(args),
        Command::Diagnose(args) => diagnose::run(args),
        Command::Merge(args) => study::merge(args),
        Command::Plan(args) => plan::run(args),
        Command::Effects(args) => effects::run(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", terminal_safe(&e.to_string()));
            if navkf_report::interrupt::requested() {
                // Stopped by Ctrl-C: the shell's code for SIGINT, as for any interrupted tool.
                ExitCode::from(130)
            } else {
                ExitCode::FAILURE
            }
        }
    }
}

fn inspect(dir: &std::path::Path, json: bool) -> Result<(), Box<dyn std::error::Error>> {
    let ds = navkf_dynamics::dataset::Dataset::read(dir)?;
    let summary = ds.summary();
    for i in &summary.implausible {
        eprintln!("implausible: {i}");
    }
    for w in &summary.warnings {
        eprintln!("warning: {w}");
    }
    if json {
        say!("{}", serde_json::to_string_pretty(&summary)?);
    } else {
        say!("{summary}");
        if !ds.model.is_platform() {
            say!("{}", attitude_line(&ds));
        }
    }
    Ok(())
}

/// A strapdown dataset's first attitude, as stated or as its data align it, with its prior.
fn attitude_line(ds: &navkf_dynamics::dataset::Dataset) -> String {
    let sigma = |v: Option<f64>| {
        v.map_or("not stated".to_string(), |s| {
            format!("{:.3} deg", s.to_degrees())
        })
    };
    match (&ds.initial, ds.align_from_data()) {
        (Some(a), _) => format!(
            "  attitude      stated: roll {:.3} deg, pitch {:.3} deg, heading {:.3} deg; prior level {}, heading {}",
            a.roll_deg,
            a.pitch_deg,
            a.heading_deg,
            sigma(ds.prior.level_rad),
            sigma(ds.prior.azimuth_rad)
        ),
        (None, Ok(al)) => format!(
            "  attitude      aligned from the data: roll {:.3} deg, pitch {:.3} deg (level from the standstill {:.0}-{:.0} s, sigma {:.3} deg), heading {:.3} deg (GPS track {:.0}-{:.0} s, sigma {:.3} deg)",
            al.attitude.roll_deg,
            al.attitude.pitch_deg,
            al.level_from[0],
            al.level_from[1],
            al.level_sigma.to_degrees(),
            al.attitude.heading_deg,
            al.heading_from[0],
            al.heading_from[1],
            al.heading_sigma.to_degrees()
        ),
        (None, Err(why)) => format!("  attitude      not stated, and the data cannot align it: {why}"),
    }
}
