//! The noise checks a diagnosis has run, kept so that a check asked for again is answered
//! without running it again.
//!
//! A check is a function of the model's fit setup, its log-likelihood and the levels it starts
//! from (the dataset, catalogue and filter are the diagnosis's own), and it costs tens of
//! filter passes. The same check comes twice whenever an effect goes first beside the noise
//! levels ([`crate::candidates::beside_noise`]): the next round checks the model that now
//! holds the effect, from the same levels, which is the check already run on the effect's
//! fit. On a 2400 s MEMS drive hiding an odometer scale that was 95 of the diagnosis's 351
//! filter passes, a fifth of its time. The answer is the same bit for bit: nothing but those
//! inputs enters a check.

use super::{check, NoiseFit, Theta};
use crate::catalogue::Catalogue;
use crate::error::DiagnoseError;
use crate::fit::{Fit, FitSetup};
use navkf_dynamics::dataset::Dataset;
use navkf_filters::FilterSpec;

/// The checks run so far on one dataset, with one catalogue and filter.
#[derive(Debug, Default)]
pub struct CheckMemo {
    /// Each check's inputs (setup, log-likelihood and starting levels, as bits) and answer.
    done: Vec<(FitSetup, u64, [u64; super::MAX_SOURCES], NoiseFit)>,
}

impl CheckMemo {
    /// [`check`] of `model` from `theta`, or its answer when it was run before.
    pub fn check(
        &mut self,
        ds: &Dataset,
        model: &Fit,
        theta: Theta,
        catalogue: &dyn Catalogue,
        filter: &FilterSpec,
    ) -> Result<NoiseFit, DiagnoseError> {
        let (loglik, start) = (model.loglik.to_bits(), theta.map(f64::to_bits));
        if let Some((.., answer)) = self
            .done
            .iter()
            .find(|(s, l, t, _)| *l == loglik && *t == start && *s == model.setup)
        {
            return Ok(answer.clone());
        }
        let answer = check(ds, model, theta, catalogue, filter)?;
        self.done
            .push((model.setup.clone(), loglik, start, answer.clone()));
        Ok(answer)
    }

    /// How many checks were run (not answered from memory).
    pub fn len(&self) -> usize {
        self.done.len()
    }

    /// Whether no check was run yet.
    pub fn is_empty(&self) -> bool {
        self.done.is_empty()
    }
}
