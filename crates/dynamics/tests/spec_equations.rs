//! The model's `rates` and `measure` against the equations of `docs/model.md`, transcribed
//! here independently of the crate (own constants, own radii, coefficients looked up by their
//! names there), for the base model, each catalogue effect alone and all of them.
//!
//! The Jacobian tests only check that the partials agree with `rates`/`measure`; these pin
//! `rates`/`measure` themselves to the contract. They catch a sign or a factor in any term,
//! a term on the wrong state, a coefficient read at the wrong offset or under the wrong
//! name, a wrong Earth constant or radius formula.

use crate::common;

use common::*;
use navkf_dynamics::state::*;
use navkf_dynamics::{Input, NoiseConfig, PlatformModel, Registry, SystemModel};

// docs/model.md eqs. (1)-(3).
const RE: f64 = 6_378_137.0;
const FLAT: f64 = 1.0 / 298.257;
const WIE: f64 = 7.292115e-5;

fn radii(lat: f64) -> (f64, f64) {
    let s2 = lat.sin().powi(2);
    (
        RE * (1.0 - 2.0 * FLAT + 3.0 * FLAT * s2),
        RE * (1.0 + FLAT * s2),
    )
}

/// A value and the sum of the magnitudes of the terms it was added up from (for the
/// rounding tolerance).
#[derive(Clone, Copy, Default)]
struct Sum {
    value: f64,
    terms: f64,
}

impl Sum {
    fn add(&mut self, t: f64) {
        self.value += t;
        self.terms += t.abs();
    }
}

/// The state equations, docs/model.md eqs. (5)-(10), plus the catalogue's rate terms
/// (docs/model.md eqs. (37)-(40)) for the effects whose coefficients `model` has (looked up by
/// name).
fn spec_rates(model: &PlatformModel, x: &[f64], f: &Input) -> [Sum; NAV_DIM] {
    let k = |name: &str| model.index_of(name).map(|i| x[i]);
    let base = |name: &str| k(name).unwrap_or_else(|| panic!("base state {name}"));
    let [fx, fy, fz] = [f[0], f[1], f[2]];
    let (px, py, pz) = (base("phi_x"), base("phi_y"), base("phi_z"));
    let (vx, vy, lat) = (base("v_x"), base("v_y"), base("L"));
    let (s, c) = lat.sin_cos();
    let tan = s / c;
    let (rm, rn) = radii(lat);
    let eps = |a: &str| {
        let mut e = Sum::default();
        e.add(base(&format!("Kg0{a}")));
        e.add(base(&format!("Kg11{a}")) * fx);
        e.add(base(&format!("Kg12{a}")) * fy);
        if let Some(kg13) = k(&format!("Kg13{a}")) {
            e.add(kg13 * fz); // gyro-fz
        }
        e
    };
    let mut nab_x = Sum::default();
    nab_x.add(base("Ka0x"));
    nab_x.add(base("Ka1x") * fx);
    let mut nab_y = Sum::default();
    nab_y.add(base("Ka0y"));
    nab_y.add(base("Ka1y") * fy);
    if let (Some(a), Some(b)) = (k("Ka2x"), k("Ka2y")) {
        nab_x.add(a * fx * fx); // accel-quadratic
        nab_y.add(b * fy * fy);
    }
    if let (Some(a), Some(b)) = (k("Ka12x"), k("Ka12y")) {
        nab_x.add(a * fy); // accel-cross-axis
        nab_y.add(b * fx);
    }
    let w_up = WIE * s + vx * tan / rn;
    let w_north = WIE * c + vx / rn;
    let mut r = [Sum::default(); NAV_DIM];
    let add_sum = |r: &mut Sum, e: Sum| {
        r.value += e.value;
        r.terms += e.terms;
    };
    r[0].add(w_up * py);
    r[0].add(-w_north * pz);
    add_sum(&mut r[0], eps("x"));
    r[1].add(-w_up * px);
    r[1].add(-(vy / rm) * pz);
    add_sum(&mut r[1], eps("y"));
    r[2].add(w_north * px);
    r[2].add((vy / rm) * py);
    add_sum(&mut r[2], eps("z"));
    let cor = 2.0 * WIE * s + vx * tan / rn;
    r[3].add(cor * vy);
    add_sum(&mut r[3], nab_x);
    r[3].add(fx);
    r[3].add(fy * pz);
    r[3].add(-fz * py);
    r[4].add(-cor * vx);
    add_sum(&mut r[4], nab_y);
    r[4].add(fy);
    r[4].add(fz * px);
    r[4].add(-fx * pz);
    r[5].add(vy / rm);
    r[6].add(vx / (rn * c));
    // torquer-scale: phi' += diag(kt) w_cmd.
    if let (Some(ktx), Some(kty), Some(ktz)) = (k("ktx"), k("kty"), k("ktz")) {
        r[0].add(ktx * (-vy / rm));
        r[1].add(kty * w_north);
        r[2].add(ktz * w_up);
    }
    r
}

/// The measurement, docs/model.md eq. (13), plus odometer-scale, gps-latency and
/// odometer-misalignment (docs/model.md eqs. (41)-(43)) when present.
fn spec_measurement(model: &PlatformModel, x: &[f64]) -> [Sum; MEAS_DIM] {
    let k = |name: &str| model.index_of(name).map(|i| x[i]);
    let (vx, vy, lat, lon) = (x[V_X], x[V_Y], x[LAT], x[LON]);
    let mut z = [Sum::default(); MEAS_DIM];
    z[0].add(vx);
    z[1].add(vy);
    z[2].add(lat);
    z[3].add(lon);
    if let Some(kod) = k("kod") {
        z[0].add(kod * vx);
        z[1].add(kod * vy);
    }
    if let Some(a) = k("a_y") {
        // R(a) v - v, R(a) = [[cos a, -sin a], [sin a, cos a]].
        z[0].add(a.cos() * vx - a.sin() * vy - vx);
        z[1].add(a.sin() * vx + a.cos() * vy - vy);
    }
    if let Some(tau) = k("tau") {
        let (rm, rn) = radii(lat);
        z[2].add(-tau * vy / rm);
        z[3].add(-tau * vx / (rn * lat.cos()));
    }
    z
}

/// Relative size of the rounding allowed, per unit of the summed term magnitudes.
const ROUND: f64 = 1e-14;

fn check(model: &PlatformModel, seed: u64) {
    let mut rng = rng(seed);
    let names = model.state_names();
    for case in 0..10 {
        let x = random_state(model, &mut rng);
        let u = random_input(&mut rng);
        let mut r = vec![0.0; NAV_DIM];
        model.rates(&x, &u, &mut r);
        for (i, want) in spec_rates(model, &x, &u).iter().enumerate() {
            assert!(
                (r[i] - want.value).abs() <= ROUND * want.terms,
                "{:?} case {case}: d{}/dt = {:e}, docs/model.md gives {:e}",
                model.effect_names(),
                names[i],
                r[i],
                want.value
            );
        }
        let mut z = vec![0.0; MEAS_DIM];
        model.measure(&x, &mut z);
        for (i, want) in spec_measurement(model, &x).iter().enumerate() {
            assert!(
                (z[i] - want.value).abs() <= ROUND * want.terms,
                "{:?} case {case}: z[{i}] = {:e}, docs/model.md gives {:e}",
                model.effect_names(),
                z[i],
                want.value
            );
        }
    }
}

#[test]
fn earth_constants_are_model_md_values() {
    use navkf_dynamics::earth;
    assert_eq!(earth::RE, RE);
    assert_eq!(earth::FLATTENING, FLAT);
    assert_eq!(earth::WIE, WIE);
    for lat in [0.0f64, 0.3, 0.785, 1.2] {
        let (rm, rn) = radii(lat);
        assert!((earth::meridian_radius(lat.sin()) - rm).abs() <= 1e-9);
        assert!((earth::prime_vertical_radius(lat.sin()) - rn).abs() <= 1e-9);
    }
}

#[test]
fn base_rates_and_measurement_follow_model_md() {
    check(&PlatformModel::base(&NoiseConfig::default()), 40);
}

#[test]
fn each_catalogue_effect_adds_its_model_md_terms() {
    let reg = Registry::catalogue();
    for (j, name) in reg.names().iter().enumerate() {
        let model =
            PlatformModel::new(vec![reg.build(name).unwrap()], &NoiseConfig::default()).unwrap();
        check(&model, 41 + j as u64);
    }
}

#[test]
fn all_catalogue_effects_together_follow_model_md() {
    let reg = Registry::catalogue();
    let model = PlatformModel::new(
        reg.build_all(&reg.names()).unwrap(),
        &NoiseConfig::default(),
    )
    .unwrap();
    check(&model, 50);
}

/// The coefficient names of each effect are docs/model.md's (the spec functions above find the
/// coefficients by these names; a renamed coefficient would silently drop its term there, so
/// pin them).
#[test]
fn catalogue_coefficient_names_are_model_md_names() {
    let want: [(&str, &[&str]); 8] = [
        ("gyro-fz", &["Kg13x", "Kg13y", "Kg13z"]),
        ("accel-quadratic", &["Ka2x", "Ka2y"]),
        ("accel-cross-axis", &["Ka12x", "Ka12y"]),
        ("torquer-scale", &["ktx", "kty", "ktz"]),
        ("odometer-scale", &["kod"]),
        ("odometer-misalignment", &["a_y"]),
        ("gps-latency", &["tau"]),
        ("gyro-bias-walk", &[]),
    ];
    let reg = Registry::catalogue();
    let mut names = reg.names();
    names.sort();
    let mut expected: Vec<String> = want.iter().map(|(n, _)| n.to_string()).collect();
    expected.sort();
    assert_eq!(
        names, expected,
        "the catalogue is docs/model.md's eight effects"
    );
    for (name, coeffs) in want {
        let e = reg.build(name).unwrap();
        assert_eq!(e.name(), name);
        assert_eq!(e.coefficient_names(), coeffs, "{name}");
        assert_eq!(e.coefficient_units().len(), coeffs.len(), "{name} units");
        assert_eq!(e.coefficient_sigma().len(), coeffs.len(), "{name} sigmas");
        assert!(
            e.coefficient_sigma()
                .iter()
                .all(|s| s.is_finite() && *s > 0.0),
            "{name} sigmas must be positive"
        );
    }
}
