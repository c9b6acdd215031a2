//! A dataset without a `[noise]` table has navkf's default noise, and the diagnosis does not
//! call it the user's statement.

use crate::common;

use common::{navkf, text, Scratch};

#[test]
fn default_noise_is_not_called_stated() {
    let dir = Scratch::new("stated-noise");
    let ds = dir.join("drive");
    let o = navkf([
        "simulate",
        "--out",
        ds.to_str().unwrap(),
        "--duration",
        "2400",
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let diagnose = |out: &str| {
        let o = navkf([
            "diagnose",
            ds.to_str().unwrap(),
            "--out",
            dir.join(out).to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", text(&o.stderr));
        text(&o.stdout)
    };
    let said = "dataset.toml states no noise";
    let with_toml = diagnose("with");
    assert!(!with_toml.contains(said), "{with_toml}");
    // The recording as a user brings it: no dataset.toml.
    std::fs::remove_file(ds.join("dataset.toml")).unwrap();
    let without = diagnose("without");
    assert!(without.contains(said), "{without}");
    let report = std::fs::read_to_string(dir.join("without/report.md")).unwrap();
    assert!(report.contains(said), "the report says it too");
}
