//! The diagnosis figures: every one is written as PNG and SVG with text, is not blank, keeps
//! its text on the canvas and off other text (measured with the bundled font,
//! [`figure_text`]), `report.md` links each of them, nothing temporary is left behind, and a
//! dataset too short for windows or whiteness lags still draws (with notes) instead of
//! panicking. The two tests draw every kind: before and after with the truth (the path in two
//! panels, the coefficient errors), and a base model alone (the path in one).

use crate::figure_text;
#[path = "../../dynamics/tests/common/scratch.rs"]
mod scratch;

use navkf_diagnose::{diagnose, plots, report, Options};
use navkf_dynamics::simulate::Prior;
use navkf_dynamics::{
    dataset::Dataset, NoiseConfig, PlatformModel, Registry, Simulator, Trajectory,
    TrajectoryConfig, TruthConfig,
};
use scratch::Scratch;
use std::collections::BTreeMap;
use std::path::Path;
use std::sync::Arc;

/// A 2400 s vehicle test whose truth has a 0.5 % odometer scale error.
fn odometer_dataset() -> Dataset {
    let noise = NoiseConfig::default();
    let fx = Registry::catalogue()
        .build_all(&["odometer-scale"])
        .unwrap();
    let model = Arc::new(PlatformModel::new(fx, &noise).unwrap());
    let traj = Arc::new(Trajectory::build(&TrajectoryConfig::default()).unwrap());
    let mut coefficients = BTreeMap::new();
    coefficients.insert("kod".to_string(), Prior::fixed(0.005));
    let cfg = TruthConfig {
        coefficients,
        ..Default::default()
    };
    let sim = Simulator::new(model, traj, cfg, noise).unwrap();
    let run = sim.run(11, 0);
    sim.dataset("figures", 11, &run)
}

fn scratch(name: &str) -> Scratch {
    Scratch::new(&format!("dfig-{name}"))
}

/// Checks figure `name` in `dir`: a PNG and an SVG with text that draw data. Returns what
/// of its text does not fit (off the canvas, over other text, over the data), so that a test
/// reports every figure's misfits at once.
fn check_figure(dir: &Path, name: &str) -> Vec<String> {
    let png = std::fs::read(dir.join(format!("{name}.png")))
        .unwrap_or_else(|e| panic!("{name}.png: {e}"));
    assert!(png.starts_with(b"\x89PNG\r\n\x1a\n"), "{name}.png");
    assert!(png.len() > 5_000, "{name}.png is nearly empty");
    let svg = std::fs::read_to_string(dir.join(format!("{name}.svg"))).unwrap();
    assert!(svg.contains("<svg") && svg.contains("<text"), "{name}.svg");
    assert!(
        figure_text::has_coloured_mark(&svg),
        "{name}.svg draws no data"
    );
    let mut misfits = figure_text::misfits(&svg, 2.0);
    misfits.extend(figure_text::over_data(&svg, 2.0));
    misfits.iter().map(|m| format!("{name}: {m}")).collect()
}

/// Draws-checks every figure of `figs` in `dir`, failing with all their misfits.
fn check_figures(dir: &Path, figs: &[navkf_report::figure::FigureOutcome]) {
    let mut misfits = Vec::new();
    for f in figs {
        assert!(f.result.is_ok(), "{}: {:?}", f.name, f.result);
        misfits.extend(check_figure(dir, &f.name));
    }
    assert!(
        misfits.is_empty(),
        "text that does not fit:\n{}",
        misfits.join("\n")
    );
}

fn no_temporaries(dir: &Path) {
    for e in std::fs::read_dir(dir).unwrap() {
        let name = e.unwrap().file_name().to_string_lossy().into_owned();
        assert!(!name.contains(".tmp"), "temporary file left behind: {name}");
    }
}

#[test]
fn before_and_after_figures_are_drawn_and_linked() {
    let ds = odometer_dataset();
    let opts = Options {
        // Two effects, so that labels are as long as the walk-through's.
        with: vec!["odometer-scale".into(), "gps-latency".into()],
        ..Default::default()
    };
    let (d, fits) = diagnose(&ds, &Registry::catalogue(), &opts).unwrap();
    assert!(fits.before.is_some(), "--with keeps the base model's fit");
    let dir = scratch("after");
    let figs = plots::draw(&d, &fits, &dir);
    let expected = [
        "measured_vs_predicted",
        "innovations",
        "innovations_before",
        "path_misfit",
        "nis",
        "whiteness",
        "coefficient_errors",
    ];
    let names: Vec<&str> = figs.iter().map(|f| f.name.as_str()).collect();
    assert_eq!(names, expected);
    check_figures(&dir, &figs);
    // The errors are in the sigma each coefficient started from (the priors table's, else
    // the typical one), which no fit's widening changes.
    for c in &d.model.coefficients {
        let s0 = plots::errors::initial_sigma(&d, &fits, &c.name).unwrap();
        if let Some(p) = d.priors.iter().find(|p| p.name == c.name) {
            assert_eq!(s0, p.sigma, "{}", c.name);
        }
        for s in d.before.iter().chain([&d.model]) {
            if let Some(q) = s.coefficients.iter().find(|q| q.name == c.name) {
                assert!(q.prior_sigma >= s0 * (1.0 - 1e-12), "{}", c.name);
            }
        }
    }
    // The before/after figures carry both models, and the path shows the base model's misfit.
    let path = std::fs::read_to_string(dir.join("path_misfit.svg")).unwrap();
    assert!(path.contains("base model (no effects)") && path.contains("final model"));
    let nis = std::fs::read_to_string(dir.join("nis.svg")).unwrap();
    assert!(nis.contains("before: base model") && nis.contains("after: with odometer-scale"));
    let md = report::markdown(&d, "navkf diagnose test", &figs);
    assert!(md.contains("## Before and after") && md.contains("| kod | not in the model |"));
    for n in expected {
        assert!(md.contains(&format!("({n}.png)")), "report.md lacks {n}");
    }
    let unasked = navkf_report::figure::embeds_without_question(&md);
    assert!(
        unasked.is_empty(),
        "embedded without a question: {unasked:?}"
    );
    no_temporaries(&dir);
}

#[test]
fn a_dataset_too_short_for_windows_still_draws() {
    // The fewest updates a diagnosis judges: shorter than one 300-s NIS window.
    let n = navkf_diagnose::MIN_UPDATES;
    let mut ds = odometer_dataset();
    ds.measurements.truncate(n);
    let t_end = ds.measurements[n - 1].t;
    ds.inputs.retain(|s| s.t <= t_end + 0.5);
    ds.truth = None;
    let (d, fits) = diagnose(&ds, &Registry::catalogue(), &Options::default()).unwrap();
    assert!(d.model.nis_windows.is_empty());
    let dir = scratch("short");
    let figs = plots::draw(&d, &fits, &dir);
    assert!(
        figs.iter().all(|f| f.name != "coefficient_errors"),
        "no truth, no error figure"
    );
    check_figures(&dir, &figs);
    no_temporaries(&dir);
    // One update fewer is refused, saying how many it needs.
    ds.measurements.truncate(n - 1);
    let e = diagnose(&ds, &Registry::catalogue(), &Options::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains(&format!("needs at least {n} updates")), "{e}");
}
