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
//! It is a declaration ([`navkf_dynamics::declared`]), `factor x coefficient x feature` on
//! the velocity rows, as a user would write it in TOML: its physics, partials and
//! coefficient-name checks are the declared effects', written once.

use navkf_dynamics::declared::{CoefficientDeclaration, EffectDeclaration, TermDeclaration};
use navkf_dynamics::outside::Drag;

/// See the module documentation. Coefficients: `m_xx`, `m_xy`, `m_yx`, `m_yy`, `s_x`, `s_y`
/// (1/s) and `kq` (1/m).
pub struct VelocityDependentAcceleration;

impl VelocityDependentAcceleration {
    /// The name it is fitted under (never named: it is not in the catalogue).
    pub const NAME: &'static str = "velocity-dependent-acceleration";
    /// Typical size of `kq`, 1/m: the linear drag's typical size at 15 m/s, 7.5e-4 m/s^2.
    pub const TYPICAL_KQ: f64 = Drag::TYPICAL / 15.0;

    /// Its declaration, to add to a registry ([`navkf_dynamics::effects::Registry::declare`]).
    pub fn declaration() -> EffectDeclaration {
        Self::declaration_avoiding(&[])
    }

    /// Its declaration with each coefficient renamed where `taken` (the registry's own
    /// coefficient names) already has it: `m_xx` becomes `m_xx_rival` (then `m_xx_rival2`,
    /// ...), so that a user's effect with a coefficient called `kq` does not drop the rival.
    pub fn declaration_avoiding(taken: &[String]) -> EffectDeclaration {
        let free = |name: &str| -> String {
            let is_taken = |n: &str| taken.iter().any(|t| t == n);
            if !is_taken(name) {
                return name.to_string();
            }
            (1..)
                .map(|i| match i {
                    1 => format!("{name}_rival"),
                    i => format!("{name}_rival{i}"),
                })
                .find(|n| !is_taken(n))
                .expect("finitely many names are taken")
        };
        let names: Vec<String> = ["m_xx", "m_xy", "m_yx", "m_yy", "s_x", "s_y", "kq"]
            .iter()
            .map(|n| free(n))
            .collect();
        let [m_xx, m_xy, m_yx, m_yy, s_x, s_y, kq] = [0, 1, 2, 3, 4, 5, 6].map(|i| &*names[i]);
        let coefficient = |name: &str, unit: &str, sigma: f64| CoefficientDeclaration {
            name: name.into(),
            unit: unit.into(),
            sigma,
            bound: None,
            bound_reason: None,
        };
        let term = |to: &str, coefficient: &str, feature: &str, factor: f64| TermDeclaration {
            to: to.into(),
            coefficient: coefficient.into(),
            feature: feature.into(),
            factor,
        };
        let d = Drag::TYPICAL;
        EffectDeclaration {
            name: Self::NAME.into(),
            description: "v' += M v + s |v| - kq v |v| (an acceleration error depending on the \
                          velocity: linear in it along any direction, along a fixed direction \
                          with the speed, and a quadratic drag; outside the catalogue)"
                .into(),
            coefficients: vec![
                coefficient(m_xx, "1/s", d),
                coefficient(m_xy, "1/s", d),
                coefficient(m_yx, "1/s", d),
                coefficient(m_yy, "1/s", d),
                coefficient(s_x, "1/s", d),
                coefficient(s_y, "1/s", d),
                coefficient(kq, "1/m", Self::TYPICAL_KQ),
            ],
            rates: vec![
                term("v_x", m_xx, "v_x", 1.0),
                term("v_x", m_xy, "v_y", 1.0),
                term("v_y", m_yx, "v_x", 1.0),
                term("v_y", m_yy, "v_y", 1.0),
                term("v_x", s_x, "speed", 1.0),
                term("v_y", s_y, "speed", 1.0),
                term("v_x", kq, "v_x_speed", -1.0),
                term("v_y", kq, "v_y_speed", -1.0),
            ],
            measurement: Vec::new(),
            places: Vec::new(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use navkf_dynamics::effect::DynEffect;
    use navkf_dynamics::effects::Registry;
    use navkf_dynamics::kinematics::Kinematics;
    use navkf_dynamics::partials_check::check_effect;
    use navkf_dynamics::state::{NAV_DIM, V_X, V_Y};
    use navkf_dynamics::NoiseConfig;

    fn built() -> Box<dyn DynEffect> {
        let mut registry = Registry::catalogue();
        registry
            .declare(&[VelocityDependentAcceleration::declaration()])
            .unwrap();
        registry.build(VelocityDependentAcceleration::NAME).unwrap()
    }

    #[test]
    fn its_partials_agree_with_finite_differences() {
        for seed in [1, 2, 3] {
            let report = check_effect(built(), &NoiseConfig::default(), 16, seed).unwrap();
            assert!(report.passes(), "{report:?}");
        }
    }

    #[test]
    fn a_coefficient_name_a_user_took_is_renamed_not_dropped() {
        use crate::catalogue::{coefficient_names, Catalogue};
        let user = navkf_dynamics::declared::parse_declarations(
            r#"
            [[effect]]
            name = "user-drag"
            description = "v' -= kq v |v|"
            coefficients = [{ name = "kq", unit = "1/m", sigma = 1e-6 }]
            rates = [{ to = "v_x", coefficient = "kq", feature = "v_x_speed", factor = -1.0 }]
            "#,
        )
        .unwrap();
        let mut registry = Registry::catalogue();
        registry.declare(&user).unwrap();
        let (with_rival, name) = registry
            .with_levels_rival()
            .expect("declared")
            .expect("the rival, renamed");
        let rival = with_rival.effect(name).unwrap().coefficients;
        assert_eq!(rival[6], "kq_rival");
        assert_eq!(rival[..6], ["m_xx", "m_xy", "m_yx", "m_yy", "s_x", "s_y"]);
        // A second clash takes the next free name.
        let taken = [coefficient_names(&registry), vec!["kq_rival".into()]].concat();
        let d = VelocityDependentAcceleration::declaration_avoiding(&taken);
        assert_eq!(d.coefficients[6].name, "kq_rival2");
    }

    #[test]
    fn each_law_adds_what_it_says() {
        let effect = built();
        let k = Kinematics {
            v_x: 3.0,
            v_y: 4.0,
            ..Kinematics::default()
        };
        let rates = |c: [f64; 7]| {
            let mut r = [0.0; NAV_DIM];
            effect.add_rates(&k, &c, &mut r);
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
