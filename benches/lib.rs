//! Shared set-up for the benchmarks: a realistic filter state mid-trajectory.

use navkf_dynamics::prior::base_coefficient_sigma;
use navkf_dynamics::sensors::observation_of;
use navkf_dynamics::state::*;
use navkf_dynamics::*;
use navkf_filters::*;
use std::sync::Arc;

/// Two catalogued effects that add rates, the benchmarks' with-effects case (every candidate
/// fit of a diagnosis carries some).
pub const RATE_EFFECTS: [&str; 2] = ["accel-cross-axis", "torquer-scale"];

/// A filter warmed up on 300 s of a simulated run, with the next window (1 s, 10 input
/// sub-steps, cruising) and its measurement.
pub struct Scenario {
    /// The model: the base one, or with effects.
    pub model: Arc<PlatformModel>,
    /// Initial state for `reset`.
    pub x0: Vec<f64>,
    /// Initial covariance.
    pub p0: Vec<f64>,
    /// Inputs of the simulated run.
    pub sim: Simulator,
    /// The run.
    pub run: SimulatedRun,
}

impl Scenario {
    /// Builds the scenario (seed 1, run 0, default trajectory) on the base model.
    pub fn new() -> Self {
        Self::with_effects(&[])
    }

    /// The scenario with catalogued effects switched on, in the truth and in the filters (their
    /// coefficients drawn from, and started at, their typical sigma).
    pub fn with_effects(effects: &[&str]) -> Self {
        Self::with_effect_objects(Registry::catalogue().build_all(effects).unwrap())
    }

    /// The scenario with these effects switched on (see [`Scenario::with_effects`]).
    pub fn with_effect_objects(effects: Vec<Box<dyn DynEffect>>) -> Self {
        Self::with_model(effects, Attitude::SmallAngle)
    }

    /// The base model in the exact-attitude variant, in the truth and in the filters.
    pub fn exact_attitude() -> Self {
        Self::with_model(Vec::new(), Attitude::Exact)
    }

    /// The scenario with these effects and attitude equations.
    pub fn with_model(effects: Vec<Box<dyn DynEffect>>, attitude: Attitude) -> Self {
        let noise = NoiseConfig::default();
        let model = Arc::new(
            PlatformModel::new(effects, &noise)
                .unwrap()
                .with_attitude(attitude),
        );
        let traj = Arc::new(Trajectory::build(&TrajectoryConfig::default()).unwrap());
        let sim = Simulator::new(model.clone(), traj, TruthConfig::default(), noise).unwrap();
        let run = sim.run(1, 0);
        let n = model.dim();
        let mut x0 = vec![0.0; n];
        x0[LAT] = run.truth.states[0][LAT];
        x0[LON] = run.truth.states[0][LON];
        let mut p0 = vec![0.0; n * n];
        for i in 0..n {
            let s = match i {
                PHI_X | PHI_Y => 4.85e-5,
                PHI_Z => 2.91e-4,
                V_X | V_Y => 0.01,
                LAT | LON => 5e-7,
                _ if i < BASE_DIM => base_coefficient_sigma(i),
                _ => 0.0,
            };
            p0[i + i * n] = s * s;
        }
        for (i, s) in model.effect_coefficient_sigmas() {
            p0[i + i * n] = s * s;
        }
        Scenario {
            model,
            x0,
            p0,
            sim,
            run,
        }
    }

    /// Resets `f` and runs it over the first `seconds` of the run.
    pub fn warm_up<F: Filter + ?Sized>(&self, f: &mut F, seconds: f64) {
        f.reset(&self.x0, &self.p0).unwrap();
        let meas: Vec<_> = self
            .run
            .measurements
            .iter()
            .filter(|m| m.t <= seconds)
            .copied()
            .collect();
        Runner::new(16)
            .run(f, 0.0, self.sim.inputs(), &meas, self.sim.noise(), |_| {})
            .unwrap();
    }

    /// The window from `t` to `t + 1` s (10 input sub-steps) and the measurement at `t + 1`.
    pub fn window_at(&self, t: f64) -> (InputWindow, [f64; 4], [f64; 4], [bool; 4]) {
        let mut w = InputWindow::with_capacity(11);
        for s in self
            .sim
            .inputs()
            .iter()
            .filter(|s| s.t >= t - 1e-9 && s.t <= t + 1.0 + 1e-9)
        {
            w.push_linear(s.t, s.f);
        }
        let m = self
            .run
            .measurements
            .iter()
            .find(|m| (m.t - (t + 1.0)).abs() < 1e-9)
            .unwrap();
        let (z, s, a) = observation_of(m, self.sim.noise(), 0.8);
        (w, z, s, a)
    }
}

/// An effect that adds five coefficients and nothing else: what a larger state costs the
/// filters without any physics (`step_timing --idle-coefficients`, `prop_timing --idle`).
#[derive(Debug)]
pub struct IdleCoefficients;

impl Effect for IdleCoefficients {
    fn name(&self) -> &str {
        "idle-coefficients"
    }
    fn description(&self) -> &str {
        "five coefficients that enter nothing (a benchmark control)"
    }
    fn coefficient_names(&self) -> &[&str] {
        &["idle1", "idle2", "idle3", "idle4", "idle5"]
    }
    fn coefficient_units(&self) -> &[&str] {
        &["1"; 5]
    }
    fn coefficient_sigma(&self) -> &[f64] {
        &[1e-4; 5]
    }
    fn terms(&self) -> Terms {
        Terms::default()
    }
}

/// Every filter the harness has ([`FilterKind::ALL`]), built for `model` with the paper's
/// sigma-point scaling.
pub fn all_filters(model: &Arc<PlatformModel>) -> Vec<Box<dyn Filter>> {
    FilterKind::ALL
        .iter()
        .map(|k| k.build(model.clone(), SigmaScaling::default()).unwrap())
        .collect()
}

impl Default for Scenario {
    fn default() -> Self {
        Self::new()
    }
}
