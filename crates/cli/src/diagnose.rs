//! `navkf diagnose`: compare a model with a dataset and rank the missing effects.

use navkf_dynamics::dataset::Dataset;
use navkf_dynamics::Registry;
use navkf_study::diagnose::{diagnose, report, Options};
use navkf_study::output::write_atomic;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    /// The dataset folder.
    dataset: PathBuf,
    /// Effects to switch on in the model under test, comma-separated (`odometer-scale,gps-latency`).
    #[arg(long, default_value = "")]
    with: String,
    /// Output folder (default results/diagnose/<dataset name>).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Width of the sliding NIS windows, s.
    #[arg(long, default_value_t = 300.0)]
    window: f64,
}

pub fn run(a: Args) -> Result<(), Box<dyn std::error::Error>> {
    let ds = Dataset::read(&a.dataset)?;
    let registry = Registry::catalogue();
    let with: Vec<String> = a
        .with
        .split(',')
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .map(String::from)
        .collect();
    for w in &with {
        registry.build(w)?;
    }
    if !(a.window.is_finite() && a.window > 0.0) {
        return Err(format!("--window {}: expected a duration > 0 s", a.window).into());
    }
    let opts = Options {
        with,
        window_s: a.window,
        ..Default::default()
    };
    let out = a
        .out
        .unwrap_or_else(|| PathBuf::from("results/diagnose").join(&ds.name));
    let started = std::time::Instant::now();
    let (d, fits) = diagnose(&ds, &registry, &opts)?;
    let figures = navkf_study::diagnose::plots::draw(&d, &fits, &out);
    for f in &figures {
        if let Err(e) = &f.result {
            eprintln!("warning: figure {} not drawn: {e}", f.name);
        }
    }
    let command = std::env::args().collect::<Vec<_>>().join(" ");
    write_atomic(
        &out.join("diagnosis.json"),
        serde_json::to_string_pretty(&d)?.as_bytes(),
    )?;
    write_atomic(
        &out.join("report.md"),
        report::markdown(&d, &command, &figures).as_bytes(),
    )?;
    eprintln!(
        "diagnosed {} in {:.1} s ({} candidates), wrote {}",
        ds.name,
        started.elapsed().as_secs_f64(),
        d.candidates.len(),
        out.display()
    );
    println!(
        "verdict: {}{}",
        d.verdict,
        d.best
            .as_ref()
            .map(|b| format!(" (missing: {b})"))
            .unwrap_or_default()
    );
    for f in &d.findings {
        println!("- {f}");
    }
    println!(
        "\n{:<18} {:>12} {:>10} {:>9} {:>6}",
        "candidate", "dLL", "BIC gain", "removed", "named"
    );
    for c in &d.candidates {
        println!(
            "{:<18} {:>12.1} {:>10.1} {:>8.0}% {:>6}",
            c.effect,
            c.delta_loglik,
            c.bic_gain,
            100.0 * c.excess_removed,
            if c.supported { "yes" } else { "" }
        );
    }
    Ok(())
}
