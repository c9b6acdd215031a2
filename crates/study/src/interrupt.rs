//! Stopping a long run on request (Ctrl-C), between groups of runs.
//!
//! The command line installs the signal handler; the library only reads the request. A
//! Monte Carlo study ([`crate::Study::run_folded`], [`crate::Study::run_blocks`]) and a
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
