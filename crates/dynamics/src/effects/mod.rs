//! The catalogue of effects the base model leaves out (docs/model.md, "Catalogue of effects";
//! docs/model.md eqs. (37)-(44)), one file each, and the registry that builds them by name.
//!
//! Adding an effect to the catalogue is one new file here plus one line in
//! [`Registry::catalogue`]; a user adds their own with [`Registry::register`]. The registry
//! files each effect under the name the effect itself gives ([`crate::Effect::name`]).

mod accel_cross_axis;
mod accel_quadratic;
mod gps_latency;
mod gyro_bias_walk;
mod gyro_fz;
mod odometer_misalignment;
mod odometer_scale;
mod torquer_scale;

pub use accel_cross_axis::AccelCrossAxis;
pub use accel_quadratic::AccelQuadratic;
pub use gps_latency::GpsLatency;
pub use gyro_bias_walk::GyroBiasWalk;
pub use gyro_fz::GyroFz;
pub use odometer_misalignment::OdometerMisalignment;
pub use odometer_scale::OdometerScale;
pub use torquer_scale::TorquerScale;

use crate::declared::{DeclaredEffect, EffectCatalogue, EffectDeclaration};
use crate::effect::DynEffect;
use crate::error::DynamicsError;
use std::sync::Arc;

type Factory = Arc<dyn Fn() -> Box<dyn DynEffect> + Send + Sync>;

/// Effects by name. [`Registry::catalogue`] holds the seven of `docs/model.md`; users add
/// theirs.
#[derive(Clone)]
pub struct Registry {
    entries: Vec<(String, Factory)>,
}

impl std::fmt::Debug for Registry {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_list()
            .entries(self.entries.iter().map(|(n, _)| n))
            .finish()
    }
}

impl Default for Registry {
    fn default() -> Self {
        Self::catalogue()
    }
}

impl Registry {
    /// The catalogue of `docs/model.md` (docs/model.md eqs. (37)-(44)).
    pub fn catalogue() -> Self {
        let mut r = Registry {
            entries: Vec::new(),
        };
        r.register(|| Box::new(GyroFz));
        r.register(|| Box::new(AccelQuadratic));
        r.register(|| Box::new(AccelCrossAxis));
        r.register(|| Box::new(TorquerScale));
        r.register(|| Box::new(OdometerScale));
        r.register(|| Box::new(OdometerMisalignment));
        r.register(|| Box::new(GpsLatency));
        r.register(|| Box::new(GyroBiasWalk::default()));
        r
    }

    /// Adds an effect under the name it gives itself, replacing one of that name.
    pub fn register<F>(&mut self, factory: F)
    where
        F: Fn() -> Box<dyn DynEffect> + Send + Sync + 'static,
    {
        let name = factory().name().to_string();
        self.entries.retain(|(n, _)| *n != name);
        self.entries.push((name, Arc::new(factory)));
    }

    /// Adds effects declared in TOML ([`crate::declared`]), each checked against the
    /// effects known before it: a new name, new coefficient names, known features. The error
    /// names the key (`effect[1].rates[0].feature`) and what was expected; on error nothing
    /// is added. A declaration the registry holds already, word for word, is skipped: a
    /// dataset simulated with an effects file carries the file's declarations, and reading
    /// it with the same file is no conflict.
    pub fn declare(&mut self, declarations: &[EffectDeclaration]) -> Result<(), DynamicsError> {
        let mut extended = self.clone();
        for (i, d) in declarations.iter().enumerate() {
            let same = extended
                .build(&d.name)
                .is_ok_and(|known| known.declaration() == Some(d));
            if same {
                continue;
            }
            let known = extended.names();
            let effect = DeclaredEffect::new(d, &known, |c| extended.owner_of(c)).map_err(
                |(key, message)| DynamicsError::Config {
                    key: format!("effect[{i}].{key}"),
                    message,
                },
            )?;
            extended.register(move || Box::new(effect.clone()));
        }
        *self = extended;
        Ok(())
    }

    /// Names, in registration order.
    pub fn names(&self) -> Vec<String> {
        self.entries.iter().map(|(n, _)| n.clone()).collect()
    }

    /// Builds the effect called `name`.
    pub fn build(&self, name: &str) -> Result<Box<dyn DynEffect>, DynamicsError> {
        self.entries
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, f)| f())
            .ok_or_else(|| {
                DynamicsError::Effect(format!(
                    "unknown effect `{name}`; known effects: {}",
                    self.names().join(", ")
                ))
            })
    }

    /// Builds every effect in `names`, in order.
    pub fn build_all<S: AsRef<str>>(
        &self,
        names: &[S],
    ) -> Result<Vec<Box<dyn DynEffect>>, DynamicsError> {
        names.iter().map(|n| self.build(n.as_ref())).collect()
    }

    /// The effect that owns coefficient `coefficient`, if any.
    pub fn owner_of(&self, coefficient: &str) -> Option<String> {
        self.entries
            .iter()
            .find(|(_, f)| f().coefficient_names().contains(&coefficient))
            .map(|(n, _)| n.clone())
    }
}

impl EffectCatalogue for Registry {
    fn catalogue() -> Self {
        Registry::catalogue()
    }

    fn declare(&mut self, declarations: &[EffectDeclaration]) -> Result<(), DynamicsError> {
        Registry::declare(self, declarations)
    }
}
