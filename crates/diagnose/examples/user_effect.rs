//! Walk-through: an effect of your own, outside the catalogue.
//!
//! `cargo run --release -p navkf-diagnose --example user_effect`
//!
//! 1. Write the effect: one type implementing `Effect` (its coefficients, what it adds to the
//!    derivatives, and the partial derivatives the EKF needs).
//! 2. Register it next to the catalogue.
//! 3. Diagnose a dataset with it as a candidate, then with it switched on, and watch the
//!    error fall.
//!
//! Here the data come from the simulator with the effect in the truth; with recorded data,
//! read the folder with `Dataset::read` instead.

use navkf_diagnose::{diagnose, Options};
use navkf_dynamics::simulate::Prior;
use navkf_dynamics::state::{NAV_DIM, V_X, V_Y};
use navkf_dynamics::{
    Effect, Kinematics, NoiseConfig, Partials, PlatformModel, Registry, Simulator, Trajectory,
    TrajectoryConfig, TruthConfig,
};
use std::sync::Arc;

/// Step 1: a velocity-proportional drag on the platform's velocity, `v' -= kd v`.
#[derive(Debug)]
struct Drag;

impl Effect for Drag {
    fn terms(&self) -> navkf_dynamics::Terms {
        navkf_dynamics::Terms {
            rates: true,
            linear_rates: &[],
            measurement: navkf_dynamics::MeasurementTerm::None,
            noise: false,
        }
    }
    fn name(&self) -> &str {
        "drag"
    }
    fn description(&self) -> &str {
        "v' -= kd v (velocity-proportional drag)"
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
    fn add_rates<T: navkf_dynamics::Real>(
        &self,
        k: &Kinematics<T>,
        c: &[T],
        rates: &mut [T; NAV_DIM],
    ) {
        rates[V_X] -= c[0] * k.v_x;
        rates[V_Y] -= c[0] * k.v_y;
    }
    fn add_rate_partials(&self, k: &Kinematics, c: &[f64], offset: usize, p: &mut Partials) {
        p.add(V_X, V_X, -c[0]);
        p.add(V_Y, V_Y, -c[0]);
        p.add(V_X, offset, -k.v_x);
        p.add(V_Y, offset, -k.v_y);
    }
}

/// Runs the walk-through; returns (NIS before, its upper 95 % bound, NIS after, error before,
/// error after).
fn walk_through() -> (f64, f64, f64, f64, f64) {
    // A dataset whose truth has a drag of 5e-5 1/s (75 micro-g at 15 m/s).
    let noise = NoiseConfig::default();
    let truth_model = Arc::new(PlatformModel::new(vec![Box::new(Drag)], &noise).unwrap());
    let traj = Arc::new(Trajectory::build(&TrajectoryConfig::default()).unwrap());
    let mut cfg = TruthConfig::default();
    cfg.coefficients.insert("kd".into(), Prior::fixed(5e-5));
    let sim = Simulator::new(truth_model, traj, cfg, noise).unwrap();
    let ds = sim.dataset("drag-demo", 1, &sim.run(1, 0));

    // With the catalogue alone, the diagnosis refuses to blame a catalogued effect.
    let catalogue = Registry::catalogue();
    let (d, _) = diagnose(&ds, &catalogue, &Options::default()).unwrap();
    let named = |d: &navkf_diagnose::Diagnosis| d.best.clone().unwrap_or("none".into());
    println!("catalogue only: verdict {}, named {}", d.verdict, named(&d));

    // Step 2: register the new effect.
    let mut registry = Registry::catalogue();
    registry.register(|| Box::new(Drag));
    let (d, _) = diagnose(&ds, &registry, &Options::default()).unwrap();
    println!(
        "with `drag` registered: verdict {}, named {}",
        d.verdict,
        named(&d)
    );

    // Step 3: switch it on (what `navkf diagnose --with drag` does) and compare before and
    // after.
    let opts = Options {
        with: vec!["drag".into()],
        ..Default::default()
    };
    let (after, fits) = diagnose(&ds, &registry, &opts).unwrap();
    let before = after.before.clone().unwrap();
    // Each error in the prior sigma its coefficient started from: a fit may widen a prior,
    // and an error over the widened sigma reads smaller than it is.
    let err = |f: &navkf_diagnose::FitSummary| {
        let e: Vec<f64> = f
            .coefficients
            .iter()
            .filter_map(|c| {
                let s0 = navkf_diagnose::plots::errors::initial_sigma(&after, &fits, &c.name)?;
                c.truth.map(|t| ((c.estimate - t) / s0).powi(2))
            })
            .collect();
        (e.iter().sum::<f64>() / e.len() as f64).sqrt()
    };
    println!(
        "NIS {:.2} -> {:.2} (expected 4); coefficient error {:.3} -> {:.3} initial sigmas",
        before.nis.mean,
        after.model.nis.mean,
        err(&before),
        err(&after.model)
    );
    for f in &after.findings {
        println!("  {f}");
    }
    (
        before.nis.mean,
        before.nis.bounds[1],
        after.model.nis.mean,
        err(&before),
        err(&after.model),
    )
}

fn main() {
    walk_through();
}

#[test]
fn the_walk_through_finds_the_effect_and_the_error_falls() {
    let (nis_before, upper, nis_after, err_before, err_after) = walk_through();
    // Above the 95 % bound of a consistent model's mean NIS over this record (4.11).
    assert!(
        nis_before > upper,
        "the drag should show in the NIS ({nis_before}, bound {upper})"
    );
    assert!(
        (nis_after - 4.0).abs() < 0.15,
        "NIS with the drag: {nis_after}"
    );
    assert!(err_after < err_before);
}
