//! Files users name are regular files of bounded size, or refused with a message naming the
//! file and what was expected; a giant CSV line is refused before it is buffered; a TOML
//! error names the line and column and quotes only a short cut of the line.

use navkf_dynamics::dataset::Dataset;
use navkf_dynamics::input_file::{read_text, TextFile, CSV_LINE_MAX_BYTES, TOML_MAX_BYTES};

use crate::common::scratch;

use scratch::Scratch;

/// A fresh, empty folder under the system temp dir, unique to this process and `tag`,
/// removed when the test ends.
fn temp_folder(tag: &str) -> Scratch {
    Scratch::new(&format!("input-file-test-{tag}"))
}

fn assert_mentions(message: &str, parts: &[&str]) {
    for p in parts {
        assert!(message.contains(p), "message lacks {p:?}:\n{message}");
    }
}

const MEAS_OK: &str = "t,v_e,v_n,lat_deg,lon_deg\n1,0.5,0.1,45.78,126.63\n";

fn inputs_text(n: usize) -> String {
    let mut s = String::from("t,f_e,f_n,f_u\n");
    for i in 0..n {
        s += &format!("{},0.001,-0.002,9.8\n", i as f64 / 10.0);
    }
    s
}

#[test]
fn a_device_or_a_folder_is_refused_naming_what_was_expected() {
    if std::path::Path::new("/dev/zero").exists() {
        let e = read_text("/dev/zero".as_ref(), &TextFile::STUDY)
            .unwrap_err()
            .to_string();
        assert_mentions(
            &e,
            &[
                "/dev/zero",
                "not a regular file",
                "expected a study file (TOML)",
            ],
        );
    }
    let dir = temp_folder("folder");
    let e = read_text(&dir, &TextFile::SHARD).unwrap_err().to_string();
    assert_mentions(
        &e,
        &["not a regular file (a folder)", "expected a shard file"],
    );
}

#[test]
fn a_file_over_its_limit_is_refused_by_size_unread() {
    let dir = temp_folder("large");
    let path = dir.join("study.toml");
    let file = std::fs::File::create(&path).unwrap();
    // Sparse: no disk used, and nothing read.
    file.set_len(TOML_MAX_BYTES + 1).unwrap();
    drop(file);
    let e = read_text(&path, &TextFile::STUDY).unwrap_err().to_string();
    assert_mentions(&e, &["study.toml", "16.777 MB", "at most 16 MiB"]);
    // The same in a dataset folder, as its dataset.toml.
    std::fs::write(dir.join("inputs.csv"), inputs_text(50)).unwrap();
    std::fs::write(dir.join("measurements.csv"), MEAS_OK).unwrap();
    std::fs::rename(&path, dir.join("dataset.toml")).unwrap();
    let e = Dataset::read(&dir).unwrap_err().to_string();
    assert_mentions(&e, &["dataset.toml", "at most 16 MiB"]);
}

#[test]
fn text_that_is_not_utf8_is_refused_with_its_line() {
    let dir = temp_folder("utf8");
    let path = dir.join("s.toml");
    std::fs::write(&path, b"[study]\nname = \"\xff\"\n").unwrap();
    let e = read_text(&path, &TextFile::STUDY).unwrap_err().to_string();
    assert_mentions(
        &e,
        &["s.toml", "not UTF-8", "line 2", "expected a study file"],
    );
    let utf16: Vec<u8> = "[study]\n"
        .encode_utf16()
        .flat_map(|u| u.to_le_bytes())
        .collect();
    std::fs::write(&path, utf16).unwrap();
    let e = read_text(&path, &TextFile::STUDY).unwrap_err().to_string();
    assert_mentions(&e, &["UTF-16"]);
}

#[test]
fn a_csv_line_over_the_limit_is_refused_with_its_number() {
    let dir = temp_folder("csv");
    std::fs::write(dir.join("measurements.csv"), MEAS_OK).unwrap();
    // A 20 MB header: refused on line 1, not buffered (the CLI test runs it in a process).
    let header = format!("t,{}\n0,0,0,9.8\n", "f".repeat(20 << 20));
    std::fs::write(dir.join("inputs.csv"), header).unwrap();
    let e = Dataset::read(&dir).unwrap_err().to_string();
    assert_mentions(&e, &["inputs.csv:1", "longer than 64 KiB"]);
    assert!(e.len() < 1000, "{} bytes", e.len());
    // A row one byte over the limit on line 3; one at the limit is read (and refused for
    // its cell, which is no number).
    for (extra, line) in [
        (1, "inputs.csv:3: column `-`"),
        (0, "inputs.csv:3: column `f_e`"),
    ] {
        let cell = "7".repeat(CSV_LINE_MAX_BYTES - "0.1,,0,9.8".len() + extra);
        let inputs = format!("t,f_e,f_n,f_u\n0,0,0,9.8\n0.1,{cell},0,9.8\n0.2,0,0,9.8\n");
        std::fs::write(dir.join("inputs.csv"), inputs).unwrap();
        let e = Dataset::read(&dir).unwrap_err().to_string();
        assert_mentions(&e, &[line]);
    }
}

#[test]
fn a_toml_error_on_a_megabyte_line_quotes_a_short_cut_of_it() {
    let dir = temp_folder("toml");
    std::fs::write(dir.join("inputs.csv"), inputs_text(50)).unwrap();
    std::fs::write(dir.join("measurements.csv"), MEAS_OK).unwrap();
    let line = format!("gps_m = 3.0 {}", "z".repeat(1 << 20));
    std::fs::write(dir.join("dataset.toml"), format!("[noise]\n{line}\n")).unwrap();
    let e = Dataset::read(&dir).unwrap_err().to_string();
    assert!(
        e.len() < 1000,
        "{} bytes:\n{}",
        e.len(),
        &e[..2000.min(e.len())]
    );
    assert_mentions(
        &e,
        &[
            "dataset.toml:2:13: TOML parse error",
            "gps_m = 3.0 zzz",
            "...",
        ],
    );
}
