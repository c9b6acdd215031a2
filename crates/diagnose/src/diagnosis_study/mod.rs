//! The diagnosis measured: hundreds of simulated datasets whose hidden content is drawn at
//! random, each diagnosed as a user would diagnose it (default priors, noise check on), and
//! the outcomes tallied into error rates.
//!
//! A study file (`studies/diagnosis.toml`, `[study] kind = "diagnosis"`) lists classes of
//! content in `[[content]]` tables: nothing; each catalogued effect; random pairs of them;
//! effects outside the catalogue ([`navkf_dynamics::outside`]); a stated noise that is not the
//! truth's. [`content`] plans each dataset and the study's family (`family/`) draws its
//! effects and simulates it, [`rates`] turns the outcomes into the confusion matrix, the
//! false-attribution rates and the detection curves, [`report`] and [`plots`] write them.
//! Datasets are diagnosed in parallel; every draw comes from the dataset's own stream and
//! results are kept in index order, so the outcome is the same whatever the thread count.

pub mod content;
mod family;
pub mod hidden;
pub mod plots;
pub mod rates;
pub mod report;
pub mod shard;

use crate::error::DiagnoseError;
use crate::{diagnose, Options, Verdict};
use content::{Class, Hidden, Planned};
use navkf_dynamics::declared::{EffectCatalogue, EffectDeclaration};
use navkf_dynamics::input_file::{printable, read_text, toml_error, toml_message, TextFile};
use navkf_dynamics::simulate::{Alignment, InitialTilt};
use navkf_dynamics::strapdown::unit_class::UnitClass;
use navkf_dynamics::{ModelKind, NoiseConfig, Trajectory, TrajectoryConfig};
use navkf_report::executor::Executor;
use navkf_report::StudyKind;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;
use std::sync::Arc;

/// The `[study]` table of a diagnosis study.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Section {
    /// Name: results go to `results/<name>/`.
    pub name: String,
    /// Must be `"diagnosis"`: the kind a study file declares (see [`StudyKind`]).
    pub kind: StudyKind,
    /// Seed of every random stream.
    pub seed: u64,
}

/// The `[truth]` table: how the datasets are simulated besides their hidden content.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct TruthSection {
    /// RK4 rate of the truth integration, Hz.
    pub rate_hz: f64,
    /// Input recording rate, Hz.
    pub input_rate_hz: f64,
    /// Odometer and GPS rate, Hz.
    pub measurement_rate_hz: f64,
    /// Initial tilt: by default gyrocompassed, with residuals of 2 arcsec level and 20 arcsec
    /// azimuth (a few minutes of alignment against the sensors' noise).
    pub initial_tilt: InitialTilt,
}

impl Default for TruthSection {
    fn default() -> Self {
        TruthSection {
            rate_hz: 100.0,
            input_rate_hz: 10.0,
            measurement_rate_hz: 1.0,
            initial_tilt: InitialTilt {
                level_rad: 1e-5,
                azimuth_rad: 1e-4,
                alignment: Alignment::Gyrocompass,
            },
        }
    }
}

/// The `[diagnosis]` table: the settings every dataset is diagnosed with.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct DiagnosisSection {
    /// The filter of the fits.
    pub filter: navkf_filters::FilterKind,
    /// The attitude equations of the fits' model.
    pub attitude: navkf_dynamics::Attitude,
    /// Most automatic rounds.
    pub max_rounds: usize,
}

impl Default for DiagnosisSection {
    fn default() -> Self {
        DiagnosisSection {
            filter: navkf_filters::FilterKind::Ekf,
            attitude: navkf_dynamics::Attitude::SmallAngle,
            max_rounds: Options::default().max_rounds,
        }
    }
}

/// An effect outside the catalogue.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum OutsideEffect {
    /// [`navkf_dynamics::outside::Drag`].
    Drag,
    /// [`navkf_dynamics::outside::AccelWarmUp`].
    AccelWarmUp,
    /// GPS multipath ([`navkf_dynamics::sensor_faults::SensorFault::GpsStep`]): fixes off
    /// by metres for minutes.
    GpsStep,
    /// Wheel slip while accelerating
    /// ([`navkf_dynamics::sensor_faults::SensorFault::OdometerSlip`]).
    OdometerSlip,
    /// A GPS antenna away from the platform
    /// ([`navkf_dynamics::sensor_faults::SensorFault::GpsLeverArm`]).
    GpsLeverArm,
}

/// One `[[content]]` table: a class of datasets.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum ContentClass {
    /// Nothing hidden.
    Nothing {
        /// Datasets.
        count: usize,
    },
    /// One effect, each in turn.
    Single {
        /// Datasets per effect.
        count: usize,
        /// The effects taken in turn (default: the whole catalogue, declared ones included).
        #[serde(default, skip_serializing_if = "Vec::is_empty")]
        effects: Vec<String>,
    },
    /// Two different catalogued effects, drawn at random.
    Pair {
        /// Datasets.
        count: usize,
        /// The effects drawn from (default: the whole catalogue).
        #[serde(default)]
        effects: Vec<String>,
        /// Size bounds for these datasets by effect name, over `[sizes]`.
        #[serde(default)]
        sizes: BTreeMap<String, [f64; 2]>,
    },
    /// An effect outside the catalogue.
    Outside {
        /// Which.
        effect: OutsideEffect,
        /// Datasets.
        count: usize,
        /// Size bounds, multiples of its typical size.
        sizes: [f64; 2],
    },
    /// Nothing hidden, one or two noise sources stated wrong.
    MisstatedNoise {
        /// Datasets.
        count: usize,
        /// Bounds of the factor (true over stated sigma, or its inverse).
        sizes: [f64; 2],
    },
    /// Nothing hidden, but the gyro and accelerometer noise are a MEMS unit's, each drawn
    /// `sizes` times the stated (navigation-grade) sigma; the platform family only.
    MemsNoise {
        /// Datasets.
        count: usize,
        /// Bounds of the factor, true over stated sigma.
        sizes: [f64; 2],
    },
    /// Nothing hidden, but the platform starts misaligned in azimuth by an angle drawn with a
    /// sigma of `sizes` degrees (log-uniform), stated as the dataset's azimuth prior, and
    /// diagnosed with `attitude`; the platform family only.
    Misaligned {
        /// Datasets.
        count: usize,
        /// Bounds of the azimuth sigma, deg.
        sizes: [f64; 2],
        /// The attitude equations of the diagnosis.
        attitude: navkf_dynamics::Attitude,
    },
    /// Nothing hidden, but one column written in another unit; the platform family only.
    WrongUnits {
        /// Datasets.
        count: usize,
        /// Which unit.
        unit: content::WrongUnit,
    },
}

impl ContentClass {
    /// Number of datasets it makes, in a family of `catalogued` effects.
    pub fn count(&self, catalogued: usize) -> usize {
        match self {
            ContentClass::Single { count, effects } if effects.is_empty() => {
                count.saturating_mul(catalogued)
            }
            ContentClass::Single { count, effects } => count.saturating_mul(effects.len()),
            ContentClass::Nothing { count }
            | ContentClass::Pair { count, .. }
            | ContentClass::Outside { count, .. }
            | ContentClass::MisstatedNoise { count, .. }
            | ContentClass::MemsNoise { count, .. }
            | ContentClass::Misaligned { count, .. }
            | ContentClass::WrongUnits { count, .. } => *count,
        }
    }
}

/// Default size bounds of catalogued effects, multiples of their typical size (sigma): from
/// a tenth of it to a hundred times it, three decades around the typical size.
pub const DEFAULT_SIZES: [f64; 2] = [0.1, 100.0];

/// `[model]`: the family the study's datasets are of (the platform unless set).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct StudyModel {
    /// `platform` or `strapdown`.
    pub kind: ModelKind,
    /// The strapdown unit's class (MEMS if left out): the sizes of its biases, reading noise
    /// and effects.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub unit: Option<UnitClass>,
}

impl StudyModel {
    /// Whether the table says nothing (the platform, whose summaries do not write it).
    pub fn is_platform_default(&self) -> bool {
        *self == StudyModel::default()
    }
    /// The strapdown unit's class.
    pub fn unit_class(&self) -> UnitClass {
        self.unit.unwrap_or_default()
    }
}

/// A whole diagnosis study file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DiagnosisStudyConfig {
    /// `[study]`.
    pub study: Section,
    /// `[model]`.
    #[serde(default, skip_serializing_if = "StudyModel::is_platform_default")]
    pub model: StudyModel,
    /// `[trajectory]`.
    #[serde(default)]
    pub trajectory: TrajectoryConfig,
    /// `[truth]`.
    #[serde(default)]
    pub truth: TruthSection,
    /// `[noise]`: the truth's noise, and the stated one (except for mis-stated-noise datasets).
    #[serde(default)]
    pub noise: NoiseConfig,
    /// `[diagnosis]`.
    #[serde(default)]
    pub diagnosis: DiagnosisSection,
    /// `[sizes]`: size bounds of catalogued effects by name, multiples of their typical size
    /// (default [`DEFAULT_SIZES`]).
    #[serde(default)]
    pub sizes: BTreeMap<String, [f64; 2]>,
    /// `[[content]]`.
    pub content: Vec<ContentClass>,
    /// `[[effect]]`: effects declared without Rust (docs/declared-effects.md), of the study's
    /// family. They join its catalogue: each is hidden in `single` datasets and may be drawn
    /// in pairs like a catalogued one, and every dataset is diagnosed with them among the
    /// candidates (as if its `dataset.toml` declared them), clean ones included.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub effect: Vec<EffectDeclaration>,
}

impl DiagnosisStudyConfig {
    /// Parses and validates study text; errors name the key.
    pub fn parse(text: &str) -> Result<Self, String> {
        let cfg: DiagnosisStudyConfig = toml::from_str(text).map_err(|e| toml_message(text, &e))?;
        cfg.validate()?;
        Ok(cfg)
    }

    /// Reads and validates a study file (a regular file of at most
    /// [`navkf_dynamics::input_file::TOML_MAX_BYTES`], see [`read_text`]).
    pub fn load(path: &Path) -> Result<Self, DiagnoseError> {
        Self::from_file_text(path, &read_text(path, &TextFile::STUDY)?)
    }

    /// Parses and validates `text`, read from `path` (errors name the file, line and column).
    pub fn from_file_text(path: &Path, text: &str) -> Result<Self, DiagnoseError> {
        let cfg: DiagnosisStudyConfig =
            toml::from_str(text).map_err(|e| toml_error(path, text, &e))?;
        cfg.validate().map_err(|message| DiagnoseError::Config {
            path: path.to_path_buf(),
            message: printable(&message),
        })?;
        Ok(cfg)
    }

    /// Size bounds of catalogued effect `name`.
    pub fn size_range(&self, name: &str) -> [f64; 2] {
        self.sizes.get(name).copied().unwrap_or(DEFAULT_SIZES)
    }

    /// The effects of the study's family: its catalogue's, then those the file declares.
    pub fn effect_names(&self) -> Vec<String> {
        family::of(self.model.kind)
            .effect_names(self)
            .unwrap_or_default()
    }

    /// The catalogue of the file's family (`Registry`, `StrapdownRegistry`) with its
    /// `[[effect]]` declared.
    pub fn registry<R: EffectCatalogue>(&self) -> Result<R, DiagnoseError> {
        Ok(R::with_declared(&self.effect)?)
    }

    fn validate(&self) -> Result<(), String> {
        if self.study.kind != StudyKind::Diagnosis {
            return Err(
                "study.kind: expected \"diagnosis\" (a file without it is a Monte Carlo study)"
                    .into(),
            );
        }
        navkf_report::names::plain_name("study.name", &self.study.name)?;
        if self.content.is_empty() {
            return Err("content: no [[content]] table; expected at least one".into());
        }
        let family = family::of(self.model.kind);
        family.validate(self)?;
        let names = self.effect_names();
        let bounds = |key: String, [lo, hi]: [f64; 2]| {
            if lo.is_finite() && hi.is_finite() && lo > 0.0 && hi >= lo {
                Ok(())
            } else {
                Err(format!("{key} = [{lo}, {hi}]: expected 0 < low <= high"))
            }
        };
        let catalogued = |key: String, name: &String| {
            if names.contains(name) {
                Ok(())
            } else {
                Err(format!(
                    "{key}: `{name}` is not a catalogued or declared effect; expected one of {}",
                    names.join(", ")
                ))
            }
        };
        for (name, r) in &self.sizes {
            catalogued(format!("sizes.{name}"), name)?;
            bounds(format!("sizes.{name}"), *r)?;
        }
        let mut total = 0usize;
        for (i, c) in self.content.iter().enumerate() {
            let count = c.count(names.len());
            if count == 0 {
                return Err(format!("content[{i}].count = 0: expected at least one"));
            }
            total = total.saturating_add(count);
            if total > MAX_DATASETS {
                return Err(format!(
                    "content[{i}].count: with this class the study makes more than \
                     {MAX_DATASETS} datasets; expected at most {MAX_DATASETS} in all (a \
                     diagnosis takes seconds each)"
                ));
            }
            // The outside drag is the `drag` effect of navkf_dynamics::outside: a declaration
            // of it would make it catalogued, not outside.
            if let ContentClass::Outside {
                effect: OutsideEffect::Drag,
                ..
            } = c
            {
                if let Some(k) = self
                    .effect
                    .iter()
                    .position(|d| d.name == "drag" || d.coefficients.iter().any(|c| c.name == "kd"))
                {
                    return Err(format!(
                        "effect[{k}]: declares `drag` or `kd`, which content[{i}] hides as \
                         outside the catalogue; expected another name, or no outside drag"
                    ));
                }
            }
            if let Some(why) = family.refuses_class(c) {
                return Err(format!("content[{i}]: {why}"));
            }
            match c {
                ContentClass::Outside { sizes, .. }
                | ContentClass::MisstatedNoise { sizes, .. } => {
                    bounds(format!("content[{i}].sizes"), *sizes)?
                }
                ContentClass::MemsNoise { sizes, .. } => {
                    bounds(format!("content[{i}].sizes"), *sizes)?
                }
                ContentClass::Misaligned { sizes, .. } => {
                    bounds(format!("content[{i}].sizes"), *sizes)?;
                    if sizes[1] > 45.0 {
                        return Err(format!(
                            "content[{i}].sizes = [{}, {}]: deg of azimuth sigma; expected at \
                             most 45",
                            sizes[0], sizes[1]
                        ));
                    }
                }
                ContentClass::Single { effects, .. } => {
                    for (j, name) in effects.iter().enumerate() {
                        catalogued(format!("content[{i}].effects"), name)?;
                        if effects[..j].contains(name) {
                            return Err(format!("content[{i}].effects: `{name}` listed twice"));
                        }
                    }
                }
                ContentClass::Pair { effects, sizes, .. } => {
                    for (j, name) in effects.iter().enumerate() {
                        catalogued(format!("content[{i}].effects"), name)?;
                        if effects[..j].contains(name) {
                            return Err(format!(
                                "content[{i}].effects: `{name}` listed twice; a pair draws two \
                                 different effects"
                            ));
                        }
                    }
                    if effects.len() == 1 {
                        return Err(format!(
                            "content[{i}].effects: one effect; a pair needs at least two"
                        ));
                    }
                    for (name, r) in sizes {
                        catalogued(format!("content[{i}].sizes.{name}"), name)?;
                        bounds(format!("content[{i}].sizes.{name}"), *r)?;
                    }
                    let pool = if effects.is_empty() { &names } else { effects };
                    self.pairs_fit_one_model(pool)
                        .map_err(|m| format!("content[{i}].effects: {m}"))?;
                }
                _ => {}
            }
        }
        self.noise.validate()
    }

    /// Refuses a pair of `pool` that no model can hold together (two coefficients in one
    /// place of the strapdown sensor model), naming both; only pairs with a declared effect
    /// are tried, the catalogue's fitting together by construction.
    fn pairs_fit_one_model(&self, pool: &[String]) -> Result<(), String> {
        // The family's registry, built once; a pair fits if a model holds both.
        let fits = family::of(self.model.kind)
            .pair_fits(self)
            .map_err(|e| e.to_string())?;
        let declared = |n: &String| self.effect.iter().any(|d| &d.name == n);
        for (j, a) in pool.iter().enumerate() {
            for b in pool[j + 1..].iter().filter(|b| declared(a) || declared(b)) {
                fits([a, b]).map_err(|e| {
                    format!(
                        "`{a}` and `{b}` cannot be hidden together ({e}); expected a pool of \
                         effects that fit one model"
                    )
                })?;
            }
        }
        Ok(())
    }

    /// The diagnosis options every dataset gets.
    pub fn options(&self) -> Options {
        Options {
            filter: navkf_filters::FilterSpec {
                attitude: self.diagnosis.attitude,
                ..navkf_filters::FilterSpec::new(self.diagnosis.filter)
            },
            max_rounds: self.diagnosis.max_rounds,
            ..Default::default()
        }
    }
}

/// What one dataset's diagnosis said.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Record {
    /// Index.
    pub index: usize,
    /// Its class.
    pub class: Class,
    /// What its truth hid.
    pub hidden: Vec<Hidden>,
    /// The verdict; `None` if the diagnosis stopped with an error.
    pub verdict: Option<Verdict>,
    /// The effects named, in order.
    pub named: Vec<String>,
    /// Whether the noise levels were refitted (named in a round).
    pub noise_named: bool,
    /// Named effects withdrawn by the constancy test.
    pub withdrawn: Vec<String>,
    /// Automatic rounds run.
    pub rounds: usize,
    /// BIC gain, in the first automatic round, of each hidden catalogued effect (what the
    /// detection curves are made of).
    pub first_round_bic: BTreeMap<String, f64>,
    /// For the coefficients of hidden effects that were named: (estimate - truth) / sigma in
    /// the final model (standard normal if the estimates and their sigmas are honest).
    pub estimate_errors: BTreeMap<String, f64>,
    /// The error, if the diagnosis stopped.
    pub error: Option<String>,
    /// The final model's mean NIS over its dimension (what the verdict
    /// [`Verdict::DoesNotFollowModel`] is decided on).
    #[serde(default)]
    pub nis_ratio: Option<f64>,
    /// The dataset's unit warnings ([`navkf_dynamics::dataset::Dataset::warnings`]).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<navkf_dynamics::dataset::Doubt>,
    /// The last noise check's fitted over stated sigma per source, `None` where the data
    /// could not fix it (empty without a noise check).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub noise_ratios: Vec<Option<f64>>,
    /// The last noise check's 95 % interval of each source's fitted over stated sigma
    /// (empty without a noise check, and in records made before it was kept).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub noise_intervals: Vec<[f64; 2]>,
}

/// Simulates and diagnoses planned dataset `p`.
fn run_one(
    config: &DiagnosisStudyConfig,
    trajectory: &Arc<Trajectory>,
    options: &Options,
    p: &Planned,
) -> Record {
    let mut record = Record {
        index: p.index,
        class: p.class,
        hidden: p.hidden.clone(),
        verdict: None,
        named: Vec::new(),
        noise_named: false,
        withdrawn: Vec::new(),
        rounds: 0,
        first_round_bic: BTreeMap::new(),
        estimate_errors: BTreeMap::new(),
        error: None,
        nis_ratio: None,
        warnings: Vec::new(),
        noise_ratios: Vec::new(),
        noise_intervals: Vec::new(),
    };
    // A misaligned platform is diagnosed with the attitude equations its class says.
    let mut options = options.clone();
    for h in &p.hidden {
        if let Hidden::Misaligned { attitude, .. } = h {
            options.filter.attitude = *attitude;
        }
    }
    let result = content::simulate(config, trajectory, p)
        .and_then(|ds| diagnose(&ds, &*crate::catalogue::of(&ds)?, &options));
    match result {
        Ok((d, _)) => {
            record.verdict = Some(d.verdict);
            record.nis_ratio = Some(d.model.nis.mean / d.model.nis.dof).filter(|r| r.is_finite());
            record.warnings = d.data_warnings.iter().map(|w| w.doubt).collect();
            record.noise_ratios = d
                .noise
                .iter()
                .flat_map(|n| &n.sources)
                .map(|s| {
                    (s.verdict != crate::noise::levels::NoiseVerdict::Unresolved)
                        .then_some(s.sigma_ratio)
                        .filter(|r| r.is_finite())
                })
                .collect();
            record.noise_intervals = d
                .noise
                .iter()
                .flat_map(|n| &n.sources)
                .map(|s| s.sigma_ratio_interval)
                .collect();
            record.named = d.effects.clone();
            record.withdrawn = d.withdrawn.iter().map(|w| w.effect.clone()).collect();
            record.rounds = d.rounds.len();
            record.noise_named = d.rounds.iter().any(|r| r.named_noise_levels());
            // A pinned coefficient is not estimated (held at zero): no error to judge.
            for c in d
                .model
                .coefficients
                .iter()
                .filter(|c| !d.pinned.contains(&c.name))
            {
                let hidden_named = p.hidden.iter().any(|h| match h {
                    Hidden::Effect { name, values, .. } => {
                        d.effects.contains(name) && values.contains_key(&c.name)
                    }
                    _ => false,
                });
                if let (true, Some(t)) = (hidden_named, c.truth) {
                    record
                        .estimate_errors
                        .insert(c.name.clone(), (c.estimate - t) / c.sigma);
                }
            }
            if let Some(first) = d.rounds.first() {
                for h in &p.hidden {
                    if let Some(e) = h.effect() {
                        if let Some(c) = first.candidates.iter().find(|c| c.effect == e) {
                            record.first_round_bic.insert(e.to_string(), c.bic_gain);
                        }
                    }
                }
            }
        }
        Err(e) => record.error = Some(e.to_string()),
    }
    record
}

/// Runs the study: every planned dataset (or those in `only`), in parallel, results in index
/// order. `progress` is told how many are done.
pub fn run(
    config: &DiagnosisStudyConfig,
    only: Option<std::ops::Range<usize>>,
    progress: &(dyn Fn(usize) + Sync),
) -> Result<Vec<Record>, DiagnoseError> {
    let planned = content::plan(config)?;
    let trajectory = Arc::new(Trajectory::build(&config.trajectory)?);
    let options = config.options();
    let range = only.unwrap_or(0..planned.len());
    let range = range.start.min(planned.len())..range.end.min(planned.len());
    // Datasets are small once diagnosed: all are in one group, so no thread waits for a
    // group's slowest dataset (they take 0.5 to 5 s).
    let executor = Executor::new("datasets", usize::MAX);
    let mut records = Vec::with_capacity(range.len());
    executor.run(
        range,
        &|i| run_one(config, &trajectory, &options, &planned[i]),
        &progress,
        |_, record| records.push(record),
    )?;
    Ok(records)
}

/// The study family's effects (catalogued and declared) with their typical sizes (the
/// detection curves' scale).
pub fn effect_scales(config: &DiagnosisStudyConfig) -> Vec<rates::EffectScale> {
    family::of(config.model.kind).effect_scales(config)
}

/// Number of datasets the study makes.
pub fn dataset_count(config: &DiagnosisStudyConfig) -> usize {
    let catalogued = config.effect_names().len();
    config
        .content
        .iter()
        .fold(0, |n: usize, c| n.saturating_add(c.count(catalogued)))
}

/// Most datasets a diagnosis study may make: a million diagnoses take weeks on one machine,
/// and every dataset is planned before the first runs.
pub const MAX_DATASETS: usize = 1_000_000;
