//! Rank candidates: the step of a round that weighs, against the model as it stands, every
//! explanation the diagnosis knows of its misfit.
//!
//! - [`evidence`]: what a candidate is, its evidence (a BIC gain) and why BIC, and what
//!   naming it would add ([`Named`]).
//! - [`effect`]: one catalogued effect refitted into the model and weighed.
//! - [`noise_levels`]: the refitted noise levels weighed like an effect.
//! - [`beside_noise`]: an effect weighed against the noise levels with the noise refitted
//!   beside it, which decides which of the two goes first.
//! - [`mod@rank`]: all of them for one round, best first ([`rank()`]).
//!
//! Ranking decides nothing: which candidate is named is [`crate::naming`]'s business.

pub mod beside_noise;
pub mod effect;
pub mod evidence;
pub mod noise_levels;
pub mod rank;

pub use evidence::{
    Candidate, CandidateKind, Confusion, Evaluated, Model, Named, Outcome, DECISIVE_BIC,
    INDISTINGUISHABLE, NOISE_LEVELS,
};
pub use rank::{evaluate_all, rank, Confounded};
