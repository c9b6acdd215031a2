//! The diagnosis figures: every one is written as PNG and SVG with text, `report.md` links
//! each of them, nothing temporary is left behind, and a dataset too short for windows or
//! whiteness lags still draws (with notes) instead of panicking.

use navkf_diagnose::{diagnose, plots, report, Options};
use navkf_dynamics::simulate::Prior;
use navkf_dynamics::{
    dataset::Dataset, NoiseConfig, PlatformModel, Registry, Simulator, Trajectory,
    TrajectoryConfig, TruthConfig,
};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
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

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("navkf-dfig-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

fn check_figure(dir: &Path, name: &str) {
    let png = std::fs::read(dir.join(format!("{name}.png")))
        .unwrap_or_else(|e| panic!("{name}.png: {e}"));
    assert!(png.starts_with(b"\x89PNG\r\n\x1a\n"), "{name}.png");
    assert!(png.len() > 5_000, "{name}.png is nearly empty");
    let svg = std::fs::read_to_string(dir.join(format!("{name}.svg"))).unwrap();
    assert!(svg.contains("<svg") && svg.contains("<text"), "{name}.svg");
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
        with: vec!["odometer-scale".into()],
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
    for f in &figs {
        assert!(f.result.is_ok(), "{}: {:?}", f.name, f.result);
        check_figure(&dir, &f.name);
    }
    // The before/after figures carry both models.
    let nis = std::fs::read_to_string(dir.join("nis.svg")).unwrap();
    assert!(nis.contains("before: base model") && nis.contains("after: with odometer-scale"));
    let md = report::markdown(&d, "navkf diagnose test", &figs);
    assert!(md.contains("## Before and after") && md.contains("| kod | not in the model |"));
    for n in expected {
        assert!(md.contains(&format!("({n}.png)")), "report.md lacks {n}");
    }
    no_temporaries(&dir);
    std::fs::remove_dir_all(&dir).unwrap();
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
    for f in &figs {
        assert!(f.result.is_ok(), "{}: {:?}", f.name, f.result);
        check_figure(&dir, &f.name);
    }
    no_temporaries(&dir);
    std::fs::remove_dir_all(&dir).unwrap();
    // One update fewer is refused, saying how many it needs.
    ds.measurements.truncate(n - 1);
    let e = diagnose(&ds, &Registry::catalogue(), &Options::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains(&format!("needs at least {n} updates")), "{e}");
}
