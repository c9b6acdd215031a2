//! The `[model]` table of a study file: which model family it runs, and the settings of
//! the other tables that family does not read, refused by name rather than ignored.

use super::StudyConfig;
use navkf_dynamics::declared::EffectCatalogue;
use navkf_dynamics::strapdown::effect_list::StrapdownEffectList;
use navkf_dynamics::strapdown::effects::StrapdownRegistry;
use navkf_dynamics::strapdown::unit_class::UnitClass;
use navkf_dynamics::{Attitude, ModelKind, NoiseConfig, Registry};
use serde::{Deserialize, Serialize};

/// The `[model]` table.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ModelSection {
    /// The family: `platform` (the default) or `strapdown`.
    pub kind: ModelKind,
    /// The strapdown unit's class (`navigation`, `tactical`, `mems`; MEMS if left out): the
    /// sizes of its biases and the densities of its reading noise.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub unit: Option<UnitClass>,
}

impl ModelSection {
    /// Whether the table says nothing (the platform, which files need not write).
    pub fn is_platform_default(&self) -> bool {
        *self == ModelSection::default()
    }
    /// The strapdown unit's class.
    pub fn unit_class(&self) -> UnitClass {
        self.unit.unwrap_or_default()
    }
}

impl StudyConfig {
    /// The effects the study may name: its family's catalogue (`Registry`,
    /// `StrapdownRegistry`) and its `[[effect]]` declarations. The message names the key
    /// (`effect[0].rates[1].feature`).
    pub fn registry<R: EffectCatalogue>(&self) -> Result<R, String> {
        R::with_declared(&self.effect).map_err(declaration_error)
    }

    /// Checks the `[[effect]]` declarations against the study's family.
    pub(super) fn check_declarations(&self) -> Result<(), String> {
        match self.model.kind {
            ModelKind::Platform => self.registry::<Registry>().map(drop),
            ModelKind::Strapdown => self.registry::<StrapdownRegistry>().map(drop),
        }
    }

    /// The noise the truth is simulated with: `[noise]`, with the reading noise's densities
    /// of the unit class in a strapdown study.
    pub fn truth_noise(&self) -> NoiseConfig {
        match self.model.kind {
            ModelKind::Platform => self.noise,
            ModelKind::Strapdown => self.model.unit_class().errors().noise(self.noise),
        }
    }
}

/// A declaration's error as its key and message (`effect[0].rates[1].feature: ...`).
fn declaration_error(e: navkf_dynamics::DynamicsError) -> String {
    match e {
        navkf_dynamics::DynamicsError::Config { key, message } => format!("{key}: {message}"),
        other => other.to_string(),
    }
}

/// Checks that `config` sets nothing its family does not read; the message names the key.
pub(super) fn check_family_keys(config: &StudyConfig) -> Result<(), String> {
    let defaults = NoiseConfig::default();
    match config.model.kind {
        ModelKind::Platform => {
            if let Some(unit) = config.model.unit {
                return Err(format!(
                    "model.unit = \"{}\": the platform family has no unit class; expected \
                     model.kind = \"strapdown\" or no model.unit",
                    unit.name()
                ));
            }
            if config.noise.zupt_m_s.is_some() {
                return Err(
                    "noise.zupt_m_s: the zero-velocity update belongs to the strapdown family; \
                     expected model.kind = \"strapdown\" or no noise.zupt_m_s"
                        .into(),
                );
            }
            if config.noise.nhc_m_s.is_some() {
                return Err(
                    "noise.nhc_m_s: the non-holonomic constraint belongs to the \
                            strapdown family; expected model.kind = \"strapdown\" or no \
                            noise.nhc_m_s"
                        .into(),
                );
            }
        }
        ModelKind::Strapdown => {
            let refuse =
                |key: &str, why: &str| Err(format!("{key}: {why} (model.kind = \"strapdown\")"));
            let registry = config.registry::<StrapdownRegistry>()?;
            for (key, effects) in [
                ("truth.effects", &config.truth.effects),
                ("filter.effects", &config.filter.effects),
            ] {
                StrapdownEffectList::parse_entries(effects, &registry)
                    .map_err(|(i, e)| format!("{key}[{i}]: {e} (model.kind = \"strapdown\")"))?;
            }
            let attitudes = [
                ("truth.attitude", config.truth.attitude),
                ("filter.attitude", config.filter.attitude),
            ]
            .into_iter()
            .chain(
                config
                    .filter
                    .variants
                    .iter()
                    .filter_map(|(label, v)| v.attitude.map(|a| (label.as_str(), a))),
            );
            for (key, a) in attitudes {
                if a != Attitude::SmallAngle {
                    return refuse(
                        key,
                        "the attitude equations are the platform's choice; the strapdown \
                         family's are exact Euler angles (docs/model.md eqs. (53)-(55)), \
                         expected no attitude key",
                    );
                }
            }
            if config.truth.initial_tilt.alignment != Default::default() {
                return refuse(
                    "truth.initial_tilt.alignment",
                    "a MEMS unit cannot gyrocompass, and the strapdown start is drawn around \
                     the true attitude; expected no alignment key",
                );
            }
            if config.truth.rate_hz != super::TruthSection::default().rate_hz {
                return refuse(
                    "truth.rate_hz",
                    "the strapdown truth is the path itself, nothing is integrated to make \
                     it; expected no truth.rate_hz (truth.input_rate_hz is the IMU's rate)",
                );
            }
            if config.noise.gyro_psd != defaults.gyro_psd
                || config.noise.accel_psd != defaults.accel_psd
            {
                return refuse(
                    "noise.gyro_psd / noise.accel_psd",
                    "the reading noise's densities come from model.unit; expected neither \
                     key (filter.process_noise_scale mis-states them on purpose)",
                );
            }
        }
    }
    Ok(())
}
