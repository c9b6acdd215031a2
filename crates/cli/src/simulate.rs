//! `navkf simulate`: one run of the truth simulator written as a dataset folder.
//!
//! It writes only what its own reader accepts, from settings a real platform could have: a
//! fixed coefficient beyond what any real sensor has (`Ka0x=1e300`, `gps-latency=1e6`:
//! [`navkf_dynamics::sensor_classes`]) and an azimuth sigma beyond what the attitude equations
//! hold are refused before simulating, naming the setting; and the simulated dataset is read
//! back through [`Dataset::read`] before it is written, so that a truth driven non-finite or
//! off the Earth (a latitude beyond 90 deg) is refused, not written.

use crate::simulated_dataset::{read_trajectory, readable};
use navkf_dynamics::effect_spec::EffectSpec;
use navkf_dynamics::{
    NoiseConfig, PlatformModel, Simulator, Trajectory, TrajectoryConfig, TruthConfig,
};
use navkf_report::{FolderKind, ResultsDir};
use std::path::PathBuf;
use std::sync::Arc;

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
    /// Initial azimuth error of the platform, one sigma, rad (default: 1 arcmin).
    #[arg(long, value_name = "RAD")]
    azimuth_sigma: Option<f64>,
    /// Write the truth file (truth.csv); on by default.
    #[arg(long, default_value_t = true, action = clap::ArgAction::Set)]
    truth: bool,
    /// The model family: `platform` (the paper's) or `strapdown` (a unit bolted to the
    /// vehicle; writes imu.csv and the odometer's speed).
    #[arg(long, default_value = "platform", value_parser = ["platform", "strapdown"])]
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
}

pub fn run(a: Args) -> Result<(), Box<dyn std::error::Error>> {
    if a.model == "strapdown" {
        if a.effects_file.is_some() {
            return Err(
                "--effects-file: declared effects are the platform family's; a \
                        strapdown unit's effects are the strapdown catalogue's (`navkf effects \
                        --model strapdown`); expected no --effects-file with --model strapdown"
                    .into(),
            );
        }
        let mut trajectory = match &a.trajectory {
            Some(path) => read_trajectory(path)?,
            None => TrajectoryConfig::default(),
        };
        if let Some(d) = a.duration {
            trajectory.duration_s = d;
        }
        return crate::simulate_strapdown::run(crate::simulate_strapdown::Settings {
            out: a.out,
            seed: a.seed,
            run: a.run,
            effects: a.effects,
            attitude: a.attitude,
            heading_sigma: a.azimuth_sigma,
            truth: a.truth,
            unit: a.unit,
            imu_rate: a.imu_rate,
            nhc_sigma: a.nhc_sigma,
            trajectory,
        });
    }
    for (flag, given) in [
        ("--unit", a.unit.is_some()),
        ("--imu-rate", a.imu_rate.is_some()),
        ("--nhc-sigma", a.nhc_sigma.is_some()),
    ] {
        if given {
            return Err(format!(
                "{flag}: a strapdown setting; expected --model strapdown, or no {flag}"
            )
            .into());
        }
    }
    // dataset.toml records both as TOML integers, which are signed 64-bit.
    for (flag, value) in [("--seed", a.seed), ("--run", a.run)] {
        if value > i64::MAX as u64 {
            return Err(format!(
                "{flag} {value}: expected 0 to {} (dataset.toml records it as a TOML integer)",
                i64::MAX
            )
            .into());
        }
    }
    let (registry, _) = crate::effects::registry_with_file(a.effects_file.as_deref())?;
    let spec = EffectSpec::parse(&a.effects, &registry)?;
    let noise = NoiseConfig::default();
    let effect_names = spec.names();
    let attitude: navkf_dynamics::Attitude = a.attitude.parse()?;
    let model = Arc::new(PlatformModel::new(spec.effects, &noise)?.with_attitude(attitude));
    for (name, prior) in &spec.fixed {
        let bound = model
            .index_of(name)
            .and_then(|i| model.coefficient_bound(i).map(|b| (b, &model.units()[i])));
        if let Some((b, unit)) = bound.filter(|(b, _)| !b.contains(prior.mean)) {
            let owner = registry
                .owner_of(name)
                .map(|e| format!(" (of {e})"))
                .unwrap_or_default();
            let value = if (1e-3..1e6).contains(&prior.mean.abs()) {
                prior.mean.to_string()
            } else {
                format!("{:e}", prior.mean)
            };
            let limit = format!("{:.4}", b.limit);
            let limit = limit.trim_end_matches('0').trim_end_matches('.');
            let unit = if unit == "1" {
                String::new()
            } else {
                format!(" {unit}")
            };
            return Err(format!(
                "--effects: {name}={value}{owner}: beyond +-{limit}{unit}, what any real sensor \
                 has ({}); nothing was simulated",
                b.reason
            )
            .into());
        }
    }
    let mut traj_cfg = match &a.trajectory {
        Some(path) => read_trajectory(path)?,
        None => TrajectoryConfig::default(),
    };
    if let Some(d) = a.duration {
        traj_cfg.duration_s = d;
    }
    let traj = Arc::new(Trajectory::build(&traj_cfg)?);
    let mut truth_cfg = TruthConfig {
        coefficients: spec.fixed,
        ..Default::default()
    };
    if let Some(s) = a.azimuth_sigma {
        if !(s.is_finite() && s >= 0.0) {
            return Err(format!("--azimuth-sigma {s}: expected a one-sigma >= 0, rad").into());
        }
        attitude.check_tilt_sigma("--azimuth-sigma", s)?;
        truth_cfg.initial_tilt.azimuth_rad = s;
    }
    let sim = Simulator::new(model, traj, truth_cfg, noise)?;
    // Checked before simulating: a new folder, an empty one, or a dataset simulate wrote
    // there before (never a user's folder, a results folder or a user's own files).
    let staged = ResultsDir::begin_kind(&a.out, FolderKind::Dataset, &[])?;
    let run = sim.run(a.seed, a.run);
    let name = crate::simulated_dataset::dataset_name(&a.out);
    let mut ds = sim.dataset(&name, a.seed, &run);
    if !a.truth {
        ds.truth = None;
    }
    ds.write(staged.path())?;
    readable(staged.path(), &a.out, &a.effects)?;
    staged.commit()?;
    eprintln!(
        "wrote {} (effects: {})",
        a.out.display(),
        if effect_names.is_empty() {
            "none".to_string()
        } else {
            effect_names.join(", ")
        }
    );
    println!("{}", ds.summary());
    Ok(())
}
