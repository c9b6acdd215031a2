//! `navkf simulate --model strapdown`: one run of the strapdown truth simulator
//! (docs/model.md, "Simulating a strapdown test") written as a strapdown dataset folder:
//! `imu.csv` (rates), `measurements.csv` (odometer speed and GPS), `dataset.toml` (`[model]`,
//! `[initial]` as the unit's own alignment states it, `[noise]` with the constraint's sigma,
//! `[prior]`) and `truth.csv`. As for the platform, the folder is checked before simulating
//! and the dataset read back before it is put in place.

use crate::simulated_dataset::readable;
use navkf_dynamics::strapdown::effect_list::StrapdownEffectList;
use navkf_dynamics::strapdown::effects::StrapdownRegistry;
use navkf_dynamics::strapdown::model::StrapdownModel;
use navkf_dynamics::strapdown::simulate::StrapdownSimulator;
use navkf_dynamics::strapdown::unit_class::UnitClass;
use navkf_dynamics::{NoiseConfig, Trajectory, TrajectoryConfig};
use navkf_report::{FolderKind, ResultsDir};
use std::path::PathBuf;
use std::sync::Arc;

/// The IMU rate when none is given, Hz (a vehicle recording's usual 100 Hz).
const DEFAULT_IMU_HZ: f64 = 100.0;
/// The constraint's sigma when none is given, m/s (a car's sideslip and bounce).
const DEFAULT_NHC_M_S: f64 = 0.1;
/// The heading sigma of `[initial]` when none is given, rad (2 deg: a heading from the
/// first GPS track).
const DEFAULT_HEADING_SIGMA: f64 = 0.035;

/// The command line's settings, as `simulate` read them.
pub struct Settings {
    pub out: PathBuf,
    pub seed: u64,
    pub run: u64,
    pub effects: String,
    pub attitude: String,
    /// `--azimuth-sigma`: the heading sigma of `[initial]`, rad.
    pub heading_sigma: Option<f64>,
    pub truth: bool,
    pub unit: Option<String>,
    pub imu_rate: Option<f64>,
    pub nhc_sigma: Option<f64>,
    /// The test to drive, read and with `--duration` applied.
    pub trajectory: TrajectoryConfig,
}

pub fn run(a: Settings) -> Result<(), Box<dyn std::error::Error>> {
    let effects =
        StrapdownEffectList::parse_entries(&[&a.effects], &StrapdownRegistry::catalogue())
            .map_err(|(_, e)| format!("--effects: {e}"))?;
    if a.attitude != "small-angle" {
        return Err(
            "--attitude: the platform's choice; the strapdown family's attitude \
                    equations are exact Euler angles, expected no --attitude"
                .into(),
        );
    }
    let unit: UnitClass = a.unit.as_deref().unwrap_or("mems").parse()?;
    let errors = unit.errors();
    let imu_hz = a.imu_rate.unwrap_or(DEFAULT_IMU_HZ);
    let nhc = a.nhc_sigma.unwrap_or(DEFAULT_NHC_M_S);
    let heading_sigma = a.heading_sigma.unwrap_or(DEFAULT_HEADING_SIGMA);
    for (flag, v) in [
        ("--imu-rate", imu_hz),
        ("--nhc-sigma", nhc),
        ("--azimuth-sigma", heading_sigma),
    ] {
        if !(v.is_finite() && v > 0.0) {
            return Err(format!("{flag} {v}: expected a finite number > 0").into());
        }
    }
    // The odometer and GPS come once a second, at one of the readings' times.
    if imu_hz < 1.0 || imu_hz.fract() != 0.0 {
        return Err(format!(
            "--imu-rate {imu_hz}: expected a whole number of readings a second (the odometer \
             and the GPS read at 1 Hz, each at a reading's time)"
        )
        .into());
    }
    if heading_sigma > std::f64::consts::PI {
        return Err(format!(
            "--azimuth-sigma {heading_sigma}: the heading's one-sigma beyond half a turn says \
             nothing; expected at most pi rad"
        )
        .into());
    }
    // Levelling from the accelerometers leaves a tilt of about the bias over g.
    let level_sigma = errors.accel_bias / navkf_dynamics::earth::STANDARD_GRAVITY;
    let traj = Arc::new(Trajectory::build(&a.trajectory)?);
    let noise = errors.noise(NoiseConfig {
        nhc_m_s: Some(nhc),
        ..NoiseConfig::default()
    });
    let model = Arc::new(
        StrapdownModel::base(&noise)
            .with_unit(errors)
            .with_effects(&effects, unit, 1.0)
            .map_err(|e| format!("--effects: {e}"))?,
    );
    let sim = StrapdownSimulator::new(model, traj, imu_hz, 1.0, errors, &effects.fixed, noise)
        .map_err(|e| {
            e.to_string()
                .replace("truth.input_rate_hz", "--imu-rate")
                .replace("trajectory.duration_s", "--duration")
                .replace("truth.coefficients.", "--effects ")
        })?;
    let staged = ResultsDir::begin_kind(&a.out, FolderKind::Dataset, &[])?;
    let run = sim.run(a.seed, a.run);
    let name = crate::simulated_dataset::dataset_name(&a.out);
    let mut ds = sim.dataset(&name, a.seed, &run, level_sigma, heading_sigma);
    if !a.truth {
        ds.truth = None;
    }
    ds.write(staged.path())?;
    readable(staged.path(), &a.out, "")?;
    staged.commit()?;
    let hidden = if effects.effects.is_empty() {
        String::new()
    } else {
        format!(", hidden: {}", effects.names().join(", "))
    };
    eprintln!(
        "wrote {} (strapdown, {} unit, IMU at {imu_hz} Hz{hidden})",
        a.out.display(),
        unit.name()
    );
    println!("{}", ds.summary());
    Ok(())
}
