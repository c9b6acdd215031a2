//! `navkf`: the harness's command line.
//!
//! - `simulate`: write a simulated vehicle-test dataset (data-format.md);
//! - `inspect`: validate a dataset and summarise it;
//! - `study`: run a Monte Carlo study, or a shard of one;
//! - `diagnose`: compare a model with a dataset and find the missing effect;
//! - `plan`: predict which coefficients a study's test identifies, without Monte Carlo;
//! - `merge`: combine shards.

use clap::{Parser, Subcommand};
use std::path::PathBuf;
use std::process::ExitCode;

mod diagnose;
mod plan;
mod simulate;
mod study;

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
    /// Validate a dataset folder and print a summary of it.
    Inspect {
        /// The dataset folder (inputs.csv, measurements.csv, optional dataset.toml, truth.csv).
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

/// Warns on stderr of every figure that could not be drawn (the results stand without it).
fn warn_undrawn(figures: &[navkf_study::plots::FigureOutcome]) {
    for f in figures {
        if let Err(e) = &f.result {
            eprintln!("warning: figure {} not drawn: {e}", f.name);
        }
    }
}

/// Ctrl-C. A Monte Carlo or diagnosis study stops after the runs in flight, writes nothing
/// and says what it kept (`navkf_study::interrupt`); a second Ctrl-C, or one during a
/// command that takes seconds, exits at once (exit code 130).
fn handle_ctrl_c(cooperative: bool) {
    let presses = std::sync::atomic::AtomicUsize::new(0);
    let installed = ctrlc::set_handler(move || {
        let n = presses.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
        if cooperative && n == 0 {
            navkf_study::interrupt::request();
            eprintln!(
                "\ninterrupt: stopping after the runs in flight (Ctrl-C again to exit at once)"
            );
        } else {
            std::process::exit(130);
        }
    });
    if let Err(e) = installed {
        eprintln!("warning: Ctrl-C will stop the process without cleaning up: {e}");
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
    handle_ctrl_c(matches!(cli.command, Command::Study(_)));
    let result = match cli.command {
        Command::Simulate(args) => simulate::run(args),
        Command::Inspect { dir, json } => inspect(&dir, json),
        Command::Study(args) => study::run(args),
        Command::Diagnose(args) => diagnose::run(args),
        Command::Merge(args) => study::merge(args),
        Command::Plan(args) => plan::run(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", terminal_safe(&e.to_string()));
            ExitCode::FAILURE
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
        println!("{}", serde_json::to_string_pretty(&summary)?);
    } else {
        println!("{summary}");
    }
    Ok(())
}
