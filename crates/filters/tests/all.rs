//! Every integration test of the filters (`navkf-filters`) in one binary, one module per
//! file of this folder: the crate's code is compiled and linked once for them all, not once
//! per file, and their tests share the cores as one pool (`cargo test` runs binaries one
//! after another). A file whose tests need a process of their own (a process-wide switch,
//! allocator or measurement) is a `[[test]]` of its own in Cargo.toml instead, which says
//! why; `every_test_file_is_compiled` fails on a file that is neither.

mod common;
mod consistency;
mod exact_symmetry;
mod linear_model;
mod platform_agreement;
mod robustness;
mod square_root_agreement;
mod strapdown;
mod unscented_transform;
mod work_counts;

#[path = "../../dynamics/tests/common/registered.rs"]
mod registered;

#[test]
fn every_test_file_is_compiled() {
    registered::every_test_file_is_compiled(env!("CARGO_MANIFEST_DIR"));
}
