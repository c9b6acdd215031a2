//! Long calls from Python: the work runs on its own thread with the GIL released, while the
//! calling thread wakes every 100 ms to pass progress to the user's callback and to let
//! Python see a Ctrl-C.
//!
//! Ctrl-C asks the work to stop as the command line's first Ctrl-C does
//! ([`navkf_report::interrupt::request`]: a study stops after the runs in flight and writes
//! nothing); the call then raises `KeyboardInterrupt` once the work has returned, so no
//! thread is left running and no results folder is left half written.

use crate::errors::interrupted;
use pyo3::prelude::*;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Duration;

/// How far the work has got: `done` of `total` units, which the work updates and the
/// calling thread reads.
#[derive(Debug, Default)]
pub struct Progress {
    pub done: AtomicUsize,
    pub total: AtomicUsize,
}

impl Progress {
    pub fn set(&self, done: usize) {
        self.done.store(done, Ordering::Relaxed);
    }
}

/// Runs `work` with the GIL released, calling `callback(done, total)` (when given) as
/// `progress` moves, and stopping it on Ctrl-C (module documentation).
pub fn run<T: Send>(
    py: Python<'_>,
    callback: Option<&Bound<'_, PyAny>>,
    progress: &Progress,
    work: impl FnOnce() -> T + Send,
) -> PyResult<T> {
    navkf_report::interrupt::clear();
    let mut stop: Option<PyErr> = None;
    let mut callback_error: Option<PyErr> = None;
    let mut reported = usize::MAX;
    let outcome = std::thread::scope(|scope| {
        let handle = scope.spawn(work);
        loop {
            let finished = py.detach(|| {
                let mut waited = Duration::ZERO;
                while !handle.is_finished() && waited < Duration::from_millis(100) {
                    std::thread::sleep(Duration::from_millis(5));
                    waited += Duration::from_millis(5);
                }
                handle.is_finished()
            });
            let done = progress.done.load(Ordering::Relaxed);
            if let (Some(cb), None, true) = (callback, &callback_error, done != reported) {
                reported = done;
                let total = progress.total.load(Ordering::Relaxed);
                if let Err(e) = cb.call1((done, total)) {
                    // A failing callback stops the work as Ctrl-C would, then is raised.
                    navkf_report::interrupt::request();
                    callback_error = Some(e);
                }
            }
            if finished {
                break;
            }
            if stop.is_none() {
                if let Err(e) = py.check_signals() {
                    navkf_report::interrupt::request();
                    stop = Some(e);
                }
            }
        }
        handle.join()
    });
    let was_stopped = navkf_report::interrupt::requested();
    navkf_report::interrupt::clear();
    let value = match outcome {
        Ok(v) => v,
        Err(panic) => std::panic::resume_unwind(panic),
    };
    if let Some(e) = callback_error {
        return Err(e);
    }
    if let Some(e) = stop {
        return Err(e);
    }
    if was_stopped {
        return Err(interrupted("interrupted: nothing was written".into()));
    }
    Ok(value)
}
