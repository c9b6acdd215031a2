//! A study file (`studies/*.toml`): every choice of a Monte Carlo comparison, in one place.
//!
//! The truth's effects and the filters' model effects are set separately, so a study can run
//! filters whose model lacks an effect the truth carries; so are their attitude equations
//! (`attitude = "small-angle" | "exact"`). A filter listed in `study.filters` is either a
//! filter kind (`ekf`) or a variant defined under `[filter.variants.<label>]`: a kind with its
//! own attitude equations or sigma-point scaling, compared under its label. Unknown keys are
//! errors.

pub mod model;
pub mod points;

pub use model::ModelSection;

use crate::error::StudyError;
use navkf_dynamics::input_file::{printable, read_text, toml_error, toml_message, TextFile};
use navkf_dynamics::simulate::InitialTilt;
use navkf_dynamics::{Attitude, NoiseConfig, TrajectoryConfig, TruthConfig};
use navkf_filters::{FilterKind, FilterSpec, SigmaScaling};
use navkf_report::StudyKind;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;

/// The `[study]` table.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StudySection {
    /// Name: results go to `results/<name>/`.
    pub name: String,
    /// The kind of study: `monte-carlo` (the default; not written when it is). A diagnosis
    /// study is another file format, loaded by `navkf-diagnose`.
    #[serde(default, skip_serializing_if = "StudyKind::is_monte_carlo")]
    pub kind: StudyKind,
    /// Number of Monte Carlo runs.
    pub runs: usize,
    /// Seed of every random stream.
    pub seed: u64,
    /// Filters to compare, by [`navkf_filters::FilterKind`] name (`ekf`, `standard_ukf`,
    /// `standard_ukf_25`, `simplified_ukf`, `square_root_ukf`) or by the label of a
    /// `[filter.variants.<label>]` table.
    pub filters: Vec<String>,
    /// Spacing of the stored time series, s. Values are stored at measurement times: each at
    /// the first measurement at or after a multiple of the spacing, so a spacing below the
    /// measurement interval stores every measurement.
    #[serde(default = "default_series_every")]
    pub series_every_s: f64,
    /// Run whose estimates are plotted against the truth.
    #[serde(default)]
    pub example_run: usize,
}

fn default_series_every() -> f64 {
    10.0
}

/// The `[truth]` table: the truth simulator's settings plus the effects it carries.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct TruthSection {
    /// Effects the truth carries (`name`, `name=value`, `coefficient=value`).
    pub effects: Vec<String>,
    /// The truth's attitude equations.
    pub attitude: Attitude,
    /// RK4 rate of the truth integration, Hz.
    pub rate_hz: f64,
    /// Rate at which the input is recorded, Hz (the filters' sub-step rate).
    pub input_rate_hz: f64,
    /// Odometer and GPS rate, Hz.
    pub measurement_rate_hz: f64,
    /// Initial platform tilt.
    pub initial_tilt: InitialTilt,
    /// Multiplies the typical sigma of every coefficient the truth draws (a stress study sets
    /// 10).
    pub coefficient_scale: f64,
    /// Priors by coefficient name (override the typical sigmas).
    pub coefficients: BTreeMap<String, navkf_dynamics::Prior>,
}

impl Default for TruthSection {
    fn default() -> Self {
        let d = TruthConfig::default();
        TruthSection {
            effects: Vec::new(),
            attitude: Attitude::SmallAngle,
            rate_hz: d.rate_hz,
            input_rate_hz: d.input_rate_hz,
            measurement_rate_hz: d.measurement_rate_hz,
            initial_tilt: d.initial_tilt,
            coefficient_scale: 1.0,
            coefficients: BTreeMap::new(),
        }
    }
}

impl TruthSection {
    /// The simulator's configuration (without the effect list's fixed values).
    pub fn sim_config(&self) -> TruthConfig {
        TruthConfig {
            rate_hz: self.rate_hz,
            input_rate_hz: self.input_rate_hz,
            measurement_rate_hz: self.measurement_rate_hz,
            initial_tilt: self.initial_tilt,
            coefficients: self.coefficients.clone(),
        }
    }
}

/// Initial uncertainty of the filters.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct InitialSection {
    /// One-sigma of the initial velocity, m/s (the vehicle starts at rest, known to the
    /// odometer's floor).
    pub velocity_sigma: f64,
    /// One-sigma of the initial position, m (the first GPS fix).
    pub position_sigma_m: f64,
    /// One-sigma of coefficients by name; unnamed ones take the truth's prior sigma.
    pub coefficient_sigma: BTreeMap<String, f64>,
    /// Multiplies every initial sigma (a stress study sets 10).
    pub sigma_scale: f64,
}

impl Default for InitialSection {
    fn default() -> Self {
        InitialSection {
            velocity_sigma: 0.01,
            position_sigma_m: 3.0,
            coefficient_sigma: BTreeMap::new(),
            sigma_scale: 1.0,
        }
    }
}

/// The `[filter]` table: what every compared filter is built with.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FilterSection {
    /// Effects in the filters' model.
    #[serde(default)]
    pub effects: Vec<String>,
    /// The filters' attitude equations (a variant may set its own).
    #[serde(default)]
    pub attitude: Attitude,
    /// Sigma-point alpha.
    #[serde(default = "one")]
    pub alpha: f64,
    /// Sigma-point beta.
    #[serde(default = "two")]
    pub beta: f64,
    /// Sigma-point kappa.
    #[serde(default = "one")]
    pub kappa: f64,
    /// Initial uncertainty.
    #[serde(default)]
    pub initial: InitialSection,
    /// Scales the process-noise densities the filters assume (1 = the truth's). A value
    /// other than 1 mis-tunes the filters on purpose (used to test the CI guard).
    #[serde(default = "one")]
    pub process_noise_scale: f64,
    /// Filter variants by label: a kind with its own attitude equations or scaling.
    #[serde(default)]
    pub variants: BTreeMap<String, FilterVariant>,
}

/// A `[filter.variants.<label>]` table: a filter kind built with settings of its own; what
/// it leaves out comes from `[filter]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FilterVariant {
    /// The filter kind (`ekf`, `simplified_ukf`, ...).
    pub kind: FilterKind,
    /// Its attitude equations.
    pub attitude: Option<Attitude>,
    /// Sigma-point alpha.
    pub alpha: Option<f64>,
    /// Sigma-point beta.
    pub beta: Option<f64>,
    /// Sigma-point kappa.
    pub kappa: Option<f64>,
}

impl FilterSection {
    /// The filter listed as `label` in `study.filters` (a kind's name, or a label under
    /// `[filter.variants]`); the message names the key.
    pub fn plan(&self, label: &str) -> Result<FilterSpec, String> {
        let defaults = SigmaScaling {
            alpha: self.alpha,
            beta: self.beta,
            kappa: self.kappa,
        };
        if let Ok(kind) = label.parse::<FilterKind>() {
            return Ok(FilterSpec {
                kind,
                attitude: self.attitude,
                scaling: defaults,
            });
        }
        let Some(v) = self.variants.get(label) else {
            return Err(format!(
                "unknown filter `{label}`; expected one of {} or a label defined under \
                 [filter.variants]",
                FilterKind::names()
            ));
        };
        Ok(FilterSpec {
            kind: v.kind,
            attitude: v.attitude.unwrap_or(self.attitude),
            scaling: SigmaScaling {
                alpha: v.alpha.unwrap_or(defaults.alpha),
                beta: v.beta.unwrap_or(defaults.beta),
                kappa: v.kappa.unwrap_or(defaults.kappa),
            },
        })
    }
}

fn one() -> f64 {
    1.0
}
fn two() -> f64 {
    2.0
}

impl Default for FilterSection {
    fn default() -> Self {
        FilterSection {
            effects: Vec::new(),
            alpha: 1.0,
            beta: 2.0,
            kappa: 1.0,
            attitude: Attitude::SmallAngle,
            initial: InitialSection::default(),
            process_noise_scale: 1.0,
            variants: BTreeMap::new(),
        }
    }
}

/// When a run counts as diverged (besides a typed filter error or a non-finite value).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct DivergenceSection {
    /// A final coefficient error beyond this many initial sigmas.
    pub max_error_initial_sigmas: f64,
}

impl Default for DivergenceSection {
    fn default() -> Self {
        DivergenceSection {
            max_error_initial_sigmas: 50.0,
        }
    }
}

/// A whole study file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StudyConfig {
    /// `[study]`.
    pub study: StudySection,
    /// `[model]`: the model family (the platform when absent).
    #[serde(default, skip_serializing_if = "ModelSection::is_platform_default")]
    pub model: ModelSection,
    /// `[trajectory]`.
    #[serde(default)]
    pub trajectory: TrajectoryConfig,
    /// `[truth]`.
    #[serde(default)]
    pub truth: TruthSection,
    /// `[noise]`.
    #[serde(default)]
    pub noise: NoiseConfig,
    /// `[filter]`.
    #[serde(default)]
    pub filter: FilterSection,
    /// `[divergence]`.
    #[serde(default)]
    pub divergence: DivergenceSection,
    /// `[sweep]`: one setting varied over a list of values, each a full Monte Carlo
    /// ([`crate::sweep`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sweep: Option<SweepSection>,
    /// `[[effect]]`: effects declared in TOML (docs/declared-effects.md), which
    /// `truth.effects` and `filter.effects` may name like catalogued ones (terms for a
    /// platform study, places for a strapdown one).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub effect: Vec<navkf_dynamics::declared::EffectDeclaration>,
}

/// The `[sweep]` table: the dotted key of one numeric setting (`truth.initial_tilt.azimuth_rad`)
/// and the values it takes, every other setting fixed.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SweepSection {
    /// The setting, as a dotted path of study-file keys.
    pub key: String,
    /// Its values, one Monte Carlo each, in order.
    pub values: Vec<f64>,
}

impl StudyConfig {
    /// Reads and validates a study file; errors name the file and the key, or the line and
    /// column. Anything but a regular file of at most
    /// [`navkf_dynamics::input_file::TOML_MAX_BYTES`] is refused unread
    /// ([`read_text`]).
    pub fn load(path: &Path) -> Result<Self, StudyError> {
        Self::from_file_text(path, &read_text(path, &TextFile::STUDY)?)
    }

    /// Parses and validates `text`, read from `path` (errors name the file, line and column).
    pub fn from_file_text(path: &Path, text: &str) -> Result<Self, StudyError> {
        let cfg: StudyConfig = toml::from_str(text).map_err(|e| toml_error(path, text, &e))?;
        cfg.validate().map_err(|message| StudyError::Config {
            path: path.to_path_buf(),
            message: printable(&message),
        })?;
        Ok(cfg)
    }

    /// Parses and validates study text.
    pub fn parse(text: &str) -> Result<Self, String> {
        let cfg: StudyConfig = toml::from_str(text).map_err(|e| toml_message(text, &e))?;
        cfg.validate()?;
        Ok(cfg)
    }

    /// Checks every setting; the message names the key. [`StudyConfig::parse`] calls it; a
    /// configuration read another way (a shard's file, for `merge`) must call it too.
    pub fn validate(&self) -> Result<(), String> {
        if self.sweep.is_some() {
            // Every point is checked as the study it is.
            return points::points(self).map(|_| ());
        }
        let s = &self.study;
        if !s.kind.is_monte_carlo() {
            return Err(
                "study.kind = \"diagnosis\": a diagnosis study is not a Monte Carlo study; \
                 run it with `navkf study`, which reads the declared kind"
                    .into(),
            );
        }
        navkf_report::names::plain_name("study.name", &s.name)?;
        if s.runs == 0 {
            return Err("study.runs = 0: expected at least one run".into());
        }
        if s.filters.is_empty() {
            return Err("study.filters is empty: expected at least one filter".into());
        }
        for (i, f) in s.filters.iter().enumerate() {
            if s.filters[..i].contains(f) {
                return Err(format!(
                    "study.filters[{i}]: `{f}` is listed twice; expected each filter once"
                ));
            }
            self.filter
                .plan(f)
                .map_err(|e| format!("study.filters[{i}]: {e}"))?;
        }
        for (label, v) in &self.filter.variants {
            if label.parse::<FilterKind>().is_ok() {
                return Err(format!(
                    "filter.variants.{label}: a variant cannot take a filter kind's name; \
                     expected a label of its own"
                ));
            }
            if !s.filters.contains(label) {
                return Err(format!(
                    "filter.variants.{label} is defined but not listed in study.filters; list \
                     it there or remove it"
                ));
            }
            for (key, v) in [("alpha", v.alpha), ("beta", v.beta), ("kappa", v.kappa)] {
                if v.is_some_and(|v| !v.is_finite()) {
                    return Err(format!(
                        "filter.variants.{label}.{key} = {}: expected a finite number",
                        v.unwrap_or_default()
                    ));
                }
            }
        }
        if !(s.series_every_s.is_finite() && s.series_every_s > 0.0) {
            return Err(format!(
                "study.series_every_s = {}: expected > 0",
                s.series_every_s
            ));
        }
        if s.example_run >= s.runs {
            return Err(format!(
                "study.example_run = {}: expected a run index below runs = {}",
                s.example_run, s.runs
            ));
        }
        self.noise.validate()?;
        self.check_declarations()?;
        model::check_family_keys(self)?;
        self.trajectory.validate().map_err(|e| e.to_string())?;
        let f = &self.filter;
        let i = &f.initial;
        for (key, v) in [
            ("filter.initial.velocity_sigma", i.velocity_sigma),
            ("filter.initial.position_sigma_m", i.position_sigma_m),
            ("filter.initial.sigma_scale", i.sigma_scale),
            ("filter.process_noise_scale", f.process_noise_scale),
            ("truth.coefficient_scale", self.truth.coefficient_scale),
            (
                "divergence.max_error_initial_sigmas",
                self.divergence.max_error_initial_sigmas,
            ),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(format!("{key} = {v}: expected a finite number > 0"));
            }
        }
        for (name, v) in &i.coefficient_sigma {
            if !(v.is_finite() && *v > 0.0) {
                return Err(format!(
                    "filter.initial.coefficient_sigma.{name} = {v}: expected a finite number > 0"
                ));
            }
        }
        Ok(())
    }
}
