//! Verdict: the last step of a diagnosis, what it concludes.
//!
//! Two facts decide it: whether the rounds named anything that survived the check for
//! stand-ins, and whether the final model is consistent with the data ([`crate::summary`]).
//! Data that cannot be what they claim get their own verdict before anything is fitted
//! ([`crate::implausible_data`]).

use serde::{Deserialize, Serialize};

/// The verdict of a diagnosis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Verdict {
    /// Nothing named, and the model under test is consistent with the data.
    #[serde(rename = "consistent")]
    Consistent,
    /// The named effects make the model consistent.
    #[serde(rename = "explained")]
    Explained,
    /// Effects help decisively, but a misfit remains that nothing in the catalogue explains.
    /// They are suggested ([`crate::diagnosis::Diagnosis::suggested`]), not named: an effect
    /// that does not make the model fit may only stand in for what is missing (measured on the
    /// error-rate study: odometer slip named `odometer-scale` and GPS multipath steps named
    /// catalogued effects this way).
    #[serde(rename = "partly explained")]
    PartlyExplained,
    /// The model is inconsistent and nothing in the catalogue explains it.
    #[serde(rename = "unexplained")]
    Unexplained,
    /// The data cannot be what they claim ([`crate::diagnosis::Diagnosis::implausible`]):
    /// nothing is named.
    #[serde(rename = "implausible data")]
    ImplausibleData,
}

impl std::fmt::Display for Verdict {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Verdict::Consistent => "consistent",
            Verdict::Explained => "explained",
            Verdict::PartlyExplained => "partly explained",
            Verdict::Unexplained => "unexplained",
            Verdict::ImplausibleData => "implausible data",
        })
    }
}

/// The verdict on a final model that is `consistent` or not, with `named` effects or none.
pub fn judge(named: bool, consistent: bool) -> Verdict {
    match (named, consistent) {
        (false, true) => Verdict::Consistent,
        (false, false) => Verdict::Unexplained,
        (true, true) => Verdict::Explained,
        (true, false) => Verdict::PartlyExplained,
    }
}
