//! The platform family's simulation: the truth driven by the state equations (docs/model.md,
//! "State equations") with the measurements of docs/model.md, "Measurements"; here its
//! settings are checked and the simulator built.

use crate::error::StudyError;
use crate::simulation::request::{Ready, SimulationRequest};
use navkf_dynamics::declared::EffectCatalogue;
use navkf_dynamics::effect_spec::EffectSpec;
use navkf_dynamics::{
    Attitude, NoiseConfig, PlatformModel, Registry, Simulator, Trajectory, TruthConfig,
};
use navkf_report::SettingNames;
use std::sync::Arc;

/// Checks `req` for the platform and builds its simulator.
pub(in crate::family) fn prepare(
    req: &SimulationRequest,
    names: SettingNames,
) -> Result<Ready, StudyError> {
    let other = StudyError::Other;
    for (key, given) in [
        ("unit", req.unit.is_some()),
        ("imu_rate", req.imu_rate_hz.is_some()),
        ("nhc_sigma", req.nhc_sigma.is_some()),
        ("body_motion", req.body_motion_m_s.is_some()),
    ] {
        if given {
            let key = names.of(key);
            return Err(other(format!(
                "{key}: a strapdown setting; expected the strapdown model, or no {key}"
            )));
        }
    }
    let registry = Registry::with_declared(&req.declarations)?;
    let spec = EffectSpec::parse(&req.effects, &registry)?;
    let noise = NoiseConfig::default();
    let effect_names = spec.names();
    let attitude = req.attitude.unwrap_or(Attitude::SmallAngle);
    let model = Arc::new(PlatformModel::new(spec.effects, &noise)?.with_attitude(attitude));
    for (name, prior) in &spec.fixed {
        let bound = model
            .index_of(name)
            .and_then(|i| model.coefficient_bound(i).map(|b| (b, &model.units()[i])));
        if let Some((b, unit)) = bound.filter(|(b, _)| !b.contains(prior.mean)) {
            let owner = registry
                .owner_of(name)
                .map(|e| format!(" (of {e})"))
                .unwrap_or_default();
            let value = if (1e-3..1e6).contains(&prior.mean.abs()) {
                prior.mean.to_string()
            } else {
                format!("{:e}", prior.mean)
            };
            let limit = format!("{:.4}", b.limit);
            let limit = limit.trim_end_matches('0').trim_end_matches('.');
            let unit = if unit == "1" {
                String::new()
            } else {
                format!(" {unit}")
            };
            return Err(other(format!(
                "{}: {name}={value}{owner}: beyond +-{limit}{unit}, what any real sensor has \
                 ({}); nothing was simulated",
                names.of("effects"),
                b.reason
            )));
        }
    }
    let traj = Arc::new(Trajectory::build(&req.trajectory)?);
    let mut truth_cfg = TruthConfig {
        coefficients: spec.fixed,
        ..Default::default()
    };
    if let Some(s) = req.azimuth_sigma {
        let key = names.of("azimuth_sigma");
        if !(s.is_finite() && s >= 0.0) {
            return Err(other(format!("{key} {s}: expected a one-sigma >= 0, rad")));
        }
        attitude.check_tilt_sigma(&key, s).map_err(other)?;
        truth_cfg.initial_tilt.azimuth_rad = s;
    }
    let sim = Simulator::new(model, traj, truth_cfg, noise)?;
    let description = format!(
        "effects: {}",
        if effect_names.is_empty() {
            "none".to_string()
        } else {
            effect_names.join(", ")
        }
    );
    Ok(Box::new(move |name: &str, seed: u64, run: u64| {
        let truth = sim.run(seed, run);
        (sim.dataset(name, seed, &truth), description)
    }))
}
