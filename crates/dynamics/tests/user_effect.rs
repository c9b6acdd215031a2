//! An effect written outside the crate, through the public `Effect` trait only, assembled
//! into a `PlatformModel` directly and through a `Registry`; and the registry's and the
//! model's refusals (unknown name, duplicated effect, clashing or malformed coefficients).
//!
//! The user effect is a gyro input-axis misalignment, which the catalogue lacks. A gimballed
//! platform is torqued so that each gyro senses the commanded rate; a gyro whose input axis is
//! tilted by a small angle toward another platform axis also senses that axis's rate, so the
//! loop leaves the platform turning by `-m w_other`:
//!
//! ```text
//! phi_z' += -Mzy (wie cosL + v_x/RN)       z gyro tilted toward North senses w_cmd,y
//! phi_x' += -Mxz (wie sinL + v_x tanL/RN)  x gyro tilted toward Up senses w_cmd,z
//! ```
//!
//! Unlike the catalogue's gyro terms it depends on velocity and latitude, so its partials
//! have state columns as well as coefficient columns.

use crate::common;

use common::*;
use navkf_dynamics::earth::WIE;
use navkf_dynamics::state::*;
use navkf_dynamics::{
    DynamicsError, Effect, Kinematics, NoiseConfig, Partials, PhysicalBound, PlatformModel,
    Registry, SystemModel,
};

#[derive(Debug, Default)]
struct GyroMisalignment;

impl Effect for GyroMisalignment {
    fn terms(&self) -> navkf_dynamics::Terms {
        navkf_dynamics::Terms {
            rates: true,
            linear_rates: &[],
            measurement: navkf_dynamics::MeasurementTerm::None,
            noise: false,
        }
    }
    fn name(&self) -> &str {
        "gyro-misalignment"
    }
    fn description(&self) -> &str {
        "phi_z' -= Mzy w_cmd,y, phi_x' -= Mxz w_cmd,z (gyro input-axis misalignment)"
    }
    fn coefficient_names(&self) -> &[&str] {
        &["Mzy", "Mxz"]
    }
    fn coefficient_units(&self) -> &[&str] {
        &["rad", "rad"]
    }
    fn coefficient_sigma(&self) -> &[f64] {
        // 20 arcsec.
        &[1e-4, 1e-4]
    }
    fn add_rates<T: navkf_dynamics::Real>(
        &self,
        k: &Kinematics<T>,
        c: &[T],
        rates: &mut [T; NAV_DIM],
    ) {
        rates[PHI_Z] -= c[0] * k.w_cmd[1];
        rates[PHI_X] -= c[1] * k.w_cmd[2];
    }
    fn add_rate_partials(&self, k: &Kinematics, c: &[f64], offset: usize, p: &mut Partials) {
        // w_cmd,y = wie cosL + v_x/RN
        p.add(PHI_Z, offset, -k.w_cmd[1]);
        p.add(PHI_Z, V_X, -c[0] * k.inv_rn);
        p.add(PHI_Z, LAT, -c[0] * (-WIE * k.sin_l + k.v_x * k.d_inv_rn));
        // w_cmd,z = wie sinL + v_x tanL/RN
        p.add(PHI_X, offset + 1, -k.w_cmd[2]);
        p.add(PHI_X, V_X, -c[1] * k.tan_over_rn);
        p.add(
            PHI_X,
            LAT,
            -c[1] * (WIE * k.cos_l + k.v_x * k.d_tan_over_rn),
        );
    }
}

fn registry() -> Registry {
    let mut reg = Registry::catalogue();
    reg.register(|| Box::new(GyroMisalignment));
    reg
}

fn effect_error(r: Result<PlatformModel, DynamicsError>) -> String {
    match r {
        Err(DynamicsError::Effect(msg)) => msg,
        Err(other) => panic!("expected an effect error, got {other}"),
        Ok(m) => panic!("expected an error, got a model with {:?}", m.effect_names()),
    }
}

/// Catches: a model that miscounts or misnames an outside effect's coefficients.
#[test]
fn user_effect_extends_dim_and_names() {
    let m = PlatformModel::new(vec![Box::new(GyroMisalignment)], &NoiseConfig::default()).unwrap();
    assert_eq!(m.dim(), 22);
    assert_eq!(SystemModel::dim(&m), 22);
    let names = m.state_names();
    assert_eq!(&names[..20], &BASE_NAMES);
    assert_eq!(&names[20..], ["Mzy", "Mxz"]);
    assert_eq!(m.units()[20], "rad");
    assert_eq!(m.effect_names(), ["gyro-misalignment"]);
    assert_eq!(m.effect_offset(0), 20);
    assert_eq!(m.noise_channels().len(), 5);
    assert!(m.measurement_is_linear());
}

/// Registered next to the catalogue and built by name, in between catalogue effects.
/// Catches: `register` not adding, `build_all` losing order, offsets of effects that follow
/// a user effect.
#[test]
fn user_effect_registered_and_built_by_name() {
    let reg = registry();
    assert_eq!(reg.names().len(), 9);
    assert_eq!(reg.names().last().unwrap(), "gyro-misalignment");
    assert_eq!(reg.owner_of("Mxz").as_deref(), Some("gyro-misalignment"));
    let effects = reg
        .build_all(&["gyro-fz", "gyro-misalignment", "odometer-scale"])
        .unwrap();
    let m = PlatformModel::new(effects, &NoiseConfig::default()).unwrap();
    assert_eq!(m.dim(), 20 + 3 + 2 + 1);
    assert_eq!(
        &m.state_names()[20..],
        ["Kg13x", "Kg13y", "Kg13z", "Mzy", "Mxz", "kod"]
    );
    assert_eq!(
        (m.effect_offset(0), m.effect_offset(1), m.effect_offset(2)),
        (20, 23, 25)
    );
    assert_eq!(m.index_of("Mzy"), Some(23));
}

/// The user term reaches `rates` with the coefficients at its offset: the difference from
/// the base model at the same navigation state is exactly the two terms above.
/// Catches: an effect handed the wrong coefficient slice, or its rates not called.
#[test]
fn user_effect_adds_its_terms_to_the_rates() {
    let reg = registry();
    let m = PlatformModel::new(
        reg.build_all(&["gyro-fz", "gyro-misalignment"]).unwrap(),
        &NoiseConfig::default(),
    )
    .unwrap();
    let b = PlatformModel::base(&NoiseConfig::default());
    let mut rng = rng(70);
    for _ in 0..5 {
        let x = random_state(&m, &mut rng);
        let u = random_input(&mut rng);
        let (mut r, mut rb) = (vec![0.0; 7], vec![0.0; 7]);
        m.rates(&x, &u, &mut r);
        b.rates(&x[..20], &u, &mut rb);
        let (s, c) = x[LAT].sin_cos();
        let rn = navkf_dynamics::earth::prime_vertical_radius(s);
        let (mzy, mxz) = (x[23], x[24]);
        let kg13 = [x[20], x[21], x[22]];
        let mut want = rb.clone();
        for i in 0..3 {
            want[i] += kg13[i] * u[2];
        }
        want[PHI_Z] -= mzy * (WIE * c + x[V_X] / rn);
        want[PHI_X] -= mxz * (WIE * s + x[V_X] * s / c / rn);
        for i in 0..7 {
            assert!(
                (r[i] - want[i]).abs() <= 1e-14 * (want[i].abs() + 1e-6 * WIE),
                "rate {i}: {} vs {}",
                r[i],
                want[i]
            );
        }
    }
}

/// Catches: a wrong partial of the user effect, or a model that writes an outside effect's
/// partials at the wrong offset (also with the whole catalogue in front of it).
#[test]
fn user_effect_jacobian_matches_finite_differences() {
    let reg = registry();
    let mut all = reg.names();
    all.rotate_right(1); // the user effect first, then the catalogue
    for names in [vec!["gyro-misalignment".to_string()], all] {
        let m =
            PlatformModel::new(reg.build_all(&names).unwrap(), &NoiseConfig::default()).unwrap();
        let mut rng = rng(71);
        for k in 0..8 {
            let x = random_state(&m, &mut rng);
            let u = random_input(&mut rng);
            check_rate_jacobian(&m, &x, &u)
                .unwrap_or_else(|e| panic!("{names:?} state #{k}, rates:\n{e}"));
            check_measurement_jacobian(&m, &x)
                .unwrap_or_else(|e| panic!("{names:?} state #{k}, measurement:\n{e}"));
        }
    }
}

/// Catches: an unknown name silently ignored, or an error that does not help the user.
#[test]
fn unknown_effect_name_is_an_error_listing_known_names() {
    let reg = registry();
    let err = match reg.build("gyro-wobble") {
        Err(DynamicsError::Effect(msg)) => msg,
        Err(other) => panic!("expected an effect error, got {other}"),
        Ok(e) => panic!("built {e:?} for an unknown name"),
    };
    assert!(err.contains("gyro-wobble"), "{err}");
    for name in reg.names() {
        assert!(err.contains(&name), "`{name}` missing from: {err}");
    }
    assert!(reg.build_all(&["gyro-fz", "gyro-wobble"]).is_err());
    assert!(Registry::catalogue().build("gyro-misalignment").is_err());
}

/// Catches: the same effect switched on twice (its coefficients would be in the state twice
/// and its terms added twice).
#[test]
fn duplicated_effect_is_refused() {
    let reg = registry();
    let msg = effect_error(PlatformModel::new(
        reg.build_all(&["gyro-fz", "torquer-scale", "gyro-fz"])
            .unwrap(),
        &NoiseConfig::default(),
    ));
    assert!(msg.contains("gyro-fz"), "{msg}");
    let msg = effect_error(PlatformModel::new(
        vec![Box::new(GyroMisalignment), Box::new(GyroMisalignment)],
        &NoiseConfig::default(),
    ));
    assert!(msg.contains("gyro-misalignment"), "{msg}");
    // gyro-bias-walk has no coefficients: a duplicate must be refused all the same.
    effect_error(PlatformModel::new(
        reg.build_all(&["gyro-bias-walk", "gyro-bias-walk"])
            .unwrap(),
        &NoiseConfig::default(),
    ));
}

/// An effect whose coefficient clashes with a base state, or which gives names, units and
/// sigmas of unequal length, is refused. Catches: two states under one name (`index_of`
/// would find only one), or an out-of-bounds slice later on.
#[derive(Debug)]
struct Clashing(
    &'static [&'static str],
    &'static [&'static str],
    &'static [f64],
);

impl Effect for Clashing {
    fn terms(&self) -> navkf_dynamics::Terms {
        navkf_dynamics::Terms {
            rates: false,
            linear_rates: &[],
            measurement: navkf_dynamics::MeasurementTerm::None,
            noise: false,
        }
    }
    fn name(&self) -> &str {
        "clashing"
    }
    fn description(&self) -> &str {
        "test effect"
    }
    fn coefficient_names(&self) -> &[&str] {
        self.0
    }
    fn coefficient_units(&self) -> &[&str] {
        self.1
    }
    fn coefficient_sigma(&self) -> &[f64] {
        self.2
    }
}

#[test]
fn clashing_or_malformed_coefficients_are_refused() {
    let cfg = NoiseConfig::default();
    let msg = effect_error(PlatformModel::new(
        vec![Box::new(Clashing(&["Kg0x"], &["rad/s"], &[1e-7]))],
        &cfg,
    ));
    assert!(msg.contains("Kg0x"), "{msg}");
    let msg = effect_error(PlatformModel::new(
        vec![
            Box::new(GyroMisalignment),
            Box::new(Clashing(&["Mzy"], &["rad"], &[1e-4])),
        ],
        &cfg,
    ));
    assert!(msg.contains("Mzy"), "{msg}");
    effect_error(PlatformModel::new(
        vec![Box::new(Clashing(&["a", "b"], &["1"], &[1.0, 1.0]))],
        &cfg,
    ));
    effect_error(PlatformModel::new(
        vec![Box::new(Clashing(&["a"], &["1"], &[]))],
        &cfg,
    ));
    // Physical bounds: none, or one > 0 per coefficient.
    for bounds in [
        &[BOUND, BOUND][..],
        &[PhysicalBound {
            limit: 0.0,
            ..BOUND
        }],
    ] {
        let msg = effect_error(PlatformModel::new(vec![Box::new(Bounded(bounds))], &cfg));
        assert!(msg.contains("bounds"), "{msg}");
    }
    assert!(PlatformModel::new(vec![Box::new(Bounded(&[BOUND]))], &cfg).is_ok());
}

const BOUND: PhysicalBound = PhysicalBound {
    limit: 1.0,
    reason: "test",
};

/// One coefficient with the given physical bounds.
#[derive(Debug)]
struct Bounded(&'static [PhysicalBound]);

impl Effect for Bounded {
    fn terms(&self) -> navkf_dynamics::Terms {
        Clashing(&[], &[], &[]).terms()
    }
    fn name(&self) -> &str {
        "bounded"
    }
    fn description(&self) -> &str {
        "test effect"
    }
    fn coefficient_names(&self) -> &[&str] {
        &["kb"]
    }
    fn coefficient_units(&self) -> &[&str] {
        &["1"]
    }
    fn coefficient_sigma(&self) -> &[f64] {
        &[1.0]
    }
    fn coefficient_bounds(&self) -> &[PhysicalBound] {
        self.0
    }
}

/// An effect whose code adds a term its `terms()` leaves out.
#[derive(Debug)]
struct Undeclared(navkf_dynamics::Terms);

impl Effect for Undeclared {
    fn name(&self) -> &str {
        "undeclared"
    }
    fn description(&self) -> &str {
        "adds everything, declares what it is told"
    }
    fn coefficient_names(&self) -> &[&str] {
        &["u"]
    }
    fn coefficient_units(&self) -> &[&str] {
        &["1"]
    }
    fn coefficient_sigma(&self) -> &[f64] {
        &[1.0]
    }
    fn terms(&self) -> navkf_dynamics::Terms {
        self.0
    }
    fn add_rates<T: navkf_dynamics::Real>(
        &self,
        k: &Kinematics<T>,
        c: &[T],
        rates: &mut [T; NAV_DIM],
    ) {
        rates[V_X] += c[0] * k.v_y;
    }
    fn add_measurement(&self, k: &Kinematics, c: &[f64], z: &mut [f64; MEAS_DIM]) {
        z[0] += c[0] * k.v_x;
    }
    fn process_noise(&self) -> Vec<navkf_dynamics::NoiseChannel> {
        vec![navkf_dynamics::NoiseChannel {
            name: "w_u".into(),
            state: BASE_DIM,
            psd: 1e-9,
        }]
    }
}

/// Catches: a term the model never calls because the effect forgot to declare it (it would
/// be silently dropped from every filter and the truth).
#[test]
fn a_term_the_effect_adds_but_does_not_declare_is_refused() {
    use navkf_dynamics::{MeasurementTerm, Terms};
    let all = Terms {
        rates: true,
        linear_rates: &[],
        measurement: MeasurementTerm::NonLinear,
        noise: true,
    };
    let cfg = NoiseConfig::default();
    PlatformModel::new(vec![Box::new(Undeclared(all))], &cfg).unwrap();
    for (terms, what) in [
        (
            Terms {
                rates: false,
                ..all
            },
            "rates",
        ),
        (
            Terms {
                measurement: MeasurementTerm::None,
                ..all
            },
            "measurement",
        ),
        (
            Terms {
                noise: false,
                ..all
            },
            "noise",
        ),
    ] {
        let msg = effect_error(PlatformModel::new(vec![Box::new(Undeclared(terms))], &cfg));
        assert!(msg.contains("undeclared") && msg.contains(what), "{msg}");
    }
}

/// A user's effect declared as linear rate terms only, no code: `v_x' += c0 fz`,
/// `phi_z' += c1 w_cmd_z`.
#[derive(Debug)]
struct DeclaredOnly(&'static [navkf_dynamics::LinearRate]);

impl Effect for DeclaredOnly {
    fn name(&self) -> &str {
        "declared-only"
    }
    fn description(&self) -> &str {
        "v_x' += c0 fz, phi_z' += c1 w_cmd_z"
    }
    fn coefficient_names(&self) -> &[&str] {
        &["c0", "c1"]
    }
    fn coefficient_units(&self) -> &[&str] {
        &["1"; 2]
    }
    fn coefficient_sigma(&self) -> &[f64] {
        &[1e-4; 2]
    }
    fn terms(&self) -> navkf_dynamics::Terms {
        navkf_dynamics::Terms::linear(self.0)
    }
}

const DECLARED: &[navkf_dynamics::LinearRate] = &[
    navkf_dynamics::LinearRate {
        row: V_X,
        coefficient: 0,
        feature: navkf_dynamics::Feature::SpecificForce(2),
    },
    navkf_dynamics::LinearRate {
        row: PHI_Z,
        coefficient: 1,
        feature: navkf_dynamics::Feature::CommandedRate(2),
    },
];

/// Catches: declared linear terms not evaluated, evaluated on the wrong coefficient or row,
/// or without their partials (the commanded rate's depend on v_x and L), also behind the
/// whole catalogue.
#[test]
fn a_users_declared_linear_terms_enter_the_rates_and_the_jacobian() {
    let cfg = NoiseConfig::default();
    let m = PlatformModel::new(vec![Box::new(DeclaredOnly(DECLARED))], &cfg).unwrap();
    let b = PlatformModel::base(&cfg);
    let mut gen = rng(72);
    for k in 0..8 {
        let x = random_state(&m, &mut gen);
        let u = random_input(&mut gen);
        let (mut r, mut rb) = (vec![0.0; 7], vec![0.0; 7]);
        m.rates(&x, &u, &mut r);
        b.rates(&x[..20], &u, &mut rb);
        let (s, c) = x[LAT].sin_cos();
        let rn = navkf_dynamics::earth::prime_vertical_radius(s);
        let w3 = WIE * s + x[V_X] * s / c / rn;
        let mut want = rb.clone();
        want[V_X] += x[20] * u[2];
        want[PHI_Z] += x[21] * w3;
        for i in 0..7 {
            assert!(
                (r[i] - want[i]).abs() <= 1e-13 * (want[i].abs() + 1e-6 * WIE),
                "state #{k}, rate {i}: {} vs {}",
                r[i],
                want[i]
            );
        }
        check_rate_jacobian(&m, &x, &u).unwrap_or_else(|e| panic!("state #{k}:\n{e}"));
    }
    let mut effects = registry().build_all(&registry().names()).unwrap();
    effects.push(Box::new(DeclaredOnly(DECLARED)));
    let all = PlatformModel::new(effects, &cfg).unwrap();
    let mut gen2 = rng(73);
    for k in 0..4 {
        let x = random_state(&all, &mut gen2);
        let u = random_input(&mut gen2);
        check_rate_jacobian(&all, &x, &u).unwrap_or_else(|e| panic!("all, state #{k}:\n{e}"));
    }
}

/// Catches: a declared term on a row that is not a navigation state, on a coefficient the
/// effect does not have, or about a fourth axis, accepted (and indexing out of bounds later).
#[test]
fn a_malformed_linear_declaration_is_refused() {
    use navkf_dynamics::{Feature, LinearRate};
    const BAD_ROW: &[LinearRate] = &[LinearRate {
        row: NAV_DIM,
        coefficient: 0,
        feature: Feature::SpecificForce(0),
    }];
    const BAD_COEFFICIENT: &[LinearRate] = &[LinearRate {
        row: V_X,
        coefficient: 2,
        feature: Feature::SpecificForce(0),
    }];
    const BAD_AXIS: &[LinearRate] = &[LinearRate {
        row: V_X,
        coefficient: 0,
        feature: Feature::CommandedRate(3),
    }];
    for bad in [BAD_ROW, BAD_COEFFICIENT, BAD_AXIS] {
        let r = PlatformModel::new(vec![Box::new(DeclaredOnly(bad))], &NoiseConfig::default());
        let msg = effect_error(r);
        assert!(
            msg.contains("declared-only") && msg.contains("linear rate term"),
            "{msg}"
        );
    }
}
