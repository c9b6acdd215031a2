//! Human-readable tables of a summary (terminal and report.md), and `report.md` itself.

use crate::summary::{Summary, EQUIVALENCE_MARGIN};
use navkf_report::markdown::{cell, number, Number, Table};
use navkf_report::provenance::machine;
use std::fmt::Write as _;

/// Errors, sigmas and differences in the report's tables.
fn g(v: f64) -> String {
    number(v, Number::Sci(3))
}

/// A Markdown table per filter: final RMS error, claimed sigma and bound per coefficient;
/// then consistency and cost.
pub fn table(s: &Summary) -> String {
    let mut out = String::new();
    let names: Vec<&String> = s.filters.keys().collect();
    let coefs: Vec<String> = s
        .filters
        .values()
        .next()
        .map(|f| f.final_rms.keys().cloned().collect())
        .unwrap_or_default();
    let _ = writeln!(out, "\n## {} ({} runs, seed {})\n", s.study, s.runs, s.seed);
    let mut header = vec!["coefficient".to_string()];
    for n in &names {
        header.extend([format!("{n} RMS"), format!("{n} sigma")]);
    }
    header.push("bound".into());
    let mut errors = Table::new(header);
    for c in &coefs {
        let mut row = vec![c.clone()];
        let mut bound = f64::NAN;
        for n in &names {
            let f = &s.filters[*n];
            row.push(g(*f.final_rms.get(c).unwrap_or(&f64::NAN)));
            row.push(g(*f.final_sigma.get(c).unwrap_or(&f64::NAN)));
            bound = *f.final_bound.get(c).unwrap_or(&f64::NAN);
        }
        row.push(g(bound));
        errors.row(row);
    }
    out.push_str(&errors.render());
    let mut filters = Table::new([
        "filter",
        "runs ok",
        "diverged",
        "NEES (95 % bounds)",
        "NIS (95 % bounds)",
        "step median",
        "step p90",
    ]);
    for n in &names {
        let f = &s.filters[*n];
        // With no run completed there is no mean and no cost: a dash, never "NaN".
        let with_bounds = |mean: f64, bounds: [f64; 2], digits: usize| {
            if mean.is_finite() {
                format!(
                    "{} ({}-{})",
                    number(mean, Number::Fixed(digits)),
                    number(bounds[0], Number::Fixed(digits)),
                    number(bounds[1], Number::Fixed(digits))
                )
            } else {
                "-".into()
            }
        };
        filters.row([
            n.to_string(),
            f.runs_ok.to_string(),
            f.diverged.to_string(),
            with_bounds(f.nees_mean, f.nees_bounds, 2),
            with_bounds(f.nis_mean, f.nis_bounds, 3),
            number(f.step_ns_median, Number::Micros),
            number(f.step_ns_p90, Number::Micros),
        ]);
    }
    out.push('\n');
    out.push_str(&filters.render());
    out
}

/// A Markdown table of the paired differences of final squared errors, with their 95 %
/// intervals and what they say.
pub fn paired_table(s: &Summary) -> String {
    let mut out = String::new();
    if s.paired.is_empty() {
        out.push_str("\nNo paired comparison (fewer than two filters, or fewer than two runs where both finished).\n");
        return out;
    }
    let _ = writeln!(
        out,
        "\nPaired differences of the final squared error, `e_a^2 - e_b^2`, over the runs where both filters finished (95 % intervals; `relative` is the mean difference over `b`'s mean squared error).\n"
    );
    let mut table = Table::new([
        "a",
        "b",
        "coefficient",
        "runs",
        "mean difference",
        "95 % interval",
        "relative",
        "verdict",
    ]);
    let (mut excluding_zero, mut worse) = (0, 0);
    for d in &s.paired {
        excluding_zero += usize::from(d.excludes_zero());
        worse += usize::from(d.significant());
        let pct = 100.0 * d.relative;
        // Below 0.1 % the fixed form would read +0.0 %: the exponent keeps the size.
        let rel = if !pct.is_finite() || pct.abs() >= 0.1 || pct == 0.0 {
            number(d.relative, Number::SignedPercent(1))
        } else {
            format!("{pct:+.1e} %")
        };
        table.row([
            cell(&d.a),
            cell(&d.b),
            cell(&d.coefficient),
            d.n.to_string(),
            g(d.mean_sq_err_diff),
            format!("{} to {}", g(d.ci95[0]), g(d.ci95[1])),
            rel,
            d.verdict_words(),
        ]);
    }
    out.push_str(&table.render());
    let equal_but_nonzero = excluding_zero - worse;
    let equal_note = if equal_but_nonzero > 0 {
        format!(
            "; {equal_but_nonzero} of them {} within {} % of `b`'s mean squared error and {} \
             called equal: the runs are paired, so they resolve differences far below any a \
             user would choose a filter by",
            if equal_but_nonzero == 1 {
                "lies"
            } else {
                "lie"
            },
            100.0 * EQUIVALENCE_MARGIN,
            if equal_but_nonzero == 1 { "is" } else { "are" },
        )
    } else {
        String::new()
    };
    let _ = writeln!(
        out,
        "\n{excluding_zero} of {} comparisons exclude zero at 95 % (about {:.1} would by chance \
         alone if the filters were equal){equal_note}.",
        s.paired.len(),
        0.05 * s.paired.len() as f64,
    );
    out
}

/// The consistency verdict of every filter, in words.
pub fn consistency(s: &Summary) -> String {
    let mut out = String::new();
    for (name, f) in &s.filters {
        if f.runs_ok == 0 {
            let _ = writeln!(
                out,
                "- **{name}**: no run finished, so no verdict ({} diverged).",
                f.diverged
            );
            continue;
        }
        let nees = f.nees().verdict();
        let nis = f.nis().verdict();
        let overall = if nees == nis {
            nees.to_string()
        } else {
            format!("NEES {nees}, NIS {nis}")
        };
        let _ = writeln!(
            out,
            "- **{name}**: {overall}. Final NEES {:.2} against its 95 % bounds {:.2}-{:.2} ({nees}); NIS {:.3} against {:.3}-{:.3} ({nis}; {:.2} measurement dimensions on average).",
            f.nees_mean,
            f.nees_bounds[0],
            f.nees_bounds[1],
            f.nis_mean,
            f.nis_bounds[0],
            f.nis_bounds[1],
            f.nis_dof
        );
    }
    out.push_str(
        "\nConsistent: the average lies inside the 95 % band of a filter whose covariance is right. \
         Optimistic: above it, the errors are larger than the covariance claims. \
         Pessimistic: below it, the covariance is larger than the errors.\n",
    );
    out
}

/// `x` in exponent form, to four significant digits when its shortest form is longer
/// (`1e-14` stays, `7.615435494667713e-9` is `7.615e-9`).
fn short_e(x: f64) -> String {
    let full = format!("{x:e}");
    if full.len() > 10 {
        format!("{x:.3e}")
    } else {
        full
    }
}

fn settings(s: &Summary) -> String {
    let c = &s.settings;
    let list = |v: &[String]| {
        if v.is_empty() {
            "base model only".to_string()
        } else {
            v.join(", ")
        }
    };
    let mut out = String::new();
    let lines = [
        format!("runs: {} (seed {})", s.runs, c.study.seed),
        format!("filters: {}", c.study.filters.join(", ")),
        if c.trajectory.segments.is_empty() {
            format!(
                "trajectory: {} s, {} s at rest first, legs {} m north and {} m east, cruise {} m/s, start {} deg N {} deg E",
                c.trajectory.duration_s,
                c.trajectory.initial_standstill_s,
                c.trajectory.leg_north_m,
                c.trajectory.leg_east_m,
                c.trajectory.cruise_speed,
                c.trajectory.start_lat_deg,
                c.trajectory.start_lon_deg
            )
        } else {
            format!(
                "trajectory: {} s written as {} segments (below), start {} deg N {} deg E",
                c.trajectory.duration_s,
                c.trajectory.segments.len(),
                c.trajectory.start_lat_deg,
                c.trajectory.start_lon_deg
            )
        },
        crate::family::of(c.model.kind).truth_line(c, &list(&c.truth.effects)),
        {
            let n = c.truth_noise();
            let nhc = n
                .nhc_m_s
                .map_or(String::new(), |s| format!(", non-holonomic constraint {s} m/s"));
            format!(
                "noise: gyro PSD {} rad^2/s, accel PSD {} (m/s^2)^2/s, odometer {} relative (floor {} m/s), GPS {} m{nhc}",
                short_e(n.gyro_psd), short_e(n.accel_psd), n.odometer_rel, n.odometer_floor, n.gps_m
            )
        },
        format!(
            "filters' model: effects {}; sigma points alpha {}, beta {}, kappa {}; process noise x {}; initial sigmas x {}",
            list(&c.filter.effects),
            c.filter.alpha,
            c.filter.beta,
            c.filter.kappa,
            c.filter.process_noise_scale,
            c.filter.initial.sigma_scale
        ),
        format!(
            "series every {} s; example run {}; a run diverges beyond {} initial sigmas of final error",
            c.study.series_every_s, c.study.example_run, c.divergence.max_error_initial_sigmas
        ),
    ];
    for l in lines {
        let _ = writeln!(out, "- {l}");
    }
    if let Ok(toml) = toml::to_string(c) {
        let _ = writeln!(
            out,
            "\n<details><summary>The study file as run</summary>\n\n```toml\n{}```\n\n</details>",
            toml
        );
    }
    out
}

fn diverged(study: &crate::monte_carlo::Study, tally: &crate::tally::Tally) -> String {
    const SHOWN: usize = 50;
    let mut out = String::new();
    let total: usize = tally.filters.iter().map(|f| f.diverged.len()).sum();
    if total == 0 {
        let _ = writeln!(out, "No run diverged.");
        return out;
    }
    for (name, f) in study.filter_names().iter().zip(&tally.filters) {
        if f.diverged.is_empty() {
            let _ = writeln!(out, "- **{name}**: none of {} runs.", tally.runs);
            continue;
        }
        let by_cause: Vec<String> = f
            .diverged_by_cause()
            .iter()
            .map(|(cause, count)| format!("{count} {cause}"))
            .collect();
        let _ = writeln!(
            out,
            "- **{name}**: {} of {} runs diverged ({}):",
            f.diverged.len(),
            tally.runs,
            by_cause.join(", ")
        );
        for d in f.diverged.iter().take(SHOWN) {
            let _ = writeln!(
                out,
                "  - run {} ({}): {}",
                d.run,
                d.failure.cause,
                d.failure.reason.replace('\n', " ")
            );
        }
        if f.diverged.len() > SHOWN {
            let _ = writeln!(out, "  - ... and {} more", f.diverged.len() - SHOWN);
        }
    }
    out
}

/// The figures' sections; `platform`: the study is of the paper's family, whose example run
/// the paper drew.
fn figures(figs: &[navkf_report::figure::FigureOutcome], platform: bool) -> String {
    let mut out = String::new();
    let example = if platform {
        "The example run: every filter's estimate of each coefficient with its +-1 sigma band, and the true value (the paper's Figures 2 and 3)."
    } else {
        "The example run: every filter's estimate of each coefficient with its +-1 sigma band, and the true value."
    };
    let sections = [
        (
            "rms_over_time",
            "RMS error over time",
            "Each coefficient's RMS error over the runs that finished, divided by its initial sigma (log scale), per filter; dashed: the truth-linearised bound.",
        ),
        (
            "nees_nis_over_time",
            "Consistency over time",
            "Average NEES and NIS per filter against the 95 % band of a consistent filter.",
        ),
        (
            "estimates_all",
            "Estimates against the truth (example run)",
            example,
        ),
        (
            "step_cost",
            "Cost per step",
            "Median and 90th percentile of one predict + update, and the distribution over all steps.",
        ),
    ];
    for (name, heading, text) in sections {
        if let Some(f) = figs.iter().find(|f| f.name == name && f.result.is_ok()) {
            let _ = write!(out, "\n### {heading}\n\n{text}\n\n{}", f.embed());
        }
    }
    let per: Vec<String> = figs
        .iter()
        .filter(|f| f.name.starts_with("estimates_") && f.name != "estimates_all")
        .filter(|f| f.result.is_ok())
        .map(|f| format!("[{}]({}.png)", &f.name["estimates_".len()..], f.name))
        .collect();
    if !per.is_empty() {
        let _ = writeln!(
            out,
            "\nOne coefficient per figure (PNG; SVG alongside): {}",
            per.join(" · ")
        );
    }
    let failed: Vec<&navkf_report::figure::FigureOutcome> =
        figs.iter().filter(|f| f.result.is_err()).collect();
    if !failed.is_empty() {
        let _ = writeln!(out, "\nFigures that could not be drawn:\n");
        for f in failed {
            let _ = writeln!(
                out,
                "- {}: {}",
                f.name,
                f.result.as_ref().err().map_or("", String::as_str)
            );
        }
    }
    out
}

/// The text of `report.md`: the command, the settings, the tables, the paired differences,
/// the consistency verdicts, the figures (relative links) and the diverged runs.
pub fn report_md(
    study: &crate::monte_carlo::Study,
    tally: &crate::tally::Tally,
    summary: &Summary,
    command: &str,
    figs: &[navkf_report::figure::FigureOutcome],
) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "# Monte Carlo study `{}`\n", summary.study);
    let _ = writeln!(out, "Produced by:\n\n```\n{command}\n```\n");
    let _ = writeln!(out, "## Settings\n");
    out.push_str(&settings(summary));
    let _ = writeln!(out, "\n## Results");
    out.push_str(&table(summary));
    let _ = writeln!(
        out,
        "\nRMS and sigma are of the final error over the runs that finished (SI units: rad/s, rad/s/(m/s^2), m/s^2, dimensionless); the bound is the truth-linearised Riccati (posterior Cramer-Rao) bound."
    );
    let _ = writeln!(
        out,
        "\nStep cost is the wall time of one predict + update, timed in every run with {} worker threads on {}, the hot kernels compiled for {}; it is a property of that machine and build, not of the filter alone (sharded studies mix the shards' machines).",
        rayon::current_num_threads(),
        machine(),
        navkf_dynamics::instruction_set::instruction_set()
    );
    let _ = writeln!(out, "\n## Paired differences");
    out.push_str(&paired_table(summary));
    let _ = writeln!(out, "\n## Consistency\n");
    out.push_str(&consistency(summary));
    let _ = writeln!(out, "\n## Figures");
    out.push_str(&figures(figs, summary.settings.model.kind.is_platform()));
    let _ = writeln!(out, "\n## Diverged runs\n");
    out.push_str(&diverged(study, tally));
    out
}

/// Draws the figures and writes `report.md` into `dir`. `command` is the command line that
/// produced the results. The report is written even if some figure fails; the failure is
/// then listed in it and returned.
pub fn write_report(
    study: &crate::monte_carlo::Study,
    tally: &crate::tally::Tally,
    example: Option<&crate::monte_carlo::ExampleRun>,
    dir: &std::path::Path,
    command: &str,
) -> Result<(), crate::error::StudyError> {
    let summary = crate::summary::summarize(study, tally);
    let figs = crate::plots::write_all(study, tally, &summary, example, dir);
    let md = report_md(study, tally, &summary, command, &figs);
    navkf_report::write_atomic(&dir.join("report.md"), md.as_bytes())?;
    let failed: Vec<String> = figs
        .iter()
        .filter_map(|f| f.result.as_ref().err().map(|e| format!("{}: {e}", f.name)))
        .collect();
    if failed.is_empty() {
        Ok(())
    } else {
        Err(crate::error::StudyError::Other(format!(
            "report.md written, but some figures failed: {}",
            failed.join("; ")
        )))
    }
}
