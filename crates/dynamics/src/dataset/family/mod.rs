//! What a model family's dataset folder holds, and how it is checked: one implementation
//! of [`FamilyFiles`] per family, found by [`files_of`].
//!
//! Why a trait: the reader, the writer, `inspect`'s summary and the plausibility checks are
//! the same code for every family (`docs/data-format.md`); what differs is which file holds
//! the inputs and its header, how a sample holds the specific force, which odometer the
//! measurements carry, which states a truth may name and what `dataset.toml` may state.
//! Those differences live here, so that a new family's datasets are one implementation and
//! one arm of [`files_of`] (its registration), not branches through the dataset code.
//!
//! What a family cannot choose yet: the [`Measurement`](super::Measurement) record holds
//! the two odometers and the GPS pair of the families so far (a family with another
//! measurement, GPS height say, adds a field there).

mod platform;
mod strapdown;

use super::{DataWarning, Dataset, InputSample};
use crate::declared::EffectDeclaration;
use crate::effects::Registry;
use crate::error::DynamicsError;
use crate::model_kind::ModelKind;
use std::path::Path;

/// The odometer a family's `measurements.csv` carries (its columns after `t`, before the
/// GPS pair).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Odometer {
    /// `v_e,v_n`: the vehicle's East and North velocity, a pair complete or empty.
    VelocityEastNorth,
    /// `speed`: the signed speed along the vehicle's forward axis.
    ForwardSpeed,
}

/// A model family's dataset folder (module documentation).
pub trait FamilyFiles: Sync {
    /// The family.
    fn kind(&self) -> ModelKind;

    /// The file of inputs (`inputs.csv`, `imu.csv`).
    fn inputs_file(&self) -> &'static str;

    /// The header the writer gives the inputs file: `t`, then one column per number of an
    /// [`InputSample`] that the family uses, in its order.
    fn input_columns(&self) -> &'static [&'static str];

    /// Reads and checks the inputs file at `path` (every error located).
    fn read_inputs(&self, path: &Path) -> Result<Vec<InputSample>, DynamicsError>;

    /// The specific force of an input sample, m/s^2, in the frame the family's inputs are
    /// in (its magnitude is the same in any frame).
    fn specific_force(&self, sample: &InputSample) -> [f64; 3];

    /// What the first two axes of [`FamilyFiles::specific_force`] hold, in `inspect`'s
    /// manoeuvre line: the horizontal specific force where the inputs are in the navigation
    /// frame; for a strapdown unit the force in its own x-y plane, horizontal only while the
    /// unit is level.
    fn planar_force_words(&self) -> &'static str;

    /// How to read the vehicle's turn rate (rad/s, signed) off an input sample; `None` when
    /// the inputs hold no rate (then `inspect` takes the turns from the odometer's heading).
    fn turn_rate(&self) -> Option<fn(&InputSample) -> f64>;

    /// The odometer of `measurements.csv`.
    fn odometer(&self) -> Odometer;

    /// The header of `measurements.csv`: `t`, the odometer's columns, `lat_deg,lon_deg`.
    fn measurement_columns(&self) -> &'static [&'static str];

    /// What the family calls the start's angle about the vertical (`azimuth` on the
    /// platform, whose tilt is an error; `heading` for a strapdown unit), for keys, tables
    /// and figure axes.
    fn heading_word(&self) -> &'static str;

    /// The `[prior]` key of that angle's sigma (`azimuth_rad`, `heading_rad`).
    fn heading_prior_key(&self) -> String {
        format!("{}_rad", self.heading_word())
    }

    /// Declares `declared` (`dataset.toml`'s `[[effect]]`) into the family's catalogue
    /// (into `registry`, the platform's effects known so far, when the family's effects are
    /// the platform's) and returns every coefficient name `[prior.coefficients]` and
    /// `truth.csv` may use: the family's own constants, then its effects'.
    fn declare(
        &self,
        registry: &mut Registry,
        declared: &[EffectDeclaration],
    ) -> Result<Vec<String>, DynamicsError>;

    /// The navigation states a `truth.csv` may name, before the coefficients.
    fn navigation_names(&self) -> &'static [&'static str];

    /// States a `truth.csv` may name that are neither navigation states nor coefficients
    /// (a bias instability's departures, docs/model.md eq. (69)).
    fn other_truth_names(&self) -> &'static [&'static str] {
        &[]
    }

    /// Why a dataset of the family may not state `[initial]` (the whole refusal after
    /// `[initial]: `); `None`: it may, and the start attitude is checked.
    fn initial_refused(&self) -> Option<&'static str>;

    /// Whether the family reads the pseudo-measurements (`noise.nhc_m_s`, `noise.zupt_m_s`).
    fn has_pseudo_measurements(&self) -> bool;

    /// What an effects file of the family declares, for a refusal that names the other
    /// family's (`` `places` ``).
    fn declaration_terms(&self) -> &'static str;

    /// Whether `declaration` states the terms of this family ([`FamilyFiles::declaration_terms`]):
    /// what tells an effects file's family ([`crate::declared::DeclaredFile`]).
    fn states_own_terms(&self, declaration: &EffectDeclaration) -> bool;

    /// Values of `dataset` that parse, yet look written in the wrong unit, axes or form.
    fn warnings(&self, dataset: &Dataset) -> Vec<DataWarning>;
}

/// The dataset folder of `kind`: the families' registration.
pub fn files_of(kind: ModelKind) -> &'static dyn FamilyFiles {
    match kind {
        ModelKind::Platform => &platform::PlatformFiles,
        ModelKind::Strapdown => &strapdown::StrapdownFiles,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_family_is_registered_under_its_own_kind_with_consistent_headers() {
        for kind in ModelKind::ALL {
            let files = files_of(kind);
            assert_eq!(files.kind(), kind);
            assert_eq!(files.input_columns()[0], "t");
            let m = files.measurement_columns();
            assert_eq!(m[0], "t");
            assert_eq!(&m[m.len() - 2..], ["lat_deg", "lon_deg"]);
            let odometer_columns = match files.odometer() {
                Odometer::VelocityEastNorth => 2,
                Odometer::ForwardSpeed => 1,
            };
            assert_eq!(m.len(), 3 + odometer_columns, "{kind:?}");
            // The writer writes t and the first numbers of each sample.
            assert!(files.input_columns().len() <= 1 + crate::kinematics::INPUT_WIDTH);
        }
    }
}
