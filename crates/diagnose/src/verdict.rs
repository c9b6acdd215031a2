//! Verdict: the last step of a diagnosis, what it concludes.
//!
//! Three facts decide it: whether the rounds named anything that survived the check for
//! stand-ins, whether the final model is consistent with the data ([`crate::summary`]), and
//! if not, whether it fails grossly ([`crate::misfit`]).
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
    /// After the noise check and every catalogued effect, the model still fails grossly
    /// ([`crate::misfit`]): the data do not follow a model of this kind. Nothing is named;
    /// the diagnosis says where the model fails ([`crate::diagnosis::Diagnosis::misfit`]).
    #[serde(rename = "does not follow the model")]
    DoesNotFollowModel,
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
            Verdict::DoesNotFollowModel => "does not follow the model",
            Verdict::ImplausibleData => "implausible data",
        })
    }
}

/// The verdict on a final model that is `consistent` or not, with `named` effects or none;
/// an inconsistent one that fails `gross`ly ([`crate::misfit::is_gross`]) does not follow the
/// model, whatever was named.
pub fn judge(named: bool, consistent: bool, gross: bool) -> Verdict {
    match (named, consistent, gross) {
        (false, true, _) => Verdict::Consistent,
        (true, true, _) => Verdict::Explained,
        (_, false, true) => Verdict::DoesNotFollowModel,
        (false, false, false) => Verdict::Unexplained,
        (true, false, false) => Verdict::PartlyExplained,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_gross_misfit_outranks_whatever_was_named() {
        use Verdict::*;
        for (named, consistent, gross, want) in [
            (false, true, false, Consistent),
            (true, true, false, Explained),
            (false, false, false, Unexplained),
            (true, false, false, PartlyExplained),
            (false, false, true, DoesNotFollowModel),
            (true, false, true, DoesNotFollowModel),
            // A consistent model is never gross (crate::rounds asks only of inconsistent ones).
            (false, true, true, Consistent),
            (true, true, true, Explained),
        ] {
            assert_eq!(
                judge(named, consistent, gross),
                want,
                "{named} {consistent} {gross}"
            );
        }
        assert_eq!(
            serde_json::to_string(&DoesNotFollowModel).unwrap(),
            "\"does not follow the model\""
        );
    }
}
