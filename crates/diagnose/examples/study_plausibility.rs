//! The false-alarm rate of the data checks on clean data: every dataset of a diagnosis study
//! (`studies/diagnosis.toml` unless another is given: simulated vehicle tests hiding effects,
//! pairs, effects outside the catalogue and mis-stated noise) through
//! `Dataset::implausibilities`, with how close the clean data come to the bounds. None may be
//! implausible: the study's diagnoses would change.
//!
//!     cargo run --release -p navkf-diagnose --example study_plausibility [-- STUDY]

use navkf_diagnose::diagnosis_study::{content, DiagnosisStudyConfig};
use navkf_dynamics::dataset::Dataset;
use navkf_dynamics::earth::normal_gravity;
use navkf_dynamics::Trajectory;
use rayon::prelude::*;
use std::sync::Arc;

/// Smallest and largest `|f| / g`, fastest odometer reading (m/s; a strapdown unit's odometer
/// reads a speed), largest input interval (s).
fn extremes(ds: &Dataset) -> [f64; 4] {
    let lat = ds
        .measurements
        .iter()
        .find_map(|m| m.position_deg)
        .map_or(45.0, |p| p[0]);
    let g = normal_gravity(lat.to_radians().sin());
    let f: Vec<f64> = ds
        .inputs
        .iter()
        .map(|i| {
            let f = ds.specific_force(i);
            f[0].hypot(f[1]).hypot(f[2]) / g
        })
        .collect();
    [
        f.iter().copied().fold(f64::INFINITY, f64::min),
        f.iter().copied().fold(0.0, f64::max),
        ds.measurements
            .iter()
            .filter_map(|m| {
                m.velocity
                    .map(|v| v[0].hypot(v[1]))
                    .or(m.speed.map(f64::abs))
            })
            .fold(0.0, f64::max),
        ds.inputs
            .windows(2)
            .map(|w| w[1].t - w[0].t)
            .fold(0.0, f64::max),
    ]
}

fn main() {
    let path = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "studies/diagnosis.toml".into());
    let config = DiagnosisStudyConfig::load(std::path::Path::new(&path)).unwrap();
    let planned = content::plan(&config).unwrap();
    let trajectory = Arc::new(Trajectory::build(&config.trajectory).unwrap());
    let rows: Vec<(usize, Vec<String>, [f64; 4])> = planned
        .par_iter()
        .map(|p| {
            let ds = content::simulate(&config, &trajectory, p).unwrap();
            let found = ds
                .implausibilities()
                .iter()
                .map(|i| i.to_string())
                .collect();
            (p.index, found, extremes(&ds))
        })
        .collect();
    let flagged: Vec<_> = rows.iter().filter(|r| !r.1.is_empty()).collect();
    println!("{} datasets, {} implausible", rows.len(), flagged.len());
    for (i, found, _) in flagged.iter().take(10) {
        println!("dataset {i}: {found:?}");
    }
    let fold =
        |k: usize, f: fn(f64, f64) -> f64, start: f64| rows.iter().map(|r| r.2[k]).fold(start, f);
    println!(
        "|f|/g from {:.3} to {:.3}; fastest odometer reading {:.1} m/s; longest input interval \
         {:.3} s",
        fold(0, f64::min, f64::INFINITY),
        fold(1, f64::max, 0.0),
        fold(2, f64::max, 0.0),
        fold(3, f64::max, 0.0)
    );
}
