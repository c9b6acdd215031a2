//! Walk-through: an effect of your own, outside the catalogue, two ways.
//!
//! `cargo run --release -p navkf-diagnose --example user_effect`
//!
//! In Rust (a drag on the rates):
//! 1. Write the effect: one type implementing `Effect` (its coefficients, what it adds to the
//!    derivatives, and the partial derivatives the EKF needs), and check those partials
//!    against finite differences (`partials_check::check_effect`).
//! 2. Register it next to the catalogue.
//! 3. Diagnose a dataset with it as a candidate, then with it switched on, and watch the
//!    error fall.
//!
//! In TOML, without Rust (docs/declared-effects.md): the same drag declared, which the
//! diagnosis finds as it found the Rust one; then an effect on the measurement, an odometer
//! whose scale grows with speed, which the catalogue alone can only stand in for.
//!
//! Here the data come from the simulator with the effect in the truth; with recorded data,
//! read the folder with `Dataset::read` instead (a `dataset.toml` may declare effects too).

use navkf_diagnose::{diagnose, Options, Verdict};
use navkf_dynamics::declared::parse_declarations;
use navkf_dynamics::partials_check::check_effect;
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

    // Step 1, continued: the partials the EKF uses, against finite differences.
    let report = check_effect(Box::new(Drag), &noise, 16, 1).unwrap();
    println!("{report}");
    assert!(report.passes());

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

/// The drag of the walk-through and an odometer whose scale grows with speed, declared in
/// TOML: `rates[row] += coefficient x feature`, `z[channel] += coefficient x feature`.
const DECLARED: &str = r#"
[[effect]]
name = "drag-declared"
coefficients = [{ name = "kd2", unit = "1/s", sigma = 5e-5 }]
rates = [
    { to = "v_x", coefficient = "kd2", feature = "v_x", factor = -1 },
    { to = "v_y", coefficient = "kd2", feature = "v_y", factor = -1 },
]

[[effect]]
name = "odometer-speed-scale"
coefficients = [{ name = "k2", unit = "s/m", sigma = 1e-4, bound = 1e-2 }]
measurement = [
    { to = "v_x", coefficient = "k2", feature = "v_x_speed" },
    { to = "v_y", coefficient = "k2", feature = "v_y_speed" },
]
"#;

/// What one declared effect's diagnosis found (read by the test; `main` prints it as it goes).
#[cfg_attr(not(test), allow(dead_code))]
struct Found {
    /// The verdict with the catalogue alone.
    alone: Verdict,
    /// The verdict with the declared effect beside the catalogue.
    verdict: Verdict,
    /// The effect named then.
    named: Option<String>,
    /// Its coefficient's estimate.
    estimate: f64,
}

/// The declared effects' walk-through: for each, the dataset's truth carries it, and the
/// diagnosis runs with the catalogue alone and with the declared effect beside it.
fn declared_walk_through() -> Vec<Found> {
    let mut registry = Registry::catalogue();
    registry
        .declare(&parse_declarations(DECLARED).unwrap())
        .unwrap();
    let noise = NoiseConfig::default();
    let traj = Arc::new(Trajectory::build(&TrajectoryConfig::default()).unwrap());
    let mut out = Vec::new();
    for (effect, coefficient, value) in [
        ("drag-declared", "kd2", 5e-5),
        ("odometer-speed-scale", "k2", 2e-4),
    ] {
        let model = PlatformModel::new(registry.build_all(&[effect]).unwrap(), &noise).unwrap();
        let mut cfg = TruthConfig::default();
        cfg.coefficients
            .insert(coefficient.into(), Prior::fixed(value));
        let sim = Simulator::new(Arc::new(model), traj.clone(), cfg, noise).unwrap();
        let mut ds = sim.dataset(effect, 1, &sim.run(1, 0));
        // The simulated dataset declares its effect, as its dataset.toml would. To see what
        // the catalogue alone makes of the data, forget the declaration and the truth.
        let mut alone = ds.clone();
        alone.effects.clear();
        alone.truth = None;
        let (before, _) = diagnose(&alone, &Registry::catalogue(), &Options::default()).unwrap();
        ds.truth = None;
        let catalogue = navkf_diagnose::catalogue::of(&ds).unwrap();
        let (after, _) = diagnose(&ds, &*catalogue, &Options::default()).unwrap();
        let estimate = after
            .model
            .coefficients
            .iter()
            .find(|c| c.name == coefficient)
            .map_or(f64::NAN, |c| c.estimate);
        let name = |d: &navkf_diagnose::Diagnosis| d.best.clone().unwrap_or("none".into());
        println!(
            "{effect} (true {coefficient} = {value:e}): catalogue alone: {}, named {}; \
             declared: {}, named {}, {coefficient} = {estimate:.4e}",
            before.verdict,
            name(&before),
            after.verdict,
            name(&after)
        );
        out.push(Found {
            alone: before.verdict,
            verdict: after.verdict,
            named: after.best,
            estimate,
        });
    }
    out
}

fn main() {
    walk_through();
    declared_walk_through();
}

/// The declared drag is found as the Rust one is, and the declared odometer effect turns the
/// catalogue's stand-in (`odometer-scale`, partly explained) into an explained verdict.
#[test]
fn the_declared_effects_are_found_where_the_catalogue_only_stands_in() {
    let runs = declared_walk_through();
    for (found, (name, truth)) in runs
        .iter()
        .zip([("drag-declared", 5e-5), ("odometer-speed-scale", 2e-4)])
    {
        assert_ne!(
            found.alone,
            Verdict::Explained,
            "{name}: the catalogue alone"
        );
        assert_eq!(found.verdict, Verdict::Explained, "{name}");
        assert_eq!(found.named.as_deref(), Some(name));
        let e = found.estimate;
        assert!(
            (e - truth).abs() < 0.1 * truth,
            "{name}: {e} against {truth}"
        );
    }
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
