//! Simulated datasets for the tests of the data checks.

use navkf_dynamics::dataset::Dataset;
use navkf_dynamics::effect_spec::EffectSpec;
use navkf_dynamics::simulate::TruthConfig;
use navkf_dynamics::{
    NoiseConfig, PlatformModel, Registry, Simulator, Trajectory, TrajectoryConfig,
};
use std::sync::Arc;

/// A dataset named `name` simulated along `trajectory` with `effects` (as `simulate
/// --effects` takes them) and the truth's noise `noise`, without its truth file.
pub fn simulated(
    name: &str,
    effects: &str,
    trajectory: &TrajectoryConfig,
    noise: NoiseConfig,
    seed: u64,
) -> Dataset {
    let spec = EffectSpec::parse(effects, &Registry::catalogue()).unwrap();
    let model = Arc::new(PlatformModel::new(spec.effects, &noise).unwrap());
    let traj = Arc::new(Trajectory::build(trajectory).unwrap());
    let truth = TruthConfig {
        coefficients: spec.fixed,
        ..Default::default()
    };
    let sim = Simulator::new(model, traj, truth, noise).unwrap();
    let run = sim.run(seed, 0);
    let mut ds = sim.dataset(name, seed, &run);
    ds.truth = None;
    ds
}

/// The paper's test shortened to 600 s.
pub fn short() -> TrajectoryConfig {
    TrajectoryConfig {
        duration_s: 600.0,
        initial_standstill_s: 30.0,
        leg_north_m: 1500.0,
        leg_east_m: 1000.0,
        ..Default::default()
    }
}
