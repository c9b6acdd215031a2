//! Every integration test of the command line (`navkf-cli`) in one binary, one module per
//! file of this folder: the crate's code is compiled and linked once for them all, not once
//! per file, and their tests share the cores as one pool (`cargo test` runs binaries one
//! after another). A file whose tests need a process of their own (a process-wide switch,
//! allocator or measurement) is a `[[test]]` of its own in Cargo.toml instead, which says
//! why; `every_test_file_is_compiled` fails on a file that is neither.

mod attitude;
mod bad_files;
mod bad_input;
mod closed_pipe;
mod common;
mod corpus;
mod declared_effects;
mod effects;
mod folders;
mod implausible;
mod import_cycles;
mod merge;
mod plan;
mod shard_diagnosis_study;
mod stated_noise;
mod strapdown;
mod study_baseline;
mod study_files_doc;

#[path = "../../dynamics/tests/common/registered.rs"]
mod registered;

#[test]
fn every_test_file_is_compiled() {
    registered::every_test_file_is_compiled(env!("CARGO_MANIFEST_DIR"));
}
