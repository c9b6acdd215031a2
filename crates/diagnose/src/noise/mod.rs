//! Does the stated noise fit? A scale factor per noise source, fitted by maximum likelihood.
//!
//! A model can fail for two unrelated reasons: something physical is missing, or the noise
//! levels it was given are wrong. The second is the common one on recorded data (a MEMS
//! recording diagnosed with navigation-grade densities shows NIS hundreds of times the
//! expected value), and no physical effect explains it. So before ranking effects the
//! diagnosis asks whether the stated noise fits.
//!
//! Each source gets a variance scale `exp(theta)`: the gyro density `q_g` and the
//! accelerometer density `q_a` (docs/model.md eq. (12)), the odometer's sigma (its relative
//! term and its floor together) and the GPS sigma (both docs/model.md eq. (14)); the
//! strapdown family adds the tolerances of its pseudo-measurements, each a source of its own
//! (`nhc_m_s` and `zupt_m_s`, docs/model.md eqs. (60), (61)), which are no sensor's noise but
//! how far from zero the moving vehicle's sideways and vertical velocities and the standing
//! vehicle's velocity are, and which a recording's exact zeros leave pessimistic (the
//! likelihood then favours any effect that shrinks the predicted variance). A tolerance's
//! likelihood can go flat towards zero, so its level is also tested by the likelihood ratio,
//! and one stated too tight is searched for again with the process noises held
//! ([`search`]). The innovation log-likelihood `LL(theta)` is maximised over the
//! log-scales:
//!
//! 1. **Score test at the levels in use.** Central differences along each axis give the
//!    gradient `g` and curvature `H_jj` of `LL`; `g_j / sqrt(-H_jj)` is the score statistic,
//!    standard normal when the level is right. Sources beyond [`Z_FLAG`] are fitted.
//! 2. **Newton's method** over them, with the finite-difference Hessian made negative
//!    definite, a first step from the shape a pure noise scale gives the likelihood, steps
//!    clamped to [`MAX_STEP`] and halved until the likelihood rises. At the optimum the other
//!    sources' scores are taken again; a significant one joins.
//! 3. **Probes.** Process noise stated far too small leaves `LL` flat around the stated level
//!    (the filter then ignores it), so no score sees it: the gyro and accelerometer densities
//!    are also tried 10 and 100 times larger in sigma, after the local search (before it, a
//!    process noise could stand in for the measurement noise that search finds at once).
//! 4. **Resolution.** At the optimum, `sqrt(diag((-H)^-1))` is the standard error of each
//!    log-scale: the data's resolution. A fitted level's 95 % interval is the likelihood
//!    ratio's ([`likelihood_interval`]): the curvature's claimed a factor of 2 either side of
//!    a MEMS gyro level that the accelerometer's noise swamps, where the likelihood is flat
//!    far beyond. A source is *under-stated* or *over-stated* when its
//!    fitted log-scale is more than [`Z_FLAG`] standard errors from zero, *unresolved* when
//!    the data cannot fix its level within a factor [`RESOLVED_SIGMA_FACTOR`] (a
//!    navigation-grade gyro's white noise on a 40-minute drive, typically), and fits otherwise.
//!
//! Only the sources found mis-stated take their fitted level. The fitted levels are then a
//! candidate like an effect, which the diagnosis weighs against the structured ones
//! ([`crate::candidates`]).
//!
//! [`levels`] holds what a check finds ([`NoiseFit`]); [`search`] how ([`check`]); `grid`
//! the restarts that find process noise stated far off; [`memo`] the checks a diagnosis has
//! run, so that none runs twice.

mod grid;
pub mod levels;
pub mod likelihood_interval;
pub mod memo;
pub mod search;

pub use levels::{
    scaled, NoiseFit, NoiseSource, NoiseVerdict, SourceFit, Theta, WhyUnresolved, FEW_UPDATES,
    MAX_SOURCES, RESOLVED_SIGMA_FACTOR, SOURCES, TRADE_OFF, Z_FLAG,
};
pub use memo::CheckMemo;
pub use search::{check, MAX_STEP, Z_ACTIVE};
