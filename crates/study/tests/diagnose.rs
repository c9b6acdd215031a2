//! The diagnosis end to end, on simulated 2400 s vehicle tests whose truth carries effects the
//! model lacks. Effect sizes are ones a navigation engineer meets:
//!
//! - `odometer-scale` kod = 0.5 % (tyre pressure and wear change the wheel radius by that much);
//! - `gps-latency` tau = 0.2 s (an unmodelled receiver output delay);
//! - `gyro-fz` Kg13 = 0.1 deg/h/g (4.9e-8 rad/s per m/s^2) on every axis, a g-sensitive drift
//!   of an ordinary mechanical gyro, which on a level vehicle looks like a constant drift;
//! - outside the catalogue: a velocity-proportional drag on the platform's velocity,
//!   `v' -= kd v` with kd = 5e-5 1/s (7.5e-4 m/s^2 = 75 micro-g at 15 m/s), a term no
//!   catalogued effect has.

use navkf_dynamics::simulate::Prior;
use navkf_dynamics::state::{NAV_DIM, V_X, V_Y};
use navkf_dynamics::{
    dataset::Dataset, Effect, Kinematics, NoiseConfig, Partials, PlatformModel, Registry,
    Simulator, Trajectory, TrajectoryConfig, TruthConfig,
};
use navkf_study::diagnose::{diagnose, Diagnosis, Options};
use std::collections::BTreeMap;
use std::sync::Arc;

/// The drag term: not in the catalogue.
#[derive(Debug)]
struct Drag;
impl Effect for Drag {
    fn name(&self) -> &str {
        "drag"
    }
    fn description(&self) -> &str {
        "v' -= kd v"
    }
    fn coefficient_names(&self) -> &[&str] {
        &["kd"]
    }
    fn coefficient_units(&self) -> &[&str] {
        &["1/s"]
    }
    fn coefficient_sigma(&self) -> &[f64] {
        &[5e-5]
    }
    fn add_rates(&self, k: &Kinematics, c: &[f64], r: &mut [f64; NAV_DIM]) {
        r[V_X] -= c[0] * k.v_x;
        r[V_Y] -= c[0] * k.v_y;
    }
    fn add_rate_partials(&self, k: &Kinematics, c: &[f64], off: usize, p: &mut Partials) {
        p.add(V_X, V_X, -c[0]);
        p.add(V_Y, V_Y, -c[0]);
        p.add(V_X, off, -k.v_x);
        p.add(V_Y, off, -k.v_y);
    }
}

/// Simulates a dataset whose truth carries `effects` with the given fixed coefficients.
fn dataset(effects: Vec<Box<dyn Effect>>, fixed: &[(&str, f64)], seed: u64) -> Dataset {
    let noise = NoiseConfig::default();
    let model = Arc::new(PlatformModel::new(effects, &noise).unwrap());
    let traj = Arc::new(Trajectory::build(&TrajectoryConfig::default()).unwrap());
    let mut coefficients = BTreeMap::new();
    for (k, v) in fixed {
        coefficients.insert(k.to_string(), Prior::fixed(*v));
    }
    let cfg = TruthConfig {
        coefficients,
        ..Default::default()
    };
    let sim = Simulator::new(model, traj, cfg, noise).unwrap();
    let run = sim.run(seed, 0);
    sim.dataset("test", seed, &run)
}

fn catalogue(names: &[&str]) -> Vec<Box<dyn Effect>> {
    Registry::catalogue().build_all(names).unwrap()
}

fn run(ds: &Dataset, with: &[&str]) -> Diagnosis {
    let opts = Options {
        with: with.iter().map(|s| s.to_string()).collect(),
        ..Default::default()
    };
    diagnose(ds, &Registry::catalogue(), &opts).unwrap().0
}

/// RMS over the model's coefficients of (estimate - truth) / initial sigma.
fn normalised_error(d: &navkf_study::diagnose::FitSummary) -> f64 {
    let e: Vec<f64> = d
        .coefficients
        .iter()
        .filter_map(|c| c.truth.map(|t| ((c.estimate - t) / c.prior_sigma).powi(2)))
        .collect();
    (e.iter().sum::<f64>() / e.len() as f64).sqrt()
}

#[test]
fn no_hidden_effect_gives_no_confident_candidate() {
    // Catches a ranking that always names something.
    for seed in [3, 4] {
        let ds = dataset(Vec::new(), &[], seed);
        let d = run(&ds, &[]);
        assert_eq!(d.verdict, "consistent", "seed {seed}: {:#?}", d.findings);
        assert_eq!(d.best, None);
        assert!(
            d.candidates.iter().all(|c| c.bic_gain < 10.0),
            "seed {seed}: {:?}",
            d.candidates
        );
    }
}

#[test]
fn hidden_odometer_scale_ranks_first_and_adding_it_repairs_the_model() {
    let ds = dataset(catalogue(&["odometer-scale"]), &[("kod", 0.005)], 11);
    let d = run(&ds, &[]);
    assert_eq!(d.verdict, "explained");
    assert_eq!(d.best.as_deref(), Some("odometer-scale"));
    assert_eq!(d.candidates[0].effect, "odometer-scale");
    assert_eq!(d.model.nis.verdict, "above");
    // Its coefficient is recovered within 3 sigma.
    let kod = &d.candidates[0].coefficients[0];
    assert!(((kod.estimate - 0.005) / kod.sigma).abs() < 3.0, "{kod:?}");
    // Adding it: NIS inside its bounds, and the base coefficients' errors fall.
    let after = run(&ds, &["odometer-scale"]);
    assert_eq!(after.model.nis.verdict, "inside", "{:?}", after.model.nis);
    let before = after.before.as_ref().expect("before/after with --with");
    let (eb, ea) = (normalised_error(before), normalised_error(&after.model));
    assert!(
        ea < eb,
        "coefficient error did not fall: before {eb}, after {ea}"
    );
    assert_eq!(after.verdict, "consistent", "{:#?}", after.findings);
}

#[test]
fn two_hidden_effects_are_found_in_two_rounds() {
    let ds = dataset(
        catalogue(&["odometer-scale", "gps-latency"]),
        &[("kod", 0.005), ("tau", 0.2)],
        12,
    );
    let first = run(&ds, &[]);
    assert_eq!(
        first.best.as_deref(),
        Some("odometer-scale"),
        "{:#?}",
        first.findings
    );
    let second = run(&ds, &["odometer-scale"]);
    assert_eq!(
        second.best.as_deref(),
        Some("gps-latency"),
        "{:#?}",
        second.findings
    );
    let third = run(&ds, &["odometer-scale", "gps-latency"]);
    assert_eq!(third.verdict, "consistent", "{:#?}", third.findings);
}

#[test]
fn an_effect_outside_the_catalogue_is_not_attributed_to_a_catalogued_one() {
    let ds = dataset(vec![Box::new(Drag)], &[("kd", 5e-5)], 13);
    let d = run(&ds, &[]);
    assert!(
        !d.model.consistent,
        "the drag should make the base model inconsistent"
    );
    assert_eq!(
        d.verdict, "unexplained",
        "{:#?}\n{:#?}",
        d.findings, d.candidates
    );
    assert_eq!(d.best, None);
    // With the drag written as a user effect and registered, the diagnosis finds it.
    let mut reg = Registry::catalogue();
    reg.register("drag", || Box::new(Drag));
    let d = diagnose(&ds, &reg, &Options::default()).unwrap().0;
    assert_eq!(d.best.as_deref(), Some("drag"), "{:#?}", d.candidates);
}

#[test]
fn an_effect_the_trajectory_cannot_separate_is_reported_as_such_not_named() {
    // On a level vehicle fz is gravity, so Kg13 fz is a constant drift: Kg0 absorbs it.
    let k = 4.9e-8;
    let ds = dataset(
        catalogue(&["gyro-fz"]),
        &[("Kg13x", k), ("Kg13y", k), ("Kg13z", k)],
        14,
    );
    let d = run(&ds, &[]);
    assert_ne!(d.best.as_deref(), Some("gyro-fz"), "{:#?}", d.findings);
    let c = d
        .candidates
        .iter()
        .find(|c| c.effect == "gyro-fz")
        .expect("gyro-fz is a candidate");
    assert!(!c.supported);
    assert!(
        c.confused_with
            .iter()
            .any(|(p, r)| p.contains("Kg0") && r.abs() > 0.9),
        "{:?}",
        c.confused_with
    );
    assert!(
        d.findings
            .iter()
            .any(|f| f.contains("`gyro-fz` cannot be told apart")),
        "{:#?}",
        d.findings
    );
    assert_ne!(d.verdict, "explained", "{:#?}", d.findings);
}
