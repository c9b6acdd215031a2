//! The platform as a model family ([`crate::family`]): its model's units and typical
//! coefficient sizes (docs/model.md, "Catalogue of effects"), and its simulator's runs.

use super::PlatformModel;
use crate::dataset::Measurement;
use crate::family::{FamilyModel, TruthSimulation};
use crate::prior::typical_sigma;
use crate::sensors::MeasurementModel;
use crate::simulate::{Prior, SimulatedRun, Simulator};
use crate::state::{LAT, LON, V_X, V_Y};
use crate::trajectory::Trajectory;
use std::sync::Arc;

impl FamilyModel for PlatformModel {
    fn state_units(&self) -> Vec<String> {
        self.units().to_vec()
    }
    fn typical_sigma(&self, i: usize) -> f64 {
        typical_sigma(self, i)
    }
    /// The tilt is an error whose truth is drawn: a filter starts it at zero.
    fn estimate_starts_at_truth(&self, i: usize) -> bool {
        matches!(i, V_X | V_Y | LAT | LON)
    }
}

impl TruthSimulation for Simulator {
    fn truth_model(&self) -> Arc<dyn FamilyModel> {
        self.model().clone()
    }
    fn run(&self, seed: u64, run: u64) -> SimulatedRun {
        Simulator::run(self, seed, run)
    }
    fn priors(&self) -> &[Prior] {
        Simulator::priors(self)
    }
    fn sensors(&self) -> &(dyn MeasurementModel<Record = Measurement> + Sync) {
        self.noise()
    }
    fn trajectory(&self) -> &Arc<Trajectory> {
        Simulator::trajectory(self)
    }
    fn measurement_rate_hz(&self) -> f64 {
        self.config().measurement_rate_hz
    }
}
