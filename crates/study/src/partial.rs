//! A shard's results: what `navkf study --shard i/n` writes instead of a results folder, and
//! `merge` reads back ([`crate::merge`]).

use crate::monte_carlo::ExampleRun;
use crate::tally::Tally;
use serde::{Deserialize, Serialize};

/// A shard's output: its blocks' tallies, in order, and the example run if it holds it.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Partial {
    /// The study file, as run (merge checks that every shard ran the same one).
    pub config: crate::config::StudyConfig,
    /// `(i, n)` of `--shard i/n`.
    pub shard: (usize, usize),
    /// Tallies of whole blocks, in block order.
    pub blocks: Vec<Tally>,
    /// The example run, if it fell in this shard.
    pub example: Option<ExampleRun>,
}

/// The blocks of shard `i` of `n` ([`navkf_report::executor::shard_range`] over blocks).
pub fn shard_blocks(blocks: usize, i: usize, n: usize) -> std::ops::Range<usize> {
    navkf_report::executor::shard_range(blocks, i, n)
}
