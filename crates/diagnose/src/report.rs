//! The diagnosis in words and as `report.md`.

use super::candidates::{Candidate, CandidateKind, Outcome, DECISIVE_BIC};
use super::noise::{NoiseFit, NoiseVerdict};
use super::{Diagnosis, FitSummary, RoundKind, Verdict};
use navkf_report::figure::FigureOutcome;
use navkf_report::stats::Consistency;
use std::fmt::Write as _;

fn fmt(v: f64) -> String {
    if v.is_finite() {
        format!("{v:.4e}")
    } else {
        "-".into()
    }
}

/// A sigma ratio in words: "12x", "1.3x", "0.2x".
fn times(r: f64) -> String {
    if r >= 10.0 {
        format!("{r:.0}x")
    } else if r >= 0.1 {
        format!("{r:.2}x")
    } else {
        format!("{r:.1e}x")
    }
}

/// The noise findings of a check: mis-stated sources in words with their fitted levels, and
/// sources the data cannot resolve.
fn noise_findings(check: &NoiseFit, out: &mut Vec<String>) {
    for s in &check.sources {
        let keys = |m: &std::collections::BTreeMap<String, f64>| {
            m.iter()
                .map(|(k, v)| format!("{k} = {v:.3e}"))
                .collect::<Vec<_>>()
                .join(", ")
        };
        let [lo, hi] = s.sigma_ratio_interval;
        match s.verdict {
            NoiseVerdict::UnderStated | NoiseVerdict::OverStated => {
                let (word, r) = if s.verdict == NoiseVerdict::UnderStated {
                    ("under-stated", s.sigma_ratio)
                } else {
                    ("over-stated", 1.0 / s.sigma_ratio)
                };
                out.push(format!(
                    "{} {word} about {} (in sigma; the data put it at {}-{} of the stated level): \
                     fitted {} (stated {}). The diagnosis uses the fitted level.",
                    capitalise(s.source.label()),
                    times(r),
                    times(lo),
                    times(hi),
                    keys(&s.fitted),
                    keys(&s.stated)
                ));
            }
            NoiseVerdict::Unresolved => out.push(format!(
                "The data cannot fix the {} level: anything from {} to {} of the stated one \
                 fits (95 %). The stated level is kept.",
                s.source.label(),
                times(lo),
                times(hi)
            )),
            NoiseVerdict::Fits => {}
        }
    }
}

fn capitalise(s: &str) -> String {
    let mut c = s.chars();
    c.next()
        .map(|f| f.to_uppercase().collect::<String>() + c.as_str())
        .unwrap_or_default()
}

/// What a model's summary says of its consistency: NIS, failing channels and phases.
fn consistency_findings(m: &FitSummary, out: &mut Vec<String>) {
    if let Some(f) = &m.failure {
        out.push(format!("The filter failed on this model: {f}."));
    }
    let n = &m.nis;
    out.push(format!(
        "NIS averages {:.3} against an expected {:.2} (95 % bounds {:.3}-{:.3}): {}.",
        n.mean,
        n.dof,
        n.bounds[0],
        n.bounds[1],
        match n.verdict {
            Consistency::Consistent => "consistent",
            Consistency::Optimistic => "the innovations are larger than the model predicts",
            Consistency::Pessimistic =>
                "the innovations are smaller than the model predicts (noise set too high?)",
            Consistency::NoVerdict => "no data",
        }
    ));
    out.push(failing_channels_and_phases(m));
}

/// One sentence: which channels and phases fail, or that none does.
fn failing_channels_and_phases(m: &FitSummary) -> String {
    let channels: Vec<String> = m
        .whiteness
        .iter()
        .filter(|w| w.count > 0 && !w.white)
        .map(|w| format!("{} ({})", w.channel, w.problems.join(", ")))
        .collect();
    let phases: Vec<String> = m
        .nis_by_phase
        .iter()
        .filter(|(_, s)| s.verdict != Consistency::Consistent && s.count > 0)
        .map(|(p, s)| {
            format!(
                "{p} (NIS {:.2}, {} updates, {})",
                s.mean, s.count, s.verdict
            )
        })
        .collect();
    let mut s = if channels.is_empty() {
        "Every channel's innovations are white".to_string()
    } else {
        format!("Inconsistent channels: {}", channels.join("; "))
    };
    if !phases.is_empty() {
        s.push_str(&format!(
            "; phases where NIS leaves its bounds: {}",
            phases.join("; ")
        ));
    }
    s.push('.');
    s
}

fn coefficient_words(c: &Candidate) -> String {
    if let Some(q) = c.density {
        return format!("fitted density {q:.2e}");
    }
    c.coefficients
        .iter()
        .map(|k| {
            format!(
                "{} = {:.3e} +- {:.1e} (prior {:.1e})",
                k.name, k.estimate, k.sigma, k.prior_sigma
            )
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// A tilt prior sigma beyond which the diagnosis warns that the small-angle model is out of
/// its depth (0.5 deg: `results/misalignment/` finds its EKF consistent at 0.1 deg and not at
/// 1 deg).
pub const SMALL_ANGLE_LIMIT_RAD: f64 = 8.7e-3;

/// Plain-language findings, in the order a user should read them: the noise, where the model
/// under test fails, what each round named and why, what remains, and what cannot be told.
pub fn findings(d: &Diagnosis) -> Vec<String> {
    if d.verdict == Verdict::ImplausibleData {
        return super::plausible::implausible_findings(d);
    }
    let mut out = Vec::new();
    if !d.noise_stated {
        out.push(
            "dataset.toml states no noise (it is absent, or has no [noise] table): the noise \
             called \"stated\" below is navkf's default for a navigation-grade platform \
             (docs/data-format.md), not a statement of yours. Give your sensors' levels in a \
             [noise] table, or read the noise check as a fit of the levels from the data."
                .to_string(),
        );
    }
    // A misalignment of degrees breaks the small-angle model before anything else: first.
    if d.attitude == navkf_dynamics::Attitude::SmallAngle {
        let large: Vec<String> = d
            .priors
            .iter()
            .filter(|p| {
                matches!(p.name.as_str(), "azimuth_rad" | "level_rad")
                    && p.sigma > SMALL_ANGLE_LIMIT_RAD
            })
            .map(|p| format!("{} = {:.2} deg", p.name, p.sigma.to_degrees()))
            .collect();
        if !large.is_empty() {
            out.push(format!(
                "The tilt prior ({}) allows errors where the small-angle model does not hold \
                 (in studies/misalignment.toml its EKF turns inconsistent from 1 deg of \
                 azimuth sigma and inaccurate from 3 deg), and such a misalignment can pass \
                 for a missing effect. Diagnose again with `--attitude exact`.",
                large.join(", ")
            ));
        }
    }
    // Noise first: a wrong noise level is not a missing effect.
    if let (Some(first), Some(last)) = (d.noise_checks.first(), d.noise_checks.last()) {
        let noise_named = d.rounds.iter().any(|r| {
            r.candidates
                .iter()
                .any(|c| c.kind == CandidateKind::NoiseLevels && c.outcome == Outcome::Named)
        });
        if first.refitted && !noise_named && !last.mis_stated() && !d.effects.is_empty() {
            let looked: Vec<String> = first
                .sources
                .iter()
                .filter(|s| {
                    matches!(
                        s.verdict,
                        NoiseVerdict::UnderStated | NoiseVerdict::OverStated
                    )
                })
                .map(|s| format!("{} {}", s.source.label(), times(s.sigma_ratio)))
                .collect();
            out.push(format!(
                "Before {} was added, the noise looked off ({}); with it the stated noise \
                 fits: the misfit was structural, not noise.",
                d.effects
                    .iter()
                    .map(|e| format!("`{e}`"))
                    .collect::<Vec<_>>()
                    .join(", "),
                looked.join(", ")
            ));
        }
        noise_findings(last, &mut out);
    }
    // The model under test.
    let first_round = d.rounds.first();
    if let Some(r) = first_round {
        let label = if r.model.is_empty() {
            "The base model".to_string()
        } else {
            format!("The model with {}", r.model.join(", "))
        };
        out.push(format!(
            "{label}: NIS {:.3} against {:.2} (95 % bounds {:.3}-{:.3}), {}.",
            r.nis.mean,
            r.nis.dof,
            r.nis.bounds[0],
            r.nis.bounds[1],
            if r.consistent {
                "consistent"
            } else {
                "inconsistent"
            }
        ));
    }
    // What each round named.
    for (k, r) in d.rounds.iter().enumerate() {
        for c in r
            .candidates
            .iter()
            .filter(|c| matches!(c.outcome, Outcome::Named | Outcome::Manual))
        {
            if c.kind == CandidateKind::NoiseLevels {
                let changed: Vec<String> = c
                    .noise
                    .iter()
                    .flat_map(|n| &n.sources)
                    .filter(|s| {
                        matches!(
                            s.verdict,
                            NoiseVerdict::UnderStated | NoiseVerdict::OverStated
                        )
                    })
                    .map(|s| format!("{} x{:.2} in sigma", s.source.label(), s.sigma_ratio))
                    .collect();
                out.push(format!(
                    "Round {}: the noise levels explain the misfit better than any effect: {} \
                     (log-likelihood {:+.1}, BIC gain {:.1}); the next rounds use them.",
                    k + 1,
                    changed.join(", "),
                    c.delta_loglik,
                    c.bic_gain
                ));
                continue;
            }
            let how = if r.kind == RoundKind::Manual {
                "Added by --with"
            } else {
                "The evidence supports adding"
            };
            out.push(format!(
                "Round {}: {how} `{}`: log-likelihood {:+.1}, BIC gain {:.1}, it removes {:.0} % \
                 of the excess NIS ({}).",
                k + 1,
                c.effect,
                c.delta_loglik,
                c.bic_gain,
                100.0 * c.excess_removed,
                coefficient_words(c)
            ));
        }
        for c in r
            .candidates
            .iter()
            .filter(|c| c.outcome == Outcome::Named && !c.confused_with.is_empty())
        {
            let pairs: Vec<String> = c
                .confused_with
                .iter()
                .map(|p| format!("{} ~ {} ({:+.2})", p.coefficient, p.with, p.correlation))
                .collect();
            out.push(format!(
                "Part of `{}` cannot be told apart from the model's own coefficients on this \
                 trajectory: {}. Its other coefficients carry the evidence; these estimates \
                 mean little on their own.",
                c.effect,
                pairs.join(", ")
            ));
        }
        out.extend(r.notes.iter().cloned());
    }
    out.extend(super::plausible::refusal_findings(&d.rounds));
    for w in &d.withdrawn {
        out.push(format!(
            "`{}` was named but its coefficients do not behave as constants over the test \
             (constancy p = {:.1e}): it stood in for something the catalogue lacks, and is \
             withdrawn.",
            w.effect, w.constancy.p_value
        ));
    }
    // Where the final model stands.
    match d.verdict {
        Verdict::Consistent => consistency_findings(&d.model, &mut out),
        Verdict::Explained => out.push(format!(
            "With {} the model is consistent (NIS {:.3}, bounds {:.3}-{:.3}).",
            named_list(d),
            d.model.nis.mean,
            d.model.nis.bounds[0],
            d.model.nis.bounds[1]
        )),
        Verdict::PartlyExplained => out.push(format!(
            "With {} the model fits decisively better, but a misfit remains that nothing in \
             the catalogue explains (NIS {:.3}, bounds {:.3}-{:.3}). {}",
            named_list(d),
            d.model.nis.mean,
            d.model.nis.bounds[0],
            d.model.nis.bounds[1],
            failing_channels_and_phases(&d.model)
        )),
        Verdict::ImplausibleData => {}
        Verdict::Unexplained => {
            consistency_findings(&d.model, &mut out);
            let last = d.rounds.last().map(|r| &r.candidates[..]).unwrap_or(&[]);
            let confounded: Vec<String> = last
                .iter()
                .filter(|c| c.outcome == Outcome::Confounded)
                .map(|c| format!("`{}`", c.effect))
                .collect();
            if let Some(s) = super::plausible::unphysical_instead(last) {
                out.push(s);
            } else if confounded.is_empty() {
                out.push(format!(
                    "No catalogued effect explains the misfit: none has decisive evidence \
                     (BIC gain > {DECISIVE_BIC}) that it can carry on its own. The cause is \
                     outside the catalogue, or too small to attribute on this dataset."
                ));
            } else {
                out.push(format!(
                    "No catalogued effect can be named: {} has decisive evidence but cannot be \
                     told apart from coefficients already in the model on this trajectory \
                     (see below), so the data cannot say whether it or those coefficients carry \
                     the misfit. A trajectory that separates them (for `gyro-fz`, one with \
                     varying vertical specific force) would.",
                    confounded.join(", ")
                ));
            }
        }
    }
    // Last round: what was decisive but not named, and what cannot be told apart.
    if let Some(r) = d
        .rounds
        .iter()
        .rev()
        .find(|r| r.kind == RoundKind::Automatic)
    {
        for c in &r.candidates {
            match c.outcome {
                Outcome::NoiseLeavesMisfit => out.push(format!(
                    "`{}` improves the likelihood (BIC gain {:.0}) but only adds process \
                     noise, which can soak up any slow misfit, and leaves the model \
                     inconsistent: it is not named.",
                    c.effect, c.bic_gain
                )),
                Outcome::Confounded => {
                    let pairs: Vec<String> = c
                        .confused_with
                        .iter()
                        .map(|p| {
                            format!(
                                "{} ~ {} (correlation {:+.2})",
                                p.coefficient, p.with, p.correlation
                            )
                        })
                        .collect();
                    out.push(format!(
                        "`{}` cannot be told apart from coefficients already in the model on \
                         this trajectory: {}. If present, it is absorbed into them (their \
                         estimates then carry it).",
                        c.effect,
                        pairs.join(", ")
                    ));
                }
                _ => {}
            }
        }
    }
    for w in &d.widened {
        if w.implied_estimate.is_nan() {
            out.push(format!(
                "The prior of the initial {} error was widened from {:.2e} to {:.2e} rad: the \
                 data fit decisively better with it. A platform gyrocompassed with drifts far \
                 beyond its priors' starts that far off{}.",
                if w.name == "azimuth_rad" {
                    "azimuth"
                } else {
                    "level"
                },
                w.from,
                w.to,
                if w.to > 0.05 {
                    "; beyond a few degrees the small-angle model itself no longer holds"
                } else {
                    ""
                }
            ));
            continue;
        }
        out.push(if w.at_cap {
            format!(
                "The prior of {} was widened from {:.2e} to {:.2e}, the widest the diagnosis \
                 allows it ({} times where it started), and the data may pull it further \
                 (estimate {:.3e}). If it is a base coefficient, the platform may be of a \
                 coarser class than the priors describe: state its priors \
                 ([prior.coefficients] in dataset.toml, or --prior) and diagnose again.",
                w.name,
                w.from,
                w.to,
                (w.to / w.from).round(),
                w.implied_estimate
            )
        } else {
            format!(
                "The prior of {} was widened from {:.2e} to {:.2e}: the data put it at \
                 {:.3e}, {:.0} starting prior sigmas away, where the narrower prior would have \
                 capped it.",
                w.name,
                w.from,
                w.to,
                w.implied_estimate,
                (w.implied_estimate / w.from).abs()
            )
        });
    }
    out
}

fn named_list(d: &Diagnosis) -> String {
    let all: Vec<String> = d.model.effects.iter().map(|e| format!("`{e}`")).collect();
    all.join(", ")
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

fn noise_table(out: &mut String, check: &NoiseFit, title: &str) {
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

/// The outcome as the report's table shows it: in words, a named candidate in bold.
fn outcome_words(o: Outcome) -> String {
    match o {
        Outcome::Named => format!("**{o}**"),
        _ => o.to_string(),
    }
}

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
                    CandidateKind::NoiseLevels => crate::NOISE_LEVELS_LABEL,
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
            super::candidates::CONSTANCY_ALPHA
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
