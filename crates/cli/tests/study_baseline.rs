//! `navkf study --baseline`: passes against its own baseline, fails with a table and a
//! non-zero exit when results got worse, and refuses a baseline made with other settings.

use crate::common;

use common::{navkf, text, Scratch};
use std::path::{Path, PathBuf};

/// studies/paper.toml on a 600 s trajectory with 10 runs.
fn short_study(dir: &Path) -> PathBuf {
    let text = include_str!("../../../studies/paper.toml");
    let short: String = text
        .lines()
        .map(|l| {
            for (key, value) in [
                ("runs", "10"),
                ("duration_s", "600.0"),
                ("initial_standstill_s", "30.0"),
                ("leg_north_m", "1500.0"),
                ("leg_east_m", "1000.0"),
            ] {
                if l.starts_with(&format!("{key} =")) {
                    return format!("{key} = {value}\n");
                }
            }
            format!("{l}\n")
        })
        .collect();
    let path = dir.join("short.toml");
    std::fs::write(&path, short).unwrap();
    path
}

#[test]
fn the_guard_passes_fails_with_a_table_and_refuses_other_settings() {
    let dir = Scratch::new("cli-baseline");
    let study = short_study(&dir);
    let study = study.to_str().unwrap();
    let out = |name: &str| dir.join(name).to_str().unwrap().to_string();

    let o = navkf(["study", study, "--out", &out("base"), "--quiet"]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let baseline = out("base/summary.json");

    let o = navkf([
        "study",
        study,
        "--baseline",
        &baseline,
        "--out",
        &out("again"),
        "--quiet",
    ]);
    assert!(o.status.success(), "{}{}", text(&o.stdout), text(&o.stderr));
    assert!(
        text(&o.stdout).contains("accuracy guard passed"),
        "{}",
        text(&o.stdout)
    );

    // A baseline whose EKF estimated Kg0x ten times better than this code does.
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&baseline).unwrap()).unwrap();
    let rms = &mut v["filters"]["ekf"]["final_rms"]["Kg0x"];
    *rms = serde_json::json!(rms.as_f64().unwrap() / 10.0);
    let better = out("better.json");
    std::fs::write(&better, v.to_string()).unwrap();
    let o = navkf([
        "study",
        study,
        "--baseline",
        &better,
        "--out",
        &out("worse"),
        "--quiet",
    ]);
    assert!(!o.status.success(), "the guard must fail");
    let stdout = text(&o.stdout);
    assert!(stdout.contains("| ekf | RMS Kg0x |"), "{stdout}");
    assert!(!stdout.contains("| standard_ukf | RMS Kg0x |"), "{stdout}");
    assert!(
        text(&o.stderr).contains("accuracy guard: 1 of 48 checks worse"),
        "{}",
        text(&o.stderr)
    );

    // Another run count: not the baseline's study.
    let o = navkf([
        "study",
        study,
        "--runs",
        "5",
        "--baseline",
        &baseline,
        "--out",
        &out("x"),
        "--quiet",
    ]);
    assert!(!o.status.success());
    assert!(
        text(&o.stderr).contains("study.runs: 10 in the baseline, 5 now"),
        "{}",
        text(&o.stderr)
    );
    // Not with a shard.
    let o = navkf([
        "study",
        study,
        "--shard",
        "0/2",
        "--baseline",
        &baseline,
        "--out",
        &out("x"),
        "--quiet",
    ]);
    assert!(!o.status.success());
    assert!(text(&o.stderr).contains("--shard"), "{}", text(&o.stderr));
}
