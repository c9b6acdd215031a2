//! The kinds of study a study file can declare, and how its kind is read: `[study] kind`,
//! `"monte-carlo"` when absent (a Monte Carlo study, or a sweep of one with `[sweep]`), or
//! `"diagnosis"` (the diagnosis's error-rate study). One reading of the declared key, so that
//! no caller guesses a file's kind from what else it holds.
//!
//! ```
//! use navkf_report::StudyKind;
//! assert_eq!(StudyKind::declared("[study]\nname = \"x\"\n").unwrap(), StudyKind::MonteCarlo);
//! let text = "[study]\nname = \"x\"\nkind = \"diagnosis\"\n";
//! assert_eq!(StudyKind::declared(text).unwrap(), StudyKind::Diagnosis);
//! let e = StudyKind::declared("[study]\nkind = \"sweep\"\n").unwrap_err().to_string();
//! assert!(e.contains("unknown variant `sweep`"), "{e}");
//! ```

use serde::{Deserialize, Serialize};

/// What a study file asks for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum StudyKind {
    /// Seeded Monte Carlo runs of the filters (with `[sweep]`, one study per swept value).
    #[default]
    MonteCarlo,
    /// Simulated datasets diagnosed, to measure the diagnosis's error rates.
    Diagnosis,
}

impl StudyKind {
    /// Whether this is the default kind (a file need not say it).
    pub fn is_monte_carlo(&self) -> bool {
        *self == StudyKind::MonteCarlo
    }

    /// The kind `text` (a study file's TOML) declares in `[study] kind`. Every other key is
    /// left to the kind's own loader; a syntax error or an unknown kind is the parser's
    /// error, with its line and column.
    pub fn declared(text: &str) -> Result<StudyKind, toml::de::Error> {
        #[derive(Deserialize)]
        struct File {
            #[serde(default)]
            study: Section,
        }
        #[derive(Deserialize, Default)]
        struct Section {
            #[serde(default)]
            kind: StudyKind,
        }
        toml::from_str::<File>(text).map(|f| f.study.kind)
    }
}
