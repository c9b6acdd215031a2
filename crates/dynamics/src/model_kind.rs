//! Which model family a dataset or a study describes: a name both read, kept apart from
//! the families themselves ([`crate::family`]) so that the dataset format can name it
//! without depending on them.

use serde::{Deserialize, Serialize};
use std::str::FromStr;

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
    /// Every family, in the order refusals list them.
    pub const ALL: [ModelKind; 2] = [ModelKind::Platform, ModelKind::Strapdown];

    /// The families' names for a refusal: `platform or strapdown`, each name wrapped in
    /// `quote` (`"` for Python's keyword, nothing for the command line).
    pub fn expected(quote: &str) -> String {
        let names: Vec<String> = Self::ALL
            .iter()
            .map(|k| format!("{quote}{}{quote}", k.name()))
            .collect();
        match names.split_last() {
            Some((last, [])) => last.clone(),
            Some((last, rest)) => format!("{} or {last}", rest.join(", ")),
            None => String::new(),
        }
    }

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

impl FromStr for ModelKind {
    type Err = String;

    /// A family by its name (`platform`, `strapdown`); the refusal lists them.
    fn from_str(name: &str) -> Result<ModelKind, String> {
        Self::ALL
            .into_iter()
            .find(|k| k.name() == name)
            .ok_or_else(|| format!("`{name}`: expected {}", Self::expected("")))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_family_reads_back_by_its_name_and_serde_agrees() {
        for kind in ModelKind::ALL {
            assert_eq!(kind.name().parse::<ModelKind>(), Ok(kind));
            let quoted = format!("{:?}", kind.name());
            assert_eq!(
                toml::Value::try_from(kind).ok(),
                Some(toml::Value::String(kind.name().into())),
                "{quoted}"
            );
        }
        assert_eq!(ModelKind::expected(""), "platform or strapdown");
        assert_eq!(ModelKind::expected("\""), "\"platform\" or \"strapdown\"");
        // A variant left out of ALL: this match needs its arm, and its place must be in ALL.
        let place = |k: ModelKind| match k {
            ModelKind::Platform => 0,
            ModelKind::Strapdown => 1,
        };
        for (i, kind) in ModelKind::ALL.into_iter().enumerate() {
            assert_eq!(place(kind), i, "{kind:?}");
        }
        let refusal = "gimbal".parse::<ModelKind>().unwrap_err();
        assert_eq!(refusal, "`gimbal`: expected platform or strapdown");
    }
}
