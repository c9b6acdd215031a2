//! `navkf simulate`: one run of a model family's truth simulator written as a dataset folder.
//! What it checks and how it writes is [`navkf_study::simulation`]'s, shared with the Python
//! package; this file reads the flags and prints what was written.

use navkf_dynamics::model_kind::ModelKind;
use navkf_dynamics::TrajectoryConfig;
use navkf_study::simulation::{read_trajectory, simulate, SettingNames, SimulationRequest};
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    /// Folder to write: a new one, an empty one, or a dataset `simulate` wrote before
    /// (replaced whole).
    #[arg(long)]
    out: PathBuf,
    /// Seed of the random streams.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Run index within the seed's family of runs.
    #[arg(long, default_value_t = 0)]
    run: u64,
    /// Effects the truth carries, e.g. `gyro-fz,odometer-scale=0.002,Ka0x=1e-3` (an effect
    /// name alone draws its coefficients; `name=value` fixes them; `coefficient=value` fixes one).
    #[arg(long, default_value = "")]
    effects: String,
    /// A TOML file of `[[effect]]` tables: effects declared without Rust
    /// (docs/declared-effects.md), which `--effects` may then name; the dataset's
    /// dataset.toml carries the declarations of those it uses.
    #[arg(long, value_name = "FILE")]
    effects_file: Option<PathBuf>,
    /// Test duration, s (the path is scaled to fit only through its final standstill).
    #[arg(long)]
    duration: Option<f64>,
    /// The test to drive: the `[trajectory]` table of this TOML file (a study file, or one
    /// with only that table; e.g. a `[[trajectory.segment]]` list). Default: the paper's
    /// O-A-B-C-O path.
    #[arg(long, value_name = "FILE")]
    trajectory: Option<PathBuf>,
    /// The truth's attitude equations: `small-angle` (the paper's) or `exact` (Euler angles).
    #[arg(long, default_value = "small-angle", value_parser = crate::attitude_names())]
    attitude: String,
    /// Initial azimuth error of the platform, one sigma, rad (default: 1 arcmin); with
    /// `--model strapdown`, the heading's sigma stated in dataset.toml's [prior] heading_rad
    /// (default: 0.035, 2 deg).
    #[arg(long, value_name = "RAD")]
    azimuth_sigma: Option<f64>,
    /// Write the truth file (truth.csv); on by default.
    #[arg(long, default_value_t = true, action = clap::ArgAction::Set)]
    truth: bool,
    /// The model family: `platform` (the paper's) or `strapdown` (a unit bolted to the
    /// vehicle; writes imu.csv and the odometer's speed).
    #[arg(long, default_value = "platform", value_parser = crate::model_names())]
    model: String,
    /// The strapdown unit's class: `navigation`, `tactical` or `mems` (its bias sizes and
    /// noise densities; docs/model.md, "Simulating a strapdown test").
    #[arg(long, value_parser = ["navigation", "tactical", "mems"])]
    unit: Option<String>,
    /// The strapdown unit's sample rate, Hz.
    #[arg(long, value_name = "HZ")]
    imu_rate: Option<f64>,
    /// The non-holonomic constraint's sigma stated in dataset.toml, m/s (strapdown).
    #[arg(long, value_name = "M_S")]
    nhc_sigma: Option<f64>,
    /// The vehicle body's sideslip and bounce, m/s: the root-mean-square lateral and
    /// vertical velocity of the body when cruising (strapdown; default: the constraint's
    /// sigma, `--nhc-sigma`; 0: a rigid vehicle, whose constraint holds exactly).
    #[arg(long, value_name = "M_S")]
    body_motion: Option<f64>,
}

pub fn run(a: Args) -> Result<(), Box<dyn std::error::Error>> {
    let model: ModelKind = a.model.parse().map_err(|e| format!("--model {e}"))?;
    let declarations = crate::effects::effects_file_of(
        a.effects_file.as_deref(),
        model,
        "the model simulated (--model)",
    )?
    .map(|file| file.declarations().to_vec())
    .unwrap_or_default();
    let mut trajectory = match &a.trajectory {
        Some(path) => read_trajectory(path)?,
        None => TrajectoryConfig::default(),
    };
    if let Some(d) = a.duration {
        trajectory.duration_s = d;
    }
    // `--attitude small-angle` is the default: only another choice is a choice.
    let attitude: navkf_dynamics::Attitude = a.attitude.parse()?;
    let request = SimulationRequest {
        model,
        seed: a.seed,
        run: a.run,
        effects: a.effects,
        declarations,
        trajectory,
        attitude: (attitude != navkf_dynamics::Attitude::SmallAngle).then_some(attitude),
        azimuth_sigma: a.azimuth_sigma,
        truth: a.truth,
        unit: a.unit,
        imu_rate_hz: a.imu_rate,
        nhc_sigma: a.nhc_sigma,
        body_motion_m_s: a.body_motion,
    };
    let written = simulate(&request, &a.out, SettingNames::CommandLine)?;
    eprintln!("wrote {} ({})", a.out.display(), written.description);
    say!("{}", written.dataset.summary());
    Ok(())
}
