//! The diagnosis in words and as `report.md`: [`findings()`] says what it found, in order;
//! [`markdown`] writes the report with every round's ranking, the noise checks, the priors,
//! the constancy tests and the final model's tables. Both only read the typed
//! [`crate::diagnosis::Diagnosis`].

pub mod findings;
pub mod sentences;
pub mod tables;
pub mod words;

pub use findings::findings;

use crate::candidates::evidence::CandidateKind;
use crate::diagnosis::{Diagnosis, RoundKind};
use crate::stand_ins::CONSTANCY_ALPHA;
use navkf_report::figure::FigureOutcome;
use std::fmt::Write as _;
use tables::{before_after, fit_table, noise_table};
use words::{fmt, outcome_words};

/// `report.md` of a diagnosis, linking the figures drawn next to it (and saying which could
/// not be drawn, and why).
pub fn markdown(d: &Diagnosis, command: &str, figures: &[FigureOutcome]) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "# Diagnosis of `{}`\n", d.dataset);
    let _ = writeln!(out, "Command: `{command}`\n");
    if d.attitude != navkf_dynamics::Attitude::SmallAngle {
        let _ = writeln!(out, "Attitude equations of every fit: {}.\n", d.attitude);
    }
    if !d.implausible.is_empty() {
        let _ = writeln!(
            out,
            "**The data cannot be what they claim: no effect is named. Fix these first.**\n"
        );
        for i in &d.implausible {
            let _ = writeln!(out, "- IMPLAUSIBLE {i}");
        }
        let _ = writeln!(out);
    }
    if !d.data_warnings.is_empty() {
        let _ = writeln!(
            out,
            "**The data look wrong: the verdict below stands on them. Check these first.**\n"
        );
        for w in &d.data_warnings {
            let _ = writeln!(out, "- WARNING {w}");
        }
        let _ = writeln!(out);
    }
    let _ = writeln!(
        out,
        "**Verdict: {}**{}\n",
        d.verdict,
        if d.effects.is_empty() {
            String::new()
        } else {
            format!(
                " - missing effects, in the order named: {}",
                d.effects
                    .iter()
                    .map(|e| format!("`{e}`"))
                    .collect::<Vec<_>>()
                    .join(", ")
            )
        }
    );
    // The implausibilities were listed above; the findings repeat them first.
    for f in d.findings.iter().skip(d.implausible.len()) {
        let _ = writeln!(out, "- {f}");
    }
    if !d.noise_checks.is_empty() {
        let _ = writeln!(out, "\n## Noise levels\n");
        let n = d.noise_checks.len();
        for (i, c) in d.noise_checks.iter().enumerate() {
            let title = if n == 1 {
                "The noise check".to_string()
            } else {
                format!("Noise check {} of {n}", i + 1)
            };
            noise_table(&mut out, c, &title);
        }
    }
    let _ = writeln!(
        out,
        "## Priors\n\nWhere the diagnosis starts (flags over dataset.toml's [prior] over the defaults; see `navkf_dynamics::prior` for their reasons):\n\n| prior | one-sigma | default | source |\n|---|---|---|---|"
    );
    for p in &d.priors {
        let _ = writeln!(
            out,
            "| {} | {} | {} | {:?} |",
            p.name,
            fmt(p.sigma),
            fmt(p.default),
            p.source
        );
    }
    if !d.widened.is_empty() {
        let _ = writeln!(
            out,
            "\nWidened in the final model, because the data pulled the coefficient beyond its prior:\n\n| coefficient | from | to | estimate |\n|---|---|---|---|"
        );
        for w in &d.widened {
            let _ = writeln!(
                out,
                "| {} | {} | {} | {} |",
                w.name,
                fmt(w.from),
                fmt(w.to),
                fmt(w.implied_estimate)
            );
        }
    }
    for (k, r) in d.rounds.iter().enumerate() {
        let _ = writeln!(
            out,
            "\n## Round {} ({})\n\nModel: {}. NIS {:.3} ({}), {}.\n",
            k + 1,
            match r.kind {
                RoundKind::Manual => "manual, --with",
                RoundKind::Automatic => "automatic",
            },
            if r.model.is_empty() {
                "base".to_string()
            } else {
                format!("base + {}", r.model.join(", "))
            },
            r.nis.mean,
            r.nis.verdict,
            if r.consistent {
                "consistent"
            } else {
                "inconsistent"
            }
        );
        let _ = writeln!(
            out,
            "| effect | kind | dLL (maximised) | parameters | BIC gain | excess NIS removed | NIS with it | consistent with it | outcome | cannot be told apart from |\n|---|---|---|---|---|---|---|---|---|---|"
        );
        for c in &r.candidates {
            let _ = writeln!(
                out,
                "| {} | {} | {:.1} | {} | {:.1} | {:.0} % | {:.3} | {} | {} | {} |",
                c.effect,
                match c.kind {
                    CandidateKind::Structured => "structured",
                    CandidateKind::NoiseOnly => "noise only",
                    CandidateKind::NoiseLevels => crate::candidates::NOISE_LEVELS,
                },
                c.delta_loglik,
                c.parameters,
                c.bic_gain,
                100.0 * c.excess_removed,
                c.nis.mean,
                if c.consistent { "yes" } else { "no" },
                outcome_words(c.outcome),
                c.confused_with
                    .iter()
                    .map(|p| format!("{} ~ {} ({:+.2})", p.coefficient, p.with, p.correlation))
                    .collect::<Vec<_>>()
                    .join(", ")
            );
        }
        let _ = writeln!(
            out,
            "\n| effect | coefficient | estimate | sigma | prior tested with | true |\n|---|---|---|---|---|---|"
        );
        for c in &r.candidates {
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
            if let Some(q) = c.density {
                let _ = writeln!(
                    out,
                    "| {} | density (fitted) | {} | - | - | - |",
                    c.effect,
                    fmt(q)
                );
            }
        }
        for n in &r.notes {
            let _ = writeln!(out, "\n{n}");
        }
    }
    if !d.constancy.is_empty() {
        let _ = writeln!(
            out,
            "\n## Are the named coefficients constants?\n\nThe final model refitted on each half of the record; each coefficient's two estimates compared (chi-square, one degree of freedom; the effect fails below p = {:.0e}, Bonferroni over its coefficients):\n\n| effect | coefficient | statistic | dof | p | effect p | constant |\n|---|---|---|---|---|---|---|",
            CONSTANCY_ALPHA
        );
        for (e, c) in &d.constancy {
            match c {
                None => {
                    let _ = writeln!(
                        out,
                        "| {e} | - | - | - | - | - | not testable (too little information) |"
                    );
                }
                Some(c) => {
                    for (name, stat, dof, p) in &c.coefficients {
                        let _ = writeln!(
                            out,
                            "| {e} | {name} | {stat:.1} | {dof} | {p:.2e} | {:.2e} | {} |",
                            c.p_value,
                            if c.constant { "yes" } else { "**no**" }
                        );
                    }
                }
            }
        }
    }
    if let Some(b) = &d.before {
        before_after(&mut out, b, &d.model);
    }
    let _ = writeln!(out, "\n## The final model\n");
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
