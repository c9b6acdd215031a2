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
use crate::stand_ins::{CONSTANCY_ALPHA, NOISE_TERM_ALPHA};
use navkf_report::figure::FigureOutcome;
use navkf_report::markdown::{number, Number, Table};
use std::fmt::Write as _;
use tables::{before_after, fit_table, noise_table, yes_no};
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
        if d.effects.is_empty() && d.suggested.is_empty() {
            String::new()
        } else if d.effects.is_empty() {
            format!(
                " - nothing named; suggested (the findings say why each is not named): {}",
                d.suggested
                    .iter()
                    .map(|e| format!("`{e}`"))
                    .collect::<Vec<_>>()
                    .join(", ")
            )
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
    let mut priors = Table::new(["prior", "one-sigma", "default", "source"]);
    for p in &d.priors {
        priors.row([
            p.name.clone(),
            fmt(p.sigma),
            fmt(p.default),
            format!("{:?}", p.source),
        ]);
    }
    let _ = write!(
        out,
        "## Priors\n\nWhere the diagnosis starts (flags over dataset.toml's [prior] over the defaults, or over the alignment's sigmas for a strapdown dataset without [initial]; see `navkf_dynamics::prior` for their reasons):\n\n{}",
        priors.render()
    );
    if let Some(a) = &d.start_attitude {
        let _ = writeln!(out, "\n{}", a.sentence());
    }
    if !d.widened.is_empty() {
        let mut widened = Table::new(["coefficient", "from", "to", "estimate"]);
        for w in &d.widened {
            widened.row([
                w.name.clone(),
                fmt(w.from),
                fmt(w.to),
                fmt(w.implied_estimate),
            ]);
        }
        let _ = write!(
            out,
            "\nWidened in the final model, because the data pulled the coefficient beyond its prior:\n\n{}",
            widened.render()
        );
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
        let mut ranking = Table::new([
            "effect",
            "kind",
            "dLL (maximised)",
            "parameters",
            "BIC gain",
            "excess NIS removed",
            "NIS with it",
            "consistent with it",
            "outcome",
            "cannot be told apart from",
        ]);
        for c in &r.candidates {
            ranking.row([
                c.effect.clone(),
                match c.kind {
                    CandidateKind::Structured => "structured",
                    CandidateKind::NoiseOnly => "noise only",
                    CandidateKind::NoiseLevels => crate::candidates::NOISE_LEVELS,
                }
                .to_string(),
                number(c.delta_loglik, Number::Fixed(1)),
                c.parameters.to_string(),
                number(c.bic_gain, Number::Fixed(1)),
                number(c.excess_removed, Number::Percent(0)),
                number(c.nis.mean, Number::Fixed(3)),
                yes_no(c.consistent).to_string(),
                outcome_words(c.outcome),
                c.confused_with
                    .iter()
                    .map(|p| {
                        format!(
                            "{} ~ {} ({})",
                            p.coefficient,
                            p.with,
                            number(p.correlation, Number::SignedFixed(2))
                        )
                    })
                    .collect::<Vec<_>>()
                    .join(", "),
            ]);
        }
        out.push_str(&ranking.render());
        let mut coefficients = Table::new([
            "effect",
            "coefficient",
            "estimate",
            "sigma",
            "prior tested with",
            "true",
        ]);
        for c in &r.candidates {
            for k in &c.coefficients {
                coefficients.row([
                    c.effect.clone(),
                    k.name.clone(),
                    fmt(k.estimate),
                    fmt(k.sigma),
                    fmt(k.prior_sigma),
                    k.truth.map(fmt).unwrap_or("-".into()),
                ]);
            }
            if let Some(q) = c.density {
                coefficients.row([
                    c.effect.clone(),
                    "density (fitted)".to_string(),
                    fmt(q),
                    "-".to_string(),
                    "-".to_string(),
                    "-".to_string(),
                ]);
            }
        }
        let _ = write!(out, "\n{}", coefficients.render());
        for n in &r.notes {
            let _ = writeln!(out, "\n{n}");
        }
    }
    if !d.constancy.is_empty() {
        let mut constancy = Table::new([
            "effect",
            "coefficient",
            "statistic",
            "dof",
            "p",
            "effect p",
            "constant",
        ]);
        for (e, c) in &d.constancy {
            match c {
                None => constancy.row([
                    e.as_str(),
                    "-",
                    "-",
                    "-",
                    "-",
                    "-",
                    "not testable (too little information, or a half could not be fitted)",
                ]),
                Some(c) => {
                    for (name, stat, dof, p) in &c.coefficients {
                        constancy.row([
                            e.clone(),
                            name.clone(),
                            number(*stat, Number::Fixed(1)),
                            dof.to_string(),
                            number(*p, Number::Sci(2)),
                            number(c.p_value, Number::Sci(2)),
                            if c.constant { "yes" } else { "**no**" }.to_string(),
                        ]);
                    }
                }
            }
        }
        let _ = write!(
            out,
            "\n## Are the named coefficients constants?\n\nThe final model refitted on each half of the record, the second half resuming where the first ended; each coefficient's two estimates compared, and a noise term's density by the likelihood ratio of one density for the whole record against one for each half (chi-square, one degree of freedom; an effect fails below p = {:.0e}, Bonferroni over its coefficients, a noise term below p = {}):\n\n{}",
            CONSTANCY_ALPHA,
            NOISE_TERM_ALPHA,
            constancy.render()
        );
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
            let _ = writeln!(out, "{}", f.markdown(3));
        }
    }
    out
}
