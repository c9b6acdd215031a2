//! The one executor of every kind of study: independent units of work (a Monte Carlo run, a
//! diagnosis-study dataset), each a pure function of its index and the study's seed, run in
//! parallel and handed on in index order.
//!
//! Why one: what a study run must guarantee is the same whatever it runs.
//! - **Bit-identical whatever the thread count or sharding.** A unit depends only on its
//!   index, and results reach the sink in index order, so any fold over them adds in one
//!   fixed order. A shard is a contiguous range of units ([`shard_range`]); merged in order,
//!   shards give the bytes one machine gives.
//! - **Bounded memory.** Units are taken in groups; one group's results are held at a time.
//! - **A stop within one unit.** Ctrl-C ([`crate::interrupt`]) is checked before each unit
//!   starts; units not started are skipped, and the run ends with [`Interrupted`], so the
//!   caller writes nothing.
//! - **Progress** goes to an [`Observer`], told as each unit completes.
//!
//! (argmin's executor and observers are the model: the loop is the library's, what watches
//! it is the caller's.)
//!
//! ```
//! use navkf_report::executor::{shard_range, Executor};
//! let mut squares = Vec::new();
//! Executor::new("units", 3)
//!     .run(0..10, &|i| i * i, &|_done| {}, |i, sq| squares.push((i, sq)))
//!     .unwrap();
//! assert_eq!(squares, (0..10).map(|i| (i, i * i)).collect::<Vec<_>>());
//! // Shards tile the units in order.
//! assert_eq!([0, 1, 2].map(|i| shard_range(10, i, 3)), [0..3, 3..6, 6..10]);
//! ```

use crate::interrupt::{self, Interrupted};
use rayon::prelude::*;
use std::ops::Range;
use std::sync::atomic::{AtomicUsize, Ordering};

/// What watches a run: told each time a unit completes (from any thread), with the number
/// completed so far in this run.
pub trait Observer: Sync {
    /// `done` units of this run are complete.
    fn unit_done(&self, done: usize);
}

/// Any `Fn(done)` observes (a progress bar's `set_position`, say).
impl<F: Fn(usize) + Sync> Observer for F {
    fn unit_done(&self, done: usize) {
        self(done)
    }
}

/// Runs units in parallel, in groups, handing results on in index order.
#[derive(Debug, Clone, Copy)]
pub struct Executor {
    /// What a unit is, for the interruption message (`runs`, `datasets`).
    what: &'static str,
    /// Units held at once: results of a group are passed on before the next group starts.
    group: usize,
}

impl Executor {
    /// An executor of `what` holding at most `group` results at once (at least one).
    pub fn new(what: &'static str, group: usize) -> Self {
        Executor {
            what,
            group: group.max(1),
        }
    }

    /// Runs `work(i)` for every `i` in `units` and gives `sink(i, result)` in increasing `i`.
    /// Stops, with [`Interrupted`], if a stop is requested: units not yet started are
    /// skipped, and the group in flight is not passed on.
    pub fn run<T: Send>(
        &self,
        units: Range<usize>,
        work: &(dyn Fn(usize) -> T + Sync),
        observer: &dyn Observer,
        mut sink: impl FnMut(usize, T),
    ) -> Result<(), Interrupted> {
        let total = units.len();
        let done = AtomicUsize::new(0);
        let mut next = units.start;
        while next < units.end {
            let group = next..next.saturating_add(self.group).min(units.end);
            next = group.end;
            let results: Vec<Option<T>> = group
                .clone()
                .into_par_iter()
                .map(|i| {
                    if interrupt::requested() {
                        return None;
                    }
                    let result = work(i);
                    observer.unit_done(done.fetch_add(1, Ordering::Relaxed) + 1);
                    Some(result)
                })
                .collect();
            if results.iter().any(Option::is_none) {
                return Err(Interrupted {
                    done: done.load(Ordering::Relaxed),
                    total,
                    what: self.what,
                });
            }
            for (i, result) in group.zip(results) {
                sink(
                    i,
                    result.expect("checked above: every unit of the group ran"),
                );
            }
        }
        Ok(())
    }
}

/// Shard `i` of `n` (`i < n`) of `count` units: contiguous ranges, in order, that tile
/// `0..count`, sized within one unit of each other.
pub fn shard_range(count: usize, i: usize, n: usize) -> Range<usize> {
    let at = |k: usize| (k as u128 * count as u128 / n as u128) as usize;
    at(i)..at(i + 1)
}
