//! Scheduling runs: the one executor ([`navkf_report::executor::Executor`]) runs them in
//! parallel and hands them on in run order; they are folded into [`Tally`] blocks of
//! [`BLOCK`] runs in a fixed order, so results do not depend on threads or shards.

use super::run::RunRecord;
use super::Study;
use crate::tally::{cost_bin, Divergence, FilterTally, PairTally, Tally, BLOCK};
use navkf_report::executor::Executor;
use navkf_report::Interrupted;

impl Study {
    /// Runs `runs` (a range of run indices) and folds them into one tally per block of
    /// [`BLOCK`] runs, in order. `progress` is told how many runs are done. A stop on
    /// request ([`navkf_report::interrupt`]) ends it with what was done.
    pub fn run_blocks(
        &self,
        blocks: std::ops::Range<usize>,
        progress: &(dyn Fn(usize) + Sync),
        example: impl FnMut(&RunRecord),
    ) -> Result<Vec<Tally>, Interrupted> {
        let mut out = Vec::with_capacity(blocks.len());
        self.for_each_block(blocks, progress, self.only_example(example), |t| {
            out.push(t)
        })?;
        Ok(out)
    }

    /// [`Study::run_blocks`] folded into one tally as the blocks complete: bit-identical to
    /// `output::fold(&run_blocks(..))`, but holding one group of blocks at a time, so memory
    /// does not grow with the number of runs.
    pub fn run_folded(
        &self,
        blocks: std::ops::Range<usize>,
        progress: &(dyn Fn(usize) + Sync),
        example: impl FnMut(&RunRecord),
    ) -> Result<Tally, Interrupted> {
        self.run_folded_each(blocks, progress, self.only_example(example))
    }

    /// [`Study::run_folded`], handing every run's record to `each` (in run order) rather
    /// than the example run's alone: for a caller that keeps per-run results.
    pub fn run_folded_each(
        &self,
        blocks: std::ops::Range<usize>,
        progress: &(dyn Fn(usize) + Sync),
        each: impl FnMut(&RunRecord),
    ) -> Result<Tally, Interrupted> {
        let mut total = Tally::default();
        self.for_each_block(blocks, progress, each, |t| total.merge(&t))?;
        Ok(total)
    }

    /// `example`, called for the study's example run only.
    fn only_example<'a>(
        &'a self,
        mut example: impl FnMut(&RunRecord) + 'a,
    ) -> impl FnMut(&RunRecord) + 'a {
        move |rec| {
            if rec.run == self.config.study.example_run {
                example(rec)
            }
        }
    }

    /// Runs `blocks`, hands each run's record to `each`, and each block's tally to `sink` as
    /// soon as it is complete, in block order. The runs go through the one executor
    /// ([`navkf_report::executor::Executor`]), which hands them on in run order, so the
    /// thread count changes nothing but speed. A stop on request ends it within one run,
    /// with [`Interrupted`]; the blocks not complete are not handed on.
    fn for_each_block(
        &self,
        blocks: std::ops::Range<usize>,
        progress: &(dyn Fn(usize) + Sync),
        mut each: impl FnMut(&RunRecord),
        mut sink: impl FnMut(Tally),
    ) -> Result<(), Interrupted> {
        let total = self.config.study.runs;
        let runs = (blocks.start * BLOCK).min(total)..(blocks.end * BLOCK).min(total);
        // Several blocks in flight at once for parallelism; memory stays bounded by them,
        // however many runs the study asks for.
        let in_flight = (rayon::current_num_threads() * 4).div_ceil(BLOCK).max(1);
        let executor = Executor::new("runs", in_flight * BLOCK);
        let mut tally: Option<Tally> = None;
        // Groups hold whole blocks, so the blocks handed on before a stop are whole.
        executor.run(runs, &|r| self.run_one(r), &progress, |r, rec| {
            let block = tally.get_or_insert_with(|| self.empty_tally(r / BLOCK * BLOCK));
            self.add_run(block, &rec);
            each(&rec);
            if (r + 1) % BLOCK == 0 || r + 1 == total {
                sink(tally.take().expect("the block was started above"));
            }
        })
    }

    /// Number of blocks in the study.
    pub fn block_count(&self) -> usize {
        self.config.study.runs.div_ceil(BLOCK)
    }

    fn empty_tally(&self, first_run: usize) -> Tally {
        let f = self.filter_names();
        let mut pairs = Vec::new();
        for i in 0..f.len() {
            for j in i + 1..f.len() {
                pairs.push(PairTally {
                    a: f[i].clone(),
                    b: f[j].clone(),
                    ..Default::default()
                });
            }
        }
        Tally {
            first_run,
            runs: 0,
            filters: vec![FilterTally::default(); f.len()],
            bound: Default::default(),
            pairs,
        }
    }

    /// Folds one run into a tally.
    pub fn add_run(&self, tally: &mut Tally, rec: &RunRecord) {
        tally.runs += 1;
        for (t, fr) in tally.filters.iter_mut().zip(&rec.filters) {
            for &ns in &fr.step_ns {
                *t.step_cost.entry(cost_bin(ns)).or_insert(0) += 1;
            }
            match &fr.outcome {
                Err(failure) => t.diverged.push(Divergence {
                    run: rec.run,
                    failure: failure.clone(),
                }),
                Ok(()) => {
                    t.ok += 1;
                    let sq: Vec<Vec<f64>> = fr
                        .err
                        .iter()
                        .map(|e| e.iter().map(|v| v * v).collect())
                        .collect();
                    let mut single = FilterTally {
                        ok: 0,
                        sum_sq_err: sq,
                        sum_var: fr.var.clone(),
                        sum_nees: fr.nees.clone(),
                        sum_nis_window: fr.nis_window.clone(),
                        sum_nis: fr.nis.sum,
                        nis_count: fr.nis.updates,
                        nis_dof: fr.nis.dof,
                        ..Default::default()
                    };
                    let run_nis = fr.nis.sum / fr.nis.updates.max(1) as f64;
                    single.sum_run_nis = run_nis;
                    single.sum_run_nis_sq = run_nis * run_nis;
                    t.merge(&single);
                }
            }
        }
        if let Some(b) = &rec.bound {
            tally.bound.count += 1;
            crate::tally::add_rows(&mut tally.bound.sum_var, b);
        }
        let f = self.filter_names();
        let mut k = 0;
        for i in 0..f.len() {
            for j in i + 1..f.len() {
                let (a, b) = (&rec.filters[i], &rec.filters[j]);
                if a.outcome.is_ok() && b.outcome.is_ok() {
                    let (ea, eb) = (a.err.last().unwrap(), b.err.last().unwrap());
                    let d: Vec<f64> = ea.iter().zip(eb).map(|(x, y)| x * x - y * y).collect();
                    let d2: Vec<f64> = d.iter().map(|v| v * v).collect();
                    let p = &mut tally.pairs[k];
                    p.n += 1;
                    crate::tally::add_row(&mut p.sum_d, &d);
                    crate::tally::add_row(&mut p.sum_d2, &d2);
                }
                k += 1;
            }
        }
    }
}
