//! Every integration test of the model families, effects, trajectories, simulation and datasets (`navkf-dynamics`) in one binary, one module per
//! file of this folder: the crate's code is compiled and linked once for them all, not once
//! per file, and their tests share the cores as one pool (`cargo test` runs binaries one
//! after another). A file whose tests need a process of their own (a process-wide switch,
//! allocator or measurement) is a `[[test]]` of its own in Cargo.toml instead, which says
//! why; `every_test_file_is_compiled` fails on a file that is neither.

mod analytic;
mod attitude;
mod batch_propagation;
mod common;
mod dataset;
mod dataset_config;
mod dataset_files;
mod dataset_rows;
mod dataset_truth;
mod declared_effects;
mod docs_examples;
mod fuzz;
mod implausible;
mod input_file;
mod jacobians;
mod kitti;
mod model_doc;
mod model_sanity;
mod plausibility;
mod propagate_points;
mod rk4_order;
mod segments;
mod sensor_faults;
mod simulate;
mod spec_equations;
mod strapdown;
mod strapdown_dataset;
mod strapdown_effects;
mod strapdown_simulate;
mod trajectory;
mod user_effect;

#[path = "common/registered.rs"]
mod registered;

#[test]
fn every_test_file_is_compiled() {
    registered::every_test_file_is_compiled(env!("CARGO_MANIFEST_DIR"));
}
