//! Which model family a dataset or a study describes: a name both read, kept apart from
//! the families themselves ([`crate::family`]) so that the dataset format can name it
//! without depending on them.

use serde::{Deserialize, Serialize};

/// Which model family a dataset or a study describes (`[model] kind`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ModelKind {
    /// The paper's stabilised platform (docs/model.md): sensor errors constant in the
    /// navigation frame.
    #[default]
    Platform,
    /// A unit bolted to the vehicle: sensor errors in the body frame.
    Strapdown,
}

impl ModelKind {
    /// The family's name as files write it.
    pub fn name(self) -> &'static str {
        match self {
            ModelKind::Platform => "platform",
            ModelKind::Strapdown => "strapdown",
        }
    }
    /// Whether this is the platform (the default, which files need not write).
    pub fn is_platform(&self) -> bool {
        *self == ModelKind::Platform
    }
}
