//! The platform model of `docs/model.md`, assembled at run time from the base terms and a
//! list of effects; one implementation serves the truth simulator and every filter.
//!
//! - sensor errors `eps`, `nab`: docs/model.md eqs. (5), (6) ([`PlatformModel::base_terms`]);
//! - state equations: docs/model.md eqs. (7)-(11) ([`PlatformModel::base_rates`]), their
//!   Jacobian `F` (for docs/model.md eq. (19)), the process noise of docs/model.md eq. (12);
//! - the exact-attitude variant instead: docs/model.md eqs. (45)-(48) ([`crate::attitude`]);
//! - measurement: docs/model.md eq. (13); the effects' terms: docs/model.md eqs. (37)-(44).

mod family;
mod jacobian;
mod rates;
mod system;

use crate::attitude::Attitude;
use crate::effect::{DynEffect, MeasurementTerm, NoiseChannel};
use crate::error::DynamicsError;
use crate::kinematics::Kinematics;
use crate::linear_rates::StateLinearRate;
use crate::noise::NoiseConfig;
use crate::sensor_classes::PhysicalBound;
use crate::state::*;
use std::collections::HashSet;

/// The base model plus switched-on effects.
#[derive(Debug)]
pub struct PlatformModel {
    effects: Vec<Box<dyn DynEffect>>,
    offsets: Vec<usize>,
    /// The state indices of each effect's coefficients.
    ranges: Vec<std::ops::Range<usize>>,
    /// Effects whose own code adds rates ([`crate::Effect::add_rates`]).
    rate_effects: Vec<usize>,
    /// Every effect's declared linear rate terms, in the model's order.
    linear_rates: Vec<StateLinearRate>,
    meas_effects: Vec<usize>,
    names: Vec<String>,
    units: Vec<String>,
    noise: Vec<NoiseChannel>,
    linear_measurement: bool,
    dim: usize,
    attitude: Attitude,
}

impl PlatformModel {
    /// The bound of state `index` of this model: a base coefficient's, or the one its effect
    /// declares; `None` for a navigation state or an effect that declares none.
    pub fn coefficient_bound(&self, index: usize) -> Option<PhysicalBound> {
        if index < BASE_DIM {
            return crate::sensor_classes::base_coefficient_bound(index);
        }
        self.effects().iter().enumerate().find_map(|(i, e)| {
            let j = index.checked_sub(self.effect_offset(i))?;
            (j < e.coefficient_names().len())
                .then(|| e.coefficient_bounds().get(j).copied())
                .flatten()
        })
    }

    /// The 20-state base model with the given process noise.
    pub fn base(noise: &NoiseConfig) -> Self {
        Self::new(Vec::new(), noise).expect("the base model has no effects to conflict")
    }

    /// Assembles the base model with `effects`, in order. Fails on a duplicated effect or
    /// coefficient name, a malformed effect (names, units, sigmas and bounds of unequal
    /// length), or an effect whose code adds a term its [`crate::Effect::terms`] does not
    /// declare.
    pub fn new(
        effects: Vec<Box<dyn DynEffect>>,
        noise: &NoiseConfig,
    ) -> Result<Self, DynamicsError> {
        let mut names: Vec<String> = BASE_NAMES.iter().map(|s| s.to_string()).collect();
        let mut units: Vec<String> = BASE_UNITS.iter().map(|s| s.to_string()).collect();
        let mut seen_effects = HashSet::new();
        let mut offsets = Vec::with_capacity(effects.len());
        for e in &effects {
            if !seen_effects.insert(e.name().to_string()) {
                return Err(DynamicsError::Effect(format!(
                    "effect `{}` is switched on twice",
                    e.name()
                )));
            }
            let c = e.coefficient_names();
            let bounds = e.coefficient_bounds();
            if e.coefficient_units().len() != c.len()
                || e.coefficient_sigma().len() != c.len()
                || !(bounds.is_empty() || bounds.len() == c.len())
                || bounds.iter().any(|b| !(b.limit > 0.0))
            {
                return Err(DynamicsError::Effect(format!(
                    "effect `{}` gives {} coefficient names, {} units, {} sigmas and {} bounds \
                     (none, or one > 0 per coefficient)",
                    e.name(),
                    c.len(),
                    e.coefficient_units().len(),
                    e.coefficient_sigma().len(),
                    bounds.len()
                )));
            }
            offsets.push(names.len());
            for (name, unit) in c.iter().zip(e.coefficient_units()) {
                if names.iter().any(|n| n == name) {
                    return Err(DynamicsError::Effect(format!(
                        "effect `{}` adds coefficient `{name}`, which the model already has",
                        e.name()
                    )));
                }
                names.push(name.to_string());
                units.push(unit.to_string());
            }
        }
        let dim = names.len();
        let mut channels = vec![
            channel("w_gx", PHI_X, noise.gyro_psd),
            channel("w_gy", PHI_Y, noise.gyro_psd),
            channel("w_gz", PHI_Z, noise.gyro_psd),
            channel("w_ax", V_X, noise.accel_psd),
            channel("w_ay", V_Y, noise.accel_psd),
        ];
        for (e, &off) in effects.iter().zip(&offsets) {
            check_declared_terms(e.as_ref(), off, dim)?;
        }
        for e in &effects {
            for ch in e.process_noise() {
                if ch.state >= dim || !(ch.psd.is_finite() && ch.psd >= 0.0) {
                    return Err(DynamicsError::Effect(format!(
                        "effect `{}` declares noise channel `{}` on state {} with density {}",
                        e.name(),
                        ch.name,
                        ch.state,
                        ch.psd
                    )));
                }
                channels.push(ch);
            }
        }
        let rate_effects = (0..effects.len())
            .filter(|&i| effects[i].terms().rates)
            .collect();
        let linear_rates = effects
            .iter()
            .zip(&offsets)
            .flat_map(|(e, &off)| {
                e.terms().linear_rates.iter().map(move |t| StateLinearRate {
                    row: t.row,
                    state: off + t.coefficient,
                    feature: t.feature,
                })
            })
            .collect();
        let meas_effects = (0..effects.len())
            .filter(|&i| effects[i].terms().measurement != MeasurementTerm::None)
            .collect();
        let linear_measurement = effects
            .iter()
            .all(|e| e.terms().measurement != MeasurementTerm::NonLinear);
        let ranges = effects
            .iter()
            .zip(&offsets)
            .map(|(e, &off)| off..off + e.coefficient_names().len())
            .collect();
        Ok(PlatformModel {
            effects,
            offsets,
            ranges,
            rate_effects,
            linear_rates,
            meas_effects,
            names,
            units,
            noise: channels,
            linear_measurement,
            dim,
            attitude: Attitude::SmallAngle,
        })
    }

    /// The same model with the attitude equations `attitude` (the small-angle form unless
    /// set).
    pub fn with_attitude(mut self, attitude: Attitude) -> Self {
        self.attitude = attitude;
        self
    }

    /// Which attitude equations the model uses.
    pub fn attitude(&self) -> Attitude {
        self.attitude
    }

    /// State dimension: 20 plus the effects' coefficients.
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// The switched-on effects, in state order.
    pub fn effects(&self) -> &[Box<dyn DynEffect>] {
        &self.effects
    }

    /// Index of the first coefficient of effect `i`.
    pub fn effect_offset(&self, i: usize) -> usize {
        self.offsets[i]
    }

    /// Names of the effects, in order.
    pub fn effect_names(&self) -> Vec<String> {
        self.effects.iter().map(|e| e.name().to_string()).collect()
    }

    /// The TOML declarations of the effects that were declared rather than written in Rust
    /// ([`crate::declared`]), in order.
    pub fn declarations(&self) -> Vec<crate::declared::EffectDeclaration> {
        self.effects
            .iter()
            .filter_map(|e| e.declaration().cloned())
            .collect()
    }

    /// Index of a state by name.
    pub fn index_of(&self, name: &str) -> Option<usize> {
        self.names.iter().position(|n| n == name)
    }

    /// Units of every state.
    pub fn units(&self) -> &[String] {
        &self.units
    }

    /// A typical one-sigma of every coefficient (base and effects), indexed like the state;
    /// `None` for the navigation states.
    pub fn effect_coefficient_sigmas(&self) -> Vec<(usize, f64)> {
        let mut out = Vec::new();
        for (e, &off) in self.effects.iter().zip(&self.offsets) {
            for (j, s) in e.coefficient_sigma().iter().enumerate() {
                out.push((off + j, *s));
            }
        }
        out
    }
}

fn channel(name: &str, state: usize, psd: f64) -> NoiseChannel {
    NoiseChannel {
        name: name.to_string(),
        state,
        psd,
    }
}

/// Checks an effect's declared [`crate::Terms`] against its code: at a probe state with
/// every quantity non-zero, an effect that declares no rates must add none, one that declares
/// no measurement term must add none, one that declares no noise must bring no channel.
/// Otherwise the model, which calls only what is declared, would silently drop the term.
fn check_declared_terms(e: &dyn DynEffect, offset: usize, dim: usize) -> Result<(), DynamicsError> {
    let terms = e.terms();
    let count = e.coefficient_names().len();
    let mut x: Vec<f64> = (0..dim).map(|i| 1e-3 * (1.0 + i as f64)).collect();
    x[V_X] = 12.0;
    x[V_Y] = -7.0;
    x[LAT] = 0.8;
    x[LON] = 2.2;
    let k = Kinematics::new(&x, &crate::kinematics::platform_input([0.4, -0.3, 9.8]));
    let c = &x[offset..offset + count];
    let undeclared = |what: &str| {
        DynamicsError::Effect(format!(
            "effect `{}` adds {what} that its `terms()` does not declare; declare it, or the \
             model would drop it",
            e.name()
        ))
    };
    for t in terms.linear_rates {
        if t.row >= NAV_DIM || t.coefficient >= count || t.feature.axis() >= 3 {
            return Err(DynamicsError::Effect(format!(
                "effect `{}` declares a linear rate term {t:?}: its row must be a navigation \
                 state (< {NAV_DIM}), its coefficient one of its {count}, its axis 0, 1 or 2",
                e.name()
            )));
        }
    }
    if !terms.rates {
        let mut r = [0.0; NAV_DIM];
        e.add_rates(&k, c, &mut r);
        if r.iter().any(|&v| v != 0.0) {
            return Err(undeclared("rates"));
        }
    }
    if terms.measurement == MeasurementTerm::None {
        let mut z = [0.0; MEAS_DIM];
        e.add_measurement(&k, c, &mut z);
        if z.iter().any(|&v| v != 0.0) {
            return Err(undeclared("a measurement term"));
        }
    }
    if !terms.noise && !e.process_noise().is_empty() {
        return Err(undeclared("process noise"));
    }
    Ok(())
}
