//! Data that cannot be what they claim, through the command line: a clean simulated dataset
//! edited as a user's file might be (a GPS step, a fix across the pole, free fall, an input
//! gap, absurd stated noise, the pole, a stuck odometer). `diagnose` answers each with the
//! verdict `implausible data` (exit 0), names no effect, and says where; `inspect` lists them.

use crate::common;

use common::{navkf, text, Scratch};
use std::path::Path;

fn scratch(name: &str) -> Scratch {
    Scratch::new(&format!("implausible-{name}"))
}

/// Rewrites every data row of `file` in `dir` through `edit` (cells as strings; `None` drops
/// the row).
fn edit_rows(dir: &Path, file: &str, edit: impl Fn(Vec<String>) -> Option<Vec<String>>) {
    let path = dir.join(file);
    let body = std::fs::read_to_string(&path).unwrap();
    let mut lines = body.lines();
    let mut out = format!("{}\n", lines.next().unwrap());
    for line in lines {
        if let Some(cells) = edit(line.split(',').map(str::to_owned).collect()) {
            out.push_str(&cells.join(","));
            out.push('\n');
        }
    }
    std::fs::write(&path, out).unwrap();
}

fn t(cells: &[String]) -> f64 {
    cells[0].parse().unwrap()
}

fn copy(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        std::fs::copy(e.path(), to.join(e.file_name())).unwrap();
    }
}

#[test]
fn every_implausible_dataset_gets_the_verdict_and_where() {
    let dir = scratch("diagnose");
    let clean = dir.join("clean");
    let o = navkf([
        "simulate".as_ref(),
        "--out".as_ref(),
        clean.as_os_str(),
        "--effects".as_ref(),
        "gps-latency=0.2".as_ref(),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let shift = (10_000.0f64 / 6.37e6).to_degrees();
    type Edit = Box<dyn Fn(&Path)>;
    let cases: Vec<(&str, Edit, &str, &[&str])> = vec![
        (
            "gps-step",
            Box::new(move |d| {
                edit_rows(d, "measurements.csv", |mut c| {
                    if t(&c) >= 300.0 {
                        c[3] = (c[3].parse::<f64>().unwrap() + shift).to_string();
                    }
                    Some(c)
                })
            }),
            "position-jump",
            &["measurements.csv: columns `lat_deg,lon_deg`", "t = 300 s"],
        ),
        (
            "across-the-pole",
            Box::new(|d| {
                edit_rows(d, "measurements.csv", |mut c| {
                    if t(&c) == 300.0 {
                        c[4] = (c[4].parse::<f64>().unwrap() - 180.0).to_string();
                    }
                    Some(c)
                })
            }),
            "position-jump",
            &["t = 300 s", "across the pole"],
        ),
        (
            "free-fall",
            Box::new(|d| {
                edit_rows(d, "inputs.csv", |c| {
                    let s = t(&c);
                    Some(if (100.0..=130.0).contains(&s) {
                        vec![c[0].clone(), "0".into(), "0".into(), "0".into()]
                    } else {
                        c
                    })
                })
            }),
            "off-ground",
            &[
                "inputs.csv: columns `f_e,f_n,f_u`",
                "t = 100 s",
                "free fall",
            ],
        ),
        (
            "input-gap",
            Box::new(|d| {
                edit_rows(d, "inputs.csv", |c| {
                    let s = t(&c);
                    (!(100.0 < s && s < 400.0)).then_some(c)
                })
            }),
            "input-gap",
            &["inputs.csv: column `t`", "from t = 100 s to t = 400 s"],
        ),
        (
            "accel-psd",
            Box::new(|d| {
                let p = d.join("dataset.toml");
                let s = std::fs::read_to_string(&p).unwrap();
                let s = s.replace("accel_psd = 1e-8", "accel_psd = 1e300");
                std::fs::write(&p, s).unwrap();
            }),
            "noise-beyond-sensors",
            &[
                "dataset.toml: `noise.accel_psd` = 1e300",
                "above any real sensor",
            ],
        ),
        (
            "gps-sigma",
            Box::new(|d| {
                let p = d.join("dataset.toml");
                let s = std::fs::read_to_string(&p).unwrap();
                let s = s.replace("gps_m = 3.0", "gps_m = 1e-12");
                std::fs::write(&p, s).unwrap();
            }),
            "noise-beyond-sensors",
            &["`noise.gps_m` = 1e-12", "below any real sensor"],
        ),
        (
            "pole",
            Box::new(|d| {
                edit_rows(d, "measurements.csv", |mut c| {
                    c[3] = "90".into();
                    Some(c)
                })
            }),
            "near-pole",
            &["column `lat_deg`", "latitude 90 deg", "t = 1 s"],
        ),
        (
            "stuck-odometer",
            Box::new(|d| {
                edit_rows(d, "measurements.csv", |mut c| {
                    c[1] = "300".into();
                    c[2] = "0".into();
                    Some(c)
                })
            }),
            "odometer-too-fast",
            &["columns `v_e,v_n`", "up to 300 m/s", "road vehicle"],
        ),
    ];
    let mut failures = Vec::new();
    for (name, edit, kind, words) in cases {
        let ds = dir.join(name);
        copy(&clean, &ds);
        edit(&ds);
        let out = dir.join(format!("{name}-out"));
        let o = navkf([
            "diagnose".as_ref(),
            ds.as_os_str(),
            "--out".as_ref(),
            out.as_os_str(),
        ]);
        let (stdout, stderr) = (text(&o.stdout), text(&o.stderr));
        let json = std::fs::read_to_string(out.join("diagnosis.json")).unwrap_or_default();
        let report = std::fs::read_to_string(out.join("report.md")).unwrap_or_default();
        let mut problems = Vec::new();
        if o.status.code() != Some(0) || stderr.contains("panicked") {
            problems.push(format!("exit {:?}", o.status.code()));
        }
        if !stdout.starts_with("verdict: implausible data\n") || stdout.contains("missing:") {
            problems.push("verdict".into());
        }
        for w in words {
            if !stdout.contains(w) || !report.contains(w) {
                problems.push(format!("lacks {w:?}"));
            }
        }
        if !json.contains("\"verdict\": \"implausible data\"")
            || !json.contains("\"effects\": []")
            || !json.contains(&format!("\"kind\": \"{kind}\""))
        {
            problems.push("diagnosis.json".into());
        }
        // First in the report, before the verdict.
        match (report.find("IMPLAUSIBLE"), report.find("**Verdict")) {
            (Some(a), Some(b)) if a < b => {}
            _ => problems.push("the report does not list it before the verdict".into()),
        }
        let o = navkf(["inspect".as_ref(), ds.as_os_str()]);
        if !o.status.success() || !text(&o.stderr).contains("implausible: ") {
            problems.push("inspect does not list it".into());
        }
        if !problems.is_empty() {
            failures.push(format!("{name}: {problems:?}\n{stdout}\n{stderr}"));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

#[test]
fn a_stuck_odometer_is_not_called_gps_longitude_in_radians() {
    let dir = scratch("odometer");
    let ds = dir.join("ds");
    let o = navkf(["simulate".as_ref(), "--out".as_ref(), ds.as_os_str()]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    edit_rows(&ds, "measurements.csv", |mut c| {
        c[1] = "300".into();
        c[2] = "0".into();
        Some(c)
    });
    let o = navkf(["inspect".as_ref(), ds.as_os_str()]);
    let said = text(&o.stderr) + &text(&o.stdout);
    assert!(said.contains("odometer reads up to 300 m/s"), "{said}");
    assert!(
        !said.contains("radians") && !said.contains("milliseconds"),
        "{said}"
    );
}
