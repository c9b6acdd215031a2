//! The check that every test file of a crate is compiled: with `autotests = false` (each
//! crate's Cargo.toml; its `tests/all.rs` says why) a new file in `tests/` that neither
//! `tests/all.rs` declares as a module nor Cargo.toml names as a `[[test]]` would never run,
//! silently. Shared through `#[path]` by the `tests/all.rs` of every crate.

use std::path::Path;

/// Panics naming each `tests/*.rs` file of the crate at `manifest_dir` that `tests/all.rs`
/// does not declare (`mod NAME;`) and Cargo.toml does not name (`path = "tests/NAME.rs"`).
pub fn every_test_file_is_compiled(manifest_dir: &str) {
    let root = Path::new(manifest_dir);
    let read =
        |p: &Path| std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
    let all = read(&root.join("tests/all.rs"));
    let manifest = read(&root.join("Cargo.toml"));
    let mut missing = Vec::new();
    for entry in std::fs::read_dir(root.join("tests")).expect("a tests folder") {
        let name = entry.expect("a readable tests folder").file_name();
        let name = name.to_string_lossy();
        let Some(stem) = name.strip_suffix(".rs") else {
            continue;
        };
        let declared = all.lines().any(|l| l.trim() == format!("mod {stem};"));
        let own = manifest.contains(&format!("path = \"tests/{stem}.rs\""));
        if stem != "all" && !declared && !own {
            missing.push(name.into_owned());
        }
    }
    missing.sort();
    assert!(
        missing.is_empty(),
        "{manifest_dir}/tests: {} neither a module of tests/all.rs nor a [[test]] of Cargo.toml, \
         so never compiled; declare each in tests/all.rs (`mod NAME;`)",
        missing.join(", ")
    );
}
