//! [`DeclaredEffect`]: a checked [`EffectDeclaration`] as an [`Effect`] the model holds like
//! a catalogued one. Its rates and measurement are sums of `factor x coefficient x feature`
//! (docs/model.md eqs. (37)-(42) have this form), its partials follow from each feature's
//! ([`TermFeature::add_state_partials`]), so nothing in it is written per effect.

use super::declaration::{CheckedTerm, EffectDeclaration};
use super::intern;
use crate::effect::{Effect, MeasurementTerm, Partials, PhysicalBound, Terms};
use crate::kinematics::Kinematics;
use crate::real::Real;
use crate::state::{MEAS_DIM, NAV_DIM};
use std::sync::Arc;

/// A declared effect. Built once per declaration ([`DeclaredEffect::new`]); a registry's
/// factory clones it.
#[derive(Debug, Clone)]
pub struct DeclaredEffect {
    declaration: Arc<EffectDeclaration>,
    description: String,
    names: Vec<&'static str>,
    units: Vec<&'static str>,
    sigma: Vec<f64>,
    bounds: Vec<PhysicalBound>,
    rates: Vec<CheckedTerm>,
    measurement: Vec<CheckedTerm>,
}

impl DeclaredEffect {
    /// Checks `declaration` against the effects known already (`effects`, and `owner_of`,
    /// the effect owning a coefficient name: its name and its coefficients' must be new). The
    /// error names the key within the declaration (`rates[1].feature`) and says what was
    /// expected. [`crate::Registry::declare`] calls it with what the registry knows.
    pub(crate) fn new(
        declaration: &EffectDeclaration,
        effects: &[String],
        owner_of: impl Fn(&str) -> Option<String>,
    ) -> Result<Self, (String, String)> {
        let (rates, measurement) = declaration.check(effects, owner_of)?;
        let c = &declaration.coefficients;
        let bounds = if c.iter().any(|c| c.bound.is_some()) {
            c.iter().map(|c| c.physical_bound()).collect()
        } else {
            Vec::new()
        };
        let description = if declaration.description.trim().is_empty() {
            declaration.written_terms()
        } else {
            declaration.description.clone()
        };
        Ok(DeclaredEffect {
            declaration: Arc::new(declaration.clone()),
            description,
            names: c.iter().map(|c| intern(&c.name)).collect(),
            units: c.iter().map(|c| intern(&c.unit)).collect(),
            sigma: c.iter().map(|c| c.sigma).collect(),
            bounds,
            rates,
            measurement,
        })
    }
}

/// `factor x c x feature` at `k`.
#[inline]
fn term<T: Real>(t: &CheckedTerm, k: &Kinematics<T>, c: &[T]) -> T {
    let v = c[t.coefficient] * t.feature.value(k);
    if t.factor == 1.0 {
        v
    } else {
        v * T::splat(t.factor)
    }
}

/// The partials of `factor x c x feature`: by the coefficient, and by the states the feature
/// reads.
fn add_term_partials(t: &CheckedTerm, k: &Kinematics, c: &[f64], offset: usize, p: &mut Partials) {
    p.add(t.row, offset + t.coefficient, t.factor * t.feature.value(k));
    t.feature
        .add_state_partials(k, t.factor * c[t.coefficient], t.row, p);
}

impl Effect for DeclaredEffect {
    fn name(&self) -> &str {
        &self.declaration.name
    }
    fn description(&self) -> &str {
        &self.description
    }
    fn coefficient_names(&self) -> &[&str] {
        &self.names
    }
    fn coefficient_units(&self) -> &[&str] {
        &self.units
    }
    fn coefficient_sigma(&self) -> &[f64] {
        &self.sigma
    }
    fn coefficient_bounds(&self) -> &[PhysicalBound] {
        &self.bounds
    }
    fn terms(&self) -> Terms {
        let measurement = if self.measurement.is_empty() {
            MeasurementTerm::None
        } else if self
            .measurement
            .iter()
            .any(|t| t.feature.depends_on_state())
        {
            MeasurementTerm::NonLinear
        } else {
            MeasurementTerm::Linear
        };
        Terms {
            rates: !self.rates.is_empty(),
            linear_rates: &[],
            measurement,
            noise: false,
        }
    }
    fn add_rates<T: Real>(&self, k: &Kinematics<T>, c: &[T], rates: &mut [T; NAV_DIM]) {
        for t in &self.rates {
            rates[t.row] += term(t, k, c);
        }
    }
    fn add_rate_partials(&self, k: &Kinematics, c: &[f64], offset: usize, p: &mut Partials) {
        for t in &self.rates {
            add_term_partials(t, k, c, offset, p);
        }
    }
    fn add_measurement(&self, k: &Kinematics, c: &[f64], z: &mut [f64; MEAS_DIM]) {
        for t in &self.measurement {
            z[t.row] += term(t, k, c);
        }
    }
    fn add_measurement_partials(&self, k: &Kinematics, c: &[f64], offset: usize, p: &mut Partials) {
        for t in &self.measurement {
            add_term_partials(t, k, c, offset, p);
        }
    }
    fn declaration(&self) -> Option<&EffectDeclaration> {
        Some(&self.declaration)
    }
}
