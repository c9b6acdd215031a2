//! The truth-linearised bound of a run (see the module documentation of
//! [`crate::monte_carlo`]): the EKF's covariance recursion with the truth model, its state
//! reset to the true state before each step.

use super::Study;
use navkf_dynamics::SimulatedRun;
use navkf_filters::{Ekf, Filter, RunFailure};

impl Study {
    pub(super) fn run_bound(&self, sim_run: &SimulatedRun) -> Option<Vec<Vec<f64>>> {
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
        let model = self.sim.truth_model();
        model
            .state_names()
            .iter()
            .enumerate()
            .map(
                |(i, name)| match self.names.iter().position(|n| n == name) {
                    Some(j) => self.initial_sigma[j],
                    None => self.sim.priors()[i].sigma.max(model.typical_sigma(i)),
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
        let model = self.sim.truth_model();
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
        let inputs = &sim_run.inputs[..];
        let sensors = self.sim.sensors();
        let nz = sensors.dim();
        let (mut z, mut sigma, mut available) = (vec![0.0; nz], vec![0.0; nz], vec![false; nz]);
        let mut cursor = navkf_dynamics::InputCursor::at(inputs, 0.0);
        for (k, m) in sim_run.measurements.iter().enumerate() {
            cursor.advance(inputs, m.t, &mut window);
            let at = |e: navkf_filters::FilterError| {
                let reason = format!("measurement {k} (t = {} s): {e}", m.t);
                RunFailure::of_filter(&e, reason)
            };
            ekf.set_state(&sim_run.truth.states[k]);
            ekf.predict(&window).map_err(at)?;
            ekf.set_state(&sim_run.truth.states[k + 1]);
            sensors.observe(m, ekf.state(), &mut z, &mut sigma, &mut available);
            ekf.update(&navkf_filters::Observation {
                z: &z,
                sigma: &sigma,
                available: &available,
            })
            .map_err(at)?;
            visit(m.t, ekf.covariance(), nt);
        }
        Ok(())
    }
}
