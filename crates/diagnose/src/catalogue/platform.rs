//! The platform family (docs/model.md, "The state" to "Catalogue of effects") as the
//! diagnosis sees it: the catalogue of [`Registry`], the odometer's velocity and the GPS fix
//! as channels, and a filter that starts level and North-pointing up to its tilt priors.

use super::{first_full_measurement, Catalogue, Channel, ChannelKind, EffectInfo, Start};
use crate::consistency::classify;
use crate::error::DiagnoseError;
use crate::rivals::{
    AccelBiasWalk, AccelSettling, GpsAntennaOffset, VelocityDependentAcceleration,
};
use navkf_dynamics::dataset::{Dataset, Measurement};
use navkf_dynamics::outside::Drag;
use navkf_dynamics::prior::{base_coefficient_sigma, default_azimuth_rad, default_level_rad};
use navkf_dynamics::state::*;
use navkf_dynamics::trajectory::Phase;
use navkf_dynamics::{
    Attitude, FamilyModel, InputWindow, MeasurementModel, ModelKind, NoiseConfig, PlatformModel,
    Registry,
};
use std::collections::BTreeMap;
use std::sync::Arc;

const CHANNELS: [Channel; MEAS_DIM] = [
    Channel {
        name: "v_x",
        title: "east velocity v_x",
        kind: ChannelKind::Velocity,
    },
    Channel {
        name: "v_y",
        title: "north velocity v_y",
        kind: ChannelKind::Velocity,
    },
    Channel {
        name: "L",
        title: "latitude L, as metres north of the first fix",
        kind: ChannelKind::Latitude,
    },
    Channel {
        name: "lambda",
        title: "longitude lambda, as metres east of the first fix",
        kind: ChannelKind::Longitude,
    },
];

/// The family's channels.
pub fn channels() -> &'static [Channel] {
    &CHANNELS
}

/// The platform's catalogue is its [`Registry`]: [`Registry::catalogue`], or that with a
/// user's effects registered.
impl Catalogue for Registry {
    fn kind(&self) -> ModelKind {
        ModelKind::Platform
    }
    fn effect_names(&self) -> Vec<String> {
        self.names()
    }
    fn effect(&self, name: &str) -> Result<EffectInfo, DiagnoseError> {
        let e = self.build(name)?;
        let coefficients: Vec<String> = e
            .coefficient_names()
            .iter()
            .map(|c| c.to_string())
            .collect();
        let noise_density = coefficients
            .is_empty()
            .then(|| e.process_noise().first().map(|c| c.psd))
            .flatten();
        Ok(EffectInfo {
            description: e.description().to_string(),
            coefficients,
            units: e
                .coefficient_units()
                .iter()
                .map(|u| u.to_string())
                .collect(),
            bounds: e.coefficient_bounds().to_vec(),
            noise_density,
        })
    }
    fn model(
        &self,
        effects: &[String],
        parameters: &BTreeMap<String, f64>,
        noise: &NoiseConfig,
        attitude: Attitude,
    ) -> Result<Arc<dyn FamilyModel>, DiagnoseError> {
        let mut effects = self.build_all(effects)?;
        for e in &mut effects {
            if let Some(&p) = parameters.get(e.name()) {
                e.set_parameter(p).map_err(DiagnoseError::Data)?;
            }
        }
        Ok(Arc::new(
            PlatformModel::new(effects, noise)?.with_attitude(attitude),
        ))
    }
    fn sensors(
        &self,
        noise: NoiseConfig,
    ) -> Box<dyn MeasurementModel<Record = Measurement> + Sync> {
        Box::new(noise)
    }
    fn channels(&self) -> &'static [Channel] {
        &CHANNELS
    }
    fn nav_dim(&self) -> usize {
        NAV_DIM
    }
    fn tilt_names(&self) -> [&'static str; 2] {
        ["level_rad", "azimuth_rad"]
    }
    fn default_tilt(&self, _ds: &Dataset, start_lat: f64) -> [f64; 2] {
        [default_level_rad(), default_azimuth_rad(start_lat)]
    }
    fn base_coefficients(&self) -> Vec<(String, f64)> {
        (NAV_DIM..BASE_DIM)
            .map(|i| (BASE_NAMES[i].to_string(), base_coefficient_sigma(i)))
            .collect()
    }
    /// Level and North-pointing up to the tilt priors, at the first row with both odometer
    /// and GPS: the odometer's velocity and the fix, with their sigmas.
    fn start(
        &self,
        ds: &Dataset,
        noise: &NoiseConfig,
        [level, azimuth]: [f64; 2],
    ) -> Result<Start, DiagnoseError> {
        let (m0, p0) = first_full_measurement(ds)?;
        let v0 = m0.velocity.unwrap_or([0.0; 2]);
        let mut x = vec![0.0; NAV_DIM];
        x[V_X] = v0[0];
        x[V_Y] = v0[1];
        x[LAT] = p0[0];
        x[LON] = p0[1];
        let sig0 = noise.measurement_sigmas(v0[0].hypot(v0[1]), p0[0]);
        let sigma = (0..NAV_DIM)
            .map(|i| match i {
                PHI_X | PHI_Y => level,
                PHI_Z => azimuth,
                _ => sig0[i - V_X],
            })
            .collect();
        Ok(Start { t: m0.t, x, sigma })
    }
    /// From the mean horizontal specific force over the step's input knots and the
    /// odometer's velocity.
    fn phase(&self, _ds: &Dataset, window: &InputWindow, m: &Measurement) -> Phase {
        let knots = window.f.len().max(1) as f64;
        let (fe, fnn) = window
            .f
            .iter()
            .fold((0.0, 0.0), |(e, n), f| (e + f[0], n + f[1]));
        classify([fe / knots, fnn / knots], m.velocity)
    }
    fn with_structured_rival(&self, effect: &str) -> Option<(Box<dyn Catalogue>, &'static str)> {
        (effect == "gps-latency").then(|| {
            let mut registry = self.clone();
            registry.register(|| Box::new(GpsAntennaOffset));
            (
                Box::new(registry) as Box<dyn Catalogue>,
                GpsAntennaOffset::NAME,
            )
        })
    }
    fn with_rival(&self) -> Option<(Box<dyn Catalogue>, &'static str, f64)> {
        let mut registry = self.clone();
        registry.register(|| Box::new(AccelBiasWalk::default()));
        Some((
            Box::new(registry),
            AccelBiasWalk::NAME,
            AccelBiasWalk::DEFAULT_PSD,
        ))
    }
    fn with_settling_rival(&self) -> Option<(Box<dyn Catalogue>, &'static str)> {
        let mut registry = self.clone();
        registry.register(|| Box::new(AccelSettling::default()));
        Some((Box::new(registry), AccelSettling::NAME))
    }
    fn with_levels_rival(&self) -> Result<Option<super::WithRival>, DiagnoseError> {
        // A drag the user declared is a candidate like any other, and so is the rival itself
        // declared under its own name.
        if self
            .names()
            .iter()
            .any(|n| n == Drag::NAME || n == VelocityDependentAcceleration::NAME)
        {
            return Ok(None);
        }
        // A declaration refuses a coefficient name another effect has (two states in one):
        // the rival's are renamed where a user's effect has them.
        let taken = super::coefficient_names(self);
        let mut registry = self.clone();
        registry
            .declare(&[VelocityDependentAcceleration::declaration_avoiding(&taken)])
            .map_err(|e| {
                DiagnoseError::Data(format!(
                    "the refitted noise levels' rival `{}` cannot be declared beside the \
                     effects given ({e}); rename the effect or coefficient it names",
                    VelocityDependentAcceleration::NAME
                ))
            })?;
        Ok(Some((
            Box::new(registry),
            VelocityDependentAcceleration::NAME,
        )))
    }
}
