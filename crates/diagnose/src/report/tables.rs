//! The tables of `report.md` that show one fit, a fit before and after the named effects,
//! and one noise check.

use super::words::fmt;
use crate::consistency::Whiteness;
use crate::noise::levels::{NoiseFit, NoiseVerdict};
use crate::summary::{Coefficient, FitSummary};
use std::fmt::Write as _;

pub fn fit_table(out: &mut String, title: &str, f: &FitSummary) {
    let _ = writeln!(out, "### {title}\n");
    let _ = writeln!(
        out,
        "Effects: {}. Log-likelihood {:.1}. NIS {:.3} (expected {:.2}, 95 % bounds {:.3}-{:.3}, {}).\n",
        if f.effects.is_empty() { "none (base model)".to_string() } else { f.effects.join(", ") },
        f.loglik,
        f.nis.mean,
        f.nis.dof,
        f.nis.bounds[0],
        f.nis.bounds[1],
        f.nis.verdict
    );
    let _ = writeln!(
        out,
        "| channel | white | Ljung-Box (critical) | mean | variance | slow drift: block-sum variance (critical) |\n|---|---|---|---|---|---|"
    );
    for w in &f.whiteness {
        let _ = writeln!(
            out,
            "| {} | {} | {:.1} ({:.1}) | {:+.3} | {:.3} | {:.2} ({:.2}) |",
            w.channel,
            if w.white { "yes" } else { "no" },
            w.ljung_box,
            w.critical,
            w.mean,
            w.variance,
            w.block_variance,
            w.block_critical
        );
    }
    let _ = writeln!(
        out,
        "\n| phase | updates | NIS | bounds | verdict |\n|---|---|---|---|---|"
    );
    for (p, s) in &f.nis_by_phase {
        let _ = writeln!(
            out,
            "| {p} | {} | {:.3} | {:.3}-{:.3} | {} |",
            s.count, s.mean, s.bounds[0], s.bounds[1], s.verdict
        );
    }
    let has_truth = f.coefficients.iter().any(|c| c.truth.is_some());
    let _ = write!(
        out,
        "\n| coefficient | estimate | sigma | prior tested with |"
    );
    if has_truth {
        let _ = write!(out, " true | error / sigma |");
    }
    let _ = writeln!(out);
    let _ = writeln!(
        out,
        "|---|---|---|---|{}",
        if has_truth { "---|---|" } else { "" }
    );
    for c in &f.coefficients {
        let _ = write!(
            out,
            "| {} | {} | {} | {} |",
            c.name,
            fmt(c.estimate),
            fmt(c.sigma),
            fmt(c.prior_sigma)
        );
        if has_truth {
            match c.truth {
                Some(t) => {
                    let _ = write!(out, " {} | {:+.2} |", fmt(t), (c.estimate - t) / c.sigma);
                }
                None => {
                    let _ = write!(out, " - | - |");
                }
            }
        }
        let _ = writeln!(out);
    }
    let _ = writeln!(out);
}

/// A coefficient's name and its normalised errors before and after.
type ErrorRow = (String, Option<f64>, Option<f64>);

/// The before/after table: log-likelihood, NIS, each channel's whiteness and, with a truth,
/// each coefficient's error in units of its prior sigma, side by side.
pub fn before_after(out: &mut String, b: &FitSummary, a: &FitSummary) {
    let _ = writeln!(
        out,
        "\n## Before and after\n\nBefore: the base model. After: with {}.\n",
        a.effects.join(", ")
    );
    let _ = writeln!(out, "| | before | after |\n|---|---|---|");
    let _ = writeln!(
        out,
        "| log-likelihood | {:.1} | {:.1} |",
        b.loglik, a.loglik
    );
    let nis = |f: &FitSummary| {
        format!(
            "{:.3} ({}, bounds {:.3}-{:.3})",
            f.nis.mean, f.nis.verdict, f.nis.bounds[0], f.nis.bounds[1]
        )
    };
    let _ = writeln!(out, "| NIS | {} | {} |", nis(b), nis(a));
    let _ = writeln!(
        out,
        "| consistent | {} | {} |",
        if b.consistent { "yes" } else { "no" },
        if a.consistent { "yes" } else { "no" }
    );
    for wa in &a.whiteness {
        let white = |w: &Whiteness| {
            format!(
                "{} (Ljung-Box {:.0}, variance {:.2})",
                if w.white { "white" } else { "not white" },
                w.ljung_box,
                w.variance
            )
        };
        let wb = b
            .whiteness
            .iter()
            .find(|w| w.channel == wa.channel)
            .map_or("-".to_string(), white);
        let _ = writeln!(out, "| {} | {} | {} |", wa.channel, wb, white(wa));
    }
    let err = |c: &Coefficient| c.truth.map(|t| (c.estimate - t) / c.prior_sigma);
    let rows: Vec<ErrorRow> = a
        .coefficients
        .iter()
        .map(|ca| {
            let eb = b
                .coefficients
                .iter()
                .find(|c| c.name == ca.name)
                .and_then(err);
            (ca.name.clone(), eb, err(ca))
        })
        .filter(|r| r.1.is_some() || r.2.is_some())
        .collect();
    if !rows.is_empty() {
        let cell =
            |v: Option<f64>| v.map_or("not in the model".to_string(), |e| format!("{e:+.3}"));
        let _ = writeln!(
            out,
            "\nCoefficient errors against truth.csv, (estimate - truth) / prior sigma:\n\n| coefficient | before | after |\n|---|---|---|"
        );
        for (name, eb, ea) in &rows {
            let _ = writeln!(out, "| {name} | {} | {} |", cell(*eb), cell(*ea));
        }
        let rms = |f: fn(&ErrorRow) -> Option<f64>| {
            let v: Vec<f64> = rows.iter().filter_map(f).collect();
            (v.iter().map(|e| e * e).sum::<f64>() / v.len().max(1) as f64).sqrt()
        };
        let _ = writeln!(
            out,
            "| RMS over the coefficients each has | {:.3} | {:.3} |",
            rms(|r| r.1),
            rms(|r| r.2)
        );
    }
}

pub fn noise_table(out: &mut String, check: &NoiseFit, title: &str) {
    let _ = writeln!(
        out,
        "{title} (on the model {}; {} filter passes; log-likelihood gain of the fitted levels {:.1}):\n",
        if check.model.is_empty() {
            "without effects".to_string()
        } else {
            format!("with {}", check.model.join(", "))
        },
        check.passes,
        check.loglik_gain
    );
    let _ = writeln!(
        out,
        "| source | stated | fitted (maximum likelihood) | fitted / stated (sigma) | 95 % | verdict |\n|---|---|---|---|---|---|"
    );
    let kv = |m: &std::collections::BTreeMap<String, f64>| {
        m.iter()
            .map(|(k, v)| format!("{k} = {v:.3e}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    for s in &check.sources {
        let _ = writeln!(
            out,
            "| {} | {} | {} | {:.3} | {:.3}-{:.3} | {} |",
            s.source.label(),
            kv(&s.stated),
            kv(&s.fitted),
            s.sigma_ratio,
            s.sigma_ratio_interval[0],
            s.sigma_ratio_interval[1],
            match s.verdict {
                NoiseVerdict::Fits => "fits",
                NoiseVerdict::UnderStated => "under-stated",
                NoiseVerdict::OverStated => "over-stated",
                NoiseVerdict::Unresolved => "unresolved",
            }
        );
    }
    let _ = writeln!(out);
}
