//! Streaming tallies: sums over runs that never grow with the number of runs, and that add
//! up in a fixed order so results are bit-identical whatever the thread count or sharding.
//!
//! Runs are grouped in blocks of [`BLOCK`]. A block folds its runs in index order; blocks fold
//! in block order. A shard writes whole blocks; `merge` folds them in the same order. Floating
//! point addition is not associative, so this fixed tree is what makes "merged shards equal
//! the single-machine run" exact rather than approximate.

use navkf_filters::{DivergenceCause, RunFailure};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Runs per block.
pub const BLOCK: usize = 10;

/// A run excluded from one filter's statistics.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Divergence {
    /// Run index.
    pub run: usize,
    /// What excluded it.
    #[serde(flatten)]
    pub failure: RunFailure,
}

/// Sums over runs of one filter's quantities at the stored times.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct FilterTally {
    /// Runs that finished and stayed within bounds.
    pub ok: u64,
    /// Runs excluded, with reasons.
    pub diverged: Vec<Divergence>,
    /// Per stored time, per state: sum of squared errors.
    pub sum_sq_err: Vec<Vec<f64>>,
    /// Per stored time, per state: sum of the filter's claimed variance.
    pub sum_var: Vec<Vec<f64>>,
    /// Per stored time: sum of NEES.
    pub sum_nees: Vec<f64>,
    /// Per stored time: sum of the NIS averaged over the preceding interval.
    pub sum_nis_window: Vec<f64>,
    /// Sum over runs and steps of NIS, and of the measurement dimension.
    pub sum_nis: f64,
    /// Number of updates in `sum_nis`.
    pub nis_count: u64,
    /// Sum of the measurement dimensions over those updates (the NIS degrees of freedom).
    pub nis_dof: u64,
    /// Sum over runs of the run's mean NIS, and of its square (spread between runs).
    pub sum_run_nis: f64,
    /// See `sum_run_nis`.
    pub sum_run_nis_sq: f64,
    /// Step cost histogram: bin index (2 % wide, see [`cost_bin`]) to count.
    pub step_cost: BTreeMap<u32, u64>,
}

/// Sums of the truth-linearised Riccati bound (see [`crate::monte_carlo`]).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct BoundTally {
    /// Runs that contributed.
    pub count: u64,
    /// Per stored time, per truth state: sum of the bound's variance.
    pub sum_var: Vec<Vec<f64>>,
}

/// Paired comparison of two filters on the same runs: final squared errors' differences.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct PairTally {
    /// First filter's name.
    pub a: String,
    /// Second filter's name.
    pub b: String,
    /// Runs where both finished.
    pub n: u64,
    /// Per state: sum of `e_a^2 - e_b^2`.
    pub sum_d: Vec<f64>,
    /// Per state: sum of `(e_a^2 - e_b^2)^2`.
    pub sum_d2: Vec<f64>,
}

/// Everything a block (or a whole study) accumulates.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct Tally {
    /// First run index covered (for ordering blocks).
    pub first_run: usize,
    /// Number of runs covered.
    pub runs: usize,
    /// Per filter, in the study's order.
    pub filters: Vec<FilterTally>,
    /// The bound.
    pub bound: BoundTally,
    /// Per pair of filters.
    pub pairs: Vec<PairTally>,
}

/// Histogram bin of a step cost in nanoseconds: 2 % wide bins.
pub fn cost_bin(ns: u64) -> u32 {
    ((ns.max(1) as f64).ln() / 1.02f64.ln()).floor() as u32
}

/// Lower edge of a bin, nanoseconds.
pub fn bin_value(bin: u32) -> f64 {
    1.02f64.powi(bin as i32)
}

/// The `q` quantile (0..1) of a cost histogram, nanoseconds (bin's geometric centre).
pub fn quantile(hist: &BTreeMap<u32, u64>, q: f64) -> f64 {
    let total: u64 = hist.values().sum();
    if total == 0 {
        return f64::NAN;
    }
    let target = (q * total as f64).ceil().max(1.0) as u64;
    let mut acc = 0;
    for (&bin, &count) in hist {
        acc += count;
        if acc >= target {
            return bin_value(bin) * 1.01;
        }
    }
    f64::NAN
}

/// Adds `b` element-wise to `a` (sized on first use).
pub fn add_row(a: &mut Vec<f64>, b: &[f64]) {
    add_vec(a, b)
}

/// Adds `b` row-wise to `a` (sized on first use).
pub fn add_rows(a: &mut Vec<Vec<f64>>, b: &[Vec<f64>]) {
    add_mat(a, b)
}

fn add_vec(a: &mut Vec<f64>, b: &[f64]) {
    if a.is_empty() {
        a.resize(b.len(), 0.0);
    }
    for (x, y) in a.iter_mut().zip(b) {
        *x += y;
    }
}

fn add_mat(a: &mut Vec<Vec<f64>>, b: &[Vec<f64>]) {
    if a.is_empty() {
        a.resize(b.len(), Vec::new());
    }
    for (x, y) in a.iter_mut().zip(b) {
        add_vec(x, y);
    }
}

impl FilterTally {
    /// The excluded runs counted by cause (causes with none left out), in the causes' order.
    pub fn diverged_by_cause(&self) -> BTreeMap<DivergenceCause, u64> {
        let mut counts = BTreeMap::new();
        for d in &self.diverged {
            *counts.entry(d.failure.cause).or_insert(0) += 1;
        }
        counts
    }

    /// Adds another tally (a later block) to this one.
    pub fn merge(&mut self, o: &FilterTally) {
        self.ok += o.ok;
        self.diverged.extend(o.diverged.iter().cloned());
        add_mat(&mut self.sum_sq_err, &o.sum_sq_err);
        add_mat(&mut self.sum_var, &o.sum_var);
        add_vec(&mut self.sum_nees, &o.sum_nees);
        add_vec(&mut self.sum_nis_window, &o.sum_nis_window);
        self.sum_nis += o.sum_nis;
        self.nis_count += o.nis_count;
        self.nis_dof += o.nis_dof;
        self.sum_run_nis += o.sum_run_nis;
        self.sum_run_nis_sq += o.sum_run_nis_sq;
        for (k, v) in &o.step_cost {
            *self.step_cost.entry(*k).or_insert(0) += v;
        }
    }
}

impl Tally {
    /// Adds a later block's tally to this one (blocks must come in order).
    pub fn merge(&mut self, o: &Tally) {
        if self.runs == 0 {
            self.first_run = o.first_run;
        }
        self.runs += o.runs;
        if self.filters.is_empty() {
            self.filters.resize(o.filters.len(), FilterTally::default());
        }
        for (a, b) in self.filters.iter_mut().zip(&o.filters) {
            a.merge(b);
        }
        self.bound.count += o.bound.count;
        add_mat(&mut self.bound.sum_var, &o.bound.sum_var);
        if self.pairs.is_empty() {
            self.pairs = o
                .pairs
                .iter()
                .map(|p| PairTally {
                    a: p.a.clone(),
                    b: p.b.clone(),
                    ..Default::default()
                })
                .collect();
        }
        for (a, b) in self.pairs.iter_mut().zip(&o.pairs) {
            a.n += b.n;
            add_vec(&mut a.sum_d, &b.sum_d);
            add_vec(&mut a.sum_d2, &b.sum_d2);
        }
    }
}
