//! The Monte Carlo engine: hundreds of seeded runs, each simulating the truth and running
//! every filter on the same data, folded into [`Tally`] blocks in a fixed order.
//!
//! Each run also carries a lower reference for the errors: the covariance recursion of the
//! EKF with the truth model, its state reset to the true state before each step, so that
//! every Jacobian is evaluated on the true path (the Riccati recursion of the posterior
//! Cramer-Rao bound for additive Gaussian noise, with the expectation over the truth taken
//! by averaging over runs). No filter can be consistently below it; a filter close to it is
//! efficient.

use crate::config::StudyConfig;
use crate::error::StudyError;
use crate::tally::{cost_bin, Divergence, FilterTally, PairTally, Tally, BLOCK};
use navkf_dynamics::effect_spec::EffectSpec;
use navkf_dynamics::prior::typical_sigma;
use navkf_dynamics::rng::{stream, Purpose};
use navkf_dynamics::state::*;
use navkf_dynamics::{
    Attitude, NoiseConfig, PlatformModel, Registry, SimulatedRun, Simulator, SystemModel,
    Trajectory,
};
use navkf_filters::{nees, DivergenceCause, Ekf, Filter, FilterSpec, RunFailure, Runner};
use navkf_report::executor::Executor;
use navkf_report::Interrupted;
use rand::Rng;
use rand_distr::StandardNormal;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// A prepared study: models, simulator and filter settings, shared by all runs.
pub struct Study {
    /// The study file.
    pub config: StudyConfig,
    /// The truth simulator.
    pub sim: Simulator,
    /// The filters' model.
    pub filter_model: Arc<PlatformModel>,
    /// Filter state index -> truth state index (by name), `None` if the truth lacks it.
    pub to_truth: Vec<Option<usize>>,
    /// Initial one-sigma of every filter state.
    pub initial_sigma: Vec<f64>,
    /// Names of the stored times' states (the filter model's).
    pub names: Vec<String>,
    /// Stored times, s.
    pub times: Vec<f64>,
    /// What each compared filter is built from, in the study's order.
    filters: Vec<FilterSetup>,
}

/// One compared filter as specified, with its model (the filters' model in the spec's
/// attitude equations).
struct FilterSetup {
    spec: FilterSpec,
    model: Arc<PlatformModel>,
}

/// An estimate at one time, for the example run's plots.
#[derive(Debug, Clone, PartialEq)]
pub struct TracePoint {
    /// Time, s.
    pub t: f64,
    /// The state estimate.
    pub estimate: Vec<f64>,
    /// The one-sigma of each state the filter claims.
    pub sigma: Vec<f64>,
}

/// NIS totals over one run.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct NisTotals {
    /// Sum of the NIS of every update.
    pub sum: f64,
    /// Number of updates.
    pub updates: u64,
    /// Sum of their measurement dimensions (the expected sum of the NIS).
    pub dof: u64,
}

/// The stored times: the first measurement time at or after each multiple of `every` below
/// `duration`, then the last measurement time, without repeats (measurements fall at
/// multiples of `dt_meas` from `dt_meas` on; a run stores at most one value per measurement).
fn stored_times(every: f64, duration: f64, dt_meas: f64) -> Vec<f64> {
    // Work in measurement indices: multiple j of `every` lands on index ceil(j every / dt).
    let last = (duration / dt_meas).floor();
    let index_of = |j: f64| (j * every / dt_meas - 1e-9).ceil();
    let mut times: Vec<f64> = Vec::new();
    // Measurements start one interval in: index 1 at the earliest.
    let mut m = index_of(1.0).max(1.0);
    while m < last && m * dt_meas < duration - 1e-9 {
        times.push(m * dt_meas);
        // The first multiple beyond index m, and at least the next index: one step per
        // stored time however small `every` is.
        let j = ((m + 1e-9) * dt_meas / every).floor() + 1.0;
        m = index_of(j).max(m + 1.0);
    }
    times.push(last * dt_meas);
    times
}

/// `a` taken into `[-pi, pi)`; NaN stays NaN.
fn wrap_angle(a: f64) -> f64 {
    use std::f64::consts::{PI, TAU};
    if (-PI..PI).contains(&a) {
        a
    } else {
        a - TAU * ((a + PI) / TAU).floor()
    }
}

/// One filter's outcome on one run.
#[derive(Debug, Clone)]
pub struct FilterRun {
    /// `Err(failure)` when the run is excluded.
    pub outcome: Result<(), RunFailure>,
    /// Per stored time: errors `x_hat - x_true`.
    pub err: Vec<Vec<f64>>,
    /// Per stored time: claimed variances.
    pub var: Vec<Vec<f64>>,
    /// Per stored time: NEES.
    pub nees: Vec<f64>,
    /// Per stored time: mean NIS since the previous stored time.
    pub nis_window: Vec<f64>,
    /// NIS over the run.
    pub nis: NisTotals,
    /// Step costs, ns.
    pub step_ns: Vec<u64>,
    /// Estimates at every step (only for the example run).
    pub trace: Option<Vec<TracePoint>>,
}

/// One run: every filter, and the bound.
#[derive(Debug, Clone)]
pub struct RunRecord {
    /// Run index.
    pub run: usize,
    /// Per filter, in the study's order.
    pub filters: Vec<FilterRun>,
    /// Per stored time, per truth state: the bound's variance (`None` if it failed).
    pub bound: Option<Vec<Vec<f64>>>,
    /// True states at every measurement (only for the example run).
    pub truth: Option<navkf_dynamics::dataset::Truth>,
}

/// The example run's traces, for the estimate-versus-truth figures.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct ExampleRun {
    /// Run index.
    pub run: usize,
    /// State names (filter model).
    pub names: Vec<String>,
    /// Times, s.
    pub t: Vec<f64>,
    /// True value of each filter state at each time (NaN where the truth lacks the state).
    #[serde(with = "navkf_report::json_nan")]
    pub truth: Vec<Vec<f64>>,
    /// Per filter: estimates and sigmas at each time.
    pub filters: Vec<ExampleFilter>,
}

/// One filter's trace in the example run.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct ExampleFilter {
    /// Filter name.
    pub name: String,
    /// Times of the estimates (may stop early if the filter diverged).
    pub t: Vec<f64>,
    /// Estimates.
    #[serde(with = "navkf_report::json_nan")]
    pub estimate: Vec<Vec<f64>>,
    /// One-sigma.
    #[serde(with = "navkf_report::json_nan")]
    pub sigma: Vec<Vec<f64>>,
}

/// The model of the effect list at study key `key` (`truth.effects`), with the coefficients
/// it fixes. A bad entry is refused with its index: `truth.effects[1]: ...`.
fn build_model(
    key: &str,
    effects: &[String],
    noise: &NoiseConfig,
    attitude: Attitude,
) -> Result<
    (
        Arc<PlatformModel>,
        std::collections::BTreeMap<String, navkf_dynamics::Prior>,
    ),
    StudyError,
> {
    let EffectSpec { effects, fixed } = EffectSpec::parse_entries(effects, &Registry::catalogue())
        .map_err(|(i, e)| StudyError::Other(format!("{key}[{i}]: {e}")))?;
    Ok((
        Arc::new(PlatformModel::new(effects, noise)?.with_attitude(attitude)),
        fixed,
    ))
}

impl Study {
    /// Prepares a study from its configuration.
    pub fn new(config: StudyConfig) -> Result<Self, StudyError> {
        if let Some(sweep) = &config.sweep {
            return Err(StudyError::Other(format!(
                "the study sweeps `{}`: each of its points is a study of its own \
                 (navkf_study::sweep::points)",
                sweep.key
            )));
        }
        let noise = config.noise;
        let (truth_model, truth_fixed) = build_model(
            "truth.effects",
            &config.truth.effects,
            &noise,
            config.truth.attitude,
        )?;
        let filter_noise = NoiseConfig {
            gyro_psd: noise.gyro_psd * config.filter.process_noise_scale,
            accel_psd: noise.accel_psd * config.filter.process_noise_scale,
            ..noise
        };
        let filter_model_in = |attitude| {
            build_model(
                "filter.effects",
                &config.filter.effects,
                &filter_noise,
                attitude,
            )
            .map(|(m, _)| m)
        };
        let filter_model = filter_model_in(config.filter.attitude)?;
        let mut filters = Vec::new();
        for label in &config.study.filters {
            let spec = config.filter.plan(label).map_err(StudyError::Other)?;
            let model = if spec.attitude == filter_model.attitude() {
                filter_model.clone()
            } else {
                filter_model_in(spec.attitude)?
            };
            navkf_filters::SigmaPoints::new(model.dim(), spec.scaling).map_err(|e| {
                StudyError::Other(format!("the sigma-point scaling of `{label}`: {e}"))
            })?;
            filters.push(FilterSetup { spec, model });
        }
        let trajectory = Arc::new(Trajectory::build(&config.trajectory)?);
        let mut sim_cfg = config.truth.sim_config();
        // Typical sigmas scaled, then the effect list's fixed values, then explicit priors.
        let scale = config.truth.coefficient_scale;
        for i in NAV_DIM..truth_model.dim() {
            let name = &truth_model.state_names()[i];
            let typical = typical_sigma(&truth_model, i);
            sim_cfg
                .coefficients
                .entry(name.clone())
                .or_insert(navkf_dynamics::Prior::zero_mean(typical * scale));
        }
        for (k, v) in &truth_fixed {
            sim_cfg.coefficients.insert(k.clone(), *v);
        }
        for (k, v) in &config.truth.coefficients {
            sim_cfg.coefficients.insert(k.clone(), *v);
        }
        let sim = Simulator::new(truth_model.clone(), trajectory, sim_cfg, noise)?;
        let names = filter_model.state_names();
        let truth_names = truth_model.state_names();
        let to_truth = names
            .iter()
            .map(|n| truth_names.iter().position(|t| t == n))
            .collect();
        let init = &config.filter.initial;
        for name in init.coefficient_sigma.keys() {
            if !names.iter().skip(NAV_DIM).any(|n| n == name) {
                return Err(StudyError::Other(format!(
                    "filter.initial.coefficient_sigma.{name}: no such coefficient in the filters' model"
                )));
            }
        }
        let tilt = config.truth.initial_tilt;
        let initial_sigma: Vec<f64> = (0..filter_model.dim())
            .map(|i| {
                let s = match i {
                    PHI_X | PHI_Y => tilt.level_rad,
                    PHI_Z => tilt.azimuth_rad,
                    V_X | V_Y => init.velocity_sigma,
                    LAT => init.position_sigma_m / navkf_dynamics::earth::meridian_radius(0.0),
                    LON => init.position_sigma_m / navkf_dynamics::earth::RE,
                    _ => init
                        .coefficient_sigma
                        .get(&names[i])
                        .copied()
                        .unwrap_or(typical_sigma(&filter_model, i) * scale),
                };
                s * init.sigma_scale
            })
            .collect();
        // A sigma whose square overflows (or a NaN) would stop every run at its first step;
        // say which setting made it instead.
        if let Some(i) = initial_sigma.iter().position(|s| !(s * s).is_finite()) {
            let key = match i {
                PHI_X | PHI_Y => "truth.initial_tilt.level_rad".to_string(),
                PHI_Z => "truth.initial_tilt.azimuth_rad".to_string(),
                V_X | V_Y => "filter.initial.velocity_sigma".to_string(),
                LAT | LON => "filter.initial.position_sigma_m".to_string(),
                _ => format!("filter.initial.coefficient_sigma.{}", names[i]),
            };
            return Err(StudyError::Other(format!(
                "the initial sigma of {} is {:e} ({key}, times filter.initial.sigma_scale = \
                 {:e}): its variance is not a finite number; expected a sigma below 1e150",
                names[i], initial_sigma[i], init.sigma_scale
            )));
        }
        let every = config.study.series_every_s;
        let duration = config.trajectory.duration_s;
        let dt_meas = 1.0 / config.truth.measurement_rate_hz;
        let times = stored_times(every, duration, dt_meas);
        Ok(Study {
            config,
            sim,
            filter_model,
            to_truth,
            initial_sigma,
            names,
            times,
            filters,
        })
    }

    /// Filter names, in order.
    pub fn filter_names(&self) -> &[String] {
        &self.config.study.filters
    }

    /// The initial estimate of run `run`: the truth's start perturbed by the initial sigmas of
    /// the navigation states (so that the filters' initial covariance is honest), zero tilt
    /// and zero coefficients.
    fn initial_estimate(&self, run: usize, truth0: &[f64]) -> Vec<f64> {
        let mut rng = stream(self.config.study.seed, run as u64, Purpose::Other(1));
        let mut x = vec![0.0; self.filter_model.dim()];
        for i in [V_X, V_Y, LAT, LON] {
            let z: f64 = rng.sample(StandardNormal);
            x[i] = truth0[i] + self.initial_sigma[i] * z;
        }
        x
    }

    /// Runs everything for run `run`.
    pub fn run_one(&self, run: usize) -> RunRecord {
        let seed = self.config.study.seed;
        let sim_run = self.sim.run(seed, run as u64);
        let example = run == self.config.study.example_run;
        let x0 = self.initial_estimate(run, &sim_run.truth.states[0]);
        let n = self.filter_model.dim();
        let mut p0 = vec![0.0; n * n];
        for i in 0..n {
            p0[i + i * n] = self.initial_sigma[i] * self.initial_sigma[i];
        }
        let filters = self
            .filters
            .iter()
            .map(|setup| self.run_filter(setup, &sim_run, &x0, &p0, example))
            .collect();
        RunRecord {
            run,
            filters,
            bound: self.run_bound(&sim_run),
            truth: example.then(|| sim_run.truth.clone()),
        }
    }

    fn truth_at<'a>(&self, sim_run: &'a SimulatedRun, t: f64) -> &'a [f64] {
        let k = sim_run.truth.t.partition_point(|&s| s < t - 1e-9);
        &sim_run.truth.states[k.min(sim_run.truth.states.len() - 1)]
    }

    fn run_filter(
        &self,
        setup: &FilterSetup,
        sim_run: &SimulatedRun,
        x0: &[f64],
        p0: &[f64],
        example: bool,
    ) -> FilterRun {
        let n = self.filter_model.dim();
        let mut out = FilterRun {
            outcome: Ok(()),
            err: Vec::with_capacity(self.times.len()),
            var: Vec::with_capacity(self.times.len()),
            nees: Vec::with_capacity(self.times.len()),
            nis_window: Vec::with_capacity(self.times.len()),
            nis: NisTotals::default(),
            step_ns: Vec::with_capacity(sim_run.measurements.len()),
            trace: example.then(Vec::new),
        };
        let mut filter = match setup.spec.build(setup.model.clone()) {
            Ok(f) => f,
            Err(e) => {
                out.outcome = Err(RunFailure::new(DivergenceCause::Setup, e.to_string()));
                return out;
            }
        };
        if let Err(e) = filter.reset(x0, p0) {
            out.outcome = Err(RunFailure::new(DivergenceCause::Setup, e.to_string()));
            return out;
        }
        let mut scratch = vec![0.0; n * n + n];
        let mut next = 0usize;
        let (mut win_sum, mut win_count) = (0.0, 0u64);
        let mut failure: Option<RunFailure> = None;
        let result = Runner::new(16).run(
            &mut *filter,
            0.0,
            self.sim.inputs(),
            &sim_run.measurements,
            self.sim.noise(),
            |v| {
                out.step_ns.push(v.step_ns);
                let nis = v.report.nis;
                out.nis.sum += nis;
                out.nis.updates += 1;
                out.nis.dof += v.report.dim() as u64;
                win_sum += nis;
                win_count += 1;
                let x = v.filter.state();
                let p = v.filter.covariance();
                if let Some(tr) = out.trace.as_mut() {
                    let sig = (0..n).map(|i| p[i + i * n].max(0.0).sqrt()).collect();
                    tr.push(TracePoint {
                        t: v.t,
                        estimate: x.to_vec(),
                        sigma: sig,
                    });
                }
                if next < self.times.len() && v.t >= self.times[next] - 1e-9 {
                    let truth = self.truth_at(sim_run, v.t);
                    let mut xt = vec![0.0; n];
                    let mut err = vec![0.0; n];
                    for i in 0..n {
                        xt[i] = self.to_truth[i].map_or(0.0, |j| truth[j]);
                        err[i] = x[i] - xt[i];
                    }
                    // The attitude errors are angles: an estimate a full turn from the truth
                    // is the same attitude (the exact-attitude model's Euler angles are
                    // periodic). The error, and the truth the NEES sees, are taken within
                    // half a turn; in the small-angle regime this never applies.
                    for i in PHI_X..=PHI_Z {
                        let e = wrap_angle(err[i]);
                        if e != err[i] {
                            err[i] = e;
                            xt[i] = x[i] - e;
                        }
                    }
                    let var: Vec<f64> = (0..n).map(|i| p[i + i * n]).collect();
                    let e = match nees(&xt, x, p, &mut scratch) {
                        Ok(e) => e,
                        Err(e) => {
                            failure.get_or_insert(RunFailure::of_filter(
                                &e,
                                format!("t = {} s: {e}", v.t),
                            ));
                            f64::NAN
                        }
                    };
                    out.err.push(err);
                    out.var.push(var);
                    out.nees.push(e);
                    out.nis_window.push(win_sum / win_count.max(1) as f64);
                    win_sum = 0.0;
                    win_count = 0;
                    next += 1;
                }
            },
        );
        if let Err(e) = result {
            out.outcome = Err(RunFailure::of_filter(&e.error, e.to_string()));
        } else if let Some(f) = failure {
            out.outcome = Err(f);
        } else if out.err.len() != self.times.len() {
            out.outcome = Err(RunFailure::new(
                DivergenceCause::Stopped,
                format!(
                    "the run stopped after {} of {} stored times",
                    out.err.len(),
                    self.times.len()
                ),
            ));
        } else {
            let bound = self.config.divergence.max_error_initial_sigmas;
            let last = out.err.last().expect("at least one stored time");
            for (i, e) in last.iter().enumerate().skip(NAV_DIM) {
                let ratio = e.abs() / self.initial_sigma[i];
                if !(ratio <= bound) {
                    out.outcome = Err(RunFailure::new(
                        DivergenceCause::ErrorBound,
                        format!(
                            "final {} error is {ratio:.1} initial sigmas (bound {bound})",
                            self.names[i]
                        ),
                    ));
                    break;
                }
            }
        }
        out
    }

    fn run_bound(&self, sim_run: &SimulatedRun) -> Option<Vec<Vec<f64>>> {
        let mut out = Vec::with_capacity(self.times.len());
        let mut next = 0;
        self.bound_recursion(sim_run, |t, p, nt| {
            if next < self.times.len() && t >= self.times[next] - 1e-9 {
                out.push((0..nt).map(|i| p[i + i * nt]).collect());
                next += 1;
            }
        })
        .ok()?;
        Some(out)
    }

    /// The initial one-sigma of every truth state in the bound's recursion: the filters'
    /// where the states coincide, the truth's prior otherwise.
    pub fn bound_prior_sigma(&self) -> Vec<f64> {
        let model = self.sim.model();
        model
            .state_names()
            .iter()
            .enumerate()
            .map(
                |(i, name)| match self.names.iter().position(|n| n == name) {
                    Some(j) => self.initial_sigma[j],
                    None => self.sim.priors()[i].sigma.max(typical_sigma(model, i)),
                },
            )
            .collect()
    }

    /// The truth-linearised bound's covariance recursion along `sim_run` (see the module
    /// documentation): the EKF with the truth model, its state reset to the true state before
    /// each step. `visit(t, P, n)` sees the covariance (column-major, `n` = the truth model's
    /// dimension) after each update. Fails with the filter's own cause, at the measurement
    /// where the recursion broke.
    pub fn bound_recursion(
        &self,
        sim_run: &SimulatedRun,
        mut visit: impl FnMut(f64, &[f64], usize),
    ) -> Result<(), RunFailure> {
        let model = self.sim.model().clone();
        let nt = model.dim();
        let mut ekf = Ekf::new(model.clone());
        let mut p0 = vec![0.0; nt * nt];
        for (i, s) in self.bound_prior_sigma().into_iter().enumerate() {
            p0[i + i * nt] = s * s;
        }
        let mut xt0 = sim_run.truth.states[0].clone();
        xt0.truncate(nt);
        ekf.reset(&xt0, &p0)
            .map_err(|e| RunFailure::of_filter(&e, format!("the initial covariance: {e}")))?;
        let mut window = navkf_dynamics::InputWindow::with_capacity(16);
        let inputs = self.sim.inputs();
        let mut t_prev = 0.0;
        let mut cursor = 0;
        for (k, m) in sim_run.measurements.iter().enumerate() {
            // Window of input samples from t_prev to m.t (both on the input grid).
            window.clear();
            while cursor < inputs.len() && inputs[cursor].t < t_prev - 1e-9 {
                cursor += 1;
            }
            let mut c = cursor;
            while c < inputs.len() && inputs[c].t <= m.t + 1e-9 {
                window.push_linear(inputs[c].t, inputs[c].f);
                c += 1;
            }
            let at = |e: navkf_filters::FilterError| {
                let reason = format!("measurement {k} (t = {} s): {e}", m.t);
                RunFailure::of_filter(&e, reason)
            };
            ekf.set_state(&sim_run.truth.states[k]);
            ekf.predict(&window).map_err(at)?;
            ekf.set_state(&sim_run.truth.states[k + 1]);
            let (z, sigma, avail) =
                navkf_dynamics::sensors::observation_of(m, self.sim.noise(), 0.0);
            ekf.update(&navkf_filters::Observation {
                z: &z,
                sigma: &sigma,
                available: &avail,
            })
            .map_err(at)?;
            t_prev = m.t;
            visit(m.t, ekf.covariance(), nt);
        }
        Ok(())
    }

    /// Runs `runs` (a range of run indices) and folds them into one tally per block of
    /// [`BLOCK`] runs, in order. `progress` is told how many runs are done. A stop on
    /// request ([`navkf_report::interrupt`]) ends it with what was done.
    pub fn run_blocks(
        &self,
        blocks: std::ops::Range<usize>,
        progress: &(dyn Fn(usize) + Sync),
        example: impl FnMut(&RunRecord),
    ) -> Result<Vec<Tally>, Interrupted> {
        let mut out = Vec::with_capacity(blocks.len());
        self.for_each_block(blocks, progress, example, |t| out.push(t))?;
        Ok(out)
    }

    /// [`Study::run_blocks`] folded into one tally as the blocks complete: bit-identical to
    /// `output::fold(&run_blocks(..))`, but holding one group of blocks at a time, so memory
    /// does not grow with the number of runs.
    pub fn run_folded(
        &self,
        blocks: std::ops::Range<usize>,
        progress: &(dyn Fn(usize) + Sync),
        example: impl FnMut(&RunRecord),
    ) -> Result<Tally, Interrupted> {
        let mut total = Tally::default();
        self.for_each_block(blocks, progress, example, |t| total.merge(&t))?;
        Ok(total)
    }

    /// Runs `blocks` and hands each block's tally to `sink` as soon as it is complete, in
    /// block order. The runs go through the one executor
    /// ([`navkf_report::executor::Executor`]), which hands them on in run order, so the
    /// thread count changes nothing but speed. A stop on request ends it within one run,
    /// with [`Interrupted`]; the blocks not complete are not handed on.
    fn for_each_block(
        &self,
        blocks: std::ops::Range<usize>,
        progress: &(dyn Fn(usize) + Sync),
        mut example: impl FnMut(&RunRecord),
        mut sink: impl FnMut(Tally),
    ) -> Result<(), Interrupted> {
        let total = self.config.study.runs;
        let runs = (blocks.start * BLOCK).min(total)..(blocks.end * BLOCK).min(total);
        // Several blocks in flight at once for parallelism; memory stays bounded by them,
        // however many runs the study asks for.
        let in_flight = (rayon::current_num_threads() * 4).div_ceil(BLOCK).max(1);
        let executor = Executor::new("runs", in_flight * BLOCK);
        let mut tally: Option<Tally> = None;
        // Groups hold whole blocks, so the blocks handed on before a stop are whole.
        executor.run(runs, &|r| self.run_one(r), &progress, |r, rec| {
            let block = tally.get_or_insert_with(|| self.empty_tally(r / BLOCK * BLOCK));
            self.add_run(block, &rec);
            if rec.run == self.config.study.example_run {
                example(&rec);
            }
            if (r + 1) % BLOCK == 0 || r + 1 == total {
                sink(tally.take().expect("the block was started above"));
            }
        })
    }

    /// Number of blocks in the study.
    pub fn block_count(&self) -> usize {
        self.config.study.runs.div_ceil(BLOCK)
    }

    fn empty_tally(&self, first_run: usize) -> Tally {
        let f = self.filter_names();
        let mut pairs = Vec::new();
        for i in 0..f.len() {
            for j in i + 1..f.len() {
                pairs.push(PairTally {
                    a: f[i].clone(),
                    b: f[j].clone(),
                    ..Default::default()
                });
            }
        }
        Tally {
            first_run,
            runs: 0,
            filters: vec![FilterTally::default(); f.len()],
            bound: Default::default(),
            pairs,
        }
    }

    /// Folds one run into a tally.
    pub fn add_run(&self, tally: &mut Tally, rec: &RunRecord) {
        tally.runs += 1;
        for (t, fr) in tally.filters.iter_mut().zip(&rec.filters) {
            for &ns in &fr.step_ns {
                *t.step_cost.entry(cost_bin(ns)).or_insert(0) += 1;
            }
            match &fr.outcome {
                Err(failure) => t.diverged.push(Divergence {
                    run: rec.run,
                    failure: failure.clone(),
                }),
                Ok(()) => {
                    t.ok += 1;
                    let sq: Vec<Vec<f64>> = fr
                        .err
                        .iter()
                        .map(|e| e.iter().map(|v| v * v).collect())
                        .collect();
                    let mut single = FilterTally {
                        ok: 0,
                        sum_sq_err: sq,
                        sum_var: fr.var.clone(),
                        sum_nees: fr.nees.clone(),
                        sum_nis_window: fr.nis_window.clone(),
                        sum_nis: fr.nis.sum,
                        nis_count: fr.nis.updates,
                        nis_dof: fr.nis.dof,
                        ..Default::default()
                    };
                    let run_nis = fr.nis.sum / fr.nis.updates.max(1) as f64;
                    single.sum_run_nis = run_nis;
                    single.sum_run_nis_sq = run_nis * run_nis;
                    t.merge(&single);
                }
            }
        }
        if let Some(b) = &rec.bound {
            tally.bound.count += 1;
            crate::tally::add_rows(&mut tally.bound.sum_var, b);
        }
        let f = self.filter_names();
        let mut k = 0;
        for i in 0..f.len() {
            for j in i + 1..f.len() {
                let (a, b) = (&rec.filters[i], &rec.filters[j]);
                if a.outcome.is_ok() && b.outcome.is_ok() {
                    let (ea, eb) = (a.err.last().unwrap(), b.err.last().unwrap());
                    let d: Vec<f64> = ea.iter().zip(eb).map(|(x, y)| x * x - y * y).collect();
                    let d2: Vec<f64> = d.iter().map(|v| v * v).collect();
                    let p = &mut tally.pairs[k];
                    p.n += 1;
                    crate::tally::add_row(&mut p.sum_d, &d);
                    crate::tally::add_row(&mut p.sum_d2, &d2);
                }
                k += 1;
            }
        }
    }

    /// The example run's traces from its record.
    pub fn example_of(&self, rec: &RunRecord) -> ExampleRun {
        let truth = rec.truth.as_ref();
        let mut ex = ExampleRun {
            run: rec.run,
            names: self.names.clone(),
            ..Default::default()
        };
        if let Some(tr) = truth {
            for (t, s) in tr.t.iter().zip(&tr.states).skip(1) {
                ex.t.push(*t);
                ex.truth.push(
                    self.to_truth
                        .iter()
                        .map(|j| j.map_or(f64::NAN, |j| s[j]))
                        .collect(),
                );
            }
        }
        for (name, fr) in self.filter_names().iter().zip(&rec.filters) {
            let mut ef = ExampleFilter {
                name: name.clone(),
                ..Default::default()
            };
            if let Some(trace) = &fr.trace {
                for point in trace {
                    ef.t.push(point.t);
                    ef.estimate.push(point.estimate.clone());
                    ef.sigma.push(point.sigma.clone());
                }
            }
            ex.filters.push(ef);
        }
        ex
    }
}
