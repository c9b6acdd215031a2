//! An effect as a user declares it in TOML (`[[effect]]`), and the checks that make a
//! declaration an effect the model can hold: every name known, every number sensible, every
//! coefficient in a term. A failure names its key (`effect[0].rates[1].feature`) and says
//! what was expected.

use super::feature::{TermFeature, TermSide};
use crate::state::{BASE_NAMES, MEASUREMENT_NAMES, NAV_DIM};
use serde::{Deserialize, Serialize};

/// One `[[effect]]` table: a name, coefficients, and terms `coefficient x feature`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EffectDeclaration {
    /// The name commands and study files use (`drag`); not a catalogued effect's.
    pub name: String,
    /// One line of meaning (default: the terms written out).
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub description: String,
    /// The coefficients it adds to the state, in order.
    pub coefficients: Vec<CoefficientDeclaration>,
    /// Terms added to navigation-state derivatives.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub rates: Vec<TermDeclaration>,
    /// Terms added to the predicted measurement.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub measurement: Vec<TermDeclaration>,
    /// A strapdown effect's places: where each coefficient sits in the sensor-error
    /// description ([`super::strapdown`]). A platform effect has terms instead.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub places: Vec<PlaceDeclaration>,
}

/// One place of a strapdown effect's coefficient: `place` holds `factor x coefficient`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlaceDeclaration {
    /// The coefficient, by name.
    pub coefficient: String,
    /// The place, as docs/model.md writes it: `E_g[x][y]`, `E_a[z][z]`, `G[x]`, `kod`,
    /// `a_y`, `a_p`, `l[x]` or `tau` ([`super::strapdown::PLACES`]).
    pub place: String,
    /// A constant factor (default 1; `-1` writes a minus sign).
    #[serde(default = "one", skip_serializing_if = "is_one")]
    pub factor: f64,
}

/// One coefficient of a declared effect.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CoefficientDeclaration {
    /// Its name, unique among all coefficients (`kd`).
    pub name: String,
    /// Its unit, for reports (`1/s`).
    pub unit: String,
    /// Its typical one-sigma size: the truth's draw and the filters' prior.
    pub sigma: f64,
    /// The largest magnitude any real instrument gives it; beyond, a diagnosis does not
    /// name the effect and the simulator refuses the value. Optional.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bound: Option<f64>,
    /// Why no real instrument exceeds `bound` (needs `bound`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bound_reason: Option<String>,
}

/// One term `factor x coefficient x feature`, added to `to`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TermDeclaration {
    /// A rate term: the state whose derivative it adds to (`phi_x`, `phi_y`, `phi_z`, `v_x`,
    /// `v_y`). A measurement term: the channel (`v_x`, `v_y`, `L`, `lambda`).
    pub to: String,
    /// The coefficient, by name.
    pub coefficient: String,
    /// The feature, by name ([`TermFeature::ALL`]).
    pub feature: String,
    /// A constant factor (default 1; `-1` writes a minus sign).
    #[serde(default = "one", skip_serializing_if = "is_one")]
    pub factor: f64,
}

impl CoefficientDeclaration {
    /// Its bound as the model holds it: unbounded when none is declared.
    pub(crate) fn physical_bound(&self) -> crate::sensor_classes::PhysicalBound {
        match self.bound {
            Some(limit) => crate::sensor_classes::PhysicalBound {
                limit,
                reason: super::intern(self.bound_reason.as_deref().unwrap_or("declared")),
            },
            None => crate::sensor_classes::PhysicalBound {
                limit: f64::INFINITY,
                reason: "no bound declared",
            },
        }
    }
}

fn one() -> f64 {
    1.0
}

fn is_one(v: &f64) -> bool {
    *v == 1.0
}

/// The rows a rate term may add to: the attitude errors (gyro errors, joining `eps` in
/// docs/model.md eq. (8)) and the velocities (accelerometer errors, joining `nab` in
/// docs/model.md eq. (9)). The position's derivatives (docs/model.md eq. (10)) are
/// kinematics, not sensor errors.
pub(crate) const RATE_ROWS: [&str; 5] = ["phi_x", "phi_y", "phi_z", "v_x", "v_y"];

/// A term checked: its row, coefficient index, feature and factor.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct CheckedTerm {
    pub row: usize,
    pub coefficient: usize,
    pub feature: TermFeature,
    pub factor: f64,
}

impl EffectDeclaration {
    /// Checks the declaration against the effects already known (`effects`, whose names it may
    /// not take, and `owner_of`, the effect owning a coefficient name). Returns its terms
    /// checked (rates, then measurement), or the key at fault, relative to this table
    /// (`rates[1].feature`), and what was expected.
    pub(crate) fn check(
        &self,
        effects: &[String],
        owner_of: impl Fn(&str) -> Option<String>,
    ) -> Result<(Vec<CheckedTerm>, Vec<CheckedTerm>), (String, String)> {
        let err = |key: String, message: String| Err((key, message));
        self.check_name_and_coefficients(effects, owner_of, &BASE_NAMES)?;
        if !self.places.is_empty() {
            return err(
                "places".into(),
                "places are the strapdown family's (a sensor-error matrix entry, the \
                 odometer's mounting, the lever arm); expected `rates` or `measurement` terms \
                 for a platform effect"
                    .into(),
            );
        }
        if self.rates.is_empty() && self.measurement.is_empty() {
            return err(
                "rates".into(),
                "no term; expected `rates` or `measurement` terms (coefficient x feature)".into(),
            );
        }
        let rates = self.check_terms("rates", &self.rates, TermSide::Rate)?;
        let measurement =
            self.check_terms("measurement", &self.measurement, TermSide::Measurement)?;
        for (i, c) in self.coefficients.iter().enumerate() {
            if !rates.iter().chain(&measurement).any(|t| t.coefficient == i) {
                return err(
                    format!("coefficients[{i}].name"),
                    format!(
                        "`{}` is in no term; expected every coefficient in a rate or \
                         measurement term (one in none cannot be estimated)",
                        c.name
                    ),
                );
            }
        }
        Ok((rates, measurement))
    }

    /// The checks both families make: a new effect name, and coefficients with new names
    /// (none a state of the base model, `base_names`), units, positive sigmas and sensible
    /// bounds.
    pub(crate) fn check_name_and_coefficients(
        &self,
        effects: &[String],
        owner_of: impl Fn(&str) -> Option<String>,
        base_names: &[&str],
    ) -> Result<(), (String, String)> {
        let err = |key: String, message: String| Err((key, message));
        if !is_name(&self.name, true) {
            return err(
                "name".into(),
                format!(
                    "`{}`: expected a name of letters, digits, `-` and `_`, starting with a \
                     letter (e.g. `drag`)",
                    self.name
                ),
            );
        }
        if effects.contains(&self.name) {
            return err(
                "name".into(),
                format!(
                    "`{}` is an effect already (known effects: {}); expected a new name",
                    self.name,
                    effects.join(", ")
                ),
            );
        }
        if self.coefficients.is_empty() {
            return err(
                "coefficients".into(),
                "empty; expected at least one coefficient (an effect without one adds \
                 nothing a filter can estimate)"
                    .into(),
            );
        }
        for (i, c) in self.coefficients.iter().enumerate() {
            let key = |k: &str| format!("coefficients[{i}].{k}");
            if !is_name(&c.name, false) {
                return err(
                    key("name"),
                    format!(
                        "`{}`: expected letters, digits and `_`, starting with a letter",
                        c.name
                    ),
                );
            }
            if self.coefficients[..i].iter().any(|d| d.name == c.name) {
                return err(key("name"), format!("`{}` is given twice", c.name));
            }
            if base_names.contains(&c.name.as_str()) {
                return err(
                    key("name"),
                    format!("`{}` is a state of the model; expected a new name", c.name),
                );
            }
            if let Some(owner) = owner_of(&c.name) {
                return err(
                    key("name"),
                    format!(
                        "`{}` is a coefficient of `{owner}` already; expected a new name",
                        c.name
                    ),
                );
            }
            if c.unit.trim().is_empty() {
                return err(
                    key("unit"),
                    "empty; expected the coefficient's unit (`1/s`, `1` for none)".into(),
                );
            }
            if !(c.sigma.is_finite() && c.sigma > 0.0) {
                return err(
                    key("sigma"),
                    format!("{}: expected a one-sigma size > 0", c.sigma),
                );
            }
            match (c.bound, &c.bound_reason) {
                (Some(b), _) if !(b.is_finite() && b > c.sigma) => {
                    return err(
                        key("bound"),
                        format!(
                            "{b}: expected a finite bound above the sigma {} (a bound below the \
                             typical size refuses typical values)",
                            c.sigma
                        ),
                    );
                }
                (None, Some(_)) => {
                    return err(
                        key("bound_reason"),
                        "a reason without a bound; expected `bound` too, or no reason".into(),
                    );
                }
                _ => {}
            }
        }
        Ok(())
    }

    fn check_terms(
        &self,
        list: &str,
        terms: &[TermDeclaration],
        side: TermSide,
    ) -> Result<Vec<CheckedTerm>, (String, String)> {
        let rows: &[&str] = match side {
            TermSide::Rate => &RATE_ROWS,
            TermSide::Measurement => &MEASUREMENT_NAMES,
        };
        let mut checked = Vec::with_capacity(terms.len());
        for (i, t) in terms.iter().enumerate() {
            let key = |k: &str| format!("{list}[{i}].{k}");
            let Some(row) = rows.iter().position(|r| *r == t.to) else {
                return Err((
                    key("to"),
                    format!("`{}`: expected one of {}", t.to, rows.join(", ")),
                ));
            };
            let coefficient = self.coefficient_index(&t.coefficient, key("coefficient"))?;
            let feature = TermFeature::parse(&t.feature)
                .filter(|f| f.allowed_on(side))
                .ok_or_else(|| {
                    (
                        key("feature"),
                        format!(
                            "`{}`: expected one of {}{}",
                            t.feature,
                            TermFeature::names_on(side).join(", "),
                            match side {
                                TermSide::Measurement => {
                                    " (a measurement has no input: the specific force and the \
                                     commanded rate are the rates' only)"
                                }
                                TermSide::Rate => "",
                            }
                        ),
                    )
                })?;
            if !(t.factor.is_finite() && t.factor != 0.0) {
                return Err((
                    key("factor"),
                    format!("{}: expected a finite factor other than 0", t.factor),
                ));
            }
            // The rate rows of the navigation state are its first five.
            debug_assert!(side == TermSide::Measurement || row < NAV_DIM);
            checked.push(CheckedTerm {
                row,
                coefficient,
                feature,
                factor: t.factor,
            });
        }
        Ok(checked)
    }

    /// The index of the coefficient called `name`, or the error at `key` listing the names.
    pub(crate) fn coefficient_index(
        &self,
        name: &str,
        key: String,
    ) -> Result<usize, (String, String)> {
        self.coefficients
            .iter()
            .position(|c| c.name == name)
            .ok_or_else(|| {
                let names: Vec<&str> = self.coefficients.iter().map(|c| c.name.as_str()).collect();
                (
                    key,
                    format!(
                        "`{name}`: expected one of this effect's coefficients ({})",
                        names.join(", ")
                    ),
                )
            })
    }

    /// The terms written out, for the description when the declaration gives none:
    /// `v_x' += kd v_x; z_L += -1 tau L_dot`.
    pub(crate) fn written_terms(&self) -> String {
        let write = |t: &TermDeclaration, target: String| {
            let factor = if t.factor == 1.0 {
                String::new()
            } else {
                format!("{} ", t.factor)
            };
            let feature = if t.feature == "1" {
                String::new()
            } else {
                format!(" {}", t.feature)
            };
            format!("{target} += {factor}{}{feature}", t.coefficient)
        };
        self.rates
            .iter()
            .map(|t| write(t, format!("{}'", t.to)))
            .chain(
                self.measurement
                    .iter()
                    .map(|t| write(t, format!("z_{}", t.to))),
            )
            .collect::<Vec<_>>()
            .join("; ")
    }
}

/// Whether `s` is a name: ASCII letters, digits, `_` (and `-` for an effect), starting with a
/// letter, at most 40 characters.
fn is_name(s: &str, dash: bool) -> bool {
    s.len() <= 40
        && s.chars().next().is_some_and(|c| c.is_ascii_alphabetic())
        && s.chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || (dash && c == '-'))
}
