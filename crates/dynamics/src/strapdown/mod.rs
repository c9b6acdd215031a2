//! The strapdown model family: an inertial unit bolted to the vehicle, whose gyro and
//! accelerometer errors live in the body frame and turn with it. It describes the platform
//! family's vehicle test (odometer, GPS, horizontal motion on the ellipsoid) with the sensors
//! most recordings come from: docs/model.md, "The strapdown family"; docs/model.md eqs. (49)-(58).
//!
//! - [`state`]: the 13 states and their names;
//! - [`attitude`]: the body-to-navigation rotation from roll, pitch and heading, and the
//!   angle rates from a body rate (docs/model.md eqs. (49), (53)-(55));
//! - [`body_motion`]: the vehicle body's sideslip and bounce about its path, for written
//!   datasets;
//! - [`batch`]: sigma points propagated eight at a time, from the same rates;
//! - [`effects`]: the catalogue of strapdown effects, each a declaration of where its
//!   coefficients act, and [`effect_list`] the lists users write;
//! - [`errors`]: the sensor errors those places describe, evaluated once for every number
//!   type (corrected readings, the readings of a unit with errors, the measurement);
//! - [`model`]: the model as a [`crate::SystemModel`]; [`measurement`] its measurement
//!   without effects, [`effect_rates`] its rates with them;
//! - [`partials_check`]: an effect's Jacobians against finite differences (`navkf effects
//!   --check`);
//! - [`rates`]: the state equations, written once over [`crate::real::Real`], and their
//!   Jacobian from the same source on dual numbers ([`crate::dual`]);
//! - [`sensors`]: odometer speed, GPS fix and the non-holonomic constraint as a filter's
//!   observation (docs/model.md eqs. (59), (60));
//! - [`simulate`]: the truth simulator, a level unit driving a [`crate::Trajectory`];
//! - [`tangent`]: the Jacobians of a model with effects, on dual numbers;
//! - [`unit_class`]: navigation, tactical and MEMS units, with the sizes of their errors.

pub mod attitude;
pub mod batch;
pub mod batch_measurement;
pub mod body_motion;
pub mod effect_list;
pub mod effect_rates;
pub mod effects;
pub mod errors;
pub mod family;
pub mod jacobian;
pub mod measurement;
pub mod model;
pub mod partials_check;
pub mod rates;
pub mod sensors;
pub mod simulate;
pub mod state;
pub mod tangent;
pub mod unit_class;
