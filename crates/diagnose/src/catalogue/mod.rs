//! What a diagnosis needs of a model family: its catalogue of effects, the model a fit runs,
//! the sensors that read the data, where a filter starts, the channels a report shows and the
//! motion phases it sorts updates into. The rounds, the noise check, the candidates, the
//! stand-in test and the verdict run on this trait alone; [`platform`] (the platform's
//! [`navkf_dynamics::Registry`] is its catalogue) and [`strapdown`] are the two families
//! (docs/model.md, "The family contract").

pub mod platform;
pub mod strapdown;

use crate::error::DiagnoseError;
use navkf_dynamics::dataset::{Dataset, Measurement};
use navkf_dynamics::declared::DeclaredFile;
use navkf_dynamics::sensor_classes::PhysicalBound;
use navkf_dynamics::trajectory::Phase;
use navkf_dynamics::{
    Attitude, FamilyModel, InputWindow, MeasurementModel, ModelKind, NoiseConfig,
};
use std::collections::BTreeMap;
use std::sync::Arc;

/// A pinned coefficient's prior, as a share of its typical size.
pub const PINNED_SIGMA: f64 = 1e-6;

/// The most measurement channels a family has (the strapdown's seven).
pub const MAX_CHANNELS: usize = 7;

/// What a channel measures, where the figures need to know.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ChannelKind {
    /// A velocity or speed, m/s.
    Velocity,
    /// Latitude, rad (shown as metres north of the first fix).
    Latitude,
    /// Longitude, rad (shown as metres east of the first fix).
    Longitude,
    /// A pseudo-measurement that reads zero (the non-holonomic constraint, a zero-velocity
    /// update), m/s.
    Constraint,
}

/// One measurement channel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Channel {
    /// Name in tables (`v_x`, `speed`).
    pub name: &'static str,
    /// Title in figures.
    pub title: &'static str,
    /// What it measures.
    pub kind: ChannelKind,
}

impl Channel {
    /// The unit it is drawn in.
    pub fn unit(&self) -> &'static str {
        match self.kind {
            ChannelKind::Velocity | ChannelKind::Constraint => "m/s",
            ChannelKind::Latitude | ChannelKind::Longitude => "m",
        }
    }
}

/// What the diagnosis reads of one effect of the catalogue.
#[derive(Debug, Clone, PartialEq)]
pub struct EffectInfo {
    /// One line: what it adds, as a formula.
    pub description: String,
    /// Its coefficients' names (empty for a noise-only term).
    pub coefficients: Vec<String>,
    /// Their units, in the same order.
    pub units: Vec<String>,
    /// The bound of each coefficient, where declared.
    pub bounds: Vec<PhysicalBound>,
    /// A noise-only term's typical density (its one parameter), `None` for an effect with
    /// coefficients or one with no noise.
    pub noise_density: Option<f64>,
}

/// Where a filter starts on a dataset.
#[derive(Debug, Clone, PartialEq)]
pub struct Start {
    /// Time of the initial state, s.
    pub t: f64,
    /// The navigation states' first estimate (the rest start at zero).
    pub x: Vec<f64>,
    /// Their prior one-sigma.
    pub sigma: Vec<f64>,
}

/// A model family as the diagnosis sees it (module documentation).
pub trait Catalogue: Send + Sync + std::fmt::Debug {
    /// The family.
    fn kind(&self) -> ModelKind;
    /// The catalogued effects' names, in order.
    fn effect_names(&self) -> Vec<String>;
    /// What the diagnosis reads of effect `name`.
    fn effect(&self, name: &str) -> Result<EffectInfo, DiagnoseError>;
    /// The model of `effects` (with the parameters of those that have one, by effect) and
    /// the process noise of `noise`, with the filter's `attitude` equations.
    fn model(
        &self,
        effects: &[String],
        parameters: &BTreeMap<String, f64>,
        noise: &NoiseConfig,
        attitude: Attitude,
    ) -> Result<Arc<dyn FamilyModel>, DiagnoseError>;
    /// The sensors that read a dataset's records under `noise`.
    fn sensors(&self, noise: NoiseConfig)
        -> Box<dyn MeasurementModel<Record = Measurement> + Sync>;
    /// The measurement channels, in the model's order.
    fn channels(&self) -> &'static [Channel];
    /// Navigation states (the rest are coefficients).
    fn nav_dim(&self) -> usize;
    /// The names the tilt priors are reported by: level, then azimuth or heading.
    fn tilt_names(&self) -> [&'static str; 2];
    /// The widest the tilt priors may be tried (level, then azimuth or heading), rad: beyond,
    /// the start says nothing the attitude equations can use.
    fn widest_tilt(&self) -> [f64; 2] {
        [f64::INFINITY; 2]
    }
    /// The tilt priors when nothing states them, on `ds` whose first fix is at latitude
    /// `start_lat` (rad).
    fn default_tilt(&self, ds: &Dataset, start_lat: f64) -> [f64; 2];
    /// The base model's coefficients with their default one-sigma, for the priors' table.
    fn base_coefficients(&self) -> Vec<(String, f64)>;
    /// Where a filter starts on `ds` under `noise`, with tilt priors `tilt` (level, then
    /// azimuth or heading).
    fn start(
        &self,
        ds: &Dataset,
        noise: &NoiseConfig,
        tilt: [f64; 2],
    ) -> Result<Start, DiagnoseError>;
    /// How many of the noise sources ([`crate::noise::SOURCES`]) the family has: the four
    /// sensors', and the strapdown family's pseudo-measurement tolerance.
    fn noise_sources(&self) -> usize {
        4
    }
    /// Base coefficients the family's measurements cannot inform, which a fit holds at zero
    /// (a prior of [`PINNED_SIGMA`] times their typical size) rather than let a filter's
    /// linearisation drift them and the widening follow the drift.
    fn pinned(&self) -> &'static [&'static str] {
        &[]
    }
    /// The attitude the filters start from on `ds` and where it came from, when the family
    /// starts from an attitude (the strapdown family's `[initial]` or its alignment from the
    /// data); the report states it.
    fn start_attitude(&self, _ds: &Dataset) -> Option<crate::start_attitude::StartAttitude> {
        None
    }
    /// Why `candidate` cannot join a model holding `effects`, if it cannot: the strapdown
    /// family holds one coefficient per place of its sensor errors, and a declared effect
    /// may take a place of a catalogued one. The rounds then do not try it, and say so.
    fn cannot_join(&self, _effects: &[String], _candidate: &str) -> Option<String> {
        None
    }
    /// The motion phase of the step ending at `m`, from the readings of its window (the
    /// readings since the last update) or from the dataset's readings and measurements about
    /// `m`.
    fn phase(&self, ds: &Dataset, window: &InputWindow, m: &Measurement) -> Phase;
    /// The catalogue with the rival of a noise-only candidate added (a random walk of the
    /// accelerometer biases, outside the catalogue) and that rival's name and typical
    /// density; `None` when the family has none.
    fn with_rival(&self) -> Option<(Box<dyn Catalogue>, &'static str, f64)>;
    /// The catalogue with the settling rival of a noise-only candidate added (the
    /// accelerometer biases settling after switch-on, outside the catalogue, a function of
    /// time: [`crate::rivals::AccelSettling`]) and that rival's name; `None` when the family
    /// has none.
    fn with_settling_rival(&self) -> Option<(Box<dyn Catalogue>, &'static str)> {
        None
    }
    /// The catalogue with the structured rival of `effect` added (an explanation outside
    /// the catalogue that looks like it on a common trajectory: a GPS antenna away from the
    /// platform for `gps-latency`) and that rival's name; `None` when `effect` has none.
    fn with_structured_rival(&self, effect: &str) -> Option<(Box<dyn Catalogue>, &'static str)>;
    /// The catalogue with the structured rival of the refitted noise levels added (an error
    /// outside the catalogue that refitted noise can cover: on the platform an
    /// acceleration error growing with speed, a drag) and that rival's name; `None` when the
    /// family has none. An error when the rival cannot be declared beside the catalogue's
    /// effects: the levels are then not tested against it, and a diagnosis that went on
    /// without a word would name them as if they had been.
    fn with_levels_rival(&self) -> Result<Option<WithRival>, DiagnoseError> {
        Ok(None)
    }
}

/// A catalogue with a rival added, and the rival's name.
pub type WithRival = (Box<dyn Catalogue>, &'static str);

/// Every coefficient name a prior may be stated for in `catalogue`'s family: the base model's
/// and every effect's.
pub fn coefficient_names(catalogue: &dyn Catalogue) -> Vec<String> {
    let base = catalogue.base_coefficients().into_iter().map(|(n, _)| n);
    let effects = catalogue.effect_names().into_iter().flat_map(|e| {
        catalogue
            .effect(&e)
            .map(|i| i.coefficients)
            .unwrap_or_default()
    });
    base.chain(effects).collect()
}

/// The title figures give the channel named `name` (the name itself when no family has it).
pub fn channel_title(name: &str) -> &str {
    platform::channels()
        .iter()
        .chain(strapdown::channels())
        .find(|c| c.name == name)
        .map_or(name, |c| c.title)
}

/// The first measurement with both an odometer reading (velocity or speed) and a GPS fix
/// (where a filter can start), with the fix in radians.
pub fn first_full_measurement(
    ds: &Dataset,
) -> Result<(&navkf_dynamics::dataset::Measurement, [f64; 2]), DiagnoseError> {
    ds.measurements
        .iter()
        .find_map(
            |m| match (m.velocity.is_some() || m.speed.is_some(), m.gps_rad()) {
                (true, Some(p)) => Some((m, p)),
                _ => None,
            },
        )
        .ok_or_else(|| {
            DiagnoseError::Data(format!(
                "dataset `{}`: no measurement row has both odometer and GPS, so the filter \
                 cannot start",
                ds.name
            ))
        })
}

/// The catalogue of `ds`'s family, with the effects its `dataset.toml` declares
/// ([`navkf_dynamics::declared`]).
pub fn of(ds: &Dataset) -> Result<Box<dyn Catalogue>, DiagnoseError> {
    with_declared(ds, None)
}

/// [`of`], with the effects of `more` (`--effects-file`) declared beside the dataset's own:
/// refused when they are of the other family or clash with the dataset's, naming the file.
pub fn with_declared(
    ds: &Dataset,
    more: Option<&DeclaredFile>,
) -> Result<Box<dyn Catalogue>, DiagnoseError> {
    if let Some(file) = more {
        file.expect_family(ds.model, &format!("dataset `{}`", ds.name))?;
    }
    let more_declarations = more.map(DeclaredFile::declarations).unwrap_or_default();
    let in_file = |e| match more {
        Some(file) => file.locate(e),
        None => e,
    };
    match ds.model {
        ModelKind::Platform => {
            let mut registry = navkf_dynamics::Registry::catalogue();
            registry.declare(&ds.effects)?;
            registry.declare(more_declarations).map_err(in_file)?;
            Ok(Box::new(registry))
        }
        ModelKind::Strapdown => {
            let mut catalogue = strapdown::StrapdownCatalogue::for_dataset(ds);
            catalogue.registry.declare(&ds.effects)?;
            catalogue
                .registry
                .declare(more_declarations)
                .map_err(in_file)?;
            Ok(Box::new(catalogue))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// What each family's catalogue says of itself agrees with its model and sensors: the
    /// channels are the sensors' rows and the model's measurement, the base coefficients are
    /// the states after the navigation ones, every effect's bounds match its coefficients,
    /// and every held coefficient is a state of the model with the whole catalogue.
    #[test]
    fn each_catalogue_agrees_with_its_model_and_sensors() {
        let catalogues: [Box<dyn Catalogue>; 2] = [
            Box::new(navkf_dynamics::Registry::catalogue()),
            Box::new(strapdown::StrapdownCatalogue::default()),
        ];
        for c in &catalogues {
            let noise = NoiseConfig::default();
            let none = BTreeMap::new();
            let base = c.model(&[], &none, &noise, Attitude::SmallAngle).unwrap();
            assert_eq!(c.channels().len(), base.meas_dim(), "{:?}", c.kind());
            assert_eq!(c.sensors(noise).dim(), base.meas_dim());
            assert!(c.channels().len() <= MAX_CHANNELS);
            let names = base.state_names();
            let coefficients: Vec<String> =
                c.base_coefficients().into_iter().map(|(n, _)| n).collect();
            assert_eq!(&names[c.nav_dim()..], &coefficients[..], "{:?}", c.kind());
            let effects = c.effect_names();
            for e in &effects {
                let info = c.effect(e).unwrap();
                assert!(
                    info.bounds.is_empty() || info.bounds.len() == info.coefficients.len(),
                    "{e}"
                );
                assert!(
                    info.coefficients.is_empty() || info.noise_density.is_none(),
                    "{e}"
                );
            }
            let all = c
                .model(&effects, &none, &noise, Attitude::SmallAngle)
                .unwrap();
            let all_names = all.state_names();
            for p in c.pinned() {
                assert!(all_names.iter().any(|n| n == p), "{p} is no state");
            }
            assert!(c.noise_sources() <= crate::noise::MAX_SOURCES);
        }
    }
}
