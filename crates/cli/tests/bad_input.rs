//! Bad input to the CLI: refused before any computing, with a message naming the key or the
//! path, a non-zero exit and no panic; nothing written outside the places asked for. Files
//! that are not what they claim (devices, FIFOs, oversized or giant-lined files) are in
//! `bad_files.rs`.

use crate::common;

use common::study_files::{refused_at_once, scratch, study_file};
use common::{navkf, text};
use std::path::Path;
use std::time::Instant;

#[test]
fn a_study_name_that_is_not_a_plain_name_is_refused() {
    let dir = scratch("names");
    for (i, name) in ["\"../../escaped\"", "\"/tmp/escaped\"", "\"\"", "\"a/b\""]
        .iter()
        .enumerate()
    {
        let study = study_file(&dir, &format!("s{i}.toml"), &[("name", name)]);
        let t = Instant::now();
        let o = navkf([Path::new("study"), &study, Path::new("--quiet")]);
        refused_at_once(&o, t.elapsed(), "study.name");
    }
    assert!(!Path::new("../escaped").exists() && !Path::new("/tmp/escaped").exists());
}

#[test]
fn a_study_file_is_what_its_declared_kind_says() {
    let dir = scratch("kind");
    // An unknown kind: refused where it is written, with the kinds there are.
    let bad = dir.join("sweep-kind.toml");
    let edited = include_str!("../../../studies/paper.toml").replacen(
        "[study]\n",
        "[study]\nkind = \"sweep\"\n",
        1,
    );
    std::fs::write(&bad, edited).unwrap();
    let t = Instant::now();
    let o = navkf([Path::new("study"), &bad, Path::new("--quiet")]);
    refused_at_once(&o, t.elapsed(), "unknown variant `sweep`");
    assert!(
        text(&o.stderr).contains("sweep-kind.toml:"),
        "{}",
        text(&o.stderr)
    );
    // A Monte Carlo study that says so is read as one: its own checks run (2 runs asked,
    // example_run 0 kept), here refused on a bad name to stay fast.
    let declared = dir.join("declared.toml");
    let edited = include_str!("../../../studies/paper.toml")
        .replacen("[study]\n", "[study]\nkind = \"monte-carlo\"\n", 1)
        .replacen("name = \"paper\"", "name = \"../x\"", 1);
    std::fs::write(&declared, edited).unwrap();
    let t = Instant::now();
    let o = navkf([Path::new("study"), &declared, Path::new("--quiet")]);
    refused_at_once(&o, t.elapsed(), "study.name");
    // A diagnosis study's file is read by the diagnosis study's loader: its key `content`
    // is required there, and the error is the diagnosis loader's.
    let diagnosis = dir.join("diagnosis.toml");
    std::fs::write(
        &diagnosis,
        "[study]\nname = \"d\"\nkind = \"diagnosis\"\nseed = 1\n",
    )
    .unwrap();
    let t = Instant::now();
    let o = navkf([Path::new("study"), &diagnosis, Path::new("--quiet")]);
    refused_at_once(&o, t.elapsed(), "missing field `content`");
}

#[test]
fn an_occupied_or_unwritable_out_fails_before_the_runs() {
    let dir = scratch("out");
    let study = study_file(&dir, "s.toml", &[]);
    let file = dir.join("a-file");
    std::fs::write(&file, "x").unwrap();
    let t = Instant::now();
    let o = navkf([
        Path::new("study"),
        &study,
        Path::new("--out"),
        &file,
        Path::new("--quiet"),
    ]);
    refused_at_once(&o, t.elapsed(), "exists and is not a folder");
    let t = Instant::now();
    let o = navkf([
        Path::new("study"),
        &study,
        Path::new("--out"),
        &file.join("below"),
        Path::new("--quiet"),
    ]);
    refused_at_once(&o, t.elapsed(), "a-file");
}

#[test]
fn a_filter_listed_twice_is_refused_with_its_index() {
    let dir = scratch("twice");
    let study = study_file(&dir, "s.toml", &[("filters", "[\"ekf\", \"ekf\"]")]);
    let t = Instant::now();
    let o = navkf([Path::new("study"), &study, Path::new("--quiet")]);
    refused_at_once(&o, t.elapsed(), "study.filters[1]: `ekf` is listed twice");
}

#[test]
fn an_edited_shard_cannot_write_outside_results() {
    let dir = scratch("shard");
    let study = study_file(&dir, "s.toml", &[]);
    let shards = dir.join("shards");
    let o = navkf([
        Path::new("study"),
        &study,
        Path::new("--shard"),
        Path::new("0/1"),
        Path::new("--out"),
        &shards,
        Path::new("--quiet"),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let partial = std::fs::read_dir(&shards)
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.extension().is_some_and(|e| e == "json"))
        .expect("a shard file");
    let json = std::fs::read_to_string(&partial).unwrap();
    let edited = json.replacen("\"name\":\"paper\"", "\"name\":\"../../escaped\"", 1);
    assert!(json != edited, "the shard file holds the study's name");
    std::fs::write(&partial, edited).unwrap();
    let o = navkf([Path::new("merge"), &partial]);
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("config.study.name"), "{err}");
    assert!(!Path::new("../escaped").exists());
}

#[cfg(unix)]
#[test]
fn arguments_that_are_not_utf8_work_as_paths_or_are_refused_cleanly() {
    use std::ffi::OsStr;
    use std::os::unix::ffi::OsStrExt;
    let dir = scratch("utf8");
    let study = study_file(&dir, "s.toml", &[]);
    // A study file and an output folder whose names are not UTF-8: they work.
    let odd_study = dir.join(OsStr::from_bytes(b"s\xff.toml"));
    std::fs::copy(&study, &odd_study).unwrap();
    let odd_out = dir.join(OsStr::from_bytes(b"out\xfe"));
    let o = navkf([
        OsStr::new("study"),
        odd_study.as_os_str(),
        OsStr::new("--out"),
        odd_out.as_os_str(),
        OsStr::new("--quiet"),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let report = std::fs::read_to_string(odd_out.join("report.md")).unwrap();
    assert!(
        report.contains("s\u{fffd}.toml"),
        "the command line, shown lossily"
    );
    // A number that is not UTF-8: a clean usage error.
    let o = navkf([
        OsStr::new("study"),
        study.as_os_str(),
        OsStr::new("--runs"),
        OsStr::from_bytes(b"\xff"),
    ]);
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("invalid UTF-8"), "{err}");
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn a_bad_or_repeated_effect_is_refused_with_its_index() {
    let dir = scratch("effects");
    for (list, needle) in [
        (
            "[\"gyro-fz\", \"gyro-fzz\"]",
            "truth.effects[1]: effect: `gyro-fzz` is neither",
        ),
        ("[\"gyro-fz\", \"gyro-fz\"]", "truth.effects[1]"),
        ("[\"kod=0.002\", \"odometer-scale=0.003\"]", "given twice"),
    ] {
        let study = study_file(&dir, "s.toml", &[("effects", list)]);
        let t = Instant::now();
        let o = navkf([Path::new("study"), &study, Path::new("--quiet")]);
        refused_at_once(&o, t.elapsed(), needle);
    }
    let t = Instant::now();
    let o = navkf([
        Path::new("simulate"),
        Path::new("--out"),
        &dir.join("sim"),
        Path::new("--effects"),
        Path::new("gyro-fz,gyro-fz"),
    ]);
    refused_at_once(&o, t.elapsed(), "effect `gyro-fz` is given twice");
    assert!(!dir.join("sim").exists(), "nothing written");
    // The families' names come from ModelKind::ALL, through clap (a usage error).
    let o = navkf([
        Path::new("simulate"),
        Path::new("--out"),
        &dir.join("sim"),
        Path::new("--model"),
        Path::new("gimbal"),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o.stderr));
    assert!(text(&o.stderr).contains("[possible values: platform, strapdown]"));
    assert!(!dir.join("sim").exists(), "nothing written");
}

#[test]
fn impossible_sizes_are_refused_with_the_memory_they_need() {
    // A billion-second test, or a study's inputs recorded at 10 MHz: refused before
    // allocating, naming the setting and the memory, instead of aborting the process.
    let dir = scratch("sizes");
    let t = Instant::now();
    let o = navkf([
        Path::new("simulate"),
        Path::new("--out"),
        &dir.join("sim"),
        Path::new("--duration"),
        Path::new("1e12"),
    ]);
    refused_at_once(&o, t.elapsed(), "trajectory.duration_s");
    assert!(text(&o.stderr).contains("of memory"), "{}", text(&o.stderr));
    assert!(!dir.join("sim").exists(), "nothing written");
    let study = study_file(
        &dir,
        "s.toml",
        &[("input_rate_hz", "1.0e9"), ("rate_hz", "1.0e9")],
    );
    let t = Instant::now();
    let o = navkf([Path::new("study"), &study, Path::new("--quiet")]);
    refused_at_once(&o, t.elapsed(), "truth.input_rate_hz");
}

#[cfg(unix)]
#[test]
fn an_edited_shard_is_refused_naming_the_file_and_the_field() {
    // Two runs make one block: shard 0/2 holds none, shard 1/2 holds it and the example run.
    let dir = scratch("shard-fields");
    let study = study_file(&dir, "s.toml", &[]);
    let shards = dir.join("shards");
    for shard in ["0/2", "1/2"] {
        let o = navkf([
            Path::new("study"),
            &study,
            Path::new("--shard"),
            Path::new(shard),
            Path::new("--out"),
            &shards,
            Path::new("--quiet"),
        ]);
        assert!(o.status.success(), "{}", text(&o.stderr));
    }
    let (empty, partial) = (
        shards.join("partial-0-of-2.json"),
        shards.join("partial-1-of-2.json"),
    );
    let valid: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&partial).unwrap()).unwrap();
    let merged = dir.join("merged");
    let merge = || {
        navkf([
            Path::new("merge"),
            &empty,
            &partial,
            Path::new("--out"),
            &merged,
        ])
    };
    /// A JSON pointer into the shard file, what to do to the value there, and what merge says.
    type Edit = (&'static str, fn(&mut serde_json::Value), &'static str);
    let edits: [Edit; 4] = [
        (
            "/blocks/0/filters/0/ok",
            |v| *v = serde_json::json!(1000030),
            "blocks[0].filters[0].ok = 1000030: more than the block's 2 runs",
        ),
        (
            "/example/filters/1/estimate",
            |v| drop(v.as_array_mut().unwrap().pop()),
            "example.filters[1].estimate has",
        ),
        (
            "/blocks/0/filters",
            |v| *v = serde_json::json!([]),
            "blocks[0].filters has 0 entries; expected 3 (one per filter in study.filters)",
        ),
        (
            "/shard",
            |v| *v = serde_json::json!([1, 3]),
            "shard = (1, 3): the first shard is one of 2",
        ),
    ];
    for (at, edit, says) in edits {
        let mut v = valid.clone();
        edit(v.pointer_mut(at).expect("the shard file has the field"));
        std::fs::write(&partial, serde_json::to_string(&v).unwrap()).unwrap();
        let t = Instant::now();
        refused_at_once(
            &merge(),
            t.elapsed(),
            &format!("partial-1-of-2.json: {says}"),
        );
        assert!(!merged.exists(), "{at}: nothing written");
    }
    // The files as written merge into what the unsharded study writes.
    std::fs::write(&partial, serde_json::to_string(&valid).unwrap()).unwrap();
    let o = merge();
    assert!(o.status.success(), "{}", text(&o.stderr));
    let whole = dir.join("whole");
    let o = navkf([
        Path::new("study"),
        &study,
        Path::new("--out"),
        &whole,
        Path::new("--quiet"),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    for file in ["rms_over_time.csv", "example_run.csv"] {
        let read = |d: &Path| std::fs::read(d.join(file)).unwrap();
        assert!(read(&merged) == read(&whole), "{file} differs");
    }
}

#[test]
fn simulate_refuses_coefficients_no_sensor_has_and_truths_it_cannot_read_back() {
    let dir = scratch("unreal");
    // Beyond any real sensor: refused before simulating, the setting named.
    for (effects, needle) in [
        ("Ka0x=1e300", "Ka0x=1e300: beyond +-1.9613 m/s^2"),
        ("gps-latency=1e6", "tau=1e6 (of gps-latency): beyond +-2 s"),
        (
            "odometer-scale=-1",
            "kod=-1 (of odometer-scale): beyond +-0.2",
        ),
    ] {
        let t = Instant::now();
        let o = navkf([
            Path::new("simulate"),
            Path::new("--out"),
            &dir.join("sim"),
            Path::new("--effects"),
            Path::new(effects),
        ]);
        refused_at_once(&o, t.elapsed(), needle);
        assert!(!dir.join("sim").exists(), "{effects}: nothing written");
    }
    // A walk of the drifts no gyro has: the truth leaves the Earth, which the reader refuses;
    // so does simulate, before writing.
    for (effects, needle) in [
        ("gyro-bias-walk=1e300", "`NaN` is not finite"),
        ("gyro-bias-walk=1e-3", "is outside"),
    ] {
        let o = navkf([
            Path::new("simulate"),
            Path::new("--out"),
            &dir.join("sim"),
            Path::new("--effects"),
            Path::new(effects),
        ]);
        let err = text(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{effects}: {err}");
        assert!(
            err.contains("not one navkf reads back") && err.contains(needle),
            "{effects}: {err}"
        );
        assert!(!dir.join("sim").exists(), "{effects}: nothing written");
        let leftovers: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
        assert!(leftovers.is_empty(), "{effects}: {leftovers:?}");
    }
    // A tilt sigma the attitude equations do not hold.
    let t = Instant::now();
    let o = navkf([
        Path::new("simulate"),
        Path::new("--out"),
        &dir.join("sim"),
        Path::new("--azimuth-sigma"),
        Path::new("100"),
    ]);
    refused_at_once(
        &o,
        t.elapsed(),
        "--azimuth-sigma 100: beyond what the small-angle model",
    );
    assert!(text(&o.stderr).contains("--attitude exact"));
}

#[test]
fn diagnose_refuses_options_that_make_no_sense() {
    let dir = scratch("diagnose-options");
    let ds = dir.join("ds");
    let o = navkf([Path::new("simulate"), Path::new("--out"), &ds]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    for (args, needle) in [
        (
            &["--max-rounds", "0"][..],
            "--max-rounds 0: expected at least 1",
        ),
        (
            &["--azimuth-sigma", "100"],
            "--azimuth-sigma 100: beyond what the small-angle model holds",
        ),
        (
            &["--level-sigma", "100"],
            "--level-sigma 100: beyond what the small-angle model holds",
        ),
        (
            &["--azimuth-sigma", "100", "--attitude", "exact"],
            "--azimuth-sigma 100: beyond pi",
        ),
        (
            // Its variance overflowed the filter's first step ("step 0: initial state or
            // covariance is not finite", naming no setting).
            &["--prior", "Kg0x=1e200"],
            "--prior Kg0x: 1e200: expected a one-sigma, > 0, whose square is finite",
        ),
    ] {
        let t = Instant::now();
        let out = dir.join("out");
        let mut argv: Vec<&std::ffi::OsStr> = vec![
            "diagnose".as_ref(),
            ds.as_os_str(),
            "--out".as_ref(),
            out.as_os_str(),
        ];
        argv.extend(args.iter().map(std::ffi::OsStr::new));
        let o = navkf(argv);
        refused_at_once(&o, t.elapsed(), needle);
        assert!(!dir.join("out").exists(), "{args:?}: nothing written");
    }
    // The same tilt stated in dataset.toml.
    let toml = ds.join("dataset.toml");
    let text = std::fs::read_to_string(&toml).unwrap();
    std::fs::write(&toml, format!("{text}\n[prior]\nazimuth_rad = 100.0\n")).unwrap();
    let out = dir.join("out");
    let t = Instant::now();
    let o = navkf([
        "diagnose".as_ref(),
        ds.as_os_str(),
        "--out".as_ref(),
        out.as_os_str(),
    ]);
    refused_at_once(
        &o,
        t.elapsed(),
        "dataset.toml [prior] azimuth_rad = 100: beyond what the small-angle model holds",
    );
}
