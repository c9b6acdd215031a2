//! Fitting a model to the data: what every step of the diagnosis is made of.
//!
//! - [`setup`]: what one pass fits (effects, parameters, noise, priors) and with which filter.
//! - [`pass`]: one filter pass over the dataset, keeping the innovations, the likelihood
//!   (docs/model.md eq. (18)) and the estimates; the likelihood at the estimates, which does
//!   not depend on how wide a prior was ([`Fit::profile_loglik`]); why a pass failed.
//! - [`widening`]: a pass repeated with wider priors where the data pull a coefficient beyond
//!   its prior, kept only if the evidence rises, so that a prior does not cap what is found.
//! - [`density`]: the density of a noise-only term, by maximum likelihood over passes.
//! - [`time_constant`]: the same for a rival's time constant (a bias settling after
//!   switch-on).
//!
//! None of them knows about rounds, candidates or verdicts: they answer "how well does this
//! model fit", and the steps of [`crate::rounds`] ask it.

pub mod density;
pub mod pass;
pub mod setup;
pub mod time_constant;
pub mod widening;

pub use density::{fit_density, DensityFit};
pub use pass::{fit, marginal_states, CoefficientTrack, Fit};
pub use setup::FitSetup;
pub use widening::{fit_adaptive, widen_tilt, Widening};
