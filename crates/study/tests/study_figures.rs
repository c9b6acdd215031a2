//! Every figure kind of a study, drawn on a small case, checked for what a reviewer would
//! reject: each is written as PNG and SVG, is not blank, keeps its text on the canvas, off
//! other text and off the data (measured with the bundled font, [`figure_text`], shared with
//! the diagnosis figures' test); the x axis of a sweep's and a plan comparison's figures names
//! the swept setting in words, in its display unit, with ticks in that unit; and every
//! report links the PNGs (the SVGs are not committed).
//!
//! The case: the paper's three filters on a 900 s path with two effects in truth and filters
//! (so coefficient names and units are as long as a real study's), 3 runs; its plan; sweeps
//! of 3 points of 2 runs, of the initial azimuth error (in rad, shown in deg) and of a turn
//! rate of a test of one's own (its key says "deg", it is deg/s); and plan comparisons over
//! the GPS noise and over the speed a segment of that test reaches (its key, `to`, says no
//! unit).

use crate::common;

// Shared with the diagnosis figures' test; not every function of it is used here.
#[allow(dead_code)]
#[path = "../../diagnose/tests/figure_text/mod.rs"]
mod figure_text;

use common::Scratch;
use navkf_dynamics::state::NAV_DIM;
use navkf_study::config::SweepSection;
use navkf_study::output::write_results;
use navkf_study::plan::{plan, Comparison, Design};
use navkf_study::plan_output::{write_comparison, write_plan};
use navkf_study::sweep::{self, points, SweepSummary};
use navkf_study::{Study, StudyConfig};
use std::path::Path;

const COMMAND: &str = "cargo test -p navkf-study --test all study_figures";

/// A short study: the paper's filters, odometer scale and GPS latency in truth and filters.
const STUDY: &str = r#"
[study]
name = "figures"
runs = 3
seed = 7
filters = ["ekf", "standard_ukf", "simplified_ukf"]
series_every_s = 10.0
example_run = 0

[trajectory]
duration_s = 900.0
leg_north_m = 1500.0
leg_east_m = 1000.0

[truth]
effects = ["odometer-scale", "gps-latency"]

[filter]
effects = ["odometer-scale", "gps-latency"]
"#;

/// A test of one's own (docs/study-files.md's example, shortened), to sweep a setting inside
/// a list of segments.
const OWN_TEST: &str = r#"
[study]
name = "own-test"
runs = 2
seed = 1
filters = ["ekf"]

[trajectory]
duration_s = 900.0

[[trajectory.segment]]
kind = "hold"
duration_s = 60.0

[[trajectory.segment]]
kind = "speed"
to = 15.0
accel = 1.0

[[trajectory.segment]]
kind = "cruise"
distance_m = 1500.0

[[trajectory.segment]]
kind = "turn"
angle_deg = 90.0
rate_deg = 6.0

[[trajectory.segment]]
kind = "slalom"
count = 3
angle_deg = 20.0
rate_deg = 10.0

[[trajectory.segment]]
kind = "figure_eight"
rate_deg = 10.0

[truth]
effects = ["odometer-scale"]

[filter]
effects = ["odometer-scale"]
"#;

/// A fresh folder for one test's figures, removed when the test ends unless
/// `NAVKF_KEEP_FIGURES` is set (to look at the figures).
fn scratch(name: &str) -> Scratch {
    let dir = Scratch::new(&format!("sfig-{name}"));
    if std::env::var_os("NAVKF_KEEP_FIGURES").is_some() {
        dir.kept()
    } else {
        dir
    }
}

/// Width and height of a PNG, from its header.
fn png_size(png: &[u8]) -> (u32, u32) {
    assert!(png.starts_with(b"\x89PNG\r\n\x1a\n") && &png[12..16] == b"IHDR");
    let be = |b: &[u8]| u32::from_be_bytes([b[0], b[1], b[2], b[3]]);
    (be(&png[16..20]), be(&png[20..24]))
}

/// The size of a PNG of `size` pixels, all white, written as the figures are.
fn blank_png_len(size: (u32, u32)) -> usize {
    use plotters::prelude::*;
    // A name of its own per call: the tests run in parallel threads and ask for the same sizes.
    static CALLS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let call = CALLS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let path = std::env::temp_dir().join(format!(
        "navkf-sfig-blank-{}x{}-{}-{call}.png",
        size.0,
        size.1,
        std::process::id()
    ));
    {
        let root = BitMapBackend::new(&path, size).into_drawing_area();
        root.fill(&WHITE).unwrap();
        root.present().unwrap();
    }
    let len = std::fs::metadata(&path).unwrap().len() as usize;
    std::fs::remove_file(&path).unwrap();
    len
}

/// Whether `svg` draws data: a line or a box in a colour (the grid, the axes, the bounds are
/// grey or black; the notes are coloured, but text).
fn draws_data(svg: &str) -> bool {
    let coloured = |tag: &str, attr: &str| {
        let key = format!(" {attr}=\"#");
        let hex = tag
            .find(&key)
            .and_then(|i| tag.get(i + key.len()..i + key.len() + 6));
        hex.is_some_and(|h| !(h[0..2] == h[2..4] && h[2..4] == h[4..6]))
    };
    svg.split('<').any(|tag| {
        (tag.starts_with("polyline ") && coloured(tag, "stroke"))
            || (tag.starts_with("rect ") && coloured(tag, "fill"))
    })
}

/// Checks figure `name` in `dir`: a PNG and an SVG of the same size, with text, that draw
/// data (a coloured line or box), the PNG well above a blank one. Returns its SVG and what
/// of its text does not fit (off the canvas, over other text, over the data), so that a test
/// reports every figure's misfits at once.
fn check_figure(dir: &Path, name: &str) -> (String, Vec<String>) {
    let png = std::fs::read(dir.join(format!("{name}.png")))
        .unwrap_or_else(|e| panic!("{name}.png: {e}"));
    let svg = std::fs::read_to_string(dir.join(format!("{name}.svg")))
        .unwrap_or_else(|e| panic!("{name}.svg: {e}"));
    assert!(svg.contains("<svg") && svg.contains("<text"), "{name}.svg");
    let (w, h) = figure_text::canvas(&svg);
    let size = png_size(&png);
    assert_eq!(
        (size.0 as f64, size.1 as f64),
        (w, h),
        "{name}: PNG and SVG"
    );
    // A blank canvas compresses to almost nothing; axes, text and curves do not.
    let blank = blank_png_len(size);
    assert!(
        png.len() > 3 * blank,
        "{name}.png is nearly blank: {} bytes, a blank one {blank}",
        png.len()
    );
    assert!(draws_data(&svg), "{name}.svg draws no data");
    let mut misfits = figure_text::misfits(&svg, 2.0);
    misfits.extend(figure_text::over_data(&svg, 2.0));
    let misfits = misfits.iter().map(|m| format!("{name}: {m}")).collect();
    (svg, misfits)
}

/// Checks every figure of `names` in `dir`, failing with all their misfits; returns their
/// SVGs.
fn check_figures(dir: &Path, names: &[String]) -> Vec<String> {
    let mut misfits = Vec::new();
    let mut svgs = Vec::new();
    for n in names {
        let (svg, m) = check_figure(dir, n);
        svgs.push(svg);
        misfits.extend(m);
    }
    assert!(
        misfits.is_empty(),
        "text that does not fit:\n{}",
        misfits.join("\n")
    );
    svgs
}

/// The report `md` (in `dir`) links each of `names` as a PNG that exists, and no SVG.
fn links_pngs(dir: &Path, md: &str, names: &[String]) {
    let file = dir.display();
    for n in names {
        assert!(
            md.contains(&format!("]({n}.png)")),
            "{file}: no link to {n}.png"
        );
        assert!(dir.join(format!("{n}.png")).is_file());
    }
    assert!(!md.contains(".svg)"), "{file}: links an SVG");
    let unasked = navkf_report::figure::embeds_without_question(md);
    assert!(
        unasked.is_empty(),
        "{file}: figures embedded without the question they answer: {unasked:?}"
    );
}

fn no_temporaries(dir: &Path) {
    for e in std::fs::read_dir(dir).unwrap() {
        let name = e.unwrap().file_name().to_string_lossy().into_owned();
        assert!(!name.contains(".tmp"), "temporary file left behind: {name}");
    }
}

/// The name of the x axis of a one-row figure: the unturned text nearest the bottom edge.
fn x_axis_name(svg: &str) -> String {
    let (_, h) = figure_text::canvas(svg);
    figure_text::texts(svg)
        .into_iter()
        .filter(|t| t.x.1 - t.x.0 > t.y.1 - t.y.0 && t.y.1 <= h + 2.0)
        .filter(|t| t.text.parse::<f64>().is_err())
        .max_by(|a, b| a.y.1.total_cmp(&b.y.1))
        .map(|t| t.text)
        .unwrap_or_default()
}

/// The numbers on the x axis: the numeric texts on the row just above its name (of every
/// panel of the figure: its panels share the swept axis).
fn x_ticks(svg: &str, name: &str) -> Vec<f64> {
    let boxes = figure_text::texts(svg);
    let Some(axis) = boxes.iter().find(|t| t.text == name) else {
        return Vec::new();
    };
    let row: Vec<&figure_text::TextBox> = boxes
        .iter()
        .filter(|t| t.y.1 <= axis.y.0 + 2.0 && t.y.1 > axis.y.0 - 40.0)
        .filter(|t| t.text.parse::<f64>().is_ok())
        .collect();
    row.iter().filter_map(|t| t.text.parse().ok()).collect()
}

/// The x axis of figure `svg` (named `fig`, swept over `key` = `values`): named in words
/// (no dotted key, no underscore, no index in brackets), ending in `(unit)`, and its ticks
/// spanning the values times `factor` (the display unit's), not the key's own.
fn swept_axis_is_readable(
    fig: &str,
    svg: &str,
    key: &str,
    unit: &str,
    values: &[f64],
    factor: f64,
) {
    let name = x_axis_name(svg);
    assert!(
        !name.contains(key) && !name.contains('_') && !name.contains('[') && !name.contains('.'),
        "{fig}: x axis {name:?} is the key {key:?}, not words"
    );
    assert!(
        name.ends_with(&format!("({unit})")),
        "{fig}: x axis {name:?} is not in {unit}"
    );
    let ticks = x_ticks(svg, &name);
    assert!(ticks.len() >= 2, "{fig}: x ticks {ticks:?}");
    let (lo, hi) = ticks
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), t| {
            (a.min(*t), b.max(*t))
        });
    let (vlo, vhi) = values
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v * factor), b.max(v * factor))
        });
    // The ticks lie inside the axis, which spans the values: in the display unit, the
    // highest tick is above the lowest value and the lowest below the highest.
    assert!(
        hi >= vlo && lo <= vhi,
        "{fig}: x ticks {ticks:?} do not span the values {vlo}..{vhi} {unit}"
    );
}

#[test]
fn a_study_and_its_plan_draw_every_figure_legibly() {
    let study = Study::new(StudyConfig::parse(STUDY).unwrap()).unwrap();
    let mut example = None;
    let blocks = study
        .run_blocks(0..study.block_count(), &|_| {}, |rec| {
            example = Some(study.example_of(rec))
        })
        .expect("not interrupted");
    let tally = navkf_study::output::fold(&blocks);
    let dir = scratch("study");
    write_results(&study, &tally, example.as_ref(), &dir).unwrap();
    let mut names: Vec<String> = [
        "estimates_all",
        "rms_over_time",
        "nees_nis_over_time",
        "step_cost",
    ]
    .map(String::from)
    .into();
    names.extend(
        study.names[NAV_DIM..]
            .iter()
            .map(|n| format!("estimates_{n}")),
    );
    assert!(
        study.names.len() > NAV_DIM + 13,
        "the effects' coefficients are estimated"
    );
    let svgs = check_figures(&dir, &names);
    // The legends name every filter in full.
    for (n, svg) in names.iter().zip(&svgs) {
        let texts: Vec<String> = figure_text::texts(svg)
            .into_iter()
            .map(|t| t.text)
            .collect();
        for f in ["ekf", "standard_ukf", "simplified_ukf"] {
            let label = match n.as_str() {
                "rms_over_time" => format!("{f} RMS error"),
                n if n.starts_with("estimates") => format!("{f} estimate"),
                _ => f.to_string(),
            };
            assert!(texts.contains(&label), "{n}: no legend {label:?}");
        }
    }
    let md = std::fs::read_to_string(dir.join("report.md")).unwrap();
    links_pngs(&dir, &md, &names);
    no_temporaries(&dir);

    // Its plan: plan_sigma, one panel per unit, each curve named on itself.
    let p = plan(&study).unwrap();
    let pdir = dir.join("plan");
    let figs = write_plan(&p, &pdir, COMMAND, true).unwrap();
    let drawn: Vec<String> = figs.iter().map(|f| f.name.clone()).collect();
    assert_eq!(drawn, ["plan_sigma"]);
    assert!(figs.iter().all(|f| f.result.is_ok()), "{figs:?}");
    let svg = &check_figures(&pdir, &drawn)[0];
    let texts: Vec<String> = figure_text::texts(svg)
        .into_iter()
        .map(|t| t.text)
        .collect();
    for c in &p.coefficients {
        assert!(
            texts.contains(&c.name),
            "plan_sigma: {} is not named",
            c.name
        );
    }
    // Its panels are named in the units the other figures use, not the model's SI.
    let captions: Vec<&String> = texts
        .iter()
        .filter(|t| t.starts_with("coefficients"))
        .collect();
    assert!(captions.len() >= 5, "plan_sigma: {captions:?}");
    for si in ["rad/s", "1", "m/s^2", "rad/s/(m/s^2)"] {
        let caption = format!("coefficients in {si}");
        assert!(!texts.contains(&caption), "plan_sigma: {caption:?}");
    }
    let md = std::fs::read_to_string(pdir.join("plan.md")).unwrap();
    links_pngs(&pdir, &md, &drawn);
    no_temporaries(&pdir);
}

/// Runs a sweep of `key` over `values` in `config` (2 runs a point) into `dir`, as `navkf
/// study` does; returns the sweep's figures.
fn run_sweep(mut config: StudyConfig, key: &str, values: &[f64], dir: &Path) -> Vec<String> {
    config.study.runs = 2;
    config.sweep = Some(SweepSection {
        key: key.into(),
        values: values.to_vec(),
    });
    let mut rows = Vec::new();
    let mut state_count = 0;
    for (i, c) in points(&config).unwrap().into_iter().enumerate() {
        let study = Study::new(c).unwrap();
        state_count = study.names.len();
        let mut example = None;
        let tally = study
            .run_folded(0..study.block_count(), &|_| {}, |rec| {
                example = Some(study.example_of(rec))
            })
            .expect("not interrupted");
        rows.push(sweep::write_point(i, values[i], &study, &tally, example.as_ref(), dir).unwrap());
    }
    let summary = SweepSummary {
        study: config.study.name.clone(),
        key: key.into(),
        model: config.model.kind,
        runs: config.study.runs,
        filters: config.study.filters.clone(),
        points: rows,
    };
    let figs = sweep::write_sweep(&summary, state_count, dir, COMMAND).unwrap();
    assert!(figs.iter().all(|f| f.result.is_ok()), "{figs:?}");
    let names: Vec<String> = figs.iter().map(|f| f.name.clone()).collect();
    assert_eq!(names, ["sweep_accuracy", "sweep_nees"]);
    let md = std::fs::read_to_string(dir.join("sweep.md")).unwrap();
    links_pngs(dir, &md, &names);
    no_temporaries(dir);
    names
}

#[test]
fn sweeps_draw_against_the_setting_in_words_and_units() {
    // An angle in rad shown in deg, and a turn rate whose key says only "deg".
    for (name, text, key, values, unit, factor) in [
        (
            "azimuth",
            STUDY,
            "truth.initial_tilt.azimuth_rad",
            &[3e-3, 3e-2, 3e-1][..],
            "deg",
            180.0 / std::f64::consts::PI,
        ),
        (
            "turn-rate",
            OWN_TEST,
            "trajectory.segment[5].rate_deg",
            &[4.0, 10.0, 30.0][..],
            "deg/s",
            1.0,
        ),
    ] {
        let dir = scratch(&format!("sweep-{name}"));
        let names = run_sweep(StudyConfig::parse(text).unwrap(), key, values, &dir);
        let svgs = check_figures(&dir, &names);
        for (n, svg) in names.iter().zip(&svgs) {
            swept_axis_is_readable(n, svg, key, unit, values, factor);
        }
    }
}

/// Plans every point of a sweep of `key` over `values` in `config` as designs compared in
/// `dir`, as `navkf plan` does; returns the comparison's figures.
fn compare(mut config: StudyConfig, key: &str, values: &[f64], dir: &Path) -> Vec<String> {
    config.sweep = Some(SweepSection {
        key: key.into(),
        values: values.to_vec(),
    });
    let designs = points(&config)
        .unwrap()
        .into_iter()
        .zip(values)
        .enumerate()
        .map(|(i, (c, v))| {
            let p = plan(&Study::new(c).unwrap()).unwrap();
            let figs = write_plan(&p, &dir.join(format!("design-{i:02}")), COMMAND, false);
            assert!(
                figs.unwrap().is_empty(),
                "a sweep's designs draw no figure each"
            );
            Design::of(format!("{key} = {v}"), Some(*v), &p)
        })
        .collect();
    let c = Comparison {
        key: Some(key.into()),
        model: navkf_dynamics::ModelKind::Platform,
        designs,
    };
    let figs = write_comparison(&c, dir, COMMAND).unwrap();
    assert!(figs.iter().all(|f| f.result.is_ok()), "{figs:?}");
    let names: Vec<String> = figs.iter().map(|f| f.name.clone()).collect();
    assert_eq!(names, ["plan_sweep"]);
    let md = std::fs::read_to_string(dir.join("designs.md")).unwrap();
    links_pngs(dir, &md, &names);
    no_temporaries(dir);
    names
}

#[test]
fn plan_comparisons_draw_against_the_setting_in_words_and_units() {
    for (name, text, key, values, unit) in [
        ("gps", STUDY, "noise.gps_m", &[0.5, 3.0, 30.0][..], "m"),
        (
            "speed",
            OWN_TEST,
            "trajectory.segment[1].to",
            &[3.0, 10.0, 30.0][..],
            "m/s",
        ),
    ] {
        let dir = scratch(&format!("designs-{name}"));
        let names = compare(StudyConfig::parse(text).unwrap(), key, values, &dir);
        let svgs = check_figures(&dir, &names);
        swept_axis_is_readable(&names[0], &svgs[0], key, unit, values, 1.0);
    }
}
