//! `dataset.toml`: noise, prior and provenance, every key known, an unknown one named with
//! its line.

use super::*;
use crate::declared::EffectDeclaration;
use crate::strapdown::effects::StrapdownRegistry;

/// `dataset.toml`: the `[noise]`, `[prior]`, `[simulation]`, `[model]` and `[initial]`
/// tables, nothing else.
#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub(super) struct ConfigFile {
    #[serde(default)]
    pub(super) noise: Option<NoiseConfig>,
    #[serde(default)]
    pub(super) prior: PlatformPrior,
    #[serde(default)]
    pub(super) simulation: Option<Provenance>,
    #[serde(default)]
    pub(super) model: Option<ModelTable>,
    #[serde(default)]
    pub(super) initial: Option<InitialAttitude>,
    /// `[[effect]]`: effects declared in TOML.
    #[serde(default)]
    pub(super) effect: Vec<EffectDeclaration>,
}

/// `[model]`: the family.
#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub(super) struct ModelTable {
    pub(super) kind: ModelKind,
}

impl ConfigFile {
    /// The family the file states (the platform when it says none).
    pub(super) fn kind(&self) -> ModelKind {
        self.model.as_ref().map(|m| m.kind).unwrap_or_default()
    }
}

/// The coefficient names `[prior.coefficients]` and `truth.csv` may use in a strapdown
/// dataset: the biases and the coefficients of `catalogue` (the strapdown catalogue with the
/// dataset's declared effects).
pub(in crate::dataset) fn strapdown_coefficients(catalogue: &StrapdownRegistry) -> Vec<String> {
    let effects = catalogue
        .names()
        .into_iter()
        .filter_map(|n| catalogue.get(n).ok().map(|e| e.coefficient_names()))
        .flatten();
    crate::strapdown::state::STATE_NAMES[crate::strapdown::state::NAV_DIM..]
        .iter()
        .copied()
        .chain(effects)
        .map(str::to_string)
        .collect()
}

/// Every coefficient name a `[prior.coefficients]` key may take: the base model's and those
/// of `registry`'s effects.
pub(in crate::dataset) fn known_coefficients(registry: &Registry) -> Vec<String> {
    let mut names: Vec<String> = BASE_NAMES[NAV_DIM..]
        .iter()
        .map(|s| s.to_string())
        .collect();
    for effect in registry.names() {
        if let Ok(e) = registry.build(&effect) {
            names.extend(e.coefficient_names().iter().map(|s| s.to_string()));
        }
    }
    names
}

/// Reads and checks `dataset.toml`, and returns it with every coefficient name its
/// `[prior.coefficients]` and `truth.csv` may use ([`FamilyFiles::declare`]). `registry`
/// holds the platform effects known before the file's own declarations.
pub(super) fn read_config(
    path: &Path,
    registry: &Registry,
) -> Result<(ConfigFile, Vec<String>), DynamicsError> {
    let text = read_text(path, &TextFile::DATASET_CONFIG)?;
    let config: ConfigFile = toml::from_str(&text).map_err(|e| toml_error(path, &text, &e))?;
    let files = files_of(config.kind());
    let known = files
        .declare(&mut registry.clone(), &config.effect)
        .map_err(|e| DynamicsError::File {
            path: path.to_path_buf(),
            message: printable(&e.to_string().replace("configuration: ", "")),
        })?;
    let located = |table: &str, key: &str, message: String| match key_line(&text, table, key) {
        Some(line) => data_error(path, line, &format!("{table}.{key}"), message),
        None => DynamicsError::File {
            path: path.to_path_buf(),
            message: printable(&format!("{table}.{key}: {message}")),
        },
    };
    if let Some(a) = &config.initial {
        if let Some(why) = files.initial_refused() {
            return Err(DynamicsError::File {
                path: path.to_path_buf(),
                message: format!("[initial]: {why}"),
            });
        }
        for (key, v, limit) in [
            ("roll_deg", a.roll_deg, 180.0),
            ("pitch_deg", a.pitch_deg, 90.0),
            ("heading_deg", a.heading_deg, f64::INFINITY),
        ] {
            if !(v.is_finite() && v.abs() <= limit) {
                return Err(located(
                    "initial",
                    key,
                    format!("{v}: expected finite degrees within +-{limit}"),
                ));
            }
        }
        if a.pitch_deg.abs() == 90.0 {
            return Err(located(
                "initial",
                "pitch_deg",
                "90 deg: the Euler angles are singular there; expected |pitch| < 90".into(),
            ));
        }
    }
    if let Err(message) = config.noise.unwrap_or_default().validate() {
        // validate() names the key as `noise.<key>`; point at its line when we can find it.
        let key = message
            .strip_prefix("noise.")
            .and_then(|m| m.split_whitespace().next())
            .unwrap_or("");
        return Err(match key_line(&text, "noise", key) {
            Some(line) => data_error(path, line, &format!("noise.{key}"), message),
            None => DynamicsError::File {
                path: path.to_path_buf(),
                message: printable(&message),
            },
        });
    }
    for (key, set) in [
        ("nhc_m_s", config.noise.is_some_and(|n| n.nhc_m_s.is_some())),
        (
            "zupt_m_s",
            config.noise.is_some_and(|n| n.zupt_m_s.is_some()),
        ),
    ] {
        if !files.has_pseudo_measurements() && set {
            let message = format!(
                "the strapdown family's pseudo-measurements; expected [model] kind = \
                 \"strapdown\" or no noise.{key}"
            );
            return Err(match key_line(&text, "noise", key) {
                Some(line) => data_error(path, line, &format!("noise.{key}"), message),
                None => DynamicsError::File {
                    path: path.to_path_buf(),
                    message: format!("noise.{key}: {message}"),
                },
            });
        }
    }
    if let Err((key, message)) =
        config
            .prior
            .validate(&known, &files.heading_prior_key(), files.navigation_names())
    {
        // `prior.level_rad` sits in [prior]; `prior.coefficients.X` in [prior.coefficients].
        // The heading's sigma may be written under any family's word (a serde alias): the
        // error names the one the file has.
        let (table, name) = key.rsplit_once('.').unwrap_or(("prior", &key));
        let heading_keys = ModelKind::ALL.map(|k| files_of(k).heading_prior_key());
        let spellings: &[String] = if heading_keys.iter().any(|h| h == name) {
            &heading_keys
        } else {
            &[]
        };
        let written = std::iter::once(name)
            .chain(spellings.iter().map(String::as_str))
            .find_map(|n| key_line(&text, table, n).map(|line| (line, n)));
        return Err(match written {
            Some((line, n)) => data_error(path, line, &format!("{table}.{n}"), message),
            None => DynamicsError::File {
                path: path.to_path_buf(),
                message: printable(&format!("{key}: {message}")),
            },
        });
    }
    Ok((config, known))
}

/// The 1-based line of `key = ...` inside `[table]`, for the simple layout this project
/// writes; `None` for other layouts (inline or dotted tables).
pub(super) fn key_line(text: &str, table: &str, key: &str) -> Option<usize> {
    if key.is_empty() {
        return None;
    }
    let header = format!("[{table}]");
    let mut inside = false;
    for (i, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.starts_with('[') {
            inside = line.split('#').next().is_some_and(|h| h.trim() == header);
        } else if inside {
            if let Some(rest) = line.strip_prefix(key) {
                if rest.trim_start().starts_with('=') {
                    return Some(i + 1);
                }
            }
        }
    }
    None
}
