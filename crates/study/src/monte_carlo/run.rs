//! One Monte Carlo run: simulate the truth with the run's seed, run every filter on the same
//! data, and record errors, sigmas, NEES, NIS and step costs at the stored times; a filter
//! that fails is a typed [`RunFailure`], counted, not a crash.

use super::{FilterSetup, Study};
use navkf_dynamics::state::*;
use navkf_dynamics::SimulatedRun;
use navkf_filters::{nees, DivergenceCause, RunFailure, Runner};

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
    /// Per stored time: the NIS since the previous stored time, per measured row, times the
    /// run's average number of rows (the mean NIS when the rows present do not vary).
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

impl Study {
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
        let (mut win_sum, mut win_dof) = (0.0, 0u64);
        let mut failure: Option<RunFailure> = None;
        let result = Runner::new(16).run(
            &mut *filter,
            0.0,
            &sim_run.inputs,
            &sim_run.measurements,
            self.sim.sensors(),
            |v| {
                out.step_ns.push(v.step_ns);
                let nis = v.report.nis;
                out.nis.sum += nis;
                out.nis.updates += 1;
                out.nis.dof += v.report.dim() as u64;
                win_sum += nis;
                win_dof += v.report.dim() as u64;
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
                    // NIS per measured row; scaled to the run's average rows below.
                    out.nis_window.push(win_sum / win_dof.max(1) as f64);
                    win_sum = 0.0;
                    win_dof = 0;
                    next += 1;
                }
            },
        );
        // Each window's NIS per row times the run's average rows: where the rows present vary
        // (a strapdown vehicle at a standstill has four, moving five) every window then has
        // the same expected value, the one the figure draws. With the platform's four rows at
        // every update this is the window's mean NIS bit for bit (dividing and multiplying by
        // four round nothing).
        if out.nis.updates > 0 {
            let rows = out.nis.dof as f64 / out.nis.updates as f64;
            for w in &mut out.nis_window {
                *w *= rows;
            }
        }
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
}
