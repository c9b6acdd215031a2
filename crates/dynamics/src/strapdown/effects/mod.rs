//! The catalogue of strapdown effects, one file each, and the registry that finds them by
//! name: docs/model.md, "Strapdown effects"; docs/model.md eqs. (63)-(70).
//!
//! A strapdown effect is a declaration, not code: every term the catalogue names is a
//! coefficient in one place of the sensor-error description the model evaluates
//! ([`super::errors`]): an entry of a gyro or accelerometer error matrix, a g-sensitivity,
//! the odometer's scale or mounting angles, the antenna's lever arm, the fix's latency; or a
//! first-order Gauss-Markov law for a bias. The physics of those places is written once,
//! generic over the number type, so the truth simulator, the EKF's tangent (through dual
//! numbers) and the UKFs' batches all run the same equations, and a new effect is one file
//! with its coefficients' places and sizes, plus one line in [`StrapdownRegistry::catalogue`].
//! A user declares their own the same way and passes it to [`StrapdownRegistry::register`].

mod accel_bias_instability;
mod accel_misalignment;
mod accel_scale;
mod gps_latency;
mod gps_lever_arm;
mod gyro_bias_instability;
mod gyro_g_sensitivity;
mod gyro_misalignment;
mod gyro_scale;
mod odometer_misalignment;
mod odometer_scale;

use super::unit_class::UnitClass;
use crate::declared::{EffectCatalogue, EffectDeclaration};
use crate::error::DynamicsError;
pub use crate::sensor_classes::PhysicalBound;
use std::sync::Arc;

/// Where a coefficient acts (docs/model.md eqs. (63)-(68)).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Slot {
    /// `E_g[i][j]`: gyro axis `i` senses the rate about axis `j` (scale on the diagonal).
    Gyro(usize, usize),
    /// `E_a[i][j]`: accelerometer axis `i` senses the force along axis `j`.
    Accel(usize, usize),
    /// `G[i]`: gyro axis `i` senses the specific force along the same axis.
    GyroG(usize),
    /// `kod`: the odometer's scale error.
    OdometerScale,
    /// `a_y`: the vehicle's forward axis turned left of the unit's x axis.
    OdometerYaw,
    /// `a_p`: the vehicle's forward axis turned up.
    OdometerPitch,
    /// `l[i]`: the GPS antenna's offset from the unit along body axis `i`.
    LeverArm(usize),
    /// `tau`: the GPS fix refers to `tau` seconds before its time stamp.
    Latency,
}

impl Slot {
    /// Whether the slot changes the unit's readings (the rates) rather than the measurement.
    pub fn is_reading(self) -> bool {
        matches!(self, Slot::Gyro(..) | Slot::Accel(..) | Slot::GyroG(_))
    }
}

/// As docs/model.md writes the place (`E_g[x][y]`, `kod`, `l[z]`), which declarations use
/// ([`crate::declared::strapdown::parse_place`] reads it back).
impl std::fmt::Display for Slot {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let axis = |i: usize| ["x", "y", "z"].get(i).copied().unwrap_or("?");
        match *self {
            Slot::Gyro(i, j) => write!(f, "E_g[{}][{}]", axis(i), axis(j)),
            Slot::Accel(i, j) => write!(f, "E_a[{}][{}]", axis(i), axis(j)),
            Slot::GyroG(i) => write!(f, "G[{}]", axis(i)),
            Slot::OdometerScale => f.write_str("kod"),
            Slot::OdometerYaw => f.write_str("a_y"),
            Slot::OdometerPitch => f.write_str("a_p"),
            Slot::LeverArm(i) => write!(f, "l[{}]", axis(i)),
            Slot::Latency => f.write_str("tau"),
        }
    }
}

/// A place and the factor a coefficient enters it with: the place holds `factor x c`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Place {
    /// Where.
    pub slot: Slot,
    /// The constant factor (1 for every catalogued coefficient).
    pub factor: f64,
}

/// Where a coefficient acts: one place as it is (every catalogued coefficient), or several,
/// each with a factor (a declared one: a unit turned on its mount by a small angle `d` about
/// z puts `-d` in `E_g[x][y]` and `d` in `E_g[y][x]`, and the same in `E_a`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Places {
    /// One place, factor 1.
    One(Slot),
    /// Several places, each with its factor.
    Many(&'static [Place]),
}

impl Places {
    /// Each place with its factor.
    pub fn iter(&self) -> impl Iterator<Item = Place> + '_ {
        let (one, many) = match self {
            Places::One(slot) => (
                Some(Place {
                    slot: *slot,
                    factor: 1.0,
                }),
                &[][..],
            ),
            Places::Many(places) => (None, *places),
        };
        one.into_iter().chain(many.iter().copied())
    }
}

/// One coefficient of an effect: a random constant that joins the state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Coefficient {
    /// Name, as files and reports write it (`s_gx`).
    pub name: &'static str,
    /// Unit, for reports.
    pub unit: &'static str,
    /// Where it acts.
    pub places: Places,
    /// Typical one-sigma size per unit class, in [`UnitClass::ALL`]'s order (navigation,
    /// tactical, MEMS): the default spread of the truth's draw and a filter's prior.
    pub sigma: [f64; 3],
    /// The largest magnitude a real instrument gives it.
    pub bound: PhysicalBound,
}

impl Coefficient {
    /// The typical one-sigma for `class`.
    pub fn sigma_for(&self, class: UnitClass) -> f64 {
        self.sigma[class_index(class)]
    }
}

fn class_index(class: UnitClass) -> usize {
    UnitClass::ALL.iter().position(|c| *c == class).unwrap_or(2)
}

/// Which sensor triad a bias instability belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Triad {
    /// The gyros: the states `bgx, bgy, bgz`.
    Gyro,
    /// The accelerometers: `bax, bay, baz`.
    Accel,
}

/// A first-order Gauss-Markov law for a triad's biases' departures from their turn-on
/// values, `d' = -d / T + w`, steady one-sigma `sigma` (docs/model.md eq. (69)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Instability {
    /// Whose biases wander.
    pub triad: Triad,
    /// Correlation time `T`, s.
    pub time_s: f64,
    /// Steady one-sigma per unit class, in [`UnitClass::ALL`]'s order, (rad/s or m/s^2).
    pub sigma: [f64; 3],
    /// The parameters' names, as effect lists set them: `[T, sigma]`.
    pub parameter_names: [&'static str; 2],
}

impl Instability {
    /// The typical steady sigma for `class`.
    pub fn sigma_for(&self, class: UnitClass) -> f64 {
        self.sigma[class_index(class)]
    }
}

/// A strapdown effect (module documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct StrapdownEffect {
    /// Name, as command lines and study files write it (`gyro-scale`).
    pub name: &'static str,
    /// One line: what it adds, as a formula.
    pub description: &'static str,
    /// The coefficients it adds to the state (may be empty).
    pub coefficients: &'static [Coefficient],
    /// The Gauss-Markov law it gives a triad's biases, if that is what it adds.
    pub instability: Option<Instability>,
    /// The user's declaration it was made from (`None` for the catalogue's).
    pub declaration: Option<Arc<EffectDeclaration>>,
}

impl StrapdownEffect {
    /// The coefficients' names.
    pub fn coefficient_names(&self) -> Vec<&'static str> {
        self.coefficients.iter().map(|c| c.name).collect()
    }
}

/// Strapdown effects by name. [`StrapdownRegistry::catalogue`] holds the eleven of
/// docs/model.md; users add theirs.
#[derive(Debug, Clone)]
pub struct StrapdownRegistry {
    effects: Vec<StrapdownEffect>,
}

impl Default for StrapdownRegistry {
    fn default() -> Self {
        Self::catalogue()
    }
}

impl StrapdownRegistry {
    /// The catalogue (docs/model.md eqs. (63)-(70)).
    pub fn catalogue() -> Self {
        let mut r = StrapdownRegistry {
            effects: Vec::new(),
        };
        r.register(gyro_scale::GYRO_SCALE);
        r.register(accel_scale::ACCEL_SCALE);
        r.register(gyro_misalignment::GYRO_MISALIGNMENT);
        r.register(accel_misalignment::ACCEL_MISALIGNMENT);
        r.register(gyro_g_sensitivity::GYRO_G_SENSITIVITY);
        r.register(odometer_scale::ODOMETER_SCALE);
        r.register(odometer_misalignment::ODOMETER_MISALIGNMENT);
        r.register(gps_lever_arm::GPS_LEVER_ARM);
        r.register(gps_latency::GPS_LATENCY);
        r.register(gyro_bias_instability::GYRO_BIAS_INSTABILITY);
        r.register(accel_bias_instability::ACCEL_BIAS_INSTABILITY);
        r
    }

    /// Adds `effect`, replacing one of its name.
    pub fn register(&mut self, effect: StrapdownEffect) {
        self.effects.retain(|e| e.name != effect.name);
        self.effects.push(effect);
    }

    /// Adds effects declared in TOML ([`crate::declared::strapdown`]), each checked against
    /// the effects known before it: a new name, new coefficient names, known places. The
    /// error names the key (`effect[1].places[0].place`) and what was expected; on error
    /// nothing is added. A declaration the registry holds already, word for word, is
    /// skipped (a simulated dataset carries the declarations of its effects file).
    pub fn declare(&mut self, declarations: &[EffectDeclaration]) -> Result<(), DynamicsError> {
        let mut extended = self.clone();
        for (i, d) in declarations.iter().enumerate() {
            let same = extended
                .get(&d.name)
                .is_ok_and(|known| known.declaration.as_deref() == Some(d));
            if same {
                continue;
            }
            let known: Vec<String> = extended.names().iter().map(|n| n.to_string()).collect();
            let located = |(key, message): (String, String)| DynamicsError::Config {
                key: format!("effect[{i}].{key}"),
                message,
            };
            // A bias instability's parameter (`T_g`) is set by name as a coefficient is.
            for (k, c) in d.coefficients.iter().enumerate() {
                if let Some(owner) = extended.owner_of_parameter(&c.name) {
                    return Err(located((
                        format!("coefficients[{k}].name"),
                        format!(
                            "`{}` is a parameter of `{}` already; expected a new name",
                            c.name, owner.name
                        ),
                    )));
                }
            }
            let effect = d
                .strapdown_effect(&known, |c| extended.owner_of(c).map(|e| e.name.to_string()))
                .map_err(located)?;
            extended.register(effect);
        }
        *self = extended;
        Ok(())
    }

    /// Names, in registration order.
    pub fn names(&self) -> Vec<&'static str> {
        self.effects.iter().map(|e| e.name).collect()
    }

    /// The effect called `name`.
    pub fn get(&self, name: &str) -> Result<&StrapdownEffect, DynamicsError> {
        self.effects.iter().find(|e| e.name == name).ok_or_else(|| {
            DynamicsError::Effect(format!(
                "unknown strapdown effect `{name}`; known effects: {}",
                self.names().join(", ")
            ))
        })
    }

    /// The effect that owns coefficient `coefficient`, if any.
    pub fn owner_of(&self, coefficient: &str) -> Option<&StrapdownEffect> {
        self.effects
            .iter()
            .find(|e| e.coefficients.iter().any(|c| c.name == coefficient))
    }

    /// The effect whose instability has the parameter `name`, if any.
    pub fn owner_of_parameter(&self, name: &str) -> Option<&StrapdownEffect> {
        self.effects.iter().find(|e| {
            e.instability
                .is_some_and(|i| i.parameter_names.contains(&name))
        })
    }
}

/// The same size for every unit class (a sensor that is not the inertial unit's).
const fn every_class(sigma: f64) -> [f64; 3] {
    [sigma, sigma, sigma]
}

/// Degrees per hour, rad/s.
const DEG_PER_H: f64 = std::f64::consts::PI / 180.0 / 3600.0;
/// Standard gravity, m/s^2.
const G0: f64 = crate::earth::STANDARD_GRAVITY;

impl EffectCatalogue for StrapdownRegistry {
    fn catalogue() -> Self {
        StrapdownRegistry::catalogue()
    }

    fn declare(&mut self, declarations: &[EffectDeclaration]) -> Result<(), DynamicsError> {
        StrapdownRegistry::declare(self, declarations)
    }
}
