//! Stopping a long run on request (Ctrl-C), between groups of runs.
//!
//! The command line installs the signal handler; the library only reads the request. A
//! Monte Carlo study (`Study::run_folded`, `Study::run_blocks` in navkf-study) and a
//! diagnosis study check it before each group of runs, so they stop within one group (a few
//! runs) and return what they completed; the caller then writes nothing, and its results
//! folder stays as it was (see `ResultsDir`).

use std::sync::atomic::{AtomicBool, Ordering};

static REQUESTED: AtomicBool = AtomicBool::new(false);

/// Asks every running study to stop after the runs in flight.
pub fn request() {
    REQUESTED.store(true, Ordering::SeqCst);
}

/// Whether a stop was asked for.
pub fn requested() -> bool {
    REQUESTED.load(Ordering::SeqCst)
}

/// Clears the request (a test that asked for a stop, before the next one).
pub fn clear() {
    REQUESTED.store(false, Ordering::SeqCst);
}

/// A stop on request ([`request`]) before the work was complete: what was done, of what.
/// The caller writes nothing, so its results folder stays as it was.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("interrupted after {done} of {total} {what}: nothing was written")]
pub struct Interrupted {
    /// Units of work completed.
    pub done: usize,
    /// Units asked for.
    pub total: usize,
    /// What they are (runs, datasets).
    pub what: &'static str,
}
