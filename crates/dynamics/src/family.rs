//! Model families: what the harness (studies, reports, plans) needs to know of a model
//! beyond the filters' [`SystemModel`], so that it runs the stabilised platform of
//! docs/model.md and the strapdown unit of docs/model.md, "The strapdown family", through
//! the same code.
//!
//! A family gives two things: a [`FamilyModel`] (its states' units, the typical size of
//! each constant state, and which navigation states a filter's first estimate takes from
//! the truth) and a [`TruthSimulation`] (runs of seeded truth with the family's inputs and
//! sensors). Both families so far share the layout of their first seven states (three
//! attitude angles, East and North velocity, latitude and longitude), which the studies'
//! initial sigmas and angle wrapping rely on; the states after them are constants
//! (coefficients or biases).
//!
//! A new family is a folder (its model, sensors, simulator) plus a [`ModelKind`] (listed in
//! [`ModelKind::ALL`]) and, each registered by one arm of a match the compiler points to: its
//! dataset files ([`crate::dataset::FamilyFiles`]), its study parts (`StudyFamily` in
//! `crates/study/src/family/`), its diagnosis catalogue (`crates/diagnose/src/catalogue/`)
//! and its diagnosis study (`StudyFamily` in `crates/diagnose/src/diagnosis_study/family/`).
//! docs/model.md, "The family contract", lists what still names the families directly.

use crate::dataset::Measurement;
pub use crate::model_kind::ModelKind;
use crate::sensors::MeasurementModel;
use crate::simulate::{Prior, SimulatedRun};
use crate::system::SystemModel;
use crate::trajectory::Trajectory;
use std::sync::Arc;

/// A model as the harness sees it: the filters' [`SystemModel`] plus what tables, figures
/// and Monte Carlo set-up need to know of its states.
pub trait FamilyModel: SystemModel {
    /// The unit of every state, for tables and axes (`rad`, `m/s`, `rad/s`, ...).
    fn state_units(&self) -> Vec<String>;
    /// The typical one-sigma of constant state `i` (a coefficient or a bias): the truth's
    /// draw where a study states none, and the filters' prior; zero for a navigation state.
    fn typical_sigma(&self, i: usize) -> f64;
    /// Whether a filter's first estimate of navigation state `i` is the truth plus a draw of
    /// its initial sigma (`true`), or zero because the state is itself an error whose truth
    /// was drawn from that sigma (the platform's tilt).
    fn estimate_starts_at_truth(&self, i: usize) -> bool;
}

/// Seeded truth runs of one family: the same run for the same seed, whatever the thread.
pub trait TruthSimulation: Send + Sync {
    /// The truth's model.
    fn truth_model(&self) -> Arc<dyn FamilyModel>;
    /// Run `run` of seed `seed`: inputs, measurements and true states.
    fn run(&self, seed: u64, run: u64) -> SimulatedRun;
    /// The prior every state's truth is drawn from (sigma 0: given).
    fn priors(&self) -> &[Prior];
    /// The sensors that read the runs' measurements, with the truth's noise.
    fn sensors(&self) -> &(dyn MeasurementModel<Record = Measurement> + Sync);
    /// The path driven.
    fn trajectory(&self) -> &Arc<Trajectory>;
    /// Odometer and GPS rate, Hz.
    fn measurement_rate_hz(&self) -> f64;
}
