//! `navkf plan` from the command line: one study file, several, and a sweep; and the tests
//! it plans driven by `simulate --trajectory`.

use crate::common;

use common::{navkf, text, Scratch};

fn scratch(name: &str) -> Scratch {
    Scratch::new(&format!("plan-{name}"))
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
}

#[test]
fn simulate_drives_a_written_test_and_locates_a_bad_one() {
    let dir = scratch("simulate");
    let run = |file: &std::path::Path, out: &str| {
        navkf([
            "simulate".as_ref(),
            "--trajectory".as_ref(),
            file.as_os_str(),
            "--out".as_ref(),
            dir.join(out).as_os_str(),
        ])
    };
    // A study file's [trajectory]: the identify-all laps, one hour.
    let o = run("../../studies/identify-all.toml".as_ref(), "laps");
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(text(&o.stdout).contains("3601 rows"), "{}", text(&o.stdout));
    // A misspelt key: the file, its line and column.
    let bad = dir.join("misspelt.toml");
    std::fs::write(
        &bad,
        "[trajectory]\nduration_s = 100.0\n[[trajectory.segment]]\nkind = \"hold\"\nduratio_s = 10.0\n",
    )
    .unwrap();
    let o = run(&bad, "a");
    assert_eq!(o.status.code(), Some(1));
    let e = text(&o.stderr);
    assert!(
        e.contains("misspelt.toml:3:1:") && e.contains("duratio_s"),
        "{e}"
    );
    // A value the trajectory refuses: the file and the segment's key.
    let bad = dir.join("refused.toml");
    std::fs::write(
        &bad,
        "[trajectory]\nduration_s = 100.0\n[[trajectory.segment]]\nkind = \"hold\"\nduration_s = 10.0\n\
         [[trajectory.segment]]\nkind = \"speed\"\nto = 0.0\naccel = 1.0\n",
    )
    .unwrap();
    let o = run(&bad, "b");
    assert_eq!(o.status.code(), Some(1));
    let e = text(&o.stderr);
    assert!(
        e.contains("refused.toml") && e.contains("trajectory.segment[1].to"),
        "{e}"
    );
    assert!(!dir.join("a").exists() && !dir.join("b").exists());
}

#[test]
fn a_results_folder_is_replaced_whole_and_a_users_folder_is_refused() {
    let dir = scratch("replace");
    // An earlier comparison of two designs left design-01/; planning one file replaces
    // the folder whole, so nothing of the comparison survives beside the new plan.
    let out = dir.join("out");
    let o = navkf([
        "plan".as_ref(),
        PAPER.as_ref(),
        "../../studies/identify-all.toml".as_ref(),
        "--out".as_ref(),
        out.as_os_str(),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(out.join("design-01").is_dir() && out.join("designs.json").is_file());
    let o = navkf([
        "plan".as_ref(),
        PAPER.as_ref(),
        "--out".as_ref(),
        out.as_os_str(),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(out.join("plan.md").is_file());
    assert!(!out.join("design-01").exists() && !out.join("designs.json").exists());
    // A folder of the user's own is refused before any work, and left as it was.
    let theirs = dir.join("theirs");
    std::fs::create_dir_all(&theirs).unwrap();
    std::fs::write(theirs.join("notes.txt"), "mine").unwrap();
    let o = navkf([
        "plan".as_ref(),
        PAPER.as_ref(),
        "--out".as_ref(),
        theirs.as_os_str(),
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        text(&o.stderr).contains("a folder navkf did not make"),
        "{}",
        text(&o.stderr)
    );
    let left: Vec<_> = std::fs::read_dir(&theirs).unwrap().collect();
    assert_eq!(left.len(), 1);
    // Nothing is left beside them.
    let names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert!(names.iter().all(|n| !n.contains("navkf-")), "{names:?}");
}

#[test]
fn a_diagnosis_study_is_refused_with_what_plan_reads() {
    let o = navkf(["plan", "../../studies/diagnosis.toml"]);
    assert_eq!(o.status.code(), Some(1));
    let e = text(&o.stderr);
    assert!(
        e.contains("diagnosis.toml: a diagnosis study") && e.contains("Monte Carlo study file"),
        "{e}"
    );
    assert!(!e.contains("unknown field"), "{e}");
}

/// What studies/strapdown-manoeuvres.toml's header claims, planned from its Monte Carlo twin:
/// hard starts, stops and quick turns both ways identify the forward g-sensitivity the
/// paper's drive leaves near its prior, and no level drive identifies a gyro sensing the
/// vertical rate, which stays confounded with the odometer's pitch.
#[test]
fn the_manoeuvre_drive_reveals_the_g_sensitivity_but_no_level_drive_a_tilted_gyro() {
    let dir = scratch("manoeuvres");
    let o = navkf([
        "plan".as_ref(),
        "../../studies/strapdown-effects.toml".as_ref(),
        "../../studies/designs/strapdown-manoeuvres.toml".as_ref(),
        "--out".as_ref(),
        dir.join("plan").as_os_str(),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let json = std::fs::read_to_string(dir.join("plan/designs.json")).unwrap();
    let designs: serde_json::Value = serde_json::from_str(&json).unwrap();
    let coefficient = |design: usize, name: &str| -> &serde_json::Value {
        designs["designs"][design]["coefficients"]
            .as_array()
            .unwrap()
            .iter()
            .find(|c| c["name"] == name)
            .unwrap_or_else(|| panic!("{name} missing"))
    };
    let ratio = |design: usize, name: &str| coefficient(design, name)["ratio"].as_f64().unwrap();
    let (paper, manoeuvres) = (0, 1);
    assert!(ratio(paper, "g_x") > 0.6, "{}", ratio(paper, "g_x"));
    assert!(
        ratio(manoeuvres, "g_x") < 0.3,
        "{}",
        ratio(manoeuvres, "g_x")
    );
    for design in [paper, manoeuvres] {
        for tilted in ["m_gxz", "m_gyz"] {
            assert!(
                ratio(design, tilted) > 0.8,
                "{tilted}: {}",
                ratio(design, tilted)
            );
        }
    }
    let m_gxz = &coefficient(manoeuvres, "m_gxz")["confounded"];
    assert!(
        m_gxz
            .as_array()
            .unwrap()
            .iter()
            .any(|c| c["with"] == "a_p" && c["correlation"].as_f64().unwrap() > 0.99),
        "{m_gxz}"
    );
}
