//! A MEMS-class test diagnosed with the navigation-grade defaults (no `[noise]` table): gyro
//! and accelerometer noise 218x and 267x the stated sigma. Newton's method alone stopped on
//! the ridge where a gyro noise 5900x the stated one stood in for the accelerometer's (NIS
//! 4.18 against bounds 3.89-4.11, the accelerometer "unresolved"); the grid of
//! `noise::grid` finds both levels. `examples/noise_from_afar.rs` measures this over 100 draws.

use navkf_diagnose::noise::NoiseVerdict;
use navkf_diagnose::{diagnose, Options, Verdict};
use navkf_dynamics::{
    NoiseConfig, PlatformModel, Registry, Simulator, Trajectory, TrajectoryConfig,
};
use std::sync::Arc;

#[test]
fn process_noise_hundreds_of_times_the_stated_is_found() {
    let truth = [217.9, 267.4];
    let d = NoiseConfig::default();
    let noise = NoiseConfig {
        gyro_psd: d.gyro_psd * truth[0] * truth[0],
        accel_psd: d.accel_psd * truth[1] * truth[1],
        ..d
    };
    let traj = Arc::new(Trajectory::build(&TrajectoryConfig::default()).unwrap());
    let sim = Simulator::new(
        Arc::new(PlatformModel::base(&noise)),
        traj,
        Default::default(),
        noise,
    )
    .unwrap();
    let mut ds = sim.dataset("mems", 0, &sim.run(0, 0));
    ds.noise = NoiseConfig::default();
    ds.noise_stated = false;
    ds.truth = None;
    let (diagnosis, _) = diagnose(&ds, &Registry::catalogue(), &Options::default()).unwrap();
    assert_eq!(
        diagnosis.verdict,
        Verdict::Consistent,
        "{:#?}",
        diagnosis.findings
    );
    assert!(diagnosis.best.is_none());
    let fit = diagnosis.noise.as_ref().unwrap();
    for (j, t) in truth.iter().enumerate() {
        let s = &fit.sources[j];
        assert_eq!(s.verdict, NoiseVerdict::UnderStated, "{s:?}");
        let [lo, hi] = s.sigma_ratio_interval;
        assert!(lo <= *t && *t <= hi, "{s:?} against the truth {t}");
    }
    let accel = fit.sources[1].sigma_ratio;
    assert!(
        (accel / truth[1] - 1.0).abs() < 0.2,
        "accelerometer {accel}"
    );
}
