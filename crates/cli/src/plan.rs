//! `navkf plan`: which coefficients the test of a study file identifies, predicted from the
//! information along it, without Monte Carlo (see `navkf_study::plan`).

use navkf_study::output::write_atomic;
use navkf_study::plan::{plan, table};
use navkf_study::{Study, StudyConfig};
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct Args {
    /// The study file whose test to plan, e.g. studies/paper.toml.
    file: PathBuf,
    /// Output folder (default results/plan/<study name>).
    #[arg(long)]
    out: Option<PathBuf>,
}

pub fn run(a: Args) -> Result<(), Box<dyn std::error::Error>> {
    let config = StudyConfig::load(&a.file)?;
    if let Some(s) = &config.sweep {
        return Err(format!(
            "{}: the study sweeps `{}`; plan one design at a time for now (sweeps in plan \
             are not built yet)",
            a.file.display(),
            s.key
        )
        .into());
    }
    let out = a
        .out
        .unwrap_or_else(|| PathBuf::from("results/plan").join(&config.study.name));
    navkf_study::output::check_output_dir(&out)?;
    let started = std::time::Instant::now();
    let study = Study::new(config)?;
    let p = plan(&study)?;
    let text = table(&p);
    let figure = navkf_study::plots::plan::draw(&p, &out);
    if let Err(e) = &figure.result {
        eprintln!("warning: figure {} not drawn: {e}", figure.name);
    }
    write_atomic(
        &out.join("plan.json"),
        serde_json::to_string_pretty(&p)?.as_bytes(),
    )?;
    let command = navkf_study::output::command_line();
    let mut md = format!(
        "# Plan of `{}`\n\nCommand: `{command}`\n\nPredicted by the truth-linearised bound \
         along run 0 of the study's seed ({:.0} s test), without Monte Carlo.\n\n```text\n{text}```\n",
        p.study, p.duration_s
    );
    if figure.result.is_ok() {
        md.push_str(&format!("\n![{}](plan_sigma.svg)\n", figure.caption));
    }
    write_atomic(&out.join("plan.md"), md.as_bytes())?;
    print!("{text}");
    eprintln!(
        "planned {} in {:.2} s, wrote {}",
        p.study,
        started.elapsed().as_secs_f64(),
        out.display()
    );
    Ok(())
}
