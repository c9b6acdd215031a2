//! An acceleration error that depends on the vehicle's velocity, outside the catalogue: the
//! rival the refitted noise levels must beat before they are named on the platform
//! ([`super`]).
//!
//! `v' += M v + s |v| - kq v |v|` on the East and North axes (`v = (v_x, v_y)`, `|v|` the
//! horizontal speed):
//! - `M`, a 2x2 matrix: every force linear in the velocity. A drag is `M = -kd I` (the
//!   simulator's own [`navkf_dynamics::outside::Drag`]), a mis-stated Coriolis or transport
//!   term the antisymmetric `M = kc [[0, 1], [-1, 0]]`, a drag of different sizes along the
//!   two axes the rest;
//! - `s`: a bias along a fixed direction that grows with speed;
//! - `kq`: the quadratic drag of air and rolling resistance at road speeds.
//!
//! Each law alone was not enough. With the linear drag as the only rival, 5 of 6 quadratic
//! drags (3-30 times a tenth of the accelerometer bias at 15 m/s) ended `consistent` with the
//! gyro noise refitted at 95-723 times the level the data were made with; with both drags,
//! a mis-stated Coriolis term and an East error proportional to speed still did, 4 of 4, at
//! 56-273 times (docs/diagnosis.md, "Rounds"). All seven are linear in their coefficients, so
//! the filters estimate them like any rate term, and the levels are weighed against the
//! BIC that counts only the coefficients the data inform: a law the trajectory does not
//! excite costs nothing.
//!
//! The values and slopes of `v`, `|v|` and `v |v|` are the declared effects' ([`TermFeature`]),
//! written once.

use navkf_dynamics::declared::TermFeature;
use navkf_dynamics::effect::{Effect, Partials, Terms};
use navkf_dynamics::kinematics::Kinematics;
use navkf_dynamics::outside::Drag;
use navkf_dynamics::real::Real;
use navkf_dynamics::state::{NAV_DIM, V_X, V_Y};

/// See the module documentation. Coefficients: `m_xx`, `m_xy`, `m_yx`, `m_yy`, `s_x`, `s_y`
/// (1/s) and `kq` (1/m).
#[derive(Debug, Default, Clone)]
pub struct VelocityDependentAcceleration;

impl VelocityDependentAcceleration {
    /// The name it is fitted under (never named: it is not in the catalogue).
    pub const NAME: &'static str = "velocity-dependent-acceleration";
    /// Typical size of `kq`, 1/m: the linear drag's typical size at 15 m/s, 7.5e-4 m/s^2.
    pub const TYPICAL_KQ: f64 = Drag::TYPICAL / 15.0;
}

/// Each term: the velocity state it adds to, its coefficient's index, its feature, and the
/// sign it enters with.
const TERMS: [(usize, usize, TermFeature, f64); 8] = [
    (V_X, 0, TermFeature::Velocity(0), 1.0),
    (V_X, 1, TermFeature::Velocity(1), 1.0),
    (V_Y, 2, TermFeature::Velocity(0), 1.0),
    (V_Y, 3, TermFeature::Velocity(1), 1.0),
    (V_X, 4, TermFeature::Speed, 1.0),
    (V_Y, 5, TermFeature::Speed, 1.0),
    (V_X, 6, TermFeature::VelocityTimesSpeed(0), -1.0),
    (V_Y, 6, TermFeature::VelocityTimesSpeed(1), -1.0),
];

impl Effect for VelocityDependentAcceleration {
    fn name(&self) -> &str {
        Self::NAME
    }
    fn description(&self) -> &str {
        "v' += M v + s |v| - kq v |v| (an acceleration error depending on the velocity: \
         linear in it along any direction, along a fixed direction with the speed, and a \
         quadratic drag; outside the catalogue)"
    }
    fn terms(&self) -> Terms {
        Terms::RATES
    }
    fn coefficient_names(&self) -> &[&str] {
        &["m_xx", "m_xy", "m_yx", "m_yy", "s_x", "s_y", "kq"]
    }
    fn coefficient_units(&self) -> &[&str] {
        &["1/s", "1/s", "1/s", "1/s", "1/s", "1/s", "1/m"]
    }
    fn coefficient_sigma(&self) -> &[f64] {
        const D: f64 = Drag::TYPICAL;
        &[D, D, D, D, D, D, VelocityDependentAcceleration::TYPICAL_KQ]
    }
    fn add_rates<T: Real>(&self, k: &Kinematics<T>, c: &[T], r: &mut [T; NAV_DIM]) {
        for (state, i, feature, sign) in TERMS {
            r[state] += T::splat(sign) * c[i] * feature.value(k);
        }
    }
    fn add_rate_partials(&self, k: &Kinematics, c: &[f64], offset: usize, p: &mut Partials) {
        for (state, i, feature, sign) in TERMS {
            feature.add_state_partials(k, sign * c[i], state, p);
            p.add(state, offset + i, sign * feature.value(k));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use navkf_dynamics::partials_check::check_effect;
    use navkf_dynamics::NoiseConfig;

    #[test]
    fn its_partials_agree_with_finite_differences() {
        for seed in [1, 2, 3] {
            let effect = Box::new(VelocityDependentAcceleration);
            let report = check_effect(effect, &NoiseConfig::default(), 16, seed).unwrap();
            assert!(report.passes(), "{report:?}");
        }
    }

    #[test]
    fn each_law_adds_what_it_says() {
        let k = Kinematics {
            v_x: 3.0,
            v_y: 4.0,
            ..Kinematics::default()
        };
        let rates = |c: [f64; 7]| {
            let mut r = [0.0; NAV_DIM];
            VelocityDependentAcceleration.add_rates(&k, &c, &mut r);
            (r[V_X], r[V_Y])
        };
        let close = |(a, b): (f64, f64), (x, y): (f64, f64)| {
            assert!((a - x).abs() < 1e-18 && (b - y).abs() < 1e-18, "{a} {b}");
        };
        // A linear drag: -kd v.
        close(
            rates([-1e-4, 0.0, 0.0, -1e-4, 0.0, 0.0, 0.0]),
            (-3e-4, -4e-4),
        );
        // A Coriolis-like rotation: (kc v_y, -kc v_x).
        close(rates([0.0, 2e-4, -2e-4, 0.0, 0.0, 0.0, 0.0]), (8e-4, -6e-4));
        // A bias growing with speed (|v| = 5), East only.
        close(rates([0.0, 0.0, 0.0, 0.0, 1e-4, 0.0, 0.0]), (5e-4, 0.0));
        // A quadratic drag: -kq v |v|.
        close(
            rates([0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1e-5]),
            (-1.5e-4, -2e-4),
        );
    }
}
