//! Sentences about one part of a diagnosis, which the findings put in order: a noise check,
//! a model's consistency, data that cannot be what they claim, and candidates refused as no
//! real sensor's.

use super::words::{capitalise, times};
use crate::candidates::evidence::{Candidate, Outcome};
use crate::diagnosis::{Diagnosis, Round};
use crate::noise::levels::{NoiseFit, NoiseVerdict, WhyUnresolved, FIXED_WITHIN};
use crate::summary::FitSummary;
use navkf_report::stats::Consistency;

/// The noise findings of a check: mis-stated sources in words with their fitted levels, and
/// sources the data cannot resolve.
pub fn noise_findings(check: &NoiseFit, adopted: bool, out: &mut Vec<String>) {
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
                let coarse = if s.fixed() {
                    String::new()
                } else {
                    let why = if lo > 0.0 {
                        s.unresolved_because.map(why_unresolved).unwrap_or_default()
                    } else {
                        ", because the likelihood keeps rising as the level falls (the noise is \
                         too small for this record to see, or the readings are exact)"
                            .to_string()
                    };
                    format!(
                        " The record fixes this level only coarsely (its 95 % interval is wider \
                         than {:.0} % either way){why}: take it as an order of magnitude.",
                        100.0 * FIXED_WITHIN,
                    )
                };
                // A likelihood that never falls far enough below the fit leaves that side open.
                let span = if lo > 0.0 {
                    format!("at {}-{}", times(lo), times(hi))
                } else {
                    format!("below {}", times(hi))
                };
                let used = if adopted {
                    "The diagnosis uses the fitted level."
                } else {
                    "The refitted levels were not named (below), so the diagnosis keeps the \
                     stated level."
                };
                out.push(format!(
                    "{} {word} about {} (in sigma; the data put it {span} of the stated level): \
                     fitted {} (stated {}). {used}{coarse}",
                    capitalise(s.source.label()),
                    times(r),
                    keys(&s.fitted),
                    keys(&s.stated)
                ));
            }
            NoiseVerdict::Unresolved => out.push(format!(
                "The data cannot fix the {} level: anything from {} to {} of the stated one \
                 fits (95 %){}. The stated level is kept.",
                s.source.label(),
                times(lo),
                times(hi),
                s.unresolved_because.map(why_unresolved).unwrap_or_default()
            )),
            NoiseVerdict::Fits => {}
        }
    }
}

/// Why a level is unresolved, as a clause after the interval.
fn why_unresolved(why: WhyUnresolved) -> String {
    match why {
        WhyUnresolved::FewUpdates { updates } => {
            format!(", because its channel has only {updates} updates")
        }
        WhyUnresolved::TradesOff { with, correlation } => format!(
            ", because it trades off against the {} level (their log-scales correlate {:+.2}): \
             the data fix a combination of the two, not each",
            with.label(),
            correlation
        ),
        WhyUnresolved::Flat => ", because the likelihood is flat in it: no measurement of this \
                                record resolves that noise under the others"
            .to_string(),
        WhyUnresolved::Weak => ", because little of the innovations' variance is this noise's \
                                beside the other sources'"
            .to_string(),
    }
}

/// What a model's summary says of its consistency: NIS, failing channels and phases.
pub fn consistency_findings(m: &FitSummary, out: &mut Vec<String>) {
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
pub fn failing_channels_and_phases(m: &FitSummary) -> String {
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

/// The findings of an implausible-data diagnosis: each implausibility, where it is, then what
/// follows.
pub fn implausible_findings(d: &Diagnosis) -> Vec<String> {
    let mut out: Vec<String> = d.implausible.iter().map(|i| format!("{i}.")).collect();
    out.push(format!(
        "The data are not what they claim ({}, found in the data themselves): no effect is \
         named and no noise level is fitted, because any answer would stand in for the defect. \
         Correct or cut the data and diagnose again.",
        match d.implausible.len() {
            1 => "the finding above".to_string(),
            n => format!("the {n} findings above"),
        }
    ));
    if let Some(f) = &d.model.failure {
        out.push(format!(
            "The model under test could not even be run over them at the stated noise: {f}."
        ));
    }
    out
}

/// Sentences for the candidates of `rounds` that were decisive but not named because their
/// fitted values are no real sensor's.
pub fn refusal_findings(rounds: &[Round]) -> Vec<String> {
    let mut out = Vec::new();
    for (k, r) in rounds.iter().enumerate() {
        for c in r
            .candidates
            .iter()
            .filter(|c| c.outcome == Outcome::Unphysical)
        {
            out.push(refusal(k + 1, c));
        }
    }
    out
}

fn refusal(round: usize, c: &Candidate) -> String {
    let values: Vec<String> = c.beyond_bounds.iter().map(|b| b.to_string()).collect();
    format!(
        "Round {round}: `{}` has decisive evidence (BIC gain {:.1}) but is not named: fitted, \
         {}. No real sensor has that value; the data, or what is stated about them, are more \
         likely at fault than the instrument.",
        c.effect,
        c.bic_gain,
        values.join("; ")
    )
}

/// The effects of the candidates in `last` with `outcome`, quoted as the report quotes them.
fn quoted_with(last: &[Candidate], outcome: Outcome) -> Vec<String> {
    last.iter()
        .filter(|c| c.outcome == outcome)
        .map(|c| format!("`{}`", c.effect))
        .collect()
}

/// When the last round refused decisive candidates as no real sensor's: why no catalogued
/// effect is named (instead of "none has decisive evidence").
pub fn unphysical_instead(last: &[Candidate]) -> Option<String> {
    let refused = quoted_with(last, Outcome::Unphysical);
    (!refused.is_empty()).then(|| {
        format!(
            "No catalogued effect can be named: {} explain the misfit decisively, but only \
             with values no real sensor has (above), and nothing else explains it as well. The \
             cause is outside the catalogue, or the data are not what they claim.",
            refused.join(", ")
        )
    })
}

/// When the last round's choice was not named because the small-angle model is out of its
/// depth under the tilt prior ([`crate::naming`]): why no catalogued effect is named.
pub fn small_angle_instead(last: &[Candidate]) -> Option<String> {
    let held = quoted_with(last, Outcome::BeyondSmallAngle);
    (!held.is_empty()).then(|| {
        format!(
            "No catalogued effect can be named: {} explains the misfit decisively, but the \
             small-angle model is out of its depth under this tilt prior, and a misalignment of \
             degrees can pass for it. It is suggested; diagnose again with `--attitude exact`.",
            held.join(", ")
        )
    })
}

/// When the last round found decisive explanations it could not tell apart
/// ([`crate::naming`]'s tie rule): why no catalogued effect is named.
pub fn indistinguishable_instead(last: &[Candidate]) -> Option<String> {
    let tied = quoted_with(last, Outcome::Indistinguishable);
    (!tied.is_empty()).then(|| {
        format!(
            "No catalogued effect can be named: {} each explain the misfit decisively, and \
             equally well (above), so naming one would be a coin toss. They are suggested.",
            tied.join(" and ")
        )
    })
}

/// When the last round found a decisive explanation that something outside the catalogue
/// explains as well ([`crate::rivals`]): why no catalogued effect is named.
pub fn looks_like_outside_instead(last: &[Candidate]) -> Option<String> {
    let alike = quoted_with(last, Outcome::LooksLikeOutside);
    (!alike.is_empty()).then(|| {
        format!(
            "No catalogued effect can be named: {} would explain the misfit decisively, but \
             an explanation outside the catalogue explains it as well on this trajectory \
             (above). It is suggested, not named.",
            alike.join(" and ")
        )
    })
}

/// When the last round did not name the refitted noise levels because an error outside the
/// catalogue explains the misfit as well ([`crate::naming`]): why nothing is named.
pub fn outside_instead_of_levels(last: &[Candidate]) -> Option<String> {
    last.iter()
        .any(|c| c.outcome == Outcome::NoiseLevelsLikeOutside)
        .then(|| {
            "No catalogued effect can be named, and the refitted noise levels are not: an \
             error outside the catalogue explains the misfit as well as they do or better \
             (above), and noise refitted to cover it would misstate the sensors."
                .to_string()
        })
}

/// When the last round set aside a noise-only term that explains the misfit decisively
/// because a drift outside the catalogue fits as well, and with it the noise levels
/// ([`crate::naming`]): why nothing is named (instead of "none has decisive evidence").
pub fn drift_instead(last: &[Candidate]) -> Option<String> {
    let drift = quoted_with(last, Outcome::NoiseNotSpecific);
    let below = last
        .iter()
        .any(|c| c.outcome == Outcome::NoiseLevelsBelowDrift);
    (below && !drift.is_empty()).then(|| {
        format!(
            "No catalogued effect can be named: a slow drift explains the misfit decisively \
             better than refitted noise, but {} and a drift outside the catalogue explain it \
             as well (above), so the data cannot say which sensor drifts: a sensor warming up, \
             a temperature change or a walk of either sensor would look like this.",
            drift.join(" and ")
        )
    })
}
