//! Checking a shard file against its own structure and against the study it ran, before
//! `merge` folds it.
//!
//! A shard file is data a user can edit, truncate or write by hand, not output this process
//! made. The fold and the summaries index its arrays by the study's stored times and states
//! and divide by its counts: a short array would panic, an `ok` count beyond the runs would
//! be believed, a block with its filters removed would drop its runs without a word, and a
//! negative sum of squares would reach the RMS. So every count is held to what the study's
//! runs and [`BLOCK`] imply, every array to the length the study's times, states and filters
//! imply, and every sum to being finite (and non-negative where it adds squares, variances,
//! NEES or NIS). Each refusal names the field, as `blocks[2].filters[0].sum_sq_err[17]`.
//!
//! The expected shapes are those [`Study::add_run`] produces: a filter's sums are empty while
//! none of its runs finished, and one row per stored time of one value per state after.

use crate::monte_carlo::{ExampleRun, Study};
use crate::partial::{shard_blocks, Partial};
use crate::tally::{cost_bin, FilterTally, Tally, BLOCK};
use navkf_report::names::shown;
use std::ops::Range;

/// What the shard files of a study must hold, from the study built from their config.
struct Expected<'a> {
    /// Runs in the study.
    runs: usize,
    /// Blocks in the study.
    blocks: usize,
    /// Stored times.
    times: usize,
    /// The filters' state names.
    names: &'a [String],
    /// States of the truth model (the bound's rows).
    truth_states: usize,
    /// The compared filters, in order.
    filters: &'a [String],
    /// At most this many filter steps (one per measurement) in one run.
    steps_per_run: u64,
    /// The run whose traces the example holds.
    example_run: usize,
    /// Measurement rows of the filters' model: at most this many in one update.
    meas_dim: u64,
}

impl<'a> Expected<'a> {
    fn of(study: &'a Study) -> Self {
        let measurements = study.sim.trajectory().duration() * study.sim.measurement_rate_hz();
        Expected {
            runs: study.config.study.runs,
            blocks: study.block_count(),
            times: study.times.len(),
            names: &study.names,
            truth_states: study.sim.truth_model().dim(),
            filters: study.filter_names(),
            steps_per_run: measurements.max(0.0).ceil() as u64 + 1,
            example_run: study.config.study.example_run,
            meas_dim: study.filter_model.meas_dim() as u64,
        }
    }

    /// The runs of block `b`.
    fn block_runs(&self, b: usize) -> Range<usize> {
        let start = b.saturating_mul(BLOCK);
        start..b.saturating_add(1).saturating_mul(BLOCK).min(self.runs)
    }
}

/// The length an array must have, and why.
#[derive(Clone, Copy)]
struct Len {
    want: usize,
    why: &'static str,
}

impl Len {
    const NONE: Len = Len::new(0, "no run of the block finished");

    const fn new(want: usize, why: &'static str) -> Self {
        Len { want, why }
    }

    /// `field` (an array of `have` entries, counted as `unit`) has the wanted length.
    fn check(self, field: &str, have: usize, unit: &str) -> Result<(), String> {
        if have == self.want {
            return Ok(());
        }
        let want = match self.want {
            0 => "none".to_string(),
            n => n.to_string(),
        };
        Err(format!(
            "{field} has {have} {unit}; expected {want} ({})",
            self.why
        ))
    }
}

/// Which values a sum may take.
#[derive(Clone, Copy)]
enum Sum {
    /// Any finite value (a sum of differences).
    Finite,
    /// A finite value >= 0; the words say what it adds up.
    NonNegative(&'static str),
}

impl Sum {
    /// Whether `v` is a valid sum of this kind.
    fn accepts(self, v: f64) -> bool {
        match self {
            Sum::Finite => v.is_finite(),
            Sum::NonNegative(_) => v.is_finite() && v >= 0.0,
        }
    }

    fn check(self, field: &str, v: f64) -> Result<(), String> {
        match self {
            Sum::Finite if v.is_finite() => Ok(()),
            Sum::Finite => Err(format!("{field} = {v}: expected a finite sum")),
            Sum::NonNegative(_) if v.is_finite() && v >= 0.0 => Ok(()),
            Sum::NonNegative(what) => Err(format!(
                "{field} = {v}: expected a finite sum >= 0 (it adds {what})"
            )),
        }
    }
}

/// `values` (the array `field`) has `len` values, each a valid `sum`.
fn row(field: &str, values: &[f64], len: Len, sum: Sum) -> Result<(), String> {
    len.check(field, values.len(), "values")?;
    // The field's name is formatted only for the value that fails (a shard holds millions).
    if let Some((k, &v)) = values.iter().enumerate().find(|(_, &v)| !sum.accepts(v)) {
        sum.check(&format!("{field}[{k}]"), v)?;
    }
    Ok(())
}

/// `rows` (the array `field`) has `len` rows of `cols` values, each a valid `sum`.
fn rows(field: &str, rows: &[Vec<f64>], len: Len, cols: Len, sum: Sum) -> Result<(), String> {
    len.check(field, rows.len(), "rows")?;
    for (k, r) in rows.iter().enumerate() {
        row(&format!("{field}[{k}]"), r, cols, sum)?;
    }
    Ok(())
}

/// Checks shard file `part` against the study built from its config: its shard index, its
/// blocks (exactly those [`shard_blocks`] gives it, each with its runs, filters, bound and
/// pairs in the shapes the study implies), and the example run when the example run is one of
/// its runs. The error names the field: `blocks[0].filters[1].ok = 1000030: more than the
/// block's 10 runs`.
pub fn check(part: &Partial, study: &Study) -> Result<(), String> {
    let want = Expected::of(study);
    let (i, n) = part.shard;
    if n == 0 || i >= n {
        return Err(format!(
            "shard = ({i}, {n}): expected shard i of n with 0 <= i < n"
        ));
    }
    if (i + 1).checked_mul(want.blocks).is_none() {
        return Err(format!(
            "shard = ({i}, {n}): more shards than a study of {} blocks can be split into",
            want.blocks
        ));
    }
    let range = shard_blocks(want.blocks, i, n);
    let holds = format!(
        "shard {i}/{n} holds blocks {}..{} of the study's {}, {BLOCK} runs each",
        range.start, range.end, want.blocks
    );
    if part.blocks.len() > range.len() {
        return Err(format!(
            "blocks has {} entries; expected {} ({holds})",
            part.blocks.len(),
            range.len()
        ));
    }
    for (k, b) in part.blocks.iter().enumerate() {
        let index = range.start + k;
        let runs = want.block_runs(index);
        if b.first_run != runs.start {
            return Err(format!(
                "blocks[{k}].first_run = {}: expected {} ({holds}; a block missing?)",
                b.first_run, runs.start
            ));
        }
        check_block(&format!("blocks[{k}]"), b, runs, &want)?;
    }
    if part.blocks.len() < range.len() {
        return Err(format!(
            "blocks has {} entries; expected {} ({holds})",
            part.blocks.len(),
            range.len()
        ));
    }
    let runs = range.start.saturating_mul(BLOCK).min(want.runs)
        ..range.end.saturating_mul(BLOCK).min(want.runs);
    match (&part.example, runs.contains(&want.example_run)) {
        (None, false) => Ok(()),
        (Some(_), false) => Err(format!(
            "example: this shard holds runs {}..{}, not the example run {} (study.example_run)",
            runs.start, runs.end, want.example_run
        )),
        (None, true) => Err(format!(
            "example is missing: the example run {} (study.example_run) is one of this shard's runs {}..{}",
            want.example_run, runs.start, runs.end
        )),
        (Some(ex), true) => check_example(ex, &want),
    }
}

/// Block `p` (a `Tally`), which must hold the runs `runs`.
fn check_block(p: &str, b: &Tally, runs: Range<usize>, want: &Expected) -> Result<(), String> {
    if b.runs != runs.len() {
        return Err(format!(
            "{p}.runs = {}: expected {} (the block of runs {}..{} in a study of {} runs)",
            b.runs,
            runs.len(),
            runs.start,
            runs.end,
            want.runs
        ));
    }
    let nf = want.filters.len();
    Len::new(nf, "one per filter in study.filters").check(
        &format!("{p}.filters"),
        b.filters.len(),
        "entries",
    )?;
    for (j, t) in b.filters.iter().enumerate() {
        check_filter(&format!("{p}.filters[{j}]"), t, &runs, want)?;
    }
    let bound = &b.bound;
    if bound.count > runs.len() as u64 {
        return Err(format!(
            "{p}.bound.count = {}: more than the block's {} runs",
            bound.count,
            runs.len()
        ));
    }
    let (len, cols) = match bound.count {
        0 => {
            let none = Len::new(0, "the bound counts no run");
            (none, none)
        }
        _ => (
            Len::new(want.times, "one per stored time"),
            Len::new(want.truth_states, "one per state of the truth model"),
        ),
    };
    rows(
        &format!("{p}.bound.sum_var"),
        &bound.sum_var,
        len,
        cols,
        Sum::NonNegative("variances"),
    )?;
    check_pairs(p, b, want)
}

/// Filter tally `p` of a block of the runs `runs`.
fn check_filter(
    p: &str,
    t: &FilterTally,
    runs: &Range<usize>,
    want: &Expected,
) -> Result<(), String> {
    let n = runs.len();
    if t.ok > n as u64 {
        return Err(format!("{p}.ok = {}: more than the block's {n} runs", t.ok));
    }
    if t.ok + t.diverged.len() as u64 != n as u64 {
        return Err(format!(
            "{p}: ok = {} and {} diverged runs make {}; expected the block's {n} runs (each run finishes or diverges)",
            t.ok,
            t.diverged.len(),
            t.ok + t.diverged.len() as u64
        ));
    }
    // The causes are counted from this list, so distinct runs of the block make them add up.
    for (k, d) in t.diverged.iter().enumerate() {
        let after = k.checked_sub(1).map(|j| t.diverged[j].run);
        if !runs.contains(&d.run) || after.is_some_and(|a| d.run <= a) {
            return Err(format!(
                "{p}.diverged[{k}].run = {}: expected a run of the block ({}..{}) after the previous entry's",
                d.run, runs.start, runs.end
            ));
        }
    }
    let (times, states) = match t.ok {
        0 => (Len::NONE, Len::NONE),
        _ => (
            Len::new(want.times, "one per stored time"),
            Len::new(want.names.len(), "one per state"),
        ),
    };
    let field = |name: &str| format!("{p}.{name}");
    let (squares, variances) = (
        Sum::NonNegative("squared errors"),
        Sum::NonNegative("variances"),
    );
    rows(&field("sum_sq_err"), &t.sum_sq_err, times, states, squares)?;
    rows(&field("sum_var"), &t.sum_var, times, states, variances)?;
    row(
        &field("sum_nees"),
        &t.sum_nees,
        times,
        Sum::NonNegative("NEES"),
    )?;
    let nis = Sum::NonNegative("NIS");
    row(&field("sum_nis_window"), &t.sum_nis_window, times, nis)?;
    for (name, v, sum) in [
        ("sum_nis", t.sum_nis, nis),
        ("sum_run_nis", t.sum_run_nis, nis),
        (
            "sum_run_nis_sq",
            t.sum_run_nis_sq,
            Sum::NonNegative("squared NIS"),
        ),
    ] {
        sum.check(&field(name), v)?;
        if t.ok == 0 && v != 0.0 {
            return Err(format!(
                "{p}.{name} = {v}: expected 0 (no run of the block finished)"
            ));
        }
    }
    // Every finished run updated at each stored time at least, and at most at every
    // measurement; an update has at most the model's measurement rows.
    let (fewest, most) = (
        t.ok.saturating_mul(want.times as u64),
        t.ok.saturating_mul(want.steps_per_run),
    );
    if !(fewest..=most).contains(&t.nis_count) {
        return Err(format!(
            "{p}.nis_count = {}: expected {fewest} to {most} updates ({} finished runs of {} to {} updates each)",
            t.nis_count, t.ok, want.times, want.steps_per_run
        ));
    }
    let dof = t.nis_count.saturating_mul(want.meas_dim);
    if t.nis_dof > dof {
        return Err(format!(
            "{p}.nis_dof = {}: more than {dof} ({} measurements in each of {} updates)",
            t.nis_dof, want.meas_dim, t.nis_count
        ));
    }
    check_step_cost(p, t, n, want)
}

/// The step-cost histogram of filter tally `p`: bins a cost in nanoseconds can have, and as
/// many steps as the block's runs can take (those of the finished runs at least).
fn check_step_cost(p: &str, t: &FilterTally, runs: usize, want: &Expected) -> Result<(), String> {
    let last_bin = cost_bin(u64::MAX);
    if let Some((&bin, _)) = t.step_cost.iter().find(|(&bin, _)| bin > last_bin) {
        return Err(format!(
            "{p}.step_cost has bin {bin}: expected bins 0 to {last_bin} (2 % wide bins of a cost in nanoseconds)"
        ));
    }
    let steps = t.step_cost.values().fold(0u64, |a, &c| a.saturating_add(c));
    let most = (runs as u64).saturating_mul(want.steps_per_run);
    if !(t.nis_count..=most).contains(&steps) {
        return Err(format!(
            "{p}.step_cost counts {steps} steps: expected {} to {most} (the finished runs' updates in nis_count, and at most {} steps in each of {runs} runs)",
            t.nis_count, want.steps_per_run
        ));
    }
    Ok(())
}

/// The pairs of block `p`: one per pair of filters in order, each counting the runs both
/// finished.
fn check_pairs(p: &str, b: &Tally, want: &Expected) -> Result<(), String> {
    let f = want.filters;
    let pairs: Vec<(usize, usize)> = (0..f.len())
        .flat_map(|i| (i + 1..f.len()).map(move |j| (i, j)))
        .collect();
    Len::new(pairs.len(), "one per pair of filters in study.filters").check(
        &format!("{p}.pairs"),
        b.pairs.len(),
        "entries",
    )?;
    for (k, (&(i, j), pair)) in pairs.iter().zip(&b.pairs).enumerate() {
        let q = format!("{p}.pairs[{k}]");
        if pair.a != f[i] || pair.b != f[j] {
            return Err(format!(
                "{q} compares {} with {}; expected {} with {}",
                shown(&pair.a),
                shown(&pair.b),
                shown(&f[i]),
                shown(&f[j])
            ));
        }
        let (oa, ob) = (b.filters[i].ok, b.filters[j].ok);
        let (fewest, most) = ((oa + ob).saturating_sub(b.runs as u64), oa.min(ob));
        if !(fewest..=most).contains(&pair.n) {
            return Err(format!(
                "{q}.n = {}: expected {fewest} to {most} runs that both filters finished (ok = {oa} and {ob} of the block's {} runs)",
                pair.n, b.runs
            ));
        }
        let len = match pair.n {
            0 => Len::new(0, "no run that both filters finished"),
            _ => Len::new(want.names.len(), "one per state"),
        };
        row(&format!("{q}.sum_d"), &pair.sum_d, len, Sum::Finite)?;
        let squares = Sum::NonNegative("squared differences");
        row(&format!("{q}.sum_d2"), &pair.sum_d2, len, squares)?;
    }
    Ok(())
}

/// The example run: the study's example run, with one state name, one true value per state
/// and one estimate and sigma per state at each of its times.
fn check_example(ex: &ExampleRun, want: &Expected) -> Result<(), String> {
    if ex.run != want.example_run {
        return Err(format!(
            "example.run = {}: expected {} (study.example_run)",
            ex.run, want.example_run
        ));
    }
    let states = Len::new(want.names.len(), "one per state");
    states.check("example.names", ex.names.len(), "names")?;
    for (k, (have, name)) in ex.names.iter().zip(want.names).enumerate() {
        if have != name {
            return Err(format!(
                "example.names[{k}] = {}: expected {}",
                shown(have),
                shown(name)
            ));
        }
    }
    times("example.t", &ex.t)?;
    Len::new(ex.t.len(), "one per time in example.t").check(
        "example.truth",
        ex.truth.len(),
        "rows",
    )?;
    for (k, r) in ex.truth.iter().enumerate() {
        states.check(&format!("example.truth[{k}]"), r.len(), "values")?;
    }
    Len::new(want.filters.len(), "one per filter in study.filters").check(
        "example.filters",
        ex.filters.len(),
        "entries",
    )?;
    for (j, (f, name)) in ex.filters.iter().zip(want.filters).enumerate() {
        let p = format!("example.filters[{j}]");
        if f.name != *name {
            return Err(format!(
                "{p}.name = {}: expected {}",
                shown(&f.name),
                shown(name)
            ));
        }
        times(&format!("{p}.t"), &f.t)?;
        let len = Len::new(f.t.len(), "one per time in its t");
        for (field, series) in [("estimate", &f.estimate), ("sigma", &f.sigma)] {
            len.check(&format!("{p}.{field}"), series.len(), "rows")?;
            for (k, r) in series.iter().enumerate() {
                states.check(&format!("{p}.{field}[{k}]"), r.len(), "values")?;
            }
        }
    }
    Ok(())
}

/// `t` (the array `field`) holds finite, increasing times.
fn times(field: &str, t: &[f64]) -> Result<(), String> {
    for (k, &v) in t.iter().enumerate() {
        let after = k.checked_sub(1).map(|j| t[j]);
        if !v.is_finite() || after.is_some_and(|a| !(v > a)) {
            return Err(format!(
                "{field}[{k}] = {v}: expected a finite time after the one before"
            ));
        }
    }
    Ok(())
}

/// Checks that the shards' blocks, folded in order as `merge` folds them, add up to finite
/// sums (each shard's are finite, but values near the largest double can add to infinity).
/// `parts` must be in block order and each already passed [`check`].
pub fn check_totals(parts: &[Partial]) -> Result<(), String> {
    let mut total = Tally::default();
    for p in parts {
        for b in &p.blocks {
            total.merge(b);
        }
        if let Some((field, v)) = first_non_finite(&total) {
            return Err(format!(
                "shard {}/{}: its blocks bring the merged {field} to {v}: sums too large for any run",
                p.shard.0, p.shard.1
            ));
        }
    }
    Ok(())
}

/// The first sum of `t` that is not finite, with its field.
fn first_non_finite(t: &Tally) -> Option<(String, f64)> {
    fn in_row(field: &str, row: &[f64]) -> Option<(String, f64)> {
        let k = row.iter().position(|v| !v.is_finite())?;
        Some((format!("{field}[{k}]"), row[k]))
    }
    fn in_rows(field: &str, rows: &[Vec<f64>]) -> Option<(String, f64)> {
        let k = rows.iter().position(|r| r.iter().any(|v| !v.is_finite()))?;
        in_row(&format!("{field}[{k}]"), &rows[k])
    }
    for (j, f) in t.filters.iter().enumerate() {
        let p = format!("filters[{j}]");
        let found = in_rows(&format!("{p}.sum_sq_err"), &f.sum_sq_err)
            .or_else(|| in_rows(&format!("{p}.sum_var"), &f.sum_var))
            .or_else(|| in_row(&format!("{p}.sum_nees"), &f.sum_nees))
            .or_else(|| in_row(&format!("{p}.sum_nis_window"), &f.sum_nis_window))
            .or_else(|| {
                [
                    ("sum_nis", f.sum_nis),
                    ("sum_run_nis", f.sum_run_nis),
                    ("sum_run_nis_sq", f.sum_run_nis_sq),
                ]
                .into_iter()
                .find(|(_, v)| !v.is_finite())
                .map(|(field, v)| (format!("{p}.{field}"), v))
            });
        if found.is_some() {
            return found;
        }
    }
    in_rows("bound.sum_var", &t.bound.sum_var).or_else(|| {
        t.pairs.iter().enumerate().find_map(|(k, pair)| {
            in_row(&format!("pairs[{k}].sum_d"), &pair.sum_d)
                .or_else(|| in_row(&format!("pairs[{k}].sum_d2"), &pair.sum_d2))
        })
    })
}
