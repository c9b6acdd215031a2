//! The strapdown family's simulation (docs/model.md, "Simulating a strapdown test"): `imu.csv`
//! (rates), `measurements.csv` (odometer speed and GPS), `dataset.toml` (`[model]`,
//! `[initial]` as the unit's own alignment states it, `[noise]` with the constraint's sigma,
//! `[prior]`) and `truth.csv`.

use crate::error::StudyError;
use crate::simulation::request::{Ready, SimulationRequest};
use navkf_dynamics::strapdown::body_motion::MAX_SIGMA_M_S;
use navkf_dynamics::strapdown::effect_list::StrapdownEffectList;
use navkf_dynamics::strapdown::effects::StrapdownRegistry;
use navkf_dynamics::strapdown::model::StrapdownModel;
use navkf_dynamics::strapdown::simulate::StrapdownSimulator;
use navkf_dynamics::strapdown::unit_class::UnitClass;
use navkf_dynamics::{Attitude, NoiseConfig, Trajectory};
use navkf_report::SettingNames;
use std::sync::Arc;

/// The IMU rate when none is given, Hz (a vehicle recording's usual 100 Hz).
const DEFAULT_IMU_HZ: f64 = 100.0;
/// The constraint's sigma when none is given, m/s (a car's sideslip and bounce).
const DEFAULT_NHC_M_S: f64 = 0.1;
/// The zero-velocity update's sigma a dataset with body motion states, m/s. Its car stands
/// exactly still, so any sigma well under the velocity error the accelerometer noise builds
/// between two updates (a MEMS unit's: 2 mm/s in a second) says so. The odometer's floor
/// (1e-2 m/s) would be a statement the data contradict: the diagnosis fits the standstill's
/// tolerance about 70x down (and, when it fitted it tied to the constraint's, left the verdict
/// `unexplained`).
const STANDING_M_S: f64 = 1e-4;
/// The heading sigma of `[initial]` when none is given, rad (2 deg: a heading from the
/// first GPS track).
const DEFAULT_HEADING_SIGMA: f64 = 0.035;

/// Checks `req` for a strapdown unit and builds its simulator.
pub(in crate::family) fn prepare(
    req: &SimulationRequest,
    names: SettingNames,
) -> Result<Ready, StudyError> {
    let other = StudyError::Other;
    let mut registry = StrapdownRegistry::catalogue();
    registry
        .declare(&req.declarations)
        .map_err(|e| other(format!("{}: {e}", names.of("effects_file"))))?;
    let effects = StrapdownEffectList::parse_entries(&[&req.effects], &registry)
        .map_err(|(_, e)| other(format!("{}: {e}", names.of("effects"))))?;
    if req.attitude.is_some_and(|a| a != Attitude::SmallAngle) {
        return Err(other(format!(
            "{}: the platform's choice; the strapdown family's attitude equations are exact \
             Euler angles, expected no {0}",
            names.of("attitude")
        )));
    }
    let unit: UnitClass = req
        .unit
        .as_deref()
        .unwrap_or("mems")
        .parse()
        .map_err(|e| other(format!("{}: {e}", names.of("unit"))))?;
    let errors = unit.errors();
    let imu_hz = req.imu_rate_hz.unwrap_or(DEFAULT_IMU_HZ);
    let nhc = req.nhc_sigma.unwrap_or(DEFAULT_NHC_M_S);
    let heading_sigma = req.azimuth_sigma.unwrap_or(DEFAULT_HEADING_SIGMA);
    for (key, v) in [
        ("imu_rate", imu_hz),
        ("nhc_sigma", nhc),
        ("azimuth_sigma", heading_sigma),
    ] {
        if !(v.is_finite() && v > 0.0) {
            return Err(other(format!(
                "{} {v}: expected a finite number > 0",
                names.of(key)
            )));
        }
    }
    if nhc > MAX_SIGMA_M_S {
        return Err(other(format!(
            "{} {nhc}: expected at most {MAX_SIGMA_M_S} m/s (a car's sideslip is centimetres \
             a second; cm/s given as m/s?)",
            names.of("nhc_sigma")
        )));
    }
    // The files hold no constraint readings, so the vehicle carries the sideslip and
    // bounce the stated sigma describes (dynamics::strapdown::body_motion); 0 is a rigid
    // vehicle, and any other value is checked by `with_body_motion` below.
    let body_motion = req.body_motion_m_s.unwrap_or(nhc);
    let rigid = body_motion == 0.0;
    // The odometer and GPS come once a second, at one of the readings' times.
    if imu_hz < 1.0 || imu_hz.fract() != 0.0 {
        return Err(other(format!(
            "{} {imu_hz}: expected a whole number of readings a second (the odometer and the \
             GPS read at 1 Hz, each at a reading's time)",
            names.of("imu_rate")
        )));
    }
    if heading_sigma > std::f64::consts::PI {
        return Err(other(format!(
            "{} {heading_sigma}: the heading's one-sigma beyond half a turn says nothing; \
             expected at most pi rad",
            names.of("azimuth_sigma")
        )));
    }
    // Levelling from the accelerometers leaves a tilt of about the bias over g.
    let level_sigma = errors.accel_bias / navkf_dynamics::earth::STANDARD_GRAVITY;
    let traj = Arc::new(Trajectory::build(&req.trajectory)?);
    let noise = errors.noise(NoiseConfig {
        nhc_m_s: Some(nhc),
        // With body motion the car stands exactly still, and dataset.toml says so.
        zupt_m_s: (!rigid).then_some(STANDING_M_S),
        ..NoiseConfig::default()
    });
    let model = Arc::new(
        StrapdownModel::base(&noise)
            .with_unit(errors)
            .with_effects(&effects, unit, 1.0)
            .map_err(|e| other(format!("{}: {e}", names.of("effects"))))?,
    );
    let mut sim = StrapdownSimulator::new(model, traj, imu_hz, 1.0, errors, &effects.fixed, noise)
        .map_err(|e| {
            other(
                e.to_string()
                    .replace("truth.input_rate_hz", &names.of("imu_rate"))
                    .replace("trajectory.duration_s", &names.of("duration"))
                    .replace("truth.coefficients.", &format!("{} ", names.of("effects"))),
            )
        })?;
    if !rigid {
        sim = sim.with_body_motion(body_motion).map_err(|e| {
            other(format!(
                "{}; 0: a rigid vehicle",
                e.to_string()
                    .replace("truth.body_motion_m_s:", &names.of("body_motion"))
            ))
        })?;
    }
    let hidden = if effects.effects.is_empty() {
        String::new()
    } else {
        format!(", hidden: {}", effects.names().join(", "))
    };
    let motion = if !rigid {
        format!("body sideslip and bounce {body_motion} m/s rms")
    } else {
        "a rigid vehicle".to_string()
    };
    let description = format!(
        "strapdown, {} unit, IMU at {imu_hz} Hz, {motion}{hidden}",
        unit.name()
    );
    Ok(Box::new(move |name: &str, seed: u64, run: u64| {
        let truth = sim.run(seed, run);
        (
            sim.dataset(name, seed, &truth, level_sigma, heading_sigma),
            description,
        )
    }))
}
