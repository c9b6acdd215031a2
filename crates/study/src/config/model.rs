//! The `[model]` table of a study file: which model family it runs, and the catalogues its
//! `[[effect]]` declarations join. What each family refuses of the other tables is its own
//! ([`crate::family`]).

use super::StudyConfig;
use navkf_dynamics::strapdown::effects::StrapdownRegistry;
use navkf_dynamics::strapdown::unit_class::UnitClass;
use navkf_dynamics::{ModelKind, NoiseConfig, Registry};
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
    /// The platform effects the study may name: the catalogue's and its `[[effect]]`
    /// declarations. The message names the key (`effect[0].rates[1].feature`).
    pub fn registry(&self) -> Result<Registry, String> {
        let mut registry = Registry::catalogue();
        registry.declare(&self.effect).map_err(declaration_error)?;
        Ok(registry)
    }

    /// The strapdown effects the study may name: the strapdown catalogue's and its
    /// `[[effect]]` declarations (`places`).
    pub fn strapdown_registry(&self) -> Result<StrapdownRegistry, String> {
        let mut registry = StrapdownRegistry::catalogue();
        registry.declare(&self.effect).map_err(declaration_error)?;
        Ok(registry)
    }

    /// The noise the truth is simulated with: `[noise]`, with the reading noise's densities
    /// of the unit class in a strapdown study.
    pub fn truth_noise(&self) -> NoiseConfig {
        crate::family::of(self.model.kind).truth_noise(self)
    }
}

/// A declaration's error as its key and message (`effect[0].rates[1].feature: ...`).
fn declaration_error(e: navkf_dynamics::DynamicsError) -> String {
    match e {
        navkf_dynamics::DynamicsError::Config { key, message } => format!("{key}: {message}"),
        other => other.to_string(),
    }
}
