//! `report.md` and `summary.json` of a diagnosis study.

use super::rates::{rates, sig, Rate, Rates};
use super::{DiagnosisStudyConfig, Record};
use crate::error::DiagnoseError;
use navkf_report::figure::FigureOutcome;
use navkf_report::markdown::{cell, number, Number, Table};
use navkf_report::write_atomic;
use serde::{Deserialize, Serialize};
use std::fmt::Write as _;
use std::path::Path;

/// `summary.json`: the study file as run, every dataset's outcome and the rates.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    /// The study file.
    pub config: DiagnosisStudyConfig,
    /// The rates.
    pub rates: Rates,
    /// Every dataset's outcome, in index order.
    pub records: Vec<super::Record>,
}

/// How long the study took, for the report (not part of the results).
#[derive(Debug, Clone, Copy)]
pub struct Timing {
    /// Wall time, s.
    pub wall_s: f64,
    /// Worker threads.
    pub threads: usize,
}

/// The report's text; `figure` is the detection figure's outcome, shown under its table.
pub fn markdown(
    s: &Summary,
    command: &str,
    timing: Option<Timing>,
    figure: &FigureOutcome,
) -> String {
    let r = &s.rates;
    // A study's declared effects join its catalogue; its report says so where it counts them.
    let effects = if s.config.effect.is_empty() {
        "catalogued"
    } else {
        "catalogued or declared"
    };
    let mut out = String::new();
    let _ = writeln!(out, "# Diagnosis study `{}`\n", s.config.study.name);
    let _ = writeln!(out, "Command: `{command}`\n");
    let _ = writeln!(
        out,
        "{} simulated {:.0} s vehicle tests{} on {} trajectory, seed {}, each diagnosed as a user would (default priors, noise check on, filter `{}`). {} diagnoses stopped with an error.{}\n",
        r.datasets,
        s.config.trajectory.duration_s,
        super::family::of(s.config.model.kind).unit_words(&s.config),
        if s.config.trajectory == navkf_dynamics::TrajectoryConfig::default() {
            "the paper's"
        } else {
            "the study's"
        },
        s.config.study.seed,
        s.config.diagnosis.filter,
        r.errors,
        timing.map_or(String::new(), |t| format!(
            " Wall time {:.0} s on {} threads of {}, the hot kernels compiled for {} ({:.2} s per dataset per thread).",
            t.wall_s,
            t.threads,
            navkf_report::provenance::machine(),
            navkf_dynamics::instruction_set::instruction_set(),
            t.wall_s * t.threads as f64 / r.datasets.max(1) as f64
        ))
    );
    let mut targets = Table::new(["what", "target", "measured", "met"]);
    for t in &r.targets {
        targets.row([
            t.what.to_string(),
            t.target.to_string(),
            t.measured.to_string(),
            if t.met { "yes" } else { "**no**" }.to_string(),
        ]);
    }
    let _ = writeln!(out, "## Targets\n\n{}", targets.render());
    let _ = writeln!(out, "## False attribution\n");
    let mut attribution = Table::new(["data", "an effect named", "other"]);
    attribution.row([
        "clean".to_string(),
        r.clean_named.to_string(),
        format!(
            "verdict not `consistent`: {}; noise refitted: {}",
            r.clean_not_consistent, r.clean_noise_refitted
        ),
    ]);
    // Kinds of data the study holds none of are left out, not shown as "-".
    if r.outside_named.n > 0 {
        attribution.row([
            "outside the catalogue, pooled".to_string(),
            r.outside_named.to_string(),
        ]);
    }
    for (e, rate) in &r.outside_by_effect {
        attribution.row([e.to_string(), rate.to_string()]);
    }
    if r.noise_named.n > 0 {
        attribution.row([
            "mis-stated noise, nothing hidden".to_string(),
            r.noise_named.to_string(),
            format!("noise refitted: {}", r.noise_found),
        ]);
    }
    for (label, rate) in &r.other_kind_named {
        let other = match r.wrong_units_warned.get(label) {
            Some(w) => format!("its warning given: {w}"),
            None if label == super::hidden::MEMS_NOISE_LABEL => {
                let per: Vec<String> = r
                    .mems_levels_within_20
                    .iter()
                    .map(|(s, q)| format!("{s} {}/{}", q.k, q.n))
                    .collect();
                let rate = |q: Option<Rate>| q.map_or("-".to_string(), |q| q.to_string());
                let mut text = format!(
                    "fitted levels within 20 % of the truth: {} ({}); unresolved, and said so: {}",
                    rate(r.mems_levels_pooled),
                    per.join(", "),
                    rate(r.mems_levels_unresolved)
                );
                if r.mems_levels_fixed.is_some() {
                    text += &format!(
                        "; called fixed (95 % interval within 20 %): {}, of which within 20 % \
                         of the truth: {}; the truth inside the 95 % interval: {}",
                        rate(r.mems_levels_fixed),
                        rate(r.mems_fixed_within_20),
                        rate(r.mems_intervals_cover)
                    );
                }
                text
            }
            None => String::new(),
        };
        attribution.row([label.to_string(), rate.to_string(), other]);
    }
    out.push_str(&attribution.render());
    let _ = writeln!(
        out,
        "\nSingle {effects} effects, all sizes: the hidden effect named {}; something else named too or instead {}.\n",
        r.single_found, r.single_extra
    );
    // With no named hidden effect there is no estimate to measure: a dash, not an RMS of 0.
    let rms = if r.estimates_within_3_sigma.n == 0 {
        "-".to_string()
    } else {
        format!("{:.2}", r.estimate_error_rms)
    };
    let _ = writeln!(
        out,
        "Estimates of the named hidden effects' coefficients (final model): within 3 sigma of the truth {}; RMS of (estimate - truth) / sigma {rms} (1 if the sigmas are honest).\n",
        r.estimates_within_3_sigma
    );
    let _ = writeln!(
        out,
        "## Detection\n\nPer {effects} effect, over the datasets that hid it alone (sizes log-uniform, as multiples of its typical size): the size named 90 % of the time on a logistic fit, and the share named above it.\n"
    );
    let mut detection = Table::new([
        "effect",
        "datasets",
        "typical size",
        "named 90 % of the time from",
        "named above it",
        "share named per size bin (multiples of typical)",
    ]);
    for d in &r.detection {
        let bins: Vec<String> = d
            .bins
            .iter()
            .filter(|b| b.named.n > 0)
            .map(|b| {
                format!(
                    "{}-{}: {}/{}",
                    sig(b.multiples[0], 2),
                    sig(b.multiples[1], 2),
                    b.named.k,
                    b.named.n
                )
            })
            .collect();
        detection.row([
            d.effect.to_string(),
            d.n.to_string(),
            format!("{} {}", number(d.typical, Number::Sci(2)), d.unit),
            match (d.limit_multiple, &d.no_limit) {
                (Some(m), _) => format!(
                    "{} x ({} {})",
                    sig(m, 3),
                    number(m * d.typical, Number::Sci(2)),
                    d.unit
                ),
                (None, Some(why)) => cell(why),
                _ => "-".into(),
            },
            d.above_limit.map_or("-".to_string(), |r| r.to_string()),
            bins.join("; "),
        ]);
    }
    out.push_str(&detection.render());
    for d in &r.detection {
        if let Some(u) = d.unseen.as_ref().filter(|u| u.named.n > 0) {
            let _ = writeln!(
                out,
                "\n`{}`: its sizes are those of the part a test can see. {} of its {} datasets hid only {}: no test can see that, so they are left out of its curve; it was named on {} of them.",
                d.effect,
                u.named.n,
                u.named.n + d.n,
                u.why,
                u.named.k
            );
        }
    }
    let _ = writeln!(out, "\n{}", figure.embed());
    if r.pairs_both.n > 0 {
        let _ = writeln!(
            out,
            "## Pairs\n\nPairs of {effects} effects: both named in one command {} over all sizes, {} when both sizes are above their limits.\n",
            r.pairs_both, r.pairs_both_above
        );
    }
    let _ = writeln!(out, "## Confusion matrix\n");
    let mut match_cols: Vec<String> = r
        .confusion
        .iter()
        .flat_map(|c| c.matches.keys().cloned())
        .collect();
    match_cols.sort();
    match_cols.dedup();
    let mut verdict_cols: Vec<String> = r
        .confusion
        .iter()
        .flat_map(|c| c.verdicts.keys().cloned())
        .collect();
    verdict_cols.sort();
    verdict_cols.dedup();
    let counts = |m: &std::collections::BTreeMap<String, usize>, cols: &[String]| {
        cols.iter()
            .map(|k| m.get(k).copied().unwrap_or(0).to_string())
            .collect::<Vec<_>>()
    };
    let mut confusion = Table::new(
        ["hidden".to_string(), "n".to_string()]
            .into_iter()
            .chain(match_cols.iter().cloned())
            .chain(verdict_cols.iter().map(|v| format!("verdict {v}")))
            .chain([
                "noise refitted".to_string(),
                "effects named (count)".to_string(),
            ]),
    );
    for c in &r.confusion {
        let named: Vec<String> = c.named.iter().map(|(k, v)| format!("{k} {v}")).collect();
        confusion.row(
            [c.hidden.to_string(), c.n.to_string()]
                .into_iter()
                .chain(counts(&c.matches, &match_cols))
                .chain(counts(&c.verdicts, &verdict_cols))
                .chain([c.noise_refitted.to_string(), named.join(", ")]),
        );
    }
    out.push_str(&confusion.render());
    let _ = writeln!(
        out,
        "\nColumns: `exact` names exactly the hidden {effects} effects, `hidden-and-more` them and others, `part-of-hidden` some of them, `only-others` none of them but others, `nothing-named` nothing.\n\nSingle effects, hidden (rows) against named (columns):\n"
    );
    let mut cols: Vec<String> = r
        .effect_matrix
        .values()
        .flat_map(|m| m.keys().cloned())
        .collect();
    cols.sort();
    cols.dedup();
    let mut matrix = Table::new(std::iter::once("hidden".to_string()).chain(cols.iter().cloned()));
    for (e, m) in &r.effect_matrix {
        matrix.row(std::iter::once(e.to_string()).chain(counts(m, &cols)));
    }
    out.push_str(&matrix.render());
    let _ = write!(
        out,
        "\nRates as fractions: clean {} named",
        number(r.clean_named.rate, Number::Percent(1))
    );
    if r.outside_named.n > 0 {
        let _ = write!(
            out,
            ", outside {} named",
            number(r.outside_named.rate, Number::Percent(1))
        );
    }
    out.push_str(".\n");
    out
}

/// Writes `summary.json`, `report.md` and the figure into `dir`.
pub fn write(
    config: &DiagnosisStudyConfig,
    records: Vec<Record>,
    dir: &Path,
    command: &str,
    timing: Option<Timing>,
) -> Result<Summary, DiagnoseError> {
    let summary = Summary {
        config: config.clone(),
        rates: rates(&records, &super::effect_scales(config)),
        records,
    };
    let json = serde_json::to_string_pretty(&summary)
        .map_err(|e| DiagnoseError::Content(format!("summary.json: {e}")))?;
    write_atomic(&dir.join("summary.json"), json.as_bytes())?;
    let figure = navkf_report::figure::outcome(
        "detection",
        "The share of datasets that named each effect, against its size",
        super::plots::DETECTION_QUESTION,
        || super::plots::detection(&summary.rates, dir),
    );
    let md = markdown(&summary, command, timing, &figure);
    write_atomic(&dir.join("report.md"), md.as_bytes())?;
    Ok(summary)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The report of a committed study's `summary.json`, rendered without timing.
    fn rendered(study: &str) -> String {
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../results")
            .join(study)
            .join("summary.json");
        // The rates are computed again from the records: a rate of no datasets is NaN, which
        // `summary.json` writes as null.
        #[derive(Deserialize)]
        struct Committed {
            config: DiagnosisStudyConfig,
            records: Vec<Record>,
        }
        let text = std::fs::read_to_string(&path).unwrap();
        let Committed { config, records } = serde_json::from_str(&text).unwrap();
        let summary = Summary {
            rates: rates(&records, &super::super::effect_scales(&config)),
            config,
            records,
        };
        let figure = FigureOutcome {
            name: "detection".into(),
            caption: "detection".into(),
            question: "From what size?".into(),
            result: Ok(()),
        };
        markdown(&summary, "navkf study", None, &figure)
    }

    /// A study of declared effects holding no outside content, no mis-stated noise and no
    /// pairs shows none of their rows or sections (it showed "-" in each), and counts its
    /// effects as catalogued or declared; a study of catalogued effects keeps every section
    /// and its words.
    #[test]
    fn kinds_of_data_a_study_lacks_are_left_out() {
        let declared = rendered("strapdown-declared-diagnosis");
        for absent in [
            "outside the catalogue, pooled",
            "mis-stated noise",
            "## Pairs",
            "outside - named",
        ] {
            assert!(!declared.contains(absent), "{absent}:\n{declared}");
        }
        assert!(declared.contains("Single catalogued or declared effects, all sizes"));
        // It names none of its hidden effects, so it has no estimate to measure: no RMS of 0.
        assert!(
            declared.contains("within 3 sigma of the truth -; RMS of (estimate - truth) / sigma -"),
            "{declared}"
        );
        assert!(declared.contains("Rates as fractions: clean 0.0 % named.\n"));
        let catalogued = rendered("strapdown-diagnosis");
        for present in [
            "outside the catalogue, pooled",
            "mis-stated noise, nothing hidden",
            "## Pairs\n\nPairs of catalogued effects",
            "Single catalogued effects, all sizes",
            ", outside ",
        ] {
            assert!(catalogued.contains(present), "{present}:\n{catalogued}");
        }
    }
}
