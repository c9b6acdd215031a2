//! The diagnosis in words and as `report.md`.

use super::{Candidate, Diagnosis, FitSummary, DECISIVE_BIC};
use crate::plots::FigureOutcome;
use std::fmt::Write as _;

fn fmt(v: f64) -> String {
    if v.is_finite() {
        format!("{v:.4e}")
    } else {
        "-".into()
    }
}

/// Plain-language findings: which channels and phases are inconsistent, which effect the
/// evidence supports, and which effects cannot be told apart.
pub fn findings(model: &FitSummary, cands: &[Candidate], best: Option<&str>) -> Vec<String> {
    let mut out = Vec::new();
    if let Some(f) = &model.failure {
        out.push(format!("The filter failed on this model: {f}."));
    }
    let n = &model.nis;
    out.push(format!(
        "NIS averages {:.3} against an expected {:.2} (95 % bounds {:.3}-{:.3}): {}.",
        n.mean,
        n.dof,
        n.bounds[0],
        n.bounds[1],
        match n.verdict.as_str() {
            "inside" => "consistent",
            "above" => "the innovations are larger than the model predicts",
            "below" => "the innovations are smaller than the model predicts (noise set too high?)",
            _ => "no data",
        }
    ));
    let bad_channels: Vec<String> = model
        .whiteness
        .iter()
        .filter(|w| w.count > 0 && !w.white)
        .map(|w| format!("{} ({})", w.channel, w.problems.join(", ")))
        .collect();
    if bad_channels.is_empty() {
        out.push("Every channel's innovations are white.".into());
    } else {
        out.push(format!(
            "Inconsistent channels: {}.",
            bad_channels.join("; ")
        ));
    }
    let bad_phases: Vec<String> = model
        .nis_by_phase
        .iter()
        .filter(|(_, s)| s.verdict != "inside" && s.count > 0)
        .map(|(p, s)| {
            format!(
                "{p} (NIS {:.2}, {} updates, {})",
                s.mean, s.count, s.verdict
            )
        })
        .collect();
    if !bad_phases.is_empty() {
        out.push(format!(
            "Phases where NIS leaves its bounds: {}.",
            bad_phases.join("; ")
        ));
    }
    match best {
        Some(b) => {
            let c = cands
                .iter()
                .find(|c| c.effect == b)
                .expect("best is a candidate");
            out.push(format!(
                "The evidence supports adding `{b}`: log-likelihood +{:.1}, BIC gain {:.1}, it removes {:.0} % of the excess NIS{}.",
                c.delta_loglik,
                c.bic_gain,
                100.0 * c.excess_removed,
                if c.consistent { " and makes the innovations consistent" } else { "; misfit remains, so diagnose again with it added" }
            ));
        }
        None => {
            if !model.consistent {
                // A candidate with decisive evidence that the trajectory cannot separate from
                // the model's coefficients may be the cause: the data cannot say. One without
                // decisive evidence is ruled out whatever the split (adding it did not help).
                let strong: Vec<String> = cands
                    .iter()
                    .filter(|c| c.bic_gain > DECISIVE_BIC && !c.confused_with.is_empty())
                    .map(|c| format!("`{}`", c.effect))
                    .collect();
                if strong.is_empty() {
                    out.push(format!(
                        "No catalogued effect explains the misfit: none has decisive evidence (BIC gain > {DECISIVE_BIC}) and repairs it (consistent innovations, or 90 % of the excess NIS removed). The cause is outside the catalogue, or too small to attribute on this dataset."
                    ));
                } else {
                    out.push(format!(
                        "No catalogued effect can be named: {} has decisive evidence but cannot be told apart from coefficients already in the model on this trajectory (see below), so the data cannot say whether it or those coefficients carry the misfit. A trajectory that separates them (for `gyro-fz`, one with varying vertical specific force) would.",
                        strong.join(", ")
                    ));
                }
            }
        }
    }
    for c in cands {
        if !c.supported && c.bic_gain > DECISIVE_BIC && c.confused_with.is_empty() {
            out.push(format!(
                "`{}` improves the likelihood (BIC gain {:.0}) but removes only {:.0} % of the excess NIS{}: it is not the cause, or not the only one.",
                c.effect,
                c.bic_gain,
                100.0 * c.excess_removed,
                if c.coefficients.is_empty() { " (it only adds process noise, which can soak up any slow misfit)" } else { "" }
            ));
        }
        // Said whatever the evidence: an effect the trajectory cannot separate is absorbed
        // into the model's own coefficients, so its absence from the ranking proves nothing.
        if !c.confused_with.is_empty() {
            let pairs: Vec<String> = c
                .confused_with
                .iter()
                .map(|(p, r)| format!("{p} (correlation {r:+.2})"))
                .collect();
            out.push(format!(
                "`{}` cannot be told apart from coefficients already in the model on this trajectory: {}. If present, it is absorbed into them (their estimates then carry it).",
                c.effect,
                pairs.join(", ")
            ));
        }
    }
    out
}

fn fit_table(out: &mut String, title: &str, f: &FitSummary) {
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
        "| channel | white | Ljung-Box (99 % critical) | mean | variance |\n|---|---|---|---|---|"
    );
    for w in &f.whiteness {
        let _ = writeln!(
            out,
            "| {} | {} | {:.1} ({:.1}) | {:+.3} | {:.3} |",
            w.channel,
            if w.white { "yes" } else { "no" },
            w.ljung_box,
            w.critical,
            w.mean,
            w.variance
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
    let _ = write!(out, "\n| coefficient | estimate | sigma | initial sigma |");
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
/// each coefficient's error in units of its final sigma, side by side.
fn before_after(out: &mut String, b: &FitSummary, a: &FitSummary) {
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
        let white = |w: &super::Whiteness| {
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
    let err = |c: &super::Coefficient| c.truth.map(|t| (c.estimate - t) / c.prior_sigma);
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
            "\nCoefficient errors against truth.csv, (estimate - truth) / initial sigma:\n\n| coefficient | before | after |\n|---|---|---|"
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

/// `report.md` of a diagnosis, linking the figures drawn next to it (and saying which could
/// not be drawn, and why).
pub fn markdown(d: &Diagnosis, command: &str, figures: &[FigureOutcome]) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "# Diagnosis of `{}`\n", d.dataset);
    let _ = writeln!(out, "Command: `{command}`\n");
    let _ = writeln!(
        out,
        "**Verdict: {}**{}\n",
        d.verdict,
        d.best
            .as_ref()
            .map(|b| format!(" - missing effect: `{b}`"))
            .unwrap_or_default()
    );
    for f in &d.findings {
        let _ = writeln!(out, "- {f}");
    }
    let _ = writeln!(out, "\n## Candidates (best first)\n");
    let _ = writeln!(
        out,
        "| effect | delta loglik | BIC gain | excess NIS removed | consistent with it | named | cannot be told apart from |\n|---|---|---|---|---|---|---|"
    );
    for c in &d.candidates {
        let _ = writeln!(
            out,
            "| {} | {:.1} | {:.1} | {:.0} % | {} | {} | {} |",
            c.effect,
            c.delta_loglik,
            c.bic_gain,
            100.0 * c.excess_removed,
            if c.consistent { "yes" } else { "no" },
            if c.supported { "yes" } else { "no" },
            c.confused_with
                .iter()
                .map(|(p, r)| format!("{p} ({r:+.2})"))
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    let _ = writeln!(out, "\nCandidate coefficients:\n\n| effect | coefficient | estimate | sigma | initial sigma | true |\n|---|---|---|---|---|---|");
    for c in &d.candidates {
        for k in &c.coefficients {
            let _ = writeln!(
                out,
                "| {} | {} | {} | {} | {} | {} |",
                c.effect,
                k.name,
                fmt(k.estimate),
                fmt(k.sigma),
                fmt(k.prior_sigma),
                k.truth.map(fmt).unwrap_or("-".into())
            );
        }
    }
    if let Some(b) = &d.before {
        before_after(&mut out, b, &d.model);
    }
    let _ = writeln!(out, "\n## The model under test\n");
    fit_table(&mut out, "After", &d.model);
    if let Some(b) = &d.before {
        fit_table(&mut out, "Before (base model)", b);
    }
    if !figures.is_empty() {
        let _ = writeln!(out, "## Figures\n");
        for f in figures {
            match &f.result {
                Ok(()) => {
                    let _ = writeln!(
                        out,
                        "### {}\n\n![{}]({}.png)\n",
                        f.caption, f.caption, f.name
                    );
                }
                Err(e) => {
                    let _ = writeln!(out, "### {}\n\nNot drawn: {e}\n", f.caption);
                }
            }
        }
    }
    out
}
