//! Human-readable tables of a summary (terminal and report.md).

use crate::summary::Summary;
use std::fmt::Write as _;

fn g(v: f64) -> String {
    if v.is_finite() {
        format!("{v:.3e}")
    } else {
        "-".into()
    }
}

/// A Markdown table per filter: final RMS error, claimed sigma and bound per coefficient;
/// then consistency and cost.
pub fn table(s: &Summary) -> String {
    let mut out = String::new();
    let names: Vec<&String> = s.filters.keys().collect();
    let coefs: Vec<String> = s
        .filters
        .values()
        .next()
        .map(|f| f.final_rms.keys().cloned().collect())
        .unwrap_or_default();
    let _ = writeln!(out, "\n## {} ({} runs, seed {})\n", s.study, s.runs, s.seed);
    let _ = write!(out, "| coefficient |");
    for n in &names {
        let _ = write!(out, " {n} RMS | {n} sigma |");
    }
    let _ = writeln!(out, " bound |");
    let _ = write!(out, "|---|");
    for _ in &names {
        let _ = write!(out, "---|---|");
    }
    let _ = writeln!(out, "---|");
    for c in &coefs {
        let _ = write!(out, "| {c} |");
        let mut bound = f64::NAN;
        for n in &names {
            let f = &s.filters[*n];
            let _ = write!(
                out,
                " {} | {} |",
                g(*f.final_rms.get(c).unwrap_or(&f64::NAN)),
                g(*f.final_sigma.get(c).unwrap_or(&f64::NAN))
            );
            bound = *f.final_bound.get(c).unwrap_or(&f64::NAN);
        }
        let _ = writeln!(out, " {} |", g(bound));
    }
    let _ = writeln!(
        out,
        "\n| filter | runs ok | diverged | NEES (95 % bounds) | NIS (95 % bounds) | step median | step p90 |"
    );
    let _ = writeln!(out, "|---|---|---|---|---|---|---|");
    for n in &names {
        let f = &s.filters[*n];
        let _ = writeln!(
            out,
            "| {n} | {} | {} | {:.2} ({:.2}-{:.2}) | {:.3} ({:.3}-{:.3}) | {:.1} us | {:.1} us |",
            f.runs_ok,
            f.diverged,
            f.nees_mean,
            f.nees_bounds[0],
            f.nees_bounds[1],
            f.nis_mean,
            f.nis_bounds[0],
            f.nis_bounds[1],
            f.step_ns_median / 1e3,
            f.step_ns_p90 / 1e3
        );
    }
    out
}
