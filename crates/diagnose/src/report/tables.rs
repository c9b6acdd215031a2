//! The tables of `report.md` that show one fit, a fit before and after the named effects,
//! and one noise check, written with the one Markdown writer ([`navkf_report::markdown`]).

use super::words::fmt;
use crate::consistency::Whiteness;
use crate::noise::levels::{NoiseFit, NoiseVerdict};
use crate::summary::{Coefficient, FitSummary};
use navkf_report::markdown::{number, Number, Table};
use std::fmt::Write as _;

/// `a-b`, each written as `format` says (a band or an interval).
pub fn range(a: f64, b: f64, format: Number) -> String {
    format!("{}-{}", number(a, format), number(b, format))
}

/// `yes` or `no`.
pub fn yes_no(b: bool) -> &'static str {
    if b {
        "yes"
    } else {
        "no"
    }
}

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
    let mut channels = Table::new([
        "channel",
        "white",
        "Ljung-Box (critical)",
        "mean",
        "variance",
        "slow drift: block-sum variance (critical)",
    ]);
    for w in &f.whiteness {
        channels.row([
            w.channel.to_string(),
            yes_no(w.white).to_string(),
            format!(
                "{} ({})",
                number(w.ljung_box, Number::Fixed(1)),
                number(w.critical, Number::Fixed(1))
            ),
            number(w.mean, Number::SignedFixed(3)),
            number(w.variance, Number::Fixed(3)),
            format!(
                "{} ({})",
                number(w.block_variance, Number::Fixed(2)),
                number(w.block_critical, Number::Fixed(2))
            ),
        ]);
    }
    out.push_str(&channels.render());
    let mut phases = Table::new(["phase", "updates", "NIS", "bounds", "verdict"]);
    for (p, s) in &f.nis_by_phase {
        phases.row([
            p.to_string(),
            s.count.to_string(),
            number(s.mean, Number::Fixed(3)),
            range(s.bounds[0], s.bounds[1], Number::Fixed(3)),
            s.verdict.to_string(),
        ]);
    }
    let _ = write!(out, "\n{}", phases.render());
    let has_truth = f.coefficients.iter().any(|c| c.truth.is_some());
    let mut header = vec!["coefficient", "estimate", "sigma", "prior tested with"];
    if has_truth {
        header.extend(["true", "error / sigma"]);
    }
    let mut coefficients = Table::new(header);
    for c in &f.coefficients {
        // A wandering state's estimate is its value at the end, not a constant's; a held
        // one stays at zero whatever the data (its row shows that, and no error).
        let name = if c.wanders {
            format!("{} (wanders; at the end)", c.name)
        } else if c.held {
            format!("{} (held at zero)", c.name)
        } else {
            c.name.clone()
        };
        let mut row = vec![name, fmt(c.estimate), fmt(c.sigma), fmt(c.prior_sigma)];
        if has_truth {
            match c.truth.filter(|_| !c.held) {
                Some(t) => row.extend([
                    fmt(t),
                    number((c.estimate - t) / c.sigma, Number::SignedFixed(2)),
                ]),
                None => row.extend(["-".to_string(), "-".to_string()]),
            }
        }
        coefficients.row(row);
    }
    let _ = writeln!(out, "\n{}", coefficients.render());
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
    let mut table = Table::new(["", "before", "after"]);
    table.row([
        "log-likelihood".to_string(),
        number(b.loglik, Number::Fixed(1)),
        number(a.loglik, Number::Fixed(1)),
    ]);
    let nis = |f: &FitSummary| {
        format!(
            "{} ({}, bounds {})",
            number(f.nis.mean, Number::Fixed(3)),
            f.nis.verdict,
            range(f.nis.bounds[0], f.nis.bounds[1], Number::Fixed(3))
        )
    };
    table.row(["NIS".to_string(), nis(b), nis(a)]);
    table.row([
        "consistent".to_string(),
        yes_no(b.consistent).to_string(),
        yes_no(a.consistent).to_string(),
    ]);
    for wa in &a.whiteness {
        let white = |w: &Whiteness| {
            format!(
                "{} (Ljung-Box {}, variance {})",
                if w.white { "white" } else { "not white" },
                number(w.ljung_box, Number::Fixed(0)),
                number(w.variance, Number::Fixed(2))
            )
        };
        let wb = b
            .whiteness
            .iter()
            .find(|w| w.channel == wa.channel)
            .map_or("-".to_string(), white);
        table.row([wa.channel.to_string(), wb, white(wa)]);
    }
    out.push_str(&table.render());
    // A held coefficient is not estimated: no error to judge.
    let err = |c: &Coefficient| {
        c.truth
            .filter(|_| !c.held)
            .map(|t| (c.estimate - t) / c.prior_sigma)
    };
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
        let cell = |v: Option<f64>| {
            v.map_or("not in the model".to_string(), |e| {
                number(e, Number::SignedFixed(3))
            })
        };
        let mut errors = Table::new(["coefficient", "before", "after"]);
        for (name, eb, ea) in &rows {
            errors.row([name.clone(), cell(*eb), cell(*ea)]);
        }
        let rms = |f: fn(&ErrorRow) -> Option<f64>| {
            let v: Vec<f64> = rows.iter().filter_map(f).collect();
            (v.iter().map(|e| e * e).sum::<f64>() / v.len().max(1) as f64).sqrt()
        };
        errors.row([
            "RMS over the coefficients each has".to_string(),
            number(rms(|r| r.1), Number::Fixed(3)),
            number(rms(|r| r.2), Number::Fixed(3)),
        ]);
        let _ = write!(
            out,
            "\nCoefficient errors against truth.csv, (estimate - truth) / prior sigma:\n\n{}",
            errors.render()
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
    let kv = |m: &std::collections::BTreeMap<String, f64>| {
        m.iter()
            .map(|(k, v)| format!("{k} = {}", number(*v, Number::Sci(3))))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let mut table = Table::new([
        "source",
        "stated",
        "fitted (maximum likelihood)",
        "fitted / stated (sigma)",
        "95 %",
        "verdict",
    ]);
    for s in &check.sources {
        table.row([
            s.source.label().to_string(),
            kv(&s.stated),
            kv(&s.fitted),
            number(s.sigma_ratio, Number::Fixed(3)),
            range(
                s.sigma_ratio_interval[0],
                s.sigma_ratio_interval[1],
                Number::Fixed(3),
            ),
            match s.verdict {
                NoiseVerdict::Fits => "fits",
                NoiseVerdict::UnderStated => "under-stated",
                NoiseVerdict::OverStated => "over-stated",
                NoiseVerdict::Unresolved => "unresolved",
            }
            .to_string(),
        ]);
    }
    let _ = writeln!(out, "{}", table.render());
}
