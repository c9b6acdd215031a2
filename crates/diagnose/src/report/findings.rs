//! The findings: a diagnosis in plain words, in the order a user should read them. They are
//! made from the typed result last ([`crate::rounds`]) and kept in `diagnosis.json`.

use super::sentences::{
    consistency_findings, drift_instead, failing_channels_and_phases, implausible_findings,
    indistinguishable_instead, looks_like_outside_instead, noise_findings,
    outside_instead_of_levels, refusal_findings, small_angle_instead, unphysical_instead,
};
use super::words::times;
use crate::candidates::evidence::{Candidate, CandidateKind, Outcome, DECISIVE_BIC};
use crate::diagnosis::{Diagnosis, RoundKind};
use crate::misfit::{GROSS_NIS_RATIO, SUGGEST_SHARE};
use crate::noise::levels::NoiseVerdict;
use crate::priors::beyond_small_angle;
use crate::verdict::Verdict;
use navkf_dynamics::prior::PriorSource;

/// Plain-language findings, in the order a user should read them: the noise, where the model
/// under test fails, what each round named and why, what remains, and what cannot be told.
pub fn findings(d: &Diagnosis) -> Vec<String> {
    if d.verdict == Verdict::ImplausibleData {
        return implausible_findings(d);
    }
    let mut out = Vec::new();
    if !d.noise_stated {
        out.push(format!(
            "dataset.toml states no noise (it is absent, or has no [noise] table): the noise \
             called \"stated\" below is navkf's default for a navigation-grade {} \
             (docs/data-format.md), not a statement of yours. Give your sensors' levels in a \
             [noise] table, or read the noise check as a fit of the levels from the data.",
            if d.family.is_platform() {
                "platform"
            } else {
                "unit's sensors"
            }
        ));
    }
    // A misalignment of degrees breaks the small-angle model before anything else: first.
    let large: Vec<String> = beyond_small_angle(&d.priors, d.attitude, d.family)
        .iter()
        .map(|p| format!("{} = {:.2} deg", p.name, p.sigma.to_degrees()))
        .collect();
    if !large.is_empty() {
        out.push(format!(
            "The tilt prior ({}) allows errors where the small-angle model does not hold \
             (in studies/misalignment.toml its EKF turns inconsistent from 1 deg of \
             azimuth sigma and inaccurate from 3 deg), and such a misalignment can pass \
             for a missing effect: no effect is named. Diagnose again with `--attitude \
             exact`.",
            large.join(", ")
        ));
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
        noise_findings(last, noise_named, &mut out);
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
    out.extend(refusal_findings(&d.rounds));
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
        Verdict::Consistent => {
            consistency_findings(&d.model, &mut out);
            // Consistent by the NIS tests, yet the likelihood found an effect it could not
            // tell from something outside the catalogue: say so, or the suggestion is unsaid.
            let last = d.rounds.last().map(|r| &r.candidates[..]).unwrap_or(&[]);
            out.extend(looks_like_outside_instead(last));
        }
        Verdict::Explained => out.push(format!(
            "With {} the model is consistent (NIS {:.3}, bounds {:.3}-{:.3}).",
            named_list(d),
            d.model.nis.mean,
            d.model.nis.bounds[0],
            d.model.nis.bounds[1]
        )),
        Verdict::PartlyExplained => out.push(
            format!(
                "With {} the model fits decisively better, but a misfit remains that nothing in \
             the catalogue explains (NIS {:.3}, bounds {:.3}-{:.3}), so they are suggested, \
             not named: an effect that does not make the model fit may only stand in for what \
             is missing. {}",
                named_list(d),
                d.model.nis.mean,
                d.model.nis.bounds[0],
                d.model.nis.bounds[1],
                failing_channels_and_phases(&d.model)
            ) + &when(d),
        ),
        Verdict::ImplausibleData => {}
        Verdict::DoesNotFollowModel => out.extend(does_not_follow(d)),
        Verdict::Unexplained => {
            consistency_findings(&d.model, &mut out);
            if let Some(m) = &d.misfit {
                out.push(format!("When: {}.", m.when()));
            }
            out.push(why_nothing_named(d).unwrap_or_else(|| {
                format!(
                    "No catalogued effect explains the misfit: none has decisive evidence \
                     (BIC gain > {DECISIVE_BIC}) that it can carry on its own. The cause is \
                     outside the catalogue, or too small to attribute on this dataset."
                )
            }));
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
                 data fit decisively better with it. {}{}.",
                match w.name.as_str() {
                    "azimuth_rad" => "azimuth",
                    "heading_rad" => "heading",
                    _ => "level",
                },
                w.from,
                w.to,
                if d.family.is_platform() {
                    "A platform gyrocompassed with drifts far beyond its priors' starts that far off"
                } else {
                    "The unit's own alignment was that far off"
                },
                if w.to > 0.05 && d.family.is_platform() {
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
                 (estimate {:.3e}). If it is a base coefficient, the {} may be of a \
                 coarser class than the priors describe: state its priors \
                 ([prior.coefficients] in dataset.toml, or --prior) and diagnose again.",
                w.name,
                w.from,
                w.to,
                (w.to / w.from).round(),
                w.implied_estimate,
                if d.family.is_platform() {
                    "platform"
                } else {
                    "unit"
                }
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
    if !d.widened.is_empty() && levels_refused_for_outside(d) {
        out.push(format!(
            "These priors were widened in a model that lacks an error outside the catalogue \
             (above): the widening may be that error's doing, not the {}'s class. Account for \
             the error first (declare it, or find its cause) before stating wider priors.",
            if d.family.is_platform() {
                "platform"
            } else {
                "unit"
            }
        ));
    }
    if !d.pinned.is_empty() {
        out.push(format!(
            "Held at zero in every fit, and not tested: {}. The horizontal model cannot inform \
             them (the vertical force is not integrated, and a drive turns about the vertical \
             only), and a filter's own linearisation drifts their estimates whatever the truth, \
             so a likelihood would reward the drift (docs/model.md, \"What the horizontal model \
             cannot see: the vertical accelerometer bias\"). Rotations about the unit's forward \
             and left axes, or a vertical channel, would reveal them.{}",
            d.pinned.join(", "),
            {
                let stated: Vec<&str> = d
                    .priors
                    .iter()
                    .filter(|p| d.pinned.contains(&p.name) && p.source != PriorSource::Default)
                    .map(|p| p.name.as_str())
                    .collect();
                if stated.is_empty() {
                    String::new()
                } else {
                    format!(
                        " The priors stated for {} are not used: stated or not, the data \
                         cannot inform them, and freed they drift.",
                        stated.join(", ")
                    )
                }
            }
        ));
    }
    out
}

/// Whether the last round refused the refitted noise levels for an error outside the
/// catalogue (a drift no sensor can be given, or the levels' structured rival): the final
/// model then lacks that error, and what its coefficients were pulled to is partly its doing
/// (on a drag ten times its typical size, the accelerometer biases widened to their cap with
/// an estimate of 0.25 m/s^2).
fn levels_refused_for_outside(d: &Diagnosis) -> bool {
    d.rounds.last().is_some_and(|r| {
        r.candidates.iter().any(|c| {
            matches!(
                c.outcome,
                Outcome::NoiseLevelsLikeOutside | Outcome::NoiseLevelsBelowDrift
            )
        })
    })
}

/// Why the last round named nothing although something had decisive evidence: it looks like
/// something outside the catalogue, cannot be told from another candidate, has values no
/// real sensor has, or cannot be told from the model's own coefficients. `None` when nothing
/// had decisive evidence.
fn why_nothing_named(d: &Diagnosis) -> Option<String> {
    let last = d.rounds.last().map(|r| &r.candidates[..]).unwrap_or(&[]);
    let confounded: Vec<String> = last
        .iter()
        .filter(|c| c.outcome == Outcome::Confounded)
        .map(|c| format!("`{}`", c.effect))
        .collect();
    small_angle_instead(last)
        .or_else(|| drift_instead(last))
        .or_else(|| outside_instead_of_levels(last))
        .or_else(|| looks_like_outside_instead(last))
        .or_else(|| indistinguishable_instead(last))
        .or_else(|| unphysical_instead(last))
        .or_else(|| {
            (!confounded.is_empty()).then(|| {
                format!(
                    "No catalogued effect can be named: {} has decisive evidence but cannot be \
                     told apart from coefficients already in the model on this trajectory \
                     (see below), so the data cannot say whether it or those coefficients carry \
                     the misfit. {}",
                    confounded.join(", "),
                    if d.family.is_platform() {
                        "A trajectory that separates them (for `gyro-fz`, one with varying \
                         vertical specific force) would."
                    } else {
                        "A trajectory that separates them would (docs/strapdown.md, \"What \
                         this test cannot reveal\", names the manoeuvres)."
                    }
                )
            })
        })
}

/// The findings of a gross misfit: how far off, where, what the rounds' candidates were
/// worth, and what kind of cause to look for.
fn does_not_follow(d: &Diagnosis) -> Vec<String> {
    let mut out = Vec::new();
    // The final model's noise is the fitted one only if a round named the refitted levels.
    let fitted = d.rounds.iter().any(|r| r.named_noise_levels());
    let (noise, untried) = match (d.noise_checks.last(), fitted) {
        (Some(_), true) => ("at the fitted noise levels", true),
        (Some(_), false) => ("at the stated noise levels, which no refit replaced", true),
        (None, _) => (
            "at the stated noise levels (the noise check was off)",
            false,
        ),
    };
    let why = if untried {
        ", which no noise level or catalogued effect left untried can explain"
    } else {
        ""
    };
    out.push(match &d.model.failure {
        Some(f) => format!(
            "The data do not follow this model: {noise}, and after every catalogued effect was \
             tried, its filter fails: {f}. No effect is named."
        ),
        None => format!(
            "The data do not follow this model: {noise}, and after every catalogued effect was \
             tried, its NIS is {:.3} against {:.2}, {:.1} times what a consistent model gives \
             (more than {GROSS_NIS_RATIO} times is a gross misfit{why}). No effect is named.",
            d.model.nis.mean,
            d.model.nis.dof,
            d.model.nis.mean / d.model.nis.dof,
        ),
    });
    let held: Vec<String> = d
        .model
        .effects
        .iter()
        .filter(|e| {
            let manual = d
                .rounds
                .iter()
                .any(|r| r.kind == RoundKind::Manual && r.named.contains(e));
            !manual && !d.suggested.contains(e)
        })
        .map(|e| format!("`{e}`"))
        .collect();
    if !held.is_empty() {
        out.push(format!(
            "The final model's fit, whose NIS and coefficients the report gives, holds {}: \
             each helped decisively in its round but removed too little of the misfit to be \
             named or suggested.",
            held.join(", ")
        ));
    }
    if let Some(m) = &d.misfit {
        out.push(format!("Where it fails: {m}."));
    }
    out.extend(why_nothing_named(d));
    let mut tried: Vec<&Candidate> = d
        .rounds
        .iter()
        .filter(|r| r.kind == RoundKind::Automatic)
        .flat_map(|r| &r.candidates)
        .filter(|c| c.kind != CandidateKind::NoiseLevels && c.bic_gain > DECISIVE_BIC)
        .collect();
    tried.sort_by(|a, b| b.excess_removed.total_cmp(&a.excess_removed));
    // Each effect once, at its largest share (every round ranks every candidate).
    let mut seen: Vec<&str> = Vec::new();
    tried.retain(|c| {
        let first = !seen.contains(&c.effect.as_str());
        seen.push(&c.effect);
        first
    });
    if !tried.is_empty() {
        let shares: Vec<String> = tried
            .iter()
            .take(4)
            .map(|c| format!("`{}` {:.0} %", c.effect, 100.0 * c.excess_removed))
            .collect();
        out.push(format!(
            "Catalogued effects with decisive evidence removed these shares of the excess of \
             the model they were tried in: {}. {}",
            shares.join(", "),
            if let Some(c) = tried
                .iter()
                .find(|c| c.excess_removed >= SUGGEST_SHARE && !d.suggested.contains(&c.effect))
            {
                format!(
                    "`{}` removed most of it but cannot be named ({}); the model still fails \
                     grossly without it.",
                    c.effect, c.outcome
                )
            } else if d.suggested.is_empty() {
                format!(
                    "None removed {:.0} % or more: each stands in for a part of the misfit, \
                     not for its cause.",
                    100.0 * SUGGEST_SHARE
                )
            } else {
                format!(
                    "{} removed most of it and is suggested; what remains is of another kind.",
                    d.suggested
                        .iter()
                        .map(|e| format!("`{e}`"))
                        .collect::<Vec<_>>()
                        .join(", ")
                )
            }
        ));
    }
    let mut causes = vec![
        "content no catalogued effect describes (a GPS offset for minutes, wheel slip, an \
         antenna away from the unit: look where it fails, above)",
    ];
    if d.family.is_platform() && d.attitude == navkf_dynamics::Attitude::SmallAngle {
        causes.push("a platform misaligned by degrees (diagnose again with `--attitude exact`)");
    }
    if !d.data_warnings.is_empty() {
        causes.push("a column in another unit (the warnings above)");
    }
    causes.push("a recording of another kind of unit than the model's family");
    out.push(format!("Look for: {}.", causes.join("; ")));
    out
}

/// " When: ..." for a diagnosis whose final model is inconsistent.
fn when(d: &Diagnosis) -> String {
    d.misfit
        .as_ref()
        .map(|m| format!(" When: {}.", m.when()))
        .unwrap_or_default()
}

fn named_list(d: &Diagnosis) -> String {
    let all: Vec<String> = d.model.effects.iter().map(|e| format!("`{e}`")).collect();
    all.join(", ")
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
