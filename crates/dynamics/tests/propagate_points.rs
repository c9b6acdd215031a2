//! `SystemModel::propagate_points` (what the filters call for sigma points) agrees with
//! `propagate_generic` point by point, including each point's own noise values.
//!
//! Catches: points or noise values sliced at the wrong stride, scratch too small or shared
//! state leaking from one point to the next.

use crate::common;

use common::*;
use navkf_dynamics::SystemModel;
use navkf_dynamics::{InputWindow, NoiseConfig, PlatformModel, PropagationScratch, Registry};
use rand::Rng;

#[test]
fn propagate_points_matches_point_by_point() {
    let reg = Registry::catalogue();
    let model = PlatformModel::new(
        reg.build_all(&reg.names()).unwrap(),
        &NoiseConfig::default(),
    )
    .unwrap();
    let n = model.dim();
    let nw = model.noise_channels().len();
    let mut rng = rng(80);
    let count = 5;
    let mut points: Vec<f64> = (0..count)
        .flat_map(|_| random_state(&model, &mut rng))
        .collect();
    let noise: Vec<f64> = (0..count * nw)
        .map(|_| rng.gen_range(-1e-6..1e-6))
        .collect();
    let mut w = InputWindow::default();
    for j in 0..=4 {
        w.push_linear(0.25 * j as f64, random_input(&mut rng));
    }
    let mut expected = points.clone();
    for (i, x) in expected.chunks_exact_mut(n).enumerate() {
        propagate(&model, x, Some(&noise[i * nw..(i + 1) * nw]), &w);
    }
    let mut scratch = PropagationScratch::default();
    model.propagate_points(&mut points, Some(&noise), &w, &mut scratch);
    assert_eq!(points, expected);
}
