//! Strapdown effect lists as users write them, in the platform's syntax
//! ([`crate::effect_spec`]): `gyro-scale, kod=0.002, bgz=1e-4, T_g=1800`. Each item is
//! - `name`: switch the effect on (its true coefficients drawn from their typical sigma);
//! - `name=value`: switch it on with every coefficient fixed at `value`;
//! - `coefficient=value`: fix one coefficient (a bias such as `bgz`, or an effect's, which
//!   switches that effect on);
//! - `parameter=value`: set a bias instability's correlation time (`T_g`, `T_a`, s) or
//!   steady sigma (`sigma_bg` rad/s, `sigma_ba` m/s^2), which switches it on.

use super::effects::{StrapdownEffect, StrapdownRegistry, Triad};
use super::state::{NAV_DIM, STATE_NAMES};
use super::unit_class::UnitClass;
use crate::error::DynamicsError;
use crate::input_file::printable;
use crate::sensor_classes::{ACCEL_BIAS, GYRO_DRIFT};
use crate::simulate::Prior;
use std::collections::BTreeMap;

/// A parsed strapdown effect list.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct StrapdownEffectList {
    /// The effects, in the order first named.
    pub effects: Vec<StrapdownEffect>,
    /// Fixed true values by coefficient name.
    pub fixed: BTreeMap<String, Prior>,
    /// Bias-instability parameters set by name (`T_g`, `sigma_bg`, `T_a`, `sigma_ba`).
    pub parameters: BTreeMap<String, f64>,
}

impl StrapdownEffectList {
    /// Parses `entries` (each a comma-separated list); a failure comes with its entry's index.
    ///
    /// ```
    /// use navkf_dynamics::strapdown::effect_list::StrapdownEffectList;
    /// use navkf_dynamics::strapdown::effects::StrapdownRegistry;
    /// let r = StrapdownRegistry::catalogue();
    /// let l = StrapdownEffectList::parse_entries(&["gyro-scale, kod=0.002", "T_g=1800"], &r).unwrap();
    /// let names: Vec<&str> = l.effects.iter().map(|e| e.name).collect();
    /// assert_eq!(names, ["gyro-scale", "odometer-scale", "gyro-bias-instability"]);
    /// assert_eq!(l.fixed["kod"].mean, 0.002);
    /// assert_eq!(StrapdownEffectList::parse_entries(&["gyro-scale", "gyro-scal"], &r).unwrap_err().0, 1);
    /// ```
    pub fn parse_entries<S: AsRef<str>>(
        entries: &[S],
        registry: &StrapdownRegistry,
    ) -> Result<Self, (usize, DynamicsError)> {
        let mut list = StrapdownEffectList::default();
        let mut named = Vec::new();
        for (i, entry) in entries.iter().enumerate() {
            for item in entry.as_ref().split(',').map(str::trim) {
                if !item.is_empty() {
                    list.add(item, &mut named, registry).map_err(|m| {
                        (
                            i,
                            DynamicsError::Effect(printable(&format!("`{item}`: {m}"))),
                        )
                    })?;
                }
            }
        }
        Ok(list)
    }

    fn add(
        &mut self,
        item: &str,
        named: &mut Vec<String>,
        registry: &StrapdownRegistry,
    ) -> Result<(), String> {
        let (name, value) = match item.split_once('=') {
            Some((n, v)) => {
                let v: f64 = v
                    .trim()
                    .parse()
                    .map_err(|_| format!("`{}` is not a number (expected name=value)", v.trim()))?;
                if !v.is_finite() {
                    return Err("the value must be finite".into());
                }
                (n.trim(), Some(v))
            }
            None => (item, None),
        };
        if let Ok(effect) = registry.get(name) {
            if named.iter().any(|n| n == name) {
                return Err(format!("effect `{name}` is given twice"));
            }
            named.push(name.to_string());
            self.ensure(effect);
            if let Some(v) = value {
                if effect.coefficients.is_empty() {
                    return Err(format!(
                        "`{name}` has no coefficients; set its parameters by name ({})",
                        effect
                            .instability
                            .map(|l| l.parameter_names.join(", "))
                            .unwrap_or_default()
                    ));
                }
                for c in effect.coefficients {
                    self.fix(c.name, v)?;
                }
            }
            return Ok(());
        }
        let needs_value =
            |what: &str| value.ok_or_else(|| format!("{what} `{name}` needs a value ({name}=...)"));
        if let Some(pos) = STATE_NAMES.iter().position(|n| *n == name) {
            if pos < NAV_DIM {
                return Err(format!("`{name}` is a navigation state, not a coefficient"));
            }
            return self.fix(name, needs_value("the bias")?);
        }
        if let Some(owner) = registry.owner_of(name) {
            self.ensure(owner);
            return self.fix(name, needs_value("the coefficient")?);
        }
        if let Some(owner) = registry.owner_of_parameter(name) {
            let v = needs_value("the parameter")?;
            let [time, _] = owner.instability.map_or(["", ""], |l| l.parameter_names);
            // A correlation time is between a second (shorter is white noise, the unit's
            // density) and a year; a steady sigma within what a real sensor's bias reaches.
            let (lo, hi, what) = if name == time {
                (
                    1.0,
                    3.2e7,
                    "a correlation time from 1 s to a year (3.2e7 s)",
                )
            } else if owner.instability.is_some_and(|l| l.triad == Triad::Gyro) {
                (0.0, GYRO_DRIFT.limit, GYRO_DRIFT.reason)
            } else {
                (0.0, ACCEL_BIAS.limit, ACCEL_BIAS.reason)
            };
            if !(v > lo && v <= hi) {
                return Err(format!("{v}: expected a value in ({lo}, {hi}]: {what}"));
            }
            self.ensure(owner);
            if self.parameters.insert(name.to_string(), v).is_some() {
                return Err(format!("parameter `{name}` is given twice"));
            }
            return Ok(());
        }
        Err(format!(
            "`{name}` is neither a strapdown effect, a coefficient nor a parameter; effects: {}",
            registry.names().join(", ")
        ))
    }

    fn ensure(&mut self, effect: &StrapdownEffect) {
        if !self.effects.iter().any(|e| e.name == effect.name) {
            self.effects.push(effect.clone());
        }
    }

    fn fix(&mut self, coefficient: &str, v: f64) -> Result<(), String> {
        if self.fixed.contains_key(coefficient) {
            return Err(format!("coefficient `{coefficient}` is given twice"));
        }
        self.fixed.insert(coefficient.to_string(), Prior::fixed(v));
        Ok(())
    }

    /// Names of the effects, in order.
    pub fn names(&self) -> Vec<&'static str> {
        self.effects.iter().map(|e| e.name).collect()
    }

    /// The correlation time (s) and steady sigma of `triad`'s bias instability when it is
    /// switched on: the parameters set by name, else the effect's defaults for `class`.
    pub fn instability(&self, triad: Triad, class: UnitClass) -> Option<(f64, f64)> {
        let law = self
            .effects
            .iter()
            .filter_map(|e| e.instability)
            .find(|l| l.triad == triad)?;
        let [t_name, sigma_name] = law.parameter_names;
        Some((
            self.parameters.get(t_name).copied().unwrap_or(law.time_s),
            self.parameters
                .get(sigma_name)
                .copied()
                .unwrap_or(law.sigma_for(class)),
        ))
    }
}
