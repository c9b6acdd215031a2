//! Filters for the platform model, generic over [`navkf_dynamics::SystemModel`]: the EKF, the
//! paper's standard (augmented) UKF, its simplified UKF, and a square-root UKF that carries
//! a Cholesky factor of the covariance instead of the covariance. Their equations are those
//! of `docs/model.md`, "Filters": the shared update docs/model.md eqs. (17), (18), the EKF
//! docs/model.md eqs. (19)-(22), sigma points docs/model.md eqs. (23)-(25), the UKFs
//! docs/model.md eqs. (26)-(33), the square-root UKF docs/model.md eqs. (34)-(36).
//!
//! Every filter implements [`Filter`]: `predict` across an input window, `update` with an
//! [`Observation`], each returning a typed [`FilterError`] (with the step) rather than
//! panicking or producing NaN. Steps allocate nothing; buffers are sized at construction.

pub mod ekf;
pub mod error;
mod estimate;
pub mod failure;
pub mod filter;
pub mod kernels;
pub mod kind;
pub mod linalg;
pub mod runner;
pub mod sigma_points;
mod simd;
pub mod spec;
pub mod square_root_ukf;
mod tangent;
pub mod triangular;
pub mod ukf;
pub mod update;
pub mod view;

pub use ekf::Ekf;
pub use error::FilterError;
pub use failure::{DivergenceCause, RunFailure};
pub use filter::{nees, Filter};
pub use kind::FilterKind;
pub use runner::{RunError, Runner, StepView};
pub use sigma_points::{SigmaPoints, SigmaScaling};
pub use spec::FilterSpec;
pub use square_root_ukf::SquareRootUkf;
pub use ukf::{NoiseHandling, Ukf};
pub use update::{Observation, UpdateReport};
