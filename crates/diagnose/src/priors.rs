//! The priors a diagnosis starts from.
//!
//! **Where they come from.** Command-line flags over `dataset.toml`'s `[prior]` table over the
//! defaults of [`navkf_dynamics::prior`] (which gives their reasons). Every value is kept with
//! its source for the report.
//!
//! **Why they are only a start.** A prior caps what a Kalman filter can find: an estimate
//! stalls a few prior sigmas from zero however far the data pull it. So a fit may widen them
//! ([`crate::fit::widening`]); [`Priors`] keeps, beside the sigmas in use, the ones the
//! diagnosis started from ([`Priors::restarted`]) and which coefficients are the question
//! ([`Priors::open`]), which is what the widening's caps are counted from.

use crate::catalogue::Catalogue;
use navkf_dynamics::dataset::Dataset;
use navkf_dynamics::prior::{PlatformPrior, PriorSource};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// The prior sigmas a fit starts from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Priors {
    /// Initial level error, rad.
    pub level_rad: f64,
    /// Initial azimuth error, rad.
    pub azimuth_rad: f64,
    /// Coefficients whose sigma is not their typical one (stated or widened), by name.
    pub coefficients: BTreeMap<String, f64>,
    /// The coefficient sigmas the diagnosis started from (stated ones; the others are
    /// typical): the unit of the widening's caps.
    pub stated: BTreeMap<String, f64>,
    /// Coefficients of effects whose presence and size are the question (candidates, and
    /// effects named or added by `--with`): they may widen to
    /// [`WIDEST_EFFECT`](crate::fit::widening::WIDEST_EFFECT); the base model's, to
    /// [`WIDEST_BASE`](crate::fit::widening::WIDEST_BASE).
    pub open: Vec<String>,
}

impl Priors {
    /// The sigma coefficient `name` started from: its stated one, else `typical`.
    pub fn starting_sigma(&self, name: &str, typical: f64) -> f64 {
        self.stated.get(name).copied().unwrap_or(typical)
    }

    /// The priors the diagnosis started from: every widening undone.
    pub fn restarted(&self) -> Priors {
        Priors {
            coefficients: self.stated.clone(),
            ..self.clone()
        }
    }
}

/// One prior as the report shows it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PriorEntry {
    /// `level_rad`, `azimuth_rad` or a coefficient's name.
    pub name: String,
    /// One-sigma the diagnosis starts from.
    pub sigma: f64,
    /// The project's default for it.
    pub default: f64,
    /// Where `sigma` came from.
    pub source: PriorSource,
}

/// The starting priors for `ds`: `flags` over the dataset's `[prior]` table over the defaults
/// (the azimuth's at the dataset's first latitude; a strapdown dataset without `[initial]`
/// takes its tilt defaults from its alignment, marked [`PriorSource::Aligned`]). Returns them with the report's table: the
/// tilt, the 13 base coefficients and every stated effect coefficient.
pub fn resolve(
    ds: &Dataset,
    flags: &PlatformPrior,
    start_lat: f64,
    catalogue: &dyn Catalogue,
) -> (Priors, Vec<PriorEntry>) {
    let stated = ds.prior.overridden_by(flags);
    let source = |from_flag: bool| {
        if from_flag {
            PriorSource::Flag
        } else {
            PriorSource::Dataset
        }
    };
    let mut entries = Vec::new();
    // Without [initial], the tilt defaults are the alignment's sigmas.
    let unstated = if catalogue.start_attitude(ds).is_some_and(|a| a.is_aligned()) {
        PriorSource::Aligned
    } else {
        PriorSource::Default
    };
    let mut tilt = |name: &str, value: Option<f64>, flag: Option<f64>, default: f64| {
        let (sigma, src) = match value {
            Some(v) => (v, source(flag.is_some())),
            None => (default, unstated),
        };
        entries.push(PriorEntry {
            name: name.into(),
            sigma,
            default,
            source: src,
        });
        sigma
    };
    let [level_name, azimuth_name] = catalogue.tilt_names();
    let [level_default, azimuth_default] = catalogue.default_tilt(ds, start_lat);
    let level_rad = tilt(level_name, stated.level_rad, flags.level_rad, level_default);
    let azimuth_rad = tilt(
        azimuth_name,
        stated.azimuth_rad,
        flags.azimuth_rad,
        azimuth_default,
    );
    let base = catalogue.base_coefficients();
    for (name, default) in &base {
        let (sigma, src) = match stated.coefficients.get(name) {
            Some(&v) => (v, source(flags.coefficients.contains_key(name))),
            None => (*default, PriorSource::Default),
        };
        entries.push(PriorEntry {
            name: name.to_string(),
            sigma,
            default: *default,
            source: src,
        });
    }
    for (name, &v) in &stated.coefficients {
        if !base.iter().any(|(b, _)| b == name) {
            entries.push(PriorEntry {
                name: name.clone(),
                sigma: v,
                default: f64::NAN,
                source: source(flags.coefficients.contains_key(name)),
            });
        }
    }
    (
        Priors {
            level_rad,
            azimuth_rad,
            stated: stated.coefficients.clone(),
            coefficients: stated.coefficients,
            open: Vec::new(),
        },
        entries,
    )
}

/// A tilt prior sigma beyond which the small-angle model is out of its depth (0.5 deg:
/// `results/misalignment/` finds its EKF consistent at 0.1 deg and not at 1 deg).
pub const SMALL_ANGLE_LIMIT_RAD: f64 = 8.7e-3;

/// The starting tilt priors (`level_rad`, `azimuth_rad`) beyond [`SMALL_ANGLE_LIMIT_RAD`],
/// when a platform is diagnosed with the small-angle attitude equations: then a misalignment
/// of degrees can pass for a missing effect, and no effect is named ([`crate::naming`]).
pub fn beyond_small_angle(
    entries: &[PriorEntry],
    attitude: navkf_dynamics::Attitude,
    family: navkf_dynamics::ModelKind,
) -> Vec<&PriorEntry> {
    if attitude != navkf_dynamics::Attitude::SmallAngle || !family.is_platform() {
        return Vec::new();
    }
    entries
        .iter()
        .filter(|p| {
            matches!(p.name.as_str(), "azimuth_rad" | "level_rad")
                && p.sigma > SMALL_ANGLE_LIMIT_RAD
        })
        .collect()
}
