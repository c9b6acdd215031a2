//! `navkf`: the harness's command line.
//!
//! - `simulate`: write a simulated vehicle-test dataset (data-format.md);
//! - `inspect`: validate a dataset and summarise it.

use clap::{Parser, Subcommand};
use std::path::PathBuf;
use std::process::ExitCode;

mod simulate;

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
    /// Validate a dataset folder and print a summary of it.
    Inspect {
        /// The dataset folder (inputs.csv, measurements.csv, optional dataset.toml, truth.csv).
        dir: PathBuf,
        /// Print the summary as JSON instead of text.
        #[arg(long)]
        json: bool,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Simulate(args) => simulate::run(args),
        Command::Inspect { dir, json } => inspect(&dir, json),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn inspect(dir: &std::path::Path, json: bool) -> Result<(), Box<dyn std::error::Error>> {
    let ds = navkf_dynamics::dataset::Dataset::read(dir)?;
    let summary = ds.summary();
    if json {
        println!("{}", serde_json::to_string_pretty(&summary)?);
    } else {
        println!("{summary}");
    }
    Ok(())
}
