//! The accuracy guard: compares a study's summary with a committed baseline summary and
//! lists what got worse (`navkf study studies/ci.toml --baseline studies/ci-baseline.json`).
//!
//! # Same seed
//!
//! The guard requires the study to be run with exactly the baseline's settings, seed and run
//! count included ([`settings_differences`]). With the same seed and the same code the
//! results are bit-identical, so an unchanged code base passes with every value equal (the
//! report counts them). Tolerances only matter for code changes that legitimately alter the
//! numbers: a different rounding order (bit-level changes that stay tiny, since the filters
//! are stable) or a different consumption of the random streams (a fresh Monte Carlo sample
//! of the same study, which moves every statistic by its sampling error).
//!
//! # Tolerances from the Monte Carlo standard error
//!
//! Each check is a one-sided test of "nothing changed" against "got worse", with the
//! standard error of the difference of two independent Monte Carlo estimates evaluated at the
//! baseline's value (the null hypothesis), so a degraded run does not widen its own
//! tolerance. Treating the two runs as independent is conservative for the same seed, where
//! they are strongly positively correlated.
//!
//! - RMS of a coefficient's final error over `N` runs of roughly Gaussian errors has a
//!   relative standard error of about `1/sqrt(2N)`. A coefficient is flagged when
//!   `rms_now - rms_base > k * rms_base * sqrt(1/(2 N_base) + 1/(2 N_now))`.
//! - NEES and NIS means: the summary's 95 % chi-square bounds span `+-1.96` standard errors of
//!   a consistent filter's mean, so one standard error is `width / 3.92`, scaled by
//!   `mean / expected` for a filter that is off by a factor. A mean is flagged when its
//!   distance from the expected value (state dimension, mean measurement dimension) grows by
//!   more than `k` standard errors of the difference: drifting out of consistency either
//!   way is worse, moving towards it is not.
//! - Diverged runs: any increase is flagged (the count is deterministic for the same seed;
//!   the baseline has none).
//!
//! `k = 4` ([`DEFAULT_K`]): the guard makes about 45 checks (13 coefficients, NEES and NIS for
//! 3 filters). A one-sided Gaussian test at 4 standard errors has a false-alarm rate of
//! 3.2e-5, so even a change that redraws every random number (the worst case: independent
//! samples) fails the guard by chance with probability about 45 x 3.2e-5 = 0.15 %; at k = 3
//! it would be 6 %, too often for CI. The price: with 100 runs a coefficient's RMS must
//! worsen by about 40 % (`4 * sqrt(2/200)`) to be flagged, which catches broken filters,
//! not subtle ones.

use crate::config::StudyConfig;
use crate::error::StudyError;
use crate::summary::{FilterSummary, Summary};
use navkf_dynamics::input_file::{printable, read_text, TextFile};
use navkf_report::markdown::{number, Number, Table};
use std::fmt::Write as _;
use std::path::Path;

/// Standard errors of the difference beyond which a value counts as worse (see the module
/// documentation for the choice).
pub const DEFAULT_K: f64 = 4.0;

/// Two-sided 95 % normal quantile times two: the width of a 95 % interval in standard
/// errors.
const WIDTH_95_IN_SE: f64 = 2.0 * 1.959_963_984_540_054;

/// One value that got worse than the baseline by more than the tolerance.
#[derive(Debug, Clone, PartialEq)]
pub struct Finding {
    /// Filter name.
    pub filter: String,
    /// What was compared, e.g. `RMS Kg0x`, `NEES (expected 20)`, `diverged runs`.
    pub quantity: String,
    /// Baseline value.
    pub baseline: f64,
    /// Value now (NaN when missing).
    pub current: f64,
    /// The change, in words (e.g. `+217 %`).
    pub change: String,
    /// The largest change allowed, in words.
    pub allowed: String,
    /// Change in standard errors of the difference (NaN where none applies).
    pub z: f64,
}

/// The outcome of a comparison.
#[derive(Debug, Clone, PartialEq)]
pub struct GuardReport {
    /// Standard errors allowed.
    pub k: f64,
    /// Number of values compared.
    pub checks: usize,
    /// How many of them equal the baseline bit for bit.
    pub identical: usize,
    /// The largest `z` among all checks, and what it was (the closest call).
    pub largest: Option<(f64, String)>,
    /// What got worse beyond tolerance.
    pub worse: Vec<Finding>,
}

impl GuardReport {
    /// True when nothing got worse beyond tolerance.
    pub fn passed(&self) -> bool {
        self.worse.is_empty()
    }

    /// A readable account: one line when passed, a Markdown table of what got worse
    /// otherwise.
    pub fn table(&self) -> String {
        let mut out = String::new();
        let closest = match &self.largest {
            Some((z, what)) if *z > 0.0 => {
                format!("; closest: {what}, {z:.2} standard errors worse")
            }
            _ => String::new(),
        };
        if self.passed() {
            let _ = writeln!(
                out,
                "\naccuracy guard passed: {} checks, {} identical to the baseline, none worse by more than {} standard errors{closest}",
                self.checks, self.identical, self.k
            );
            return out;
        }
        let _ = writeln!(
            out,
            "\naccuracy guard FAILED: {} of {} checks got worse than the baseline by more than {} standard errors\n",
            self.worse.len(),
            self.checks,
            self.k
        );
        let mut table = Table::new([
            "filter",
            "quantity",
            "baseline",
            "now",
            "change",
            "allowed",
            "standard errors",
        ]);
        for f in &self.worse {
            table.row([
                f.filter.clone(),
                f.quantity.clone(),
                g(f.baseline),
                g(f.current),
                f.change.clone(),
                f.allowed.clone(),
                number(f.z, Number::Fixed(1)),
            ]);
        }
        out.push_str(&table.render());
        out
    }
}

fn g(v: f64) -> String {
    if !v.is_finite() {
        "missing".into()
    } else if v == v.trunc() && v.abs() < 1e6 {
        format!("{v}")
    } else if (0.01..1e5).contains(&v.abs()) {
        format!("{v:.4}")
    } else {
        format!("{v:.4e}")
    }
}

/// Reads a baseline `summary.json`: a regular file of at most
/// [`navkf_dynamics::input_file::SUMMARY_MAX_BYTES`] ([`read_text`]); the parser's message is
/// cut ([`printable`]: it may quote a string from the file).
pub fn load_baseline(path: &Path) -> Result<Summary, StudyError> {
    let text = read_text(path, &TextFile::SUMMARY)?;
    serde_json::from_str(&text).map_err(|e| StudyError::Config {
        path: path.to_path_buf(),
        message: printable(&format!("not a study summary.json: {e}")),
    })
}

/// Settings (dotted keys) where `config` differs from the one the baseline was made with,
/// e.g. `study.seed: 1 in the baseline, 2 now`. Empty when the guard's comparison is the
/// intended one: same study, same seed, same run count.
pub fn settings_differences(baseline: &Summary, config: &StudyConfig) -> Vec<String> {
    let a = serde_json::to_value(&baseline.settings).unwrap_or_default();
    let b = serde_json::to_value(config).unwrap_or_default();
    let mut out = Vec::new();
    diff_values("", &a, &b, &mut out);
    out
}

fn diff_values(key: &str, a: &serde_json::Value, b: &serde_json::Value, out: &mut Vec<String>) {
    use serde_json::Value;
    match (a, b) {
        (Value::Object(x), Value::Object(y)) => {
            let mut keys: Vec<&String> = x.keys().chain(y.keys()).collect();
            keys.sort();
            keys.dedup();
            for k in keys {
                let sub = if key.is_empty() {
                    k.clone()
                } else {
                    format!("{key}.{k}")
                };
                let null = Value::Null;
                diff_values(
                    &sub,
                    x.get(k).unwrap_or(&null),
                    y.get(k).unwrap_or(&null),
                    out,
                );
            }
        }
        _ if a != b => out.push(format!("{key}: {a} in the baseline, {b} now")),
        _ => {}
    }
}

/// Compares `current` with `baseline`, flagging what got worse by more than `k` standard
/// errors (see the module documentation). Settings are not compared here: see
/// [`settings_differences`].
pub fn compare(baseline: &Summary, current: &Summary, k: f64) -> GuardReport {
    let mut r = GuardReport {
        k,
        checks: 0,
        identical: 0,
        largest: None,
        worse: Vec::new(),
    };
    for (name, b) in &baseline.filters {
        let Some(c) = current.filters.get(name) else {
            r.checks += 1;
            r.worse.push(Finding {
                filter: name.clone(),
                quantity: "filter".into(),
                baseline: b.runs_ok as f64,
                current: f64::NAN,
                change: "not in this study".into(),
                allowed: "present".into(),
                z: f64::NAN,
            });
            continue;
        };
        check_filter(&mut r, name, b, c);
    }
    r
}

impl GuardReport {
    fn record(&mut self, base: f64, now: f64, z: f64, what: impl FnOnce() -> String) {
        self.checks += 1;
        if base.to_bits() == now.to_bits() {
            self.identical += 1;
        }
        let beyond = match &self.largest {
            Some((m, _)) => z > *m,
            None => true,
        };
        if z.is_finite() && beyond {
            self.largest = Some((z, what()));
        }
    }
}

fn check_filter(r: &mut GuardReport, name: &str, b: &FilterSummary, c: &FilterSummary) {
    let k = r.k;
    // Divergence: any increase.
    r.record(b.diverged as f64, c.diverged as f64, f64::NAN, String::new);
    if c.diverged > b.diverged {
        r.worse.push(Finding {
            filter: name.into(),
            quantity: "diverged runs".into(),
            baseline: b.diverged as f64,
            current: c.diverged as f64,
            change: format!("+{}", c.diverged - b.diverged),
            allowed: "no increase".into(),
            z: f64::NAN,
        });
    }
    if c.runs_ok == 0 {
        r.worse.push(Finding {
            filter: name.into(),
            quantity: "runs finished".into(),
            baseline: b.runs_ok as f64,
            current: 0.0,
            change: "no run finished: nothing else to compare".into(),
            allowed: "-".into(),
            z: f64::NAN,
        });
        return;
    }
    let (n0, n1) = (b.runs_ok as f64, c.runs_ok as f64);
    // Final RMS per coefficient.
    for (coef, &rb) in &b.final_rms {
        if !(rb.is_finite() && n0 > 0.0) {
            continue;
        }
        let rc = c.final_rms.get(coef).copied().unwrap_or(f64::NAN);
        let se = rb * (1.0 / (2.0 * n0) + 1.0 / (2.0 * n1)).sqrt();
        let z = (rc - rb) / se;
        r.record(rb, rc, z, || format!("{name} RMS {coef}"));
        if !(rc.is_finite() && rc - rb <= k * se) {
            r.worse.push(Finding {
                filter: name.into(),
                quantity: format!("RMS {coef}"),
                baseline: rb,
                current: rc,
                change: number(rc / rb - 1.0, Number::SignedPercent(1)),
                allowed: number(k * se / rb, Number::SignedPercent(1)),
                z,
            });
        }
    }
    // NEES and NIS means: distance from the expected value.
    let n_states = (b.final_rms.len() + b.final_rms_nav.len()) as f64;
    for (what, expected, mb, bb, mc, bc) in [
        (
            "NEES",
            n_states,
            b.nees_mean,
            b.nees_bounds,
            c.nees_mean,
            c.nees_bounds,
        ),
        (
            "NIS",
            b.nis_dof,
            b.nis_mean,
            b.nis_bounds,
            c.nis_mean,
            c.nis_bounds,
        ),
    ] {
        if !(mb.is_finite() && expected > 0.0) {
            continue;
        }
        let se_of = |bounds: [f64; 2]| mb / expected * (bounds[1] - bounds[0]) / WIDTH_95_IN_SE;
        let se = (se_of(bb).powi(2) + se_of(bc).powi(2)).sqrt();
        let growth = (mc - expected).abs() - (mb - expected).abs();
        let z = growth / se;
        let quantity = format!("{what} mean (expected {expected})");
        r.record(mb, mc, z, || format!("{name} {quantity}"));
        if !(mc.is_finite() && growth <= k * se) {
            r.worse.push(Finding {
                filter: name.into(),
                quantity,
                baseline: mb,
                current: mc,
                change: format!("{:+.3}", mc - mb),
                allowed: format!(
                    "within {:.3}-{:.3}",
                    expected - (mb - expected).abs() - k * se,
                    expected + (mb - expected).abs() + k * se
                ),
                z,
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeMap;

    fn filter(rms: f64, runs: u64, nees: f64) -> FilterSummary {
        // Bounds of a consistent 20-state filter over `runs` runs.
        let nees_bounds = navkf_report::stats::mean_chi2_bounds(20.0 * runs as f64, runs as f64);
        let mut final_rms = BTreeMap::new();
        final_rms.insert("Kg0x".to_string(), rms);
        let final_rms_nav = (0..19).map(|i| (format!("s{i}"), 1.0)).collect();
        FilterSummary {
            final_rms,
            final_sigma: BTreeMap::new(),
            final_bound: BTreeMap::new(),
            final_rms_nav,
            nees_mean: nees,
            nees_bounds,
            nis_mean: 4.0,
            nis_bounds: navkf_report::stats::mean_chi2_bounds(4.0 * 240_000.0, 240_000.0),
            nis_dof: 4.0,
            diverged: 0,
            runs_ok: runs,
            step_ns_median: 1.0,
            step_ns_p90: 1.0,
            diverged_by_cause: Default::default(),
            diverged_examples: Vec::new(),
        }
    }

    fn summary(f: FilterSummary) -> Summary {
        let cfg = StudyConfig::parse(
            "[study]\nname = \"t\"\nruns = 100\nseed = 1\nfilters = [\"ekf\"]\n",
        )
        .unwrap();
        Summary {
            study: "t".into(),
            runs: 100,
            seed: 1,
            filters: [("ekf".to_string(), f)].into_iter().collect(),
            paired: Vec::new(),
            settings: cfg,
        }
    }

    #[test]
    fn rms_tolerance_is_k_standard_errors_of_the_difference() {
        let base = summary(filter(1.0, 100, 20.0));
        // 100 runs each: tolerance 4 * sqrt(1/200 + 1/200) = 0.4.
        let r = compare(&base, &summary(filter(1.39, 100, 20.0)), 4.0);
        assert!(r.passed(), "{}", r.table());
        let r = compare(&base, &summary(filter(1.41, 100, 20.0)), 4.0);
        assert!(!r.passed());
        assert!(r.table().contains("| ekf | RMS Kg0x |"), "{}", r.table());
        // Better is never flagged.
        assert!(compare(&base, &summary(filter(0.1, 100, 20.0)), 4.0).passed());
        // Identical passes, and is counted as identical.
        let r = compare(&base, &base, 4.0);
        assert!(r.passed());
        assert_eq!(r.identical, r.checks);
    }

    #[test]
    fn nees_is_flagged_when_it_drifts_away_from_the_state_dimension() {
        let base = summary(filter(1.0, 100, 20.0));
        // One standard error of the mean NEES over 100 runs: sqrt(2 * 20 / 100) = 0.63; of
        // the difference 0.89; k = 4: 3.6.
        assert!(compare(&base, &summary(filter(1.0, 100, 23.0)), 4.0).passed());
        assert!(compare(&base, &summary(filter(1.0, 100, 17.0)), 4.0).passed());
        let r = compare(&base, &summary(filter(1.0, 100, 24.0)), 4.0);
        assert!(
            r.table().contains("NEES mean (expected 20)"),
            "{}",
            r.table()
        );
        assert!(!compare(&base, &summary(filter(1.0, 100, 16.0)), 4.0).passed());
        // Towards consistency is not worse.
        let off = summary(filter(1.0, 100, 30.0));
        assert!(compare(&off, &summary(filter(1.0, 100, 20.5)), 4.0).passed());
    }

    #[test]
    fn more_divergences_or_a_missing_filter_fail() {
        let base = summary(filter(1.0, 100, 20.0));
        let mut f = filter(1.0, 99, 20.0);
        f.diverged = 1;
        let r = compare(&base, &summary(f), 4.0);
        assert!(
            r.table().contains("| ekf | diverged runs | 0 | 1 |"),
            "{}",
            r.table()
        );
        let mut none = summary(filter(1.0, 100, 20.0));
        none.filters.clear();
        assert!(!compare(&base, &none, 4.0).passed());
    }
}
