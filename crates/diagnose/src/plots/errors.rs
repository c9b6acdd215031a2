//! The coefficients' errors against the truth, each in the prior sigma it started from.
//!
//! The unit is the sigma a coefficient started the diagnosis with, before any widening
//! ([`crate::fit::widening`]): a fit may widen a prior 30 times, and an error divided by the
//! widened sigma reads 30 times smaller than it is (Ka1x, 31.8 starting sigmas off in the base
//! model of the walk-through, read 1.06). Widened priors are said in a note.

use super::style::{base_label, model_label, AFTER, BEFORE};
use crate::diagnosis::{Diagnosis, Fits};
use crate::summary::FitSummary;
use navkf_report::figure::*;
use plotters::prelude::*;

/// The prior sigma coefficient `name` started from, before any widening: the one the report's
/// table of priors gives, else (an effect's coefficient nobody stated) its starting sigma in
/// the final model's fit. `None` for a coefficient held at zero (pinned) or unknown.
pub fn initial_sigma(d: &Diagnosis, fits: &Fits, name: &str) -> Option<f64> {
    if d.pinned.iter().any(|p| p == name) {
        return None;
    }
    if let Some(p) = d.priors.iter().find(|p| p.name == name) {
        return Some(p.sigma);
    }
    let f = &fits.model;
    let i = f.names.iter().position(|n| n == name)?;
    Some(f.setup.priors.starting_sigma(name, f.typical_sigma[i]))
}

/// Each coefficient's `|estimate - truth|` over the prior sigma it started from, before and
/// after, on a log axis with a line at one starting sigma.
pub fn coefficient_errors(d: &Diagnosis, fits: &Fits) -> Grid {
    let mut sets: Vec<(&FitSummary, RGBColor, String)> = Vec::new();
    if let Some(b) = &d.before {
        sets.push((b, BEFORE, format!("before: {}", base_label(d))));
    }
    let after = model_label(&d.model.effects);
    sets.push((
        &d.model,
        AFTER,
        if d.before.is_some() {
            format!("after: {after}")
        } else {
            after
        },
    ));
    // Every coefficient of the model under test (a superset of the base model's), but the
    // pinned ones, which no fit estimates.
    let names: Vec<(&str, f64)> = d
        .model
        .coefficients
        .iter()
        .filter_map(|c| initial_sigma(d, fits, &c.name).map(|s| (c.name.as_str(), s)))
        .collect();
    let mut p = Panel::new(
        "|estimate - truth| at the end of the dataset, over the coefficient's initial prior sigma"
            .into(),
        "coefficient",
        "error in initial sigmas (before any widening)".into(),
        Scale::Log,
        BIG,
    );
    p.notes_above = true;
    let width = 0.8 / sets.len() as f64;
    let mut widened: Vec<Vec<String>> = vec![Vec::new(); sets.len()];
    let mut absent: Vec<&str> = Vec::new();
    for (i, (name, sigma0)) in names.iter().enumerate() {
        let x = i as f64;
        for (k, (s, c, _)) in sets.iter().enumerate() {
            let Some(coef) = s.coefficients.iter().find(|q| q.name == *name) else {
                if k == 0 && sets.len() > 1 {
                    absent.push(name);
                }
                continue;
            };
            if coef.prior_sigma > 1.000_001 * sigma0 {
                widened[k].push(format!("{name} {:.0}x", coef.prior_sigma / sigma0));
            }
            let Some(t) = coef.truth else { continue };
            let e = ((coef.estimate - t) / sigma0).abs();
            let x0 = x - 0.4 + k as f64 * width;
            p.bars.push((x0, x0 + 0.9 * width, e, c.mix(0.8).filled()));
        }
    }
    let low = p
        .bars
        .iter()
        .map(|b| b.2)
        .filter(|e| *e > 0.0 && e.is_finite())
        .fold(1.0f64, f64::min);
    let high = p
        .bars
        .iter()
        .map(|b| b.2)
        .filter(|e| e.is_finite())
        .fold(1.0f64, f64::max);
    p.y_include = vec![low, high];
    p.x_names = names
        .iter()
        .enumerate()
        .map(|(i, (n, _))| (i as f64, n.to_string()))
        .collect();
    p.x_include = vec![-0.5, names.len() as f64 - 0.5];
    p.line(
        BLACK.stroke_width(1),
        true,
        vec![(-0.5, 1.0), (names.len() as f64 - 0.5, 1.0)],
    );
    for ((_, _, label), w) in sets.iter().zip(&widened) {
        if !w.is_empty() {
            let who = label.split(':').next().unwrap_or(label);
            p.notes.push(format!(
                "{who}: prior widened in its fit (errors still in initial sigmas): {}",
                w.join(", ")
            ));
        }
    }
    if !absent.is_empty() {
        p.notes.push(format!(
            "not in the base model (one bar): {}",
            absent.join(", ")
        ));
    }
    if d.model.coefficients.iter().any(|c| c.truth.is_none()) {
        p.notes
            .push("a coefficient without a bar has no true value in truth.csv".into());
    }
    if !d.pinned.is_empty() {
        p.notes
            .push(format!("held at zero, not shown: {}", d.pinned.join(", ")));
    }
    let mut legend: Vec<Entry> = sets
        .iter()
        .map(|(_, c, l)| entry(l.clone(), c.mix(0.8).filled(), Mark::Box))
        .collect();
    legend.push(entry(
        "one initial sigma",
        BLACK.stroke_width(1),
        Mark::Dashed,
    ));
    Grid {
        title: "Coefficient errors against the truth, in initial sigmas".into(),
        panels: vec![p],
        cols: 1,
        cell: ((90 * names.len() as u32).max(1100), 640),
        legend,
    }
}
