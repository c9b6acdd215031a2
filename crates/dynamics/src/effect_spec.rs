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
use crate::input_file::printable;
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
        Self::parse_entries(&[list], registry).map_err(|(_, e)| e)
    }

    /// Parses a list given as separate entries (a study file's `effects = [...]`), each as
    /// [`EffectSpec::parse`] reads a list; a failure comes with the index of its entry.
    ///
    /// ```
    /// use navkf_dynamics::effect_spec::EffectSpec;
    /// use navkf_dynamics::Registry;
    /// let err = EffectSpec::parse_entries(&["gyro-fz", "gyro-fzz"], &Registry::catalogue());
    /// assert_eq!(err.unwrap_err().0, 1);
    /// ```
    pub fn parse_entries<S: AsRef<str>>(
        entries: &[S],
        registry: &Registry,
    ) -> Result<Self, (usize, DynamicsError)> {
        let mut spec = EffectSpec::default();
        let mut listed = Vec::new();
        for (i, entry) in entries.iter().enumerate() {
            for item in entry.as_ref().split(',').map(str::trim) {
                if !item.is_empty() {
                    spec.add_item(item, &mut listed, registry)
                        .map_err(|e| (i, printable_effect_error(e)))?;
                }
            }
        }
        Ok(spec)
    }

    /// Adds one item; `listed` holds the effects named so far (naming one twice is an error).
    fn add_item(
        &mut self,
        item: &str,
        listed: &mut Vec<String>,
        registry: &Registry,
    ) -> Result<(), DynamicsError> {
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
            if listed.iter().any(|l| l == name) {
                return Err(given_twice(item, &format!("effect `{name}`")));
            }
            listed.push(name.to_string());
            let idx = self.ensure(name, registry)?;
            if let Some(v) = value {
                let e = &mut self.effects[idx];
                if e.coefficient_names().is_empty() {
                    e.set_parameter(v)
                        .map_err(|m| DynamicsError::Effect(format!("`{item}`: {m}")))?;
                } else {
                    let names: Vec<String> = e
                        .coefficient_names()
                        .iter()
                        .map(|c| c.to_string())
                        .collect();
                    for c in &names {
                        self.fix(item, c, v)?;
                    }
                }
            }
            Ok(())
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
            self.fix(item, name, v)
        } else if let Some(owner) = registry.owner_of(name) {
            self.ensure(&owner, registry)?;
            let v = value.ok_or_else(|| {
                DynamicsError::Effect(format!(
                    "`{item}`: a coefficient needs a value ({name}=...)"
                ))
            })?;
            self.fix(item, name, v)
        } else {
            Err(DynamicsError::Effect(format!(
                "`{name}` is neither an effect nor a coefficient; effects: {}",
                registry.names().join(", ")
            )))
        }
    }

    /// Fixes `coefficient` at `v` (fixing it twice is an error).
    fn fix(&mut self, item: &str, coefficient: &str, v: f64) -> Result<(), DynamicsError> {
        if self.fixed.contains_key(coefficient) {
            return Err(given_twice(item, &format!("coefficient `{coefficient}`")));
        }
        self.fixed.insert(coefficient.to_string(), Prior::fixed(v));
        Ok(())
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

fn given_twice(item: &str, what: &str) -> DynamicsError {
    DynamicsError::Effect(format!(
        "`{item}`: {what} is given twice; expected each effect and coefficient once"
    ))
}

/// `error` with its message made safe to print ([`printable`]): an item comes from a user
/// (a study file's entry may be a megabyte long) and is quoted in the message.
fn printable_effect_error(error: DynamicsError) -> DynamicsError {
    match error {
        DynamicsError::Effect(message) => DynamicsError::Effect(printable(&message)),
        other => other,
    }
}
