//! Effects declared in TOML, from the command line: `effects --effects-file --check` lists and
//! checks them; `simulate --effects-file` writes a dataset that carries its declarations, which
//! `diagnose` then names without the file (and with it, no conflict); a study file's
//! `[[effect]]` tables reach `study` and `plan`; a malformed file is refused by file and key.

use crate::common;

use common::{navkf, text, Scratch};
use std::ffi::OsStr;
use std::path::{Path, PathBuf};

const EFFECTS: &str = "../../studies/effects/examples.toml";

fn scratch(name: &str) -> Scratch {
    Scratch::new(&format!("declared-{name}"))
}

/// Runs `navkf diagnose DATA --out DIR/refused ARGS...`, which must be refused (exit 1, no
/// results folder), and returns what it said.
fn diagnose_refused(data: &Path, dir: &Path, args: &[&OsStr]) -> String {
    let out = dir.join("refused");
    let mut all: Vec<&OsStr> = vec!["diagnose".as_ref(), data.as_os_str(), "--out".as_ref()];
    all.push(out.as_os_str());
    all.extend_from_slice(args);
    let o = navkf(&all);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o.stdout));
    assert!(!out.exists());
    text(&o.stderr)
}

/// A copy of effects file `from` in `dir` with `old` replaced by `new`: the same effects
/// declared otherwise.
fn declared_otherwise(dir: &Path, from: &str, old: &str, new: &str) -> PathBuf {
    let path = dir.join("clashing.toml");
    let text = std::fs::read_to_string(from).unwrap();
    assert!(text.contains(old), "{from}: no `{old}`");
    std::fs::write(&path, text.replace(old, new)).unwrap();
    path
}

#[test]
fn effects_lists_and_checks_declared_effects() {
    let o = navkf(["effects", "--effects-file", EFFECTS, "--check"]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let out = text(&o.stdout);
    for line in [
        "drag: v_x' += kd v_x, v_y' += kd v_y (velocity-proportional drag; kd < 0 drags)",
        "  kd        1/s             5.000e-5",
    ] {
        assert!(out.lines().any(|l| l == line), "no `{line}` in:\n{out}");
    }
    for name in ["drag", "gps-offset", "gps-latency"] {
        let prefix = format!("  {name}: partials agree with finite differences");
        assert!(
            out.lines().any(|l| l.starts_with(&prefix)),
            "{name}:\n{out}"
        );
    }
    assert!(out.contains("worst entry d(v_x')/d(v_x)") || out.contains("worst entry d(v_y')/d("));
}

#[test]
fn a_malformed_effects_file_is_refused_by_file_and_key() {
    let dir = scratch("bad");
    let file = dir.join("bad.toml");
    let good = std::fs::read_to_string(EFFECTS).unwrap();
    std::fs::write(
        &file,
        good.replacen("feature = \"v_x\"", "feature = \"velocity\"", 1),
    )
    .unwrap();
    for args in [
        vec!["effects", "--effects-file"],
        vec!["simulate", "--out", "unused", "--effects-file"],
    ] {
        let o = navkf(args.iter().map(|s| s.as_ref()).chain([file.as_os_str()]));
        assert_eq!(o.status.code(), Some(1), "{args:?}");
        let err = text(&o.stderr);
        assert!(
            err.contains(
                "bad.toml: effect[0].rates[0].feature: `velocity`: expected one of 1, f_x"
            ),
            "{err}"
        );
    }
    // A typo in a key is the parser's, with its line.
    std::fs::write(&file, good.replacen("sigma = 5e-5", "sigmaa = 5e-5", 1)).unwrap();
    let o = navkf([
        "effects".as_ref(),
        "--effects-file".as_ref(),
        file.as_os_str(),
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert!(text(&o.stderr).contains("bad.toml:"), "{}", text(&o.stderr));
    assert!(!PathBuf::from("unused").exists());
}

#[test]
fn a_dataset_simulated_with_a_declared_effect_is_diagnosed_with_it() {
    let dir = scratch("loop");
    let data = dir.join("drag");
    let o = navkf([
        "simulate".as_ref(),
        "--out".as_ref(),
        data.as_os_str(),
        "--effects-file".as_ref(),
        EFFECTS.as_ref(),
        "--effects".as_ref(),
        "drag,kd=-2e-4".as_ref(),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let toml = std::fs::read_to_string(data.join("dataset.toml")).unwrap();
    assert!(
        toml.contains("name = \"drag\"") && !toml.contains("gps-offset"),
        "{toml}"
    );
    // Without the file: dataset.toml declares it. With the same file: no conflict.
    for with_file in [false, true] {
        let out = dir.join(format!("diagnosis-{with_file}"));
        let mut args = vec![
            "diagnose".into(),
            data.clone().into_os_string(),
            "--out".into(),
            out.into_os_string(),
        ];
        if with_file {
            args.extend(["--effects-file".into(), EFFECTS.into()]);
        }
        let o = navkf(&args);
        assert!(o.status.success(), "{}", text(&o.stderr));
        let report = text(&o.stdout);
        assert!(
            report.contains("The evidence supports adding `drag`"),
            "{report}"
        );
        // The file's second effect is a candidate only when the file is given.
        assert_eq!(report.contains("gps-offset"), with_file, "{report}");
    }
    // A file declaring the dataset's `drag` otherwise is refused, naming the file.
    let clashing = declared_otherwise(&dir, EFFECTS, "sigma = 5e-5", "sigma = 6e-5");
    let err = diagnose_refused(
        &data,
        &dir,
        &["--effects-file".as_ref(), clashing.as_os_str()],
    );
    assert!(
        err.contains(&format!(
            "{}: its effects clash with the dataset's",
            clashing.display()
        )) && err.contains("`drag` is an effect already"),
        "{err}"
    );
}

#[test]
fn a_study_file_declares_effects_for_study_and_plan() {
    let dir = scratch("study");
    let file = dir.join("drag-study.toml");
    let declarations = std::fs::read_to_string(EFFECTS).unwrap();
    std::fs::write(
        &file,
        format!(
            "[study]\nname = \"drag-study\"\nruns = 4\nseed = 7\nfilters = [\"ekf\", \
             \"simplified_ukf\"]\n\n[trajectory]\nduration_s = 900.0\nleg_north_m = 1500.0\nleg_east_m = 1000.0\n\n[truth]\neffects = \
             [\"drag\"]\n\n[filter]\neffects = [\"drag\"]\n\n{declarations}"
        ),
    )
    .unwrap();
    let out = dir.join("study");
    let o = navkf([
        "study".as_ref(),
        file.as_os_str(),
        "--out".as_ref(),
        out.as_os_str(),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert!(
        summary.contains("\"kd\""),
        "kd is not among the summary's states"
    );
    let plan = dir.join("plan");
    let o = navkf([
        "plan".as_ref(),
        file.as_os_str(),
        "--out".as_ref(),
        plan.as_os_str(),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(text(&o.stdout).contains("kd"), "{}", text(&o.stdout));
}

const STRAPDOWN_EFFECTS: &str = "../../studies/effects/strapdown-examples.toml";

/// A 900-s drive on short legs, as a `[trajectory]` table.
const SHORT_DRIVE: &str =
    "[trajectory]\nduration_s = 900.0\nleg_north_m = 1500.0\nleg_east_m = 1000.0\n";

/// Strapdown effects declared with `places`: listed, hidden in a simulated dataset whose
/// `dataset.toml` carries them, tried by `diagnose` without the file, and refused with a
/// file of the other family.
#[test]
fn strapdown_effects_are_declared_with_places() {
    let o = navkf([
        "effects",
        "--model",
        "strapdown",
        "--effects-file",
        STRAPDOWN_EFFECTS,
        "--check",
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let out = text(&o.stdout);
    assert!(
        out.lines()
            .any(|l| l == "  n_axy     rad             2.000e-3"),
        "{out}"
    );
    // `--check`: every effect, catalogued and declared, through the chain rule of its places.
    for name in [
        "gyro-scale",
        "gps-latency",
        "mount-yaw",
        "mast",
        "accel-xy-skew",
    ] {
        let prefix = format!("  {name}: partials agree with finite differences at 16");
        assert!(
            out.lines().any(|l| l.starts_with(&prefix)),
            "{name}:\n{out}"
        );
    }
    let dir = scratch("strapdown");
    let drive = dir.join("drive.toml");
    std::fs::write(&drive, SHORT_DRIVE).unwrap();
    let data = dir.join("skew");
    let o = navkf([
        "simulate".as_ref(),
        "--model".as_ref(),
        "strapdown".as_ref(),
        "--trajectory".as_ref(),
        drive.as_os_str(),
        "--out".as_ref(),
        data.as_os_str(),
        "--effects-file".as_ref(),
        STRAPDOWN_EFFECTS.as_ref(),
        "--effects".as_ref(),
        "accel-xy-skew,n_axy=5e-3".as_ref(),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let toml = std::fs::read_to_string(data.join("dataset.toml")).unwrap();
    assert!(
        toml.contains("name = \"accel-xy-skew\"")
            && toml.contains("place = \"E_a[y][x]\"")
            && !toml.contains("mast"),
        "{toml}"
    );
    let truth = std::fs::read_to_string(data.join("truth.csv")).unwrap();
    assert!(
        truth.lines().next().unwrap().ends_with(",n_axy"),
        "{truth:.200}"
    );
    // dataset.toml declares it: a candidate of the diagnosis without the file.
    let o = navkf([
        "diagnose".as_ref(),
        data.as_os_str(),
        "--out".as_ref(),
        dir.join("diagnosis").as_os_str(),
        "--max-rounds".as_ref(),
        "1".as_ref(),
        "--noise".as_ref(),
        "stated".as_ref(),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let report = text(&o.stdout);
    assert!(
        report.lines().any(|l| l.starts_with("accel-xy-skew ")),
        "{report}"
    );
    // A file of the other family is refused, naming both.
    for (file, says) in [
        (EFFECTS, "declares platform effects"),
        (STRAPDOWN_EFFECTS, "declares strapdown effects"),
    ] {
        let platform = file == STRAPDOWN_EFFECTS;
        let target = if platform {
            let p = dir.join("platform");
            let o = navkf([
                "simulate".as_ref(),
                "--trajectory".as_ref(),
                drive.as_os_str(),
                "--out".as_ref(),
                p.as_os_str(),
            ]);
            assert!(o.status.success(), "{}", text(&o.stderr));
            p
        } else {
            data.clone()
        };
        let err = diagnose_refused(&target, &dir, &["--effects-file".as_ref(), file.as_ref()]);
        assert!(
            err.contains(says) && err.contains("expected a file of"),
            "{err}"
        );
    }
    // A file declaring the dataset's effect otherwise is refused, naming the file and the key.
    let clashing = declared_otherwise(&dir, STRAPDOWN_EFFECTS, "sigma = 2e-3", "sigma = 3e-3");
    let err = diagnose_refused(
        &data,
        &dir,
        &["--effects-file".as_ref(), clashing.as_os_str()],
    );
    assert!(
        err.contains(&format!(
            "{}: effect[2].name: `accel-xy-skew`",
            clashing.display()
        )),
        "{err}"
    );
    // Two effects in one place cannot share a model: refused with the settings, before a fit.
    let err = diagnose_refused(
        &data,
        &dir,
        &[
            "--with".as_ref(),
            "accel-misalignment,accel-xy-skew".as_ref(),
        ],
    );
    assert!(
        err.contains("--with: ")
            && err.contains("E_a[x][y], which `m_axy` of `accel-misalignment`"),
        "{err}"
    );
}

/// A strapdown study file's `[[effect]]` tables reach `study` and `plan`.
#[test]
fn a_strapdown_study_file_declares_effects() {
    let dir = scratch("strapdown-study");
    let file = dir.join("skew-study.toml");
    let declarations = std::fs::read_to_string(STRAPDOWN_EFFECTS).unwrap();
    std::fs::write(
        &file,
        format!(
            "[study]\nname = \"skew-study\"\nruns = 2\nseed = 7\nfilters = [\"ekf\"]\n\n\
             [model]\nkind = \"strapdown\"\n\n{SHORT_DRIVE}\n\
             [truth]\neffects = [\"accel-xy-skew\"]\n\n[filter]\neffects = \
             [\"accel-xy-skew\"]\n\n{declarations}"
        ),
    )
    .unwrap();
    let o = navkf([
        "study".as_ref(),
        file.as_os_str(),
        "--out".as_ref(),
        dir.join("study").as_os_str(),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let summary = std::fs::read_to_string(dir.join("study").join("summary.json")).unwrap();
    assert!(
        summary.contains("\"n_axy\""),
        "n_axy is not among the states"
    );
    let o = navkf([
        "plan".as_ref(),
        file.as_os_str(),
        "--out".as_ref(),
        dir.join("plan").as_os_str(),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(text(&o.stdout).contains("n_axy"), "{}", text(&o.stdout));
}
