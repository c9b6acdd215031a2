//! Parsing effect lists as users write them: `gyro-fz,odometer-scale=0.002,Ka0x=1e-3`.
//!
//! Each item is one of:
//! - `name`: switch the effect on; its true coefficients are drawn from their typical sigma;
//! - `name=value`: switch it on with every coefficient fixed at `value`, or, for an effect
//!   without coefficients (`gyro-bias-walk`), set its parameter (the walk density);
//! - `coefficient=value`: fix one coefficient (a base one such as `Ka0x`, or an effect's, which
//!   switches that effect on).

use crate::effect::DynEffect;
use crate::effects::Registry;
use crate::error::DynamicsError;
use crate::simulate::Prior;
use crate::state::{BASE_NAMES, NAV_DIM};
use std::collections::BTreeMap;

/// A parsed effect list: the effects in order, and the coefficient values it fixes.
#[derive(Debug, Default)]
pub struct EffectSpec {
    /// Effects to switch on, in the order first named.
    pub effects: Vec<Box<dyn DynEffect>>,
    /// Fixed true values by coefficient name.
    pub fixed: BTreeMap<String, Prior>,
}

impl EffectSpec {
    /// Parses `list` (comma-separated items, see the module documentation).
    ///
    /// ```
    /// use navkf_dynamics::effect_spec::EffectSpec;
    /// use navkf_dynamics::Registry;
    /// let s = EffectSpec::parse("gyro-fz, kod=0.002, Ka0x=1e-3", &Registry::catalogue()).unwrap();
    /// let names: Vec<&str> = s.effects.iter().map(|e| e.name()).collect();
    /// assert_eq!(names, ["gyro-fz", "odometer-scale"]);
    /// assert_eq!(s.fixed["kod"].mean, 0.002);
    /// assert!(EffectSpec::parse("gyro-fzz", &Registry::catalogue()).is_err());
    /// // Saying one thing twice is an error, not a silent overwrite.
    /// assert!(EffectSpec::parse("gyro-fz, gyro-fz", &Registry::catalogue()).is_err());
    /// assert!(EffectSpec::parse("kod=0.002, odometer-scale=0.003", &Registry::catalogue()).is_err());
    /// ```
    pub fn parse(list: &str, registry: &Registry) -> Result<Self, DynamicsError> {
        let mut spec = EffectSpec::default();
        let mut listed: Vec<&str> = Vec::new();
        let twice = |item: &str, what: &str| {
            DynamicsError::Effect(format!(
                "`{item}`: {what} is given twice; expected each effect and coefficient once"
            ))
        };
        for item in list.split(',').map(str::trim).filter(|s| !s.is_empty()) {
            let (name, value) = match item.split_once('=') {
                Some((n, v)) => {
                    let v: f64 = v.trim().parse().map_err(|_| {
                        DynamicsError::Effect(format!(
                            "`{item}`: `{}` is not a number (expected name=value, e.g. odometer-scale=0.002)",
                            v.trim()
                        ))
                    })?;
                    if !v.is_finite() {
                        return Err(DynamicsError::Effect(format!(
                            "`{item}`: value must be finite"
                        )));
                    }
                    (n.trim(), Some(v))
                }
                None => (item, None),
            };
            if registry.names().iter().any(|n| n == name) {
                if listed.contains(&name) {
                    return Err(twice(item, &format!("effect `{name}`")));
                }
                listed.push(name);
                let idx = spec.ensure(name, registry)?;
                if let Some(v) = value {
                    let e = &mut spec.effects[idx];
                    if e.coefficient_names().is_empty() {
                        e.set_parameter(v)
                            .map_err(|m| DynamicsError::Effect(format!("`{item}`: {m}")))?;
                    } else {
                        for c in e.coefficient_names() {
                            if spec.fixed.contains_key(*c) {
                                return Err(twice(item, &format!("coefficient `{c}`")));
                            }
                            spec.fixed.insert(c.to_string(), Prior::fixed(v));
                        }
                    }
                }
            } else if let Some(pos) = BASE_NAMES.iter().position(|n| *n == name) {
                if pos < NAV_DIM {
                    return Err(DynamicsError::Effect(format!(
                        "`{item}`: `{name}` is a navigation state, not a coefficient"
                    )));
                }
                let v = value.ok_or_else(|| {
                    DynamicsError::Effect(format!(
                        "`{item}`: a base coefficient needs a value ({name}=...)"
                    ))
                })?;
                if spec.fixed.contains_key(name) {
                    return Err(twice(item, &format!("coefficient `{name}`")));
                }
                spec.fixed.insert(name.to_string(), Prior::fixed(v));
            } else if let Some(owner) = registry.owner_of(name) {
                spec.ensure(&owner, registry)?;
                let v = value.ok_or_else(|| {
                    DynamicsError::Effect(format!(
                        "`{item}`: a coefficient needs a value ({name}=...)"
                    ))
                })?;
                if spec.fixed.contains_key(name) {
                    return Err(twice(item, &format!("coefficient `{name}`")));
                }
                spec.fixed.insert(name.to_string(), Prior::fixed(v));
            } else {
                return Err(DynamicsError::Effect(format!(
                    "`{name}` is neither an effect nor a coefficient; effects: {}",
                    registry.names().join(", ")
                )));
            }
        }
        Ok(spec)
    }

    fn ensure(&mut self, name: &str, registry: &Registry) -> Result<usize, DynamicsError> {
        if let Some(i) = self.effects.iter().position(|e| e.name() == name) {
            return Ok(i);
        }
        self.effects.push(registry.build(name)?);
        Ok(self.effects.len() - 1)
    }

    /// Names of the effects, in order.
    pub fn names(&self) -> Vec<String> {
        self.effects.iter().map(|e| e.name().to_string()).collect()
    }
}
