//! `navkf plan` from the command line: one study file, several, and a sweep.

mod common;

use common::{navkf, text};
use std::path::PathBuf;

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("navkf-plan-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

const PAPER: &str = "../../studies/paper.toml";
const STRESS: &str = "../../studies/stress-10x.toml";

#[test]
fn plan_writes_one_design_or_compares_several() {
    let dir = scratch("cli");
    let one = dir.join("one");
    let o = navkf([
        "plan".as_ref(),
        PAPER.as_ref(),
        "--out".as_ref(),
        one.as_os_str(),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(text(&o.stdout).contains("identified (final sigma below 0.5 of the prior): 3 of 13"));
    for f in ["plan.json", "plan.md", "plan_sigma.svg", "plan_sigma.png"] {
        assert!(one.join(f).is_file(), "{f}");
    }

    let two = dir.join("two");
    let o = navkf([
        "plan".as_ref(),
        PAPER.as_ref(),
        STRESS.as_ref(),
        "--out".as_ref(),
        two.as_os_str(),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let md = std::fs::read_to_string(two.join("designs.md")).unwrap();
    assert!(md.contains("| paper | 3 of 13 |"), "{md}");
    assert!(md.contains("| stress-10x |"), "{md}");
    assert!(two.join("design-01/plan.json").is_file());
    assert!(two.join("design-01/plan_sigma.png").is_file());

    let sweep = dir.join("sweep.toml");
    let text_file = std::fs::read_to_string(PAPER).unwrap()
        + "\n[sweep]\nkey = \"noise.gps_m\"\nvalues = [1.0, 3.0, 10.0, 30.0]\n";
    std::fs::write(&sweep, text_file).unwrap();
    let out = dir.join("sweep");
    let o = navkf([
        "plan".as_ref(),
        sweep.as_os_str(),
        "--out".as_ref(),
        out.as_os_str(),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let md = std::fs::read_to_string(out.join("designs.md")).unwrap();
    assert!(md.contains("| noise.gps_m = 30 |"), "{md}");
    assert!(out.join("plan_sweep.svg").is_file());
    assert!(!out.join("design-00/plan_sigma.svg").exists());
    let json = std::fs::read_to_string(out.join("designs.json")).unwrap();
    assert!(json.contains("\"key\": \"noise.gps_m\""));

    let o = navkf([
        "plan".as_ref(),
        sweep.as_os_str(),
        PAPER.as_ref(),
        "--out".as_ref(),
        dir.join("both").as_os_str(),
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        text(&o.stderr).contains("compare several files or sweep one"),
        "{}",
        text(&o.stderr)
    );
    let _ = std::fs::remove_dir_all(&dir);
}
