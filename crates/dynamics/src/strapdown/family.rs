//! The strapdown unit as a model family ([`crate::family`]): its states' units, its biases'
//! typical sizes (its unit class's), and its simulator's runs.

use super::model::StrapdownModel;
use super::simulate::StrapdownSimulator;
use super::state::*;
use crate::dataset::Measurement;
use crate::family::{FamilyModel, TruthSimulation};
use crate::sensors::MeasurementModel;
use crate::simulate::{Prior, SimulatedRun};
use crate::trajectory::Trajectory;
use std::sync::Arc;

impl FamilyModel for StrapdownModel {
    fn state_units(&self) -> Vec<String> {
        let coefficients = self.effects().iter().flat_map(|e| e.coefficients.iter());
        // A departure has its bias's unit.
        let layout = self.layout();
        let departures = [(layout.gyro_wander, BG_X), (layout.accel_wander, BA_X)]
            .into_iter()
            .filter(|(wander, _)| wander.is_some())
            .flat_map(|(_, bias)| [STATE_UNITS[bias]; 3]);
        STATE_UNITS
            .iter()
            .copied()
            .chain(departures)
            .chain(coefficients.map(|c| c.unit))
            .map(str::to_string)
            .collect()
    }
    fn typical_sigma(&self, i: usize) -> f64 {
        let unit = self.unit();
        match i {
            i if (BG_X..BG_X + 3).contains(&i) => unit.gyro_bias,
            i if (BA_X..BA_X + 3).contains(&i) => unit.accel_bias,
            i => self
                .departure_typical(i)
                .or_else(|| self.coefficient_sigma(i))
                .unwrap_or(0.0),
        }
    }
    /// Every navigation state is absolute: a filter starts from the truth off by a draw.
    fn estimate_starts_at_truth(&self, i: usize) -> bool {
        i < NAV_DIM
    }
}

impl TruthSimulation for StrapdownSimulator {
    fn truth_model(&self) -> Arc<dyn FamilyModel> {
        self.model().clone()
    }
    fn run(&self, seed: u64, run: u64) -> SimulatedRun {
        StrapdownSimulator::run(self, seed, run)
    }
    fn priors(&self) -> &[Prior] {
        StrapdownSimulator::priors(self)
    }
    fn sensors(&self) -> &(dyn MeasurementModel<Record = Measurement> + Sync) {
        self.sensors()
    }
    fn trajectory(&self) -> &Arc<Trajectory> {
        StrapdownSimulator::trajectory(self)
    }
    fn measurement_rate_hz(&self) -> f64 {
        StrapdownSimulator::measurement_rate_hz(self)
    }
}
