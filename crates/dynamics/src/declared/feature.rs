//! The quantities a declared effect's term multiplies its coefficient by: the documented list
//! of docs/declared-effects.md, open to growth (a new feature is one arm in each `match`
//! here and one line in [`TermFeature::ALL`]).
//!
//! A rate term reads the kinematics of the moment (specific force, commanded rate, velocity;
//! docs/model.md eqs. (7)-(9)); a measurement term reads only the state, since the predicted
//! measurement has no input (docs/model.md eq. (13)). Each feature gives its value, generic
//! over the number type like the base model, and its partial derivatives with respect to the
//! navigation states, which the EKF's Jacobian needs.

use crate::kinematics::Kinematics;
use crate::partials::Partials;
use crate::real::Real;
use crate::state::{LAT, V_X, V_Y};

/// A kinematic quantity a declared term multiplies its coefficient by.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TermFeature {
    /// `1`: the coefficient itself (a bias).
    One,
    /// `f_x`, `f_y`, `f_z`: the specific force along a platform axis, m/s^2 (rates only).
    SpecificForce(usize),
    /// `f_x^2`, `f_y^2`, `f_z^2`: its square, m^2/s^4 (rates only).
    SpecificForceSquared(usize),
    /// `w_x`, `w_y`, `w_z`: the rate the platform is torqued at, rad/s (rates only;
    /// docs/model.md eq. (7)).
    CommandedRate(usize),
    /// `v_x`, `v_y`: the East or North velocity, m/s.
    Velocity(usize),
    /// `L_dot`: the latitude's rate `v_y / RM`, rad/s.
    LatitudeRate,
    /// `lambda_dot`: the longitude's rate `v_x / (RN cos L)`, rad/s.
    LongitudeRate,
    /// `speed`: the horizontal speed `|v|`, m/s.
    Speed,
    /// `v_x_speed`, `v_y_speed`: a velocity component times the speed, `v_x |v|`, m^2/s^2
    /// (a quadratic drag, a tyre's radius growing with speed).
    VelocityTimesSpeed(usize),
}

/// Where a term adds: to a state derivative, or to the predicted measurement.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TermSide {
    /// A navigation-state derivative.
    Rate,
    /// A measurement channel.
    Measurement,
}

impl TermFeature {
    /// Every feature, with the name a declaration writes, its unit and one line of meaning.
    pub const ALL: [(TermFeature, &'static str, &'static str, &'static str); 19] = [
        (
            TermFeature::One,
            "1",
            "1",
            "the coefficient itself (a bias)",
        ),
        (
            TermFeature::SpecificForce(0),
            "f_x",
            "m/s^2",
            "specific force, platform x",
        ),
        (
            TermFeature::SpecificForce(1),
            "f_y",
            "m/s^2",
            "specific force, platform y",
        ),
        (
            TermFeature::SpecificForce(2),
            "f_z",
            "m/s^2",
            "specific force, platform z",
        ),
        (
            TermFeature::SpecificForceSquared(0),
            "f_x^2",
            "m^2/s^4",
            "its square",
        ),
        (
            TermFeature::SpecificForceSquared(1),
            "f_y^2",
            "m^2/s^4",
            "its square",
        ),
        (
            TermFeature::SpecificForceSquared(2),
            "f_z^2",
            "m^2/s^4",
            "its square",
        ),
        (
            TermFeature::CommandedRate(0),
            "w_x",
            "rad/s",
            "commanded rate, -v_y/RM",
        ),
        (
            TermFeature::CommandedRate(1),
            "w_y",
            "rad/s",
            "commanded rate, wie cosL + v_x/RN",
        ),
        (
            TermFeature::CommandedRate(2),
            "w_z",
            "rad/s",
            "commanded rate, wie sinL + v_x tanL/RN",
        ),
        (TermFeature::Velocity(0), "v_x", "m/s", "East velocity"),
        (TermFeature::Velocity(1), "v_y", "m/s", "North velocity"),
        (
            TermFeature::LatitudeRate,
            "L_dot",
            "rad/s",
            "latitude rate, v_y/RM",
        ),
        (
            TermFeature::LongitudeRate,
            "lambda_dot",
            "rad/s",
            "longitude rate, v_x/(RN cosL)",
        ),
        (TermFeature::Speed, "speed", "m/s", "horizontal speed |v|"),
        (
            TermFeature::VelocityTimesSpeed(0),
            "v_x_speed",
            "m^2/s^2",
            "East velocity x speed, v_x |v|",
        ),
        (
            TermFeature::VelocityTimesSpeed(1),
            "v_y_speed",
            "m^2/s^2",
            "North velocity x speed, v_y |v|",
        ),
        // Listed once more under the names a reader of the paper may try first.
        (
            TermFeature::Velocity(0),
            "v_E",
            "m/s",
            "East velocity (= v_x)",
        ),
        (
            TermFeature::Velocity(1),
            "v_N",
            "m/s",
            "North velocity (= v_y)",
        ),
    ];

    /// The feature called `name`.
    pub fn parse(name: &str) -> Option<TermFeature> {
        Self::ALL
            .iter()
            .find(|(_, n, _, _)| *n == name)
            .map(|(f, _, _, _)| *f)
    }

    /// The name a declaration writes.
    pub fn name(self) -> &'static str {
        Self::ALL
            .iter()
            .find(|(f, _, _, _)| *f == self)
            .map(|(_, n, _, _)| *n)
            .expect("every feature is listed")
    }

    /// The unit of the feature.
    pub fn unit(self) -> &'static str {
        Self::ALL
            .iter()
            .find(|(f, _, _, _)| *f == self)
            .map(|(_, _, u, _)| *u)
            .expect("every feature is listed")
    }

    /// Whether a term on `side` may read it: a measurement has no input, so the specific
    /// force and the commanded rate (which is defined with it) are the rates' only.
    pub fn allowed_on(self, side: TermSide) -> bool {
        match self {
            TermFeature::SpecificForce(_)
            | TermFeature::SpecificForceSquared(_)
            | TermFeature::CommandedRate(_) => side == TermSide::Rate,
            _ => true,
        }
    }

    /// The names a term on `side` may use, for error messages.
    pub fn names_on(side: TermSide) -> Vec<&'static str> {
        Self::ALL
            .iter()
            .filter(|(f, _, _, _)| f.allowed_on(side))
            .map(|(_, n, _, _)| *n)
            .collect()
    }

    /// Whether the feature depends on the state (then `c * feature` is non-linear in it).
    pub fn depends_on_state(self) -> bool {
        !matches!(
            self,
            TermFeature::One | TermFeature::SpecificForce(_) | TermFeature::SpecificForceSquared(_)
        )
    }

    /// Its value at kinematics `k`.
    #[inline]
    pub fn value<T: Real>(self, k: &Kinematics<T>) -> T {
        match self {
            TermFeature::One => T::splat(1.0),
            TermFeature::SpecificForce(a) => k.f[a],
            TermFeature::SpecificForceSquared(a) => k.f[a] * k.f[a],
            TermFeature::CommandedRate(a) => k.w_cmd[a],
            TermFeature::Velocity(0) => k.v_x,
            TermFeature::Velocity(_) => k.v_y,
            TermFeature::LatitudeRate => k.v_y * k.inv_rm,
            TermFeature::LongitudeRate => k.v_x * k.inv_rn * k.inv_cos,
            TermFeature::Speed => speed(k),
            TermFeature::VelocityTimesSpeed(0) => k.v_x * speed(k),
            TermFeature::VelocityTimesSpeed(_) => k.v_y * speed(k),
        }
    }

    /// Adds `scale` times the feature's partials with respect to the navigation states to
    /// row `row` (the specific force is an input, so it has none). `k` carries the latitude
    /// slopes ([`Kinematics::with_slopes`]).
    pub fn add_state_partials(self, k: &Kinematics, scale: f64, row: usize, p: &mut Partials) {
        match self {
            TermFeature::One
            | TermFeature::SpecificForce(_)
            | TermFeature::SpecificForceSquared(_) => {}
            // The commanded rate's partials are the catalogue's linear rates' (written once).
            TermFeature::CommandedRate(a) => {
                crate::linear_rates::Feature::CommandedRate(a).add_state_partials(k, scale, row, p)
            }
            TermFeature::Velocity(0) => p.add(row, V_X, scale),
            TermFeature::Velocity(_) => p.add(row, V_Y, scale),
            TermFeature::LatitudeRate => {
                p.add(row, V_Y, scale * k.inv_rm);
                p.add(row, LAT, scale * k.v_y * k.d_inv_rm);
            }
            // d|v|/dv = v/|v|: the unit vector, taken as zero at a standstill (where |v| has
            // no derivative; a filter linearising there sees the speed's smallest slope).
            TermFeature::Speed => {
                let s = speed(k);
                if s > 0.0 {
                    p.add(row, V_X, scale * k.v_x / s);
                    p.add(row, V_Y, scale * k.v_y / s);
                }
            }
            // d(v_a |v|)/dv_a = |v| + v_a^2/|v|, d(v_a |v|)/dv_b = v_a v_b / |v|: both
            // tend to 0 at a standstill, where the function is differentiable.
            TermFeature::VelocityTimesSpeed(a) => {
                let s = speed(k);
                if s > 0.0 {
                    let (va, vb, ca, cb) = if a == 0 {
                        (k.v_x, k.v_y, V_X, V_Y)
                    } else {
                        (k.v_y, k.v_x, V_Y, V_X)
                    };
                    p.add(row, ca, scale * (s + va * va / s));
                    p.add(row, cb, scale * va * vb / s);
                }
            }
            // d(sec L / RN)/dL = sec L (d(1/RN)/dL + tan L / RN)
            TermFeature::LongitudeRate => {
                p.add(row, V_X, scale * k.inv_rn * k.inv_cos);
                p.add(
                    row,
                    LAT,
                    scale * k.v_x * k.inv_cos * (k.d_inv_rn + k.inv_rn * k.tan_l),
                );
            }
        }
    }
}

/// The horizontal speed `|v|`.
#[inline]
fn speed<T: Real>(k: &Kinematics<T>) -> T {
    (k.v_x * k.v_x + k.v_y * k.v_y).sqrt()
}
