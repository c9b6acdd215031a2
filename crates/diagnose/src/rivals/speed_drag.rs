//! An acceleration error that grows with speed, outside the catalogue: the rival the refitted
//! noise levels must beat before they are named on the platform ([`super`]).
//!
//! `v' -= kd v + kq v |v|` on the East and North axes: a drag linear in the velocity (the
//! simulator's own [`navkf_dynamics::outside::Drag`]) and one quadratic in it, the law of air
//! or rolling resistance at road speeds, `|v|` the horizontal speed. Both are linear in their
//! coefficients, so the filters estimate them like any rate term. A drag of one law alone was
//! not enough: with the linear law as the only rival, 5 of 6 quadratic drags (3-30 times a
//! tenth of the accelerometer bias at 15 m/s) still ended `consistent` with the gyro noise
//! refitted at 95-723 times the level the data were made with (docs/diagnosis.md, "Rounds").
//! Two laws let the rival follow a misfit whose size grows with speed by either power, or by
//! any mixture of the two between them.
//!
//! The values and slopes of `v` and `v |v|` are the declared effects' ([`TermFeature`]),
//! written once.

use navkf_dynamics::declared::TermFeature;
use navkf_dynamics::effect::{Effect, Partials, Terms};
use navkf_dynamics::kinematics::Kinematics;
use navkf_dynamics::outside::Drag;
use navkf_dynamics::real::Real;
use navkf_dynamics::state::{NAV_DIM, V_X, V_Y};

/// See the module documentation. Coefficients: `kd` (1/s) and `kq` (1/m).
#[derive(Debug, Default, Clone)]
pub struct SpeedDrag;

impl SpeedDrag {
    /// The name it is fitted under (never named: it is not in the catalogue).
    pub const NAME: &'static str = "speed-drag";
    /// Typical size of `kq`, 1/m: the linear law's typical size at 15 m/s, 7.5e-4 m/s^2.
    pub const TYPICAL_KQ: f64 = Drag::TYPICAL / 15.0;
}

/// The axes the drag acts on: each velocity state with its features `v` and `v |v|`.
const AXES: [(usize, TermFeature, TermFeature); 2] = [
    (
        V_X,
        TermFeature::Velocity(0),
        TermFeature::VelocityTimesSpeed(0),
    ),
    (
        V_Y,
        TermFeature::Velocity(1),
        TermFeature::VelocityTimesSpeed(1),
    ),
];

impl Effect for SpeedDrag {
    fn name(&self) -> &str {
        Self::NAME
    }
    fn description(&self) -> &str {
        "v' -= kd v + kq v |v| (an acceleration error growing with speed, linearly and \
         quadratically; outside the catalogue)"
    }
    fn terms(&self) -> Terms {
        Terms::RATES
    }
    fn coefficient_names(&self) -> &[&str] {
        &["kd", "kq"]
    }
    fn coefficient_units(&self) -> &[&str] {
        &["1/s", "1/m"]
    }
    fn coefficient_sigma(&self) -> &[f64] {
        &[Drag::TYPICAL, Self::TYPICAL_KQ]
    }
    fn add_rates<T: Real>(&self, k: &Kinematics<T>, c: &[T], r: &mut [T; NAV_DIM]) {
        for (state, linear, quadratic) in AXES {
            r[state] -= c[0] * linear.value(k) + c[1] * quadratic.value(k);
        }
    }
    fn add_rate_partials(&self, k: &Kinematics, c: &[f64], offset: usize, p: &mut Partials) {
        for (state, linear, quadratic) in AXES {
            linear.add_state_partials(k, -c[0], state, p);
            quadratic.add_state_partials(k, -c[1], state, p);
            p.add(state, offset, -linear.value(k));
            p.add(state, offset + 1, -quadratic.value(k));
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
            let report =
                check_effect(Box::new(SpeedDrag), &NoiseConfig::default(), 16, seed).unwrap();
            assert!(report.passes(), "{report:?}");
        }
    }

    #[test]
    fn it_opposes_the_velocity_by_both_laws() {
        let k = Kinematics {
            v_x: 3.0,
            v_y: 4.0,
            ..Kinematics::default()
        };
        let mut r = [0.0; NAV_DIM];
        SpeedDrag.add_rates(&k, &[1e-4, 1e-5], &mut r);
        // |v| = 5: East 1e-4 * 3 + 1e-5 * 3 * 5, North 1e-4 * 4 + 1e-5 * 4 * 5.
        assert!((r[V_X] + 4.5e-4).abs() < 1e-18, "{r:?}");
        assert!((r[V_Y] + 6.0e-4).abs() < 1e-18, "{r:?}");
    }
}
