//! `navkf simulate`: one run of the truth simulator written as a dataset folder.

use navkf_dynamics::effect_spec::EffectSpec;
use navkf_dynamics::{
    NoiseConfig, PlatformModel, Registry, Simulator, Trajectory, TrajectoryConfig, TruthConfig,
};
use std::path::PathBuf;
use std::sync::Arc;

#[derive(clap::Args)]
pub struct Args {
    /// Folder to write (created if needed).
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
    /// Test duration, s (the path is scaled to fit only through its final standstill).
    #[arg(long)]
    duration: Option<f64>,
    /// Write the truth file (truth.csv); on by default.
    #[arg(long, default_value_t = true, action = clap::ArgAction::Set)]
    truth: bool,
}

pub fn run(a: Args) -> Result<(), Box<dyn std::error::Error>> {
    let spec = EffectSpec::parse(&a.effects, &Registry::catalogue())?;
    let noise = NoiseConfig::default();
    let effect_names = spec.names();
    let model = Arc::new(PlatformModel::new(spec.effects, &noise)?);
    let mut traj_cfg = TrajectoryConfig::default();
    if let Some(d) = a.duration {
        traj_cfg.duration_s = d;
    }
    let traj = Arc::new(Trajectory::build(&traj_cfg)?);
    let truth_cfg = TruthConfig {
        coefficients: spec.fixed,
        ..Default::default()
    };
    let sim = Simulator::new(model, traj, truth_cfg, noise)?;
    let run = sim.run(a.seed, a.run);
    let name = a
        .out
        .file_name()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "dataset".into());
    let mut ds = sim.dataset(&name, a.seed, &run);
    if !a.truth {
        ds.truth = None;
    }
    ds.write(&a.out)?;
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
