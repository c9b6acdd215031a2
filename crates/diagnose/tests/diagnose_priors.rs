//! A prior is where the diagnosis starts, never a cap on what it finds: a coefficient stated
//! far tighter than the data say is still found at its size.

use navkf_diagnose::{diagnose, Options};
use navkf_dynamics::simulate::Prior;
use navkf_dynamics::{
    NoiseConfig, PlatformModel, PlatformPrior, Registry, Simulator, Trajectory, TrajectoryConfig,
    TruthConfig,
};
use std::collections::BTreeMap;
use std::sync::Arc;

#[test]
fn a_tight_stated_prior_does_not_cap_an_effect_the_data_hold() {
    let noise = NoiseConfig::default();
    let effects = Registry::catalogue()
        .build_all(&["odometer-scale"])
        .unwrap();
    let model = Arc::new(PlatformModel::new(effects, &noise).unwrap());
    let traj = Arc::new(Trajectory::build(&TrajectoryConfig::default()).unwrap());
    let truth = 3e-3;
    let cfg = TruthConfig {
        coefficients: BTreeMap::from([("kod".to_string(), Prior::fixed(truth))]),
        ..Default::default()
    };
    let sim = Simulator::new(model, traj, cfg, noise).unwrap();
    let ds = sim.dataset("tight-prior", 7, &sim.run(7, 0));
    let mut prior = PlatformPrior::default();
    prior.coefficients.insert("kod".into(), 1e-9);
    let opts = Options {
        with: vec!["odometer-scale".into()],
        prior,
        ..Default::default()
    };
    let d = diagnose(&ds, &Registry::catalogue(), &opts).unwrap().0;
    let kod = d
        .model
        .coefficients
        .iter()
        .find(|c| c.name == "kod")
        .expect("kod in the final model");
    // Capped at 1000 x 1e-9 it could not exceed about 3e-6.
    assert!(
        (kod.estimate - truth).abs() < 0.1 * truth,
        "kod = {:e} +- {:e} (prior {:e}), truth {truth:e}",
        kod.estimate,
        kod.sigma,
        kod.prior_sigma
    );
}
