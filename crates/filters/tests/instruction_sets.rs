//! The two compiled copies of the hot kernels (`navkf_dynamics::instruction_set`) give the same
//! bits: every filter, on both model families, with and without effects, run over a simulated
//! drive with the copy the CPU chooses and again with the baseline copy forced, ends in the same
//! state and covariance, bit for bit. A kernel whose copies rounded differently (a fused
//! multiply-add in one copy only, say) fails here.
//!
//! In a build that targets AVX2 and FMA itself, or on a CPU without them, there is one copy
//! and the test compares it with itself (it says so).

mod common;

use navkf_dynamics::dataset::Measurement;
use navkf_dynamics::instruction_set::{force_baseline, instruction_set, InstructionSet};
use navkf_dynamics::strapdown::effect_list::StrapdownEffectList;
use navkf_dynamics::strapdown::effects::StrapdownRegistry;
use navkf_dynamics::strapdown::model::StrapdownModel;
use navkf_dynamics::strapdown::simulate::StrapdownSimulator;
use navkf_dynamics::strapdown::state::NAV_DIM as STRAPDOWN_NAV_DIM;
use navkf_dynamics::strapdown::unit_class::UnitClass;
use navkf_dynamics::{
    Attitude, FamilyModel, MeasurementModel, NoiseConfig, PlatformModel, Registry, SimulatedRun,
    Simulator, SystemModel, Trajectory, TruthConfig,
};
use navkf_filters::{FilterKind, Runner, SigmaScaling};
use std::collections::BTreeMap;
use std::sync::{Arc, Mutex};

/// `force_baseline` is process-wide: the tests of this file take turns.
static SWITCH: Mutex<()> = Mutex::new(());

/// The final state and covariance bits of `kind` over `run`, or the error it stopped with.
fn final_bits<M: SystemModel + 'static, S: MeasurementModel<Record = Measurement> + ?Sized>(
    kind: FilterKind,
    model: &Arc<M>,
    run: &SimulatedRun,
    sensors: &S,
    x0: &[f64],
    p0: &[f64],
) -> Result<Vec<u64>, String> {
    let mut f = kind
        .build(model.clone(), SigmaScaling::default())
        .map_err(|e| e.to_string())?;
    f.reset(x0, p0).map_err(|e| e.to_string())?;
    Runner::new(16)
        .run(
            &mut *f,
            0.0,
            &run.inputs,
            &run.measurements,
            sensors,
            |_| {},
        )
        .map_err(|e| e.to_string())?;
    Ok(f.state()
        .iter()
        .chain(f.covariance())
        .map(|v| v.to_bits())
        .collect())
}

/// Runs every filter with the chosen copy, then with the baseline forced; asserts equal bits.
/// Within each copy's turn the filters run side by side, one thread each: the copy is a
/// process-wide switch, but the filters share nothing else.
fn assert_copies_agree<
    M: SystemModel + 'static,
    S: MeasurementModel<Record = Measurement> + Sync + ?Sized,
>(
    what: &str,
    model: &Arc<M>,
    run: &SimulatedRun,
    sensors: &S,
    x0: &[f64],
    p0: &[f64],
) {
    let _turn = SWITCH.lock().unwrap_or_else(|e| e.into_inner());
    force_baseline(false);
    let chosen = instruction_set();
    if chosen != InstructionSet::Avx2Fma {
        eprintln!("{what}: one copy only ({chosen}); comparing it with itself");
    }
    let every_filter = |baseline: bool| {
        force_baseline(baseline);
        let bits: Vec<_> = std::thread::scope(|scope| {
            let runs: Vec<_> = FilterKind::ALL
                .into_iter()
                .map(|kind| scope.spawn(move || final_bits(kind, model, run, sensors, x0, p0)))
                .collect();
            runs.into_iter().map(|r| r.join().unwrap()).collect()
        });
        force_baseline(false);
        bits
    };
    let fast = every_filter(false);
    let plain = every_filter(true);
    for ((kind, fast), plain) in FilterKind::ALL.into_iter().zip(fast).zip(plain) {
        assert!(fast.is_ok(), "{what}, {kind}: {:?}", fast);
        assert_eq!(
            fast, plain,
            "{what}, {kind}: the copy chosen ({chosen}) and the baseline copy differ"
        );
    }
}

fn platform_case(effects: &[&str], attitude: Attitude, what: &str) {
    let noise = NoiseConfig::default();
    let fx = Registry::catalogue().build_all(effects).unwrap();
    let model = Arc::new(
        PlatformModel::new(fx, &noise)
            .unwrap()
            .with_attitude(attitude),
    );
    let traj = Arc::new(Trajectory::build(&common::short_config(600.0)).unwrap());
    let sim = Simulator::new(model.clone(), traj, TruthConfig::default(), noise).unwrap();
    let run = sim.run(7, 0);
    let (x0, mut p0) = common::initial_estimate(&sim, &run);
    // The effects' coefficients start at their typical sigma where the helper leaves none.
    let n = model.dim();
    for i in 0..n {
        if p0[i * n + i] == 0.0 {
            p0[i * n + i] = model.typical_sigma(i).powi(2);
        }
    }
    assert_copies_agree(what, &model, &run, sim.noise(), &x0, &p0);
}

#[test]
fn platform_base_model_gives_the_same_bits_in_both_copies() {
    platform_case(&[], Attitude::SmallAngle, "platform, base");
}

#[test]
fn platform_rate_effects_and_exact_attitude_give_the_same_bits_in_both_copies() {
    platform_case(
        &["accel-cross-axis", "torquer-scale", "gps-latency"],
        Attitude::Exact,
        "platform, rate effects, exact attitude",
    );
}

#[test]
fn strapdown_models_give_the_same_bits_in_both_copies() {
    let noise = NoiseConfig::default();
    for list in [
        "",
        "gyro-scale,accel-misalignment,odometer-scale,gps-lever-arm,gyro-bias-instability",
    ] {
        let mut model = StrapdownModel::base(&noise);
        if !list.is_empty() {
            let effects =
                StrapdownEffectList::parse_entries(&[list], &StrapdownRegistry::catalogue())
                    .unwrap_or_else(|(_, e)| panic!("{e}"));
            model = model.with_effects(&effects, UnitClass::Mems, 1.0).unwrap();
        }
        let model = Arc::new(model);
        let traj = Arc::new(Trajectory::build(&common::short_config(600.0)).unwrap());
        let sim = StrapdownSimulator::new(
            model.clone(),
            traj,
            50.0,
            1.0,
            UnitClass::Mems.errors(),
            &BTreeMap::new(),
            noise,
        )
        .unwrap();
        let run = sim.run(3, 0);
        let n = model.dim();
        let x0 = run.truth.states[0].clone();
        let mut p0 = vec![0.0; n * n];
        for i in 0..n {
            let sigma = if i < STRAPDOWN_NAV_DIM {
                [1e-2, 1e-2, 3e-2, 0.1, 0.1, 1e-6, 1e-6][i]
            } else {
                model.typical_sigma(i)
            };
            p0[i * n + i] = sigma * sigma;
        }
        let what = format!("strapdown [{list}]");
        assert_copies_agree(&what, &model, &run, sim.sensors(), &x0, &p0);
    }
}
