//! Sweeps: one setting of a study file varied over a list of values, every other setting
//! fixed, each value a full Monte Carlo with the same seeds for every filter.
//!
//! ```toml
//! [sweep]
//! key = "truth.initial_tilt.azimuth_rad"
//! values = [2.9e-4, 1.7e-3, 1.7e-2]
//! ```
//!
//! Any numeric key works, written in the file or left at its default (noise levels,
//! trajectory parameters, sigma-point scaling, a variant's setting), including one inside a
//! list, indexed as located errors write it (`trajectory.segment[1].to`, the speed of the
//! second segment; `trajectory.segment[3].segments[0].duration_s`): [`points`] writes the
//! value into the study's settings as TOML and reads them back, so each point is checked
//! exactly as a study file would be, and a misspelt key is refused with its name. The
//! results of a sweep are one ordinary results folder per point plus a summary across
//! points ([`SweepSummary`], `sweep.json`, `sweep.md` and the figures of
//! [`crate::plots::sweep`]).

mod axis;
pub mod shard;
mod summary;

pub use axis::axis;
pub use summary::{
    markdown, point, write_point, write_sweep, PointFilter, SweepPoint, SweepSummary,
};

pub use crate::config::points::points;

/// The folder of point `i` inside a sweep's results folder.
pub fn point_folder(i: usize) -> String {
    format!("point-{i:02}")
}
