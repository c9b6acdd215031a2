//! The strapdown effects (`strapdown::effects`, docs/model.md eqs. (63)-(70)): each one's
//! Jacobians against finite differences, the simulator's readings with each one hidden
//! against the model that carries it (the model with the truth's coefficients follows the
//! truth and predicts its measurements), the biases' Gauss-Markov law against its stated
//! statistics, the batched propagation against one point at a time, and the effect lists'
//! refusals.

use crate::common;

use navkf_dynamics::family::FamilyModel;
use navkf_dynamics::strapdown::effect_list::StrapdownEffectList;
use navkf_dynamics::strapdown::effects::StrapdownRegistry;
use navkf_dynamics::strapdown::model::{StrapdownModel, MEAS_DIM};
use navkf_dynamics::strapdown::partials_check::{random_reading, random_state, steps};
use navkf_dynamics::strapdown::rates::input_of;
use navkf_dynamics::strapdown::simulate::StrapdownSimulator;
use navkf_dynamics::strapdown::state::*;
use navkf_dynamics::strapdown::tangent::rate_jacobian_dual;
use navkf_dynamics::strapdown::unit_class::UnitClass;
use navkf_dynamics::system::propagate_generic;
use navkf_dynamics::{InputWindow, NoiseConfig, SystemModel, Trajectory, TrajectoryConfig};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::collections::BTreeMap;
use std::sync::Arc;

/// The default 2400-s vehicle test.
fn drive() -> Arc<Trajectory> {
    Arc::new(Trajectory::build(&TrajectoryConfig::default()).unwrap())
}

fn model_with(list: &str, noise: &NoiseConfig) -> StrapdownModel {
    model_in(list, noise, &StrapdownRegistry::catalogue())
}

fn model_in(list: &str, noise: &NoiseConfig, registry: &StrapdownRegistry) -> StrapdownModel {
    let list = StrapdownEffectList::parse_entries(&[list], registry)
        .unwrap_or_else(|(_, e)| panic!("{e}"));
    StrapdownModel::base(noise)
        .with_effects(&list, UnitClass::Mems, 1.0)
        .unwrap()
}

/// Central differences of `f` against its Jacobian `jac` (`rows x n`), each entry within a
/// millionth of its size plus the rounding of the quotient (the row's largest term over the
/// step).
fn check_jacobian(
    name: &str,
    x: &[f64],
    rows: usize,
    jac: &[f64],
    steps: &[f64],
    f: impl Fn(&[f64]) -> Vec<f64>,
    names: &[String],
) {
    let n = x.len();
    let f0 = f(x);
    for c in 0..n {
        let (mut xp, mut xm) = (x.to_vec(), x.to_vec());
        xp[c] += steps[c];
        xm[c] -= steps[c];
        let (fp, fm) = (f(&xp), f(&xm));
        for r in 0..rows {
            let scale: f64 =
                (0..n).map(|k| (jac[r * n + k] * x[k]).abs()).sum::<f64>() + f0[r].abs() + 10.0;
            let fd = (fp[r] - fm[r]) / (xp[c] - xm[c]);
            let a = jac[r * n + c];
            let tol = 1e-6 * a.abs().max(fd.abs()) + 256.0 * f64::EPSILON * scale / steps[c];
            assert!(
                (a - fd).abs() <= tol,
                "{name}: d(row {r})/d({}): dual {a:e}, differences {fd:e}",
                names[c]
            );
        }
    }
}

/// Effects a user declares (docs/declared-effects.md): the whole unit turned on its mount
/// about z (one angle in four places, two with factor -1), an antenna on a mast that leans
/// forward with its height, an odometer scale given as twice its coefficient, one coefficient
/// in an accelerometer's, a gyro's and a g-sensitivity's places with three factors, and a
/// latency in milliseconds. They take places of the catalogued effects in [`TAKEN`], so
/// cannot join a model with those.
const DECLARED: &str = r#"
[[effect]]
name = "mount-yaw"
coefficients = [{ name = "d_mz", unit = "rad", sigma = 2e-3 }]
places = [
    { coefficient = "d_mz", place = "E_g[x][y]", factor = -1 },
    { coefficient = "d_mz", place = "E_g[y][x]" },
    { coefficient = "d_mz", place = "E_a[x][y]", factor = -1 },
    { coefficient = "d_mz", place = "E_a[y][x]" },
]

[[effect]]
name = "mast"
coefficients = [{ name = "h_mast", unit = "m", sigma = 1.0 }]
places = [
    { coefficient = "h_mast", place = "l[z]" },
    { coefficient = "h_mast", place = "l[x]", factor = 0.5 },
]

[[effect]]
name = "odometer-double"
coefficients = [{ name = "k2", unit = "1", sigma = 5e-3 }]
places = [{ coefficient = "k2", place = "kod", factor = 2 }]

[[effect]]
name = "tilted-triad"
coefficients = [{ name = "t_x", unit = "1", sigma = 2e-3 }]
places = [
    { coefficient = "t_x", place = "E_a[x][z]", factor = 0.5 },
    { coefficient = "t_x", place = "E_g[y][z]", factor = -2 },
    { coefficient = "t_x", place = "G[x]", factor = 1e-3 },
]

[[effect]]
name = "late-fix"
coefficients = [{ name = "tau_ms", unit = "ms", sigma = 50.0 }]
places = [{ coefficient = "tau_ms", place = "tau", factor = 1e-3 }]
"#;

/// The catalogued effects whose places [`DECLARED`] take.
const TAKEN: [&str; 6] = [
    "gyro-misalignment",
    "accel-misalignment",
    "gps-lever-arm",
    "odometer-scale",
    "gyro-g-sensitivity",
    "gps-latency",
];

/// Every effect of `names` that can join one model with all of [`DECLARED`]'s.
fn beside_declared<'a>(names: impl IntoIterator<Item = &'a str>) -> String {
    names
        .into_iter()
        .filter(|n| !TAKEN.contains(n))
        .collect::<Vec<_>>()
        .join(",")
}

fn declared_registry() -> StrapdownRegistry {
    let mut registry = StrapdownRegistry::catalogue();
    registry
        .declare(&navkf_dynamics::declared::parse_declarations(DECLARED).unwrap())
        .unwrap();
    registry
}

#[test]
fn every_effects_jacobians_match_central_differences() {
    let registry = declared_registry();
    let noise = NoiseConfig::default();
    let mut lists: Vec<String> = registry.names().iter().map(|n| n.to_string()).collect();
    lists.push(StrapdownRegistry::catalogue().names().join(","));
    lists.push(beside_declared(registry.names()));
    // A declared effect first in the state.
    lists.push("tilted-triad,gyro-scale,odometer-double".into());
    let mut rng = ChaCha8Rng::seed_from_u64(63);
    for list in &lists {
        let model = model_in(list, &noise, &registry);
        let names = model.state_names();
        let (n, d) = (model.dim(), model.dynamic_dim());
        let steps = steps(&model);
        for _ in 0..10 {
            let x = random_state(&model, &mut rng);
            let imu = random_reading(&mut rng);
            let u = input_of(&imu);
            let mut jac = vec![f64::NAN; d * n];
            model.rate_jacobian(&x, &u, &mut jac);
            let rates = |x: &[f64]| {
                let mut dx = vec![0.0; d];
                model.rates(x, &u, &mut dx);
                dx
            };
            check_jacobian(list, &x, d, &jac, &steps, rates, &names);
            // The chain rule's matrix is the all-dual one to rounding.
            let mut dual = vec![f64::NAN; d * n];
            rate_jacobian_dual(model.layout(), d, &x, &imu, &mut dual, n);
            for r in 0..d {
                let row = &jac[r * n..(r + 1) * n];
                let size = row.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                for (c, (a, b)) in row.iter().zip(&dual[r * n..]).enumerate() {
                    assert!(
                        (a - b).abs() <= 1e-12 * size,
                        "{list}: d(row {r})/d({}): chain rule {a:e}, dual {b:e}",
                        names[c]
                    );
                }
            }
            // The EKF's call: the same rates and Jacobian, rows padded.
            let stride = n + 3;
            let (mut dx, mut padded) = (vec![0.0; d], vec![f64::NAN; d * stride]);
            model.rates_and_jacobian(&x, &u, &mut dx, &mut padded, stride);
            assert_eq!(dx, rates(&x));
            for r in 0..d {
                assert_eq!(
                    &padded[r * stride..r * stride + n],
                    &jac[r * n..(r + 1) * n]
                );
                assert!(padded[r * stride + n..(r + 1) * stride]
                    .iter()
                    .all(|v| *v == 0.0));
            }
            let mut h = vec![f64::NAN; MEAS_DIM * n];
            model.measurement_jacobian(&x, &mut h);
            let measure = |x: &[f64]| {
                let mut z = vec![0.0; MEAS_DIM];
                model.measure(x, &mut z);
                z
            };
            check_jacobian(list, &x, MEAS_DIM, &h, &steps, measure, &names);
        }
    }
}

/// A declared effect is the catalogued one it restates: the unit turned by `d` about z is
/// gyro and accelerometer misalignments of `-d` and `d`, an odometer scale declared as
/// `2 k2` is `kod = 2 k2`. The rates and the measurement agree bit for bit (a factor of -1 or
/// 2 is exact), and so the filters' arithmetic would.
#[test]
fn a_declared_effect_is_the_catalogued_one_it_restates() {
    let registry = declared_registry();
    let noise = NoiseConfig::default();
    let declared = model_in("mount-yaw,odometer-double", &noise, &registry);
    let catalogued = model_with(
        "gyro-misalignment,accel-misalignment,odometer-scale",
        &noise,
    );
    let index =
        |m: &StrapdownModel, name: &str| m.state_names().iter().position(|n| n == name).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(65);
    for _ in 0..20 {
        let mut x = random_state(&declared, &mut rng);
        let (d, k2) = (x[index(&declared, "d_mz")], x[index(&declared, "k2")]);
        let mut y = x[..BASE_DIM].to_vec();
        y.resize(catalogued.dim(), 0.0);
        for (name, v) in [
            ("m_gxy", -d),
            ("m_gyx", d),
            ("m_axy", -d),
            ("m_ayx", d),
            ("kod", 2.0 * k2),
        ] {
            y[index(&catalogued, name)] = v;
        }
        let u = input_of(&random_reading(&mut rng));
        let (mut a, mut b) = (vec![0.0; NAV_DIM], vec![0.0; NAV_DIM]);
        declared.rates(&x, &u, &mut a);
        catalogued.rates(&y, &u, &mut b);
        assert_eq!(a, b, "rates at d = {d:e}");
        let (mut za, mut zb) = ([0.0; MEAS_DIM], [0.0; MEAS_DIM]);
        declared.measure(&x, &mut za);
        catalogued.measure(&y, &mut zb);
        assert_eq!(za, zb, "measurement at k2 = {k2:e}");
        // And the declared coefficient does act: without it the odometer reads otherwise.
        x[index(&declared, "k2")] = 0.0;
        declared.measure(&x, &mut za);
        assert_ne!(za[0], zb[0]);
    }
}

/// What a strapdown declaration cannot mean is refused, naming the key and what was expected.
#[test]
fn strapdown_declarations_are_refused_by_key() {
    let head =
        "[[effect]]\nname = \"e\"\ncoefficients = [{ name = \"c\", unit = \"1\", sigma = 1e-3 }]\n";
    let cases = [
        ("places = [{ coefficient = \"c\", place = \"E_g[x][w]\" }]", "effect[0].places[0].place", "expected one of"),
        ("places = [{ coefficient = \"q\", place = \"kod\" }]", "effect[0].places[0].coefficient", "`q`"),
        ("places = [{ coefficient = \"c\", place = \"kod\", factor = 0 }]", "effect[0].places[0].factor", "other than 0"),
        ("places = [{ coefficient = \"c\", place = \"kod\" }, { coefficient = \"c\", place = \"kod\" }]", "effect[0].places[1].place", "already"),
        ("places = [{ coefficient = \"c\", place = \"tau\" }, { coefficient = \"c\", place = \"kod\" }]", "effect[0].coefficients[0].name", "`tau` alone"),
        ("places = []", "effect[0].places", "empty"),
        ("rates = [{ to = \"v_x\", coefficient = \"c\", feature = \"v_x\" }]", "effect[0].rates", "platform family"),
    ];
    for (tail, key, says) in cases {
        let text = format!("{head}{tail}\n");
        let d = navkf_dynamics::declared::parse_declarations(&text).unwrap();
        let e = StrapdownRegistry::catalogue()
            .declare(&d)
            .unwrap_err()
            .to_string();
        assert!(e.contains(key) && e.contains(says), "{tail}: {e}");
    }
    // Names the catalogue holds: an effect's, a coefficient's, a bias's, a parameter's.
    for (name, coefficient, key) in [
        ("gyro-scale", "c", "effect[0].name"),
        ("e", "s_gx", "effect[0].coefficients[0].name"),
        ("e", "bgz", "effect[0].coefficients[0].name"),
        ("e", "T_g", "effect[0].coefficients[0].name"),
    ] {
        let text = format!(
            "[[effect]]\nname = \"{name}\"\ncoefficients = [{{ name = \"{coefficient}\", unit = \"1\", sigma = 1e-3 }}]\nplaces = [{{ coefficient = \"{coefficient}\", place = \"kod\" }}]\n"
        );
        let d = navkf_dynamics::declared::parse_declarations(&text).unwrap();
        let e = StrapdownRegistry::catalogue()
            .declare(&d)
            .unwrap_err()
            .to_string();
        assert!(e.contains(key), "{name}/{coefficient}: {e}");
    }
    // A platform registry refuses places, and a strapdown one keeps a declaration it holds.
    let text = format!("{head}places = [{{ coefficient = \"c\", place = \"kod\" }}]\n");
    let d = navkf_dynamics::declared::parse_declarations(&text).unwrap();
    let e = navkf_dynamics::Registry::catalogue()
        .declare(&d)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("effect[0].places") && e.contains("strapdown"),
        "{e}"
    );
    let mut r = StrapdownRegistry::catalogue();
    r.declare(&d).unwrap();
    r.declare(&d).unwrap();
    assert_eq!(r.get("e").unwrap().declaration.as_deref(), Some(&d[0]));
}

/// An effect whose coefficients are all zero changes nothing: the model with it gives the
/// base model's rates and measurement (to rounding: the corrected path solves with an
/// identity).
#[test]
fn zero_coefficients_are_the_base_model() {
    let noise = NoiseConfig::default();
    let base = StrapdownModel::base(&noise);
    let all = StrapdownRegistry::catalogue()
        .names()
        .into_iter()
        .filter(|n| !n.ends_with("instability"))
        .collect::<Vec<_>>()
        .join(",");
    let full = model_with(&all, &noise);
    let mut rng = ChaCha8Rng::seed_from_u64(64);
    for _ in 0..20 {
        let mut x = random_state(&full, &mut rng);
        x[NAV_DIM..].iter_mut().for_each(|v| *v *= 0.0);
        x[BG_X] = 1e-4;
        x[BA_X + 2] = 0.03;
        let u = input_of(&random_reading(&mut rng));
        let (mut a, mut b) = (vec![0.0; NAV_DIM], vec![0.0; NAV_DIM]);
        full.rates(&x, &u, &mut a);
        base.rates(&x[..BASE_DIM], &u, &mut b);
        for i in 0..NAV_DIM {
            assert!((a[i] - b[i]).abs() <= 1e-12 * b[i].abs().max(1e-9), "{i}");
        }
        let (mut za, mut zb) = ([0.0; MEAS_DIM], [0.0; MEAS_DIM]);
        full.measure(&x, &mut za);
        base.measure(&x[..BASE_DIM], &mut zb);
        for i in 0..MEAS_DIM {
            assert!(
                (za[i] - zb[i]).abs() <= 1e-12 * zb[i].abs().max(1e-9),
                "{i}"
            );
        }
    }
}

/// A run's readings and measurements with effects hidden, against the model that knows
/// them: driven by the readings from the truth's first state, with the truth's biases and
/// coefficients, the model stays on the truth's path, and its measurement of the truth is
/// what the sensors read. The readings carry no noise here (densities of 1e-30), so any
/// error in the inverse of a reading error, the mounting's attitude or the lever arm shows.
#[test]
fn the_model_that_knows_the_hidden_effects_follows_the_simulated_run() {
    let traj = drive();
    let quiet = NoiseConfig {
        gyro_psd: 1e-30,
        accel_psd: 1e-30,
        odometer_rel: 1e-9,
        odometer_floor: 1e-6,
        gps_m: 1e-3,
        nhc_m_s: None,
        zupt_m_s: None,
    };
    let registry = declared_registry();
    let hidden: Vec<&str> = registry
        .names()
        .into_iter()
        .filter(|n| !n.ends_with("instability"))
        .collect();
    let mut lists: Vec<String> = hidden.iter().map(|n| n.to_string()).collect();
    let catalogued: Vec<&str> = StrapdownRegistry::catalogue()
        .names()
        .into_iter()
        .filter(|n| !n.ends_with("instability"))
        .collect();
    lists.push(catalogued.join(","));
    lists.push(beside_declared(hidden.iter().copied()));
    for list in &lists {
        let model = Arc::new(model_in(list, &quiet, &registry));
        let sim = StrapdownSimulator::new(
            model.clone(),
            traj.clone(),
            10.0,
            1.0,
            UnitClass::Mems.errors(),
            &BTreeMap::new(),
            quiet,
        )
        .unwrap();
        let run = sim.run(11, 2);
        let truth = &run.truth;
        let mut x = truth.states[0].clone();
        let mut scratch = vec![0.0; 4 * model.dynamic_dim() + model.dim()];
        let mut worst_m: f64 = 0.0;
        for (j, m) in run.measurements.iter().enumerate().take(900) {
            let (t0, t1) = (truth.t[j], truth.t[j + 1]);
            let mut window = InputWindow::with_capacity(12);
            for s in run
                .inputs
                .iter()
                .filter(|s| s.t >= t0 - 1e-9 && s.t <= t1 + 1e-9)
            {
                window.push_linear(s.t, s.f);
            }
            propagate_generic(model.as_ref(), &mut x, None, &window, &mut scratch);
            let xt = &truth.states[j + 1];
            let rm = navkf_dynamics::earth::meridian_radius(xt[LAT].sin());
            let off = ((x[LAT] - xt[LAT]) * rm).hypot((x[LON] - xt[LON]) * rm * xt[LAT].cos());
            worst_m = worst_m.max(off);
            let turn = (x[HEADING] - xt[HEADING]).sin().abs();
            assert!(turn < 2e-5, "{list}: heading off by {turn} rad at {t1} s");
            // The sensors' readings are the model's measurement of the truth.
            let mut z = [0.0; MEAS_DIM];
            model.measure(xt, &mut z);
            let speed = m.speed.unwrap();
            assert!(
                (speed - z[0]).abs() < 1e-5 || speed == 0.0,
                "{list}: odometer {speed} against {} at {t1} s",
                z[0]
            );
            let [lat, lon] = m.position_deg.unwrap();
            let gps = ((lat.to_radians() - z[1]) * rm)
                .hypot((lon.to_radians() - z[2]) * rm * xt[LAT].cos());
            // The latency's first-order model against the truth's exact delay: centimetres.
            assert!(gps < 0.05, "{list}: GPS {gps} m from the model's at {t1} s");
        }
        assert!(worst_m < 0.5, "{list}: {worst_m} m off the path");
        // Something was hidden: the base model reads a different odometer, GPS or turn.
        assert!(
            truth.states[0][BASE_DIM..].iter().any(|c| *c != 0.0),
            "{list}: no coefficient drawn"
        );
    }
}

/// The mounting turns the unit, not the vehicle: with the vehicle's forward axis 20 mrad left
/// of the unit's x, the unit heads 20 mrad right of the track, and the base model's
/// constraint sees the speed times the angle as sideslip.
#[test]
fn a_turned_mounting_turns_the_units_attitude() {
    let traj = drive();
    let noise = UnitClass::Mems.errors().noise(NoiseConfig::default());
    let list = "a_y=0.02, a_p=0";
    let fixed = StrapdownEffectList::parse_entries(&[list], &StrapdownRegistry::catalogue())
        .unwrap()
        .fixed;
    let model = Arc::new(model_with(list, &noise));
    let sim = StrapdownSimulator::new(
        model,
        traj.clone(),
        10.0,
        1.0,
        UnitClass::Mems.errors(),
        &fixed,
        noise,
    )
    .unwrap();
    let run = sim.run(1, 0);
    let base = StrapdownModel::base(&noise);
    for (t, x) in run.truth.t.iter().zip(&run.truth.states) {
        let st = traj.state(*t);
        if st.speed < 1.0 {
            continue;
        }
        let d = (x[HEADING] - st.heading).sin();
        assert!((d - 0.02f64.sin()).abs() < 1e-9, "{d} at {t}");
        assert!(x[ROLL].abs() < 1e-12 && x[PITCH].abs() < 1e-12, "{x:?}");
        let mut z = [0.0; MEAS_DIM];
        base.measure(&x[..BASE_DIM], &mut z);
        assert!(
            (z[3] / st.speed - 0.02f64.sin()).abs() < 1e-6,
            "{} {} {:?} {:?} {}",
            z[3],
            st.speed,
            x,
            st.v,
            st.heading
        );
    }
}

/// The biases' Gauss-Markov law (docs/model.md eq. (69)): each triad that wanders carries
/// three departures from its turn-on biases. Over 20 runs of 2400 s the turn-on biases hold
/// their drawn values, the departures start from their steady law (variance `sigma^2`), and
/// their one-second steps `d(t+1) - exp(-1/T) d(t)` have the variance
/// `sigma^2 (1 - exp(-2/T))` (chi-square within 4 sigma); the model's noise channel is
/// `2 sigma^2 / T` on each departure with rate `-d/T`, the turn-on bias's rate zero, and the
/// readings carry their sum.
#[test]
fn wandering_biases_follow_their_stated_law() {
    let traj = drive();
    let (t_g, s_g, t_a, s_a) = (120.0, 3e-5, 600.0, 2e-3);
    let noise = UnitClass::Mems.errors().noise(NoiseConfig::default());
    let list = format!("T_g={t_g}, sigma_bg={s_g}, T_a={t_a}, sigma_ba={s_a}");
    let model = Arc::new(model_with(&list, &noise));
    let (dg, da) = (BASE_DIM, BASE_DIM + 3);
    assert_eq!(
        (model.dim(), model.dynamic_dim()),
        (BASE_DIM + 6, BASE_DIM + 6)
    );
    let names = model.state_names();
    assert_eq!(
        names[dg..],
        ["dbgx", "dbgy", "dbgz", "dbax", "dbay", "dbaz"]
    );
    assert_eq!(model.coefficient_sigma(dg + 1), Some(s_g));
    assert_eq!(model.coefficient_sigma(da + 2), Some(s_a));
    // A fit's prior for a departure is the class's typical steady sigma, whatever is stated.
    let law = |name: &str| {
        StrapdownRegistry::catalogue()
            .get(name)
            .unwrap()
            .instability
            .unwrap()
            .sigma_for(UnitClass::Mems)
    };
    assert_eq!(model.typical_sigma(dg), law("gyro-bias-instability"));
    assert_eq!(model.typical_sigma(da + 1), law("accel-bias-instability"));
    let channel = |s: usize| {
        model
            .noise_channels()
            .iter()
            .find(|c| c.state == s)
            .map(|c| c.psd)
    };
    assert!((channel(dg + 1).unwrap() - 2.0 * s_g * s_g / t_g).abs() < 1e-25);
    assert!((channel(da + 2).unwrap() - 2.0 * s_a * s_a / t_a).abs() < 1e-18);
    assert_eq!(channel(BG_X), None);
    assert_eq!(channel(BA_X + 2), None);
    let mut dx = vec![0.0; BASE_DIM + 6];
    let mut x = vec![0.0; BASE_DIM + 6];
    x[BG_X] = 1e-4;
    x[BA_X] = 1e-2;
    x[dg] = 2e-5;
    x[da] = 1e-3;
    model.rates(&x, &[0.0, 0.0, 0.0, 0.0, 0.0, 9.8], &mut dx);
    assert_eq!((dx[BG_X], dx[BA_X]), (0.0, 0.0));
    assert!((dx[dg] + 2e-5 / t_g).abs() < 1e-18 && (dx[da] + 1e-3 / t_a).abs() < 1e-15);
    // The bias and its departure enter the readings as one: moving weight from one to the
    // other leaves the rates of the navigation states as they were.
    let mut y = x.clone();
    y[BA_X] += 5e-4;
    y[da] -= 5e-4;
    y[BG_X] -= 1e-5;
    y[dg] += 1e-5;
    let mut dy = vec![0.0; BASE_DIM + 6];
    model.rates(&y, &[0.01, 0.0, 0.02, 0.3, 0.0, 9.8], &mut dy);
    model.rates(&x, &[0.01, 0.0, 0.02, 0.3, 0.0, 9.8], &mut dx);
    for i in 0..NAV_DIM {
        assert!(
            (dx[i] - dy[i]).abs() <= 1e-12 * dx[i].abs().max(1e-9),
            "{i}"
        );
    }
    let sim = StrapdownSimulator::new(
        model,
        traj,
        10.0,
        1.0,
        UnitClass::Mems.errors(),
        &BTreeMap::new(),
        noise,
    )
    .unwrap();
    let (mut chi2, mut dof) = (0.0, 0.0);
    let (mut start2, mut start_dof) = (0.0, 0.0);
    for run in 0..20 {
        let r = sim.run(5, run);
        let first = &r.truth.states[0];
        for pair in r.truth.states.windows(2) {
            assert_eq!(pair[1][BG_X..BASE_DIM], first[BG_X..BASE_DIM]);
            for (d, t, s) in [(dg, t_g, s_g), (da, t_a, s_a)] {
                let phi: f64 = (-1.0 / t).exp();
                let var = s * s * (1.0 - phi * phi);
                for i in d..d + 3 {
                    chi2 += (pair[1][i] - phi * pair[0][i]).powi(2) / var;
                    dof += 1.0;
                }
            }
        }
        for (d, s) in [(dg, s_g), (da, s_a)] {
            for i in d..d + 3 {
                start2 += (first[i] / s).powi(2);
                start_dof += 1.0;
            }
        }
    }
    assert!(
        (chi2 - dof).abs() < 4.0 * (2.0 * dof).sqrt(),
        "{chi2} against {dof}"
    );
    assert!(
        (start2 - start_dof).abs() < 4.0 * (2.0 * start_dof).sqrt(),
        "{start2} against {start_dof}"
    );
}

/// One triad wandering: its three departures follow the base states, before the effects'
/// coefficients, and only they are dynamic beyond the base states.
#[test]
fn one_wandering_triad_puts_its_departures_before_the_coefficients() {
    let noise = NoiseConfig::default();
    let model = model_with("gyro-scale, accel-bias-instability, odometer-scale", &noise);
    let names = model.state_names();
    assert_eq!(
        names[BASE_DIM..BASE_DIM + 4],
        ["dbax", "dbay", "dbaz", "s_gx"]
    );
    assert_eq!(model.dynamic_dim(), BASE_DIM + 3);
    assert_eq!(model.dim(), BASE_DIM + 3 + 3 + 1);
    assert_eq!(model.state_units()[BASE_DIM], "m/s^2");
}

/// The batch of eight lands where each point lands alone, for the model with every effect.
#[test]
fn batched_propagation_with_effects_matches_one_point_at_a_time() {
    let noise = NoiseConfig {
        gyro_psd: 1e-10,
        accel_psd: 1e-6,
        ..NoiseConfig::default()
    };
    let model = model_with(&StrapdownRegistry::catalogue().names().join(","), &noise);
    let n = model.dim();
    let mut rng = ChaCha8Rng::seed_from_u64(65);
    let mut w = InputWindow::with_capacity(11);
    for k in 0..=10 {
        w.push_linear(0.1 * k as f64, input_of(&random_reading(&mut rng)));
    }
    let count = 11;
    let nw = model.noise_channels().len();
    let points: Vec<f64> = (0..count)
        .flat_map(|_| random_state(&model, &mut rng))
        .collect();
    let noise: Vec<f64> = (0..count * nw)
        .map(|_| rng.gen_range(-1e-3..1e-3))
        .collect();
    let alone = common::batch_matches_one_point(&model, &points, &noise, &w);
    // The departures wander; the turn-on biases hold.
    for p in 0..count {
        assert_ne!(alone[p * n + BASE_DIM], points[p * n + BASE_DIM]);
        assert_eq!(alone[p * n + BG_X], points[p * n + BG_X]);
    }
}

#[test]
fn effect_lists_refuse_what_they_cannot_mean() {
    let r = StrapdownRegistry::catalogue();
    let err = |s: &str| {
        StrapdownEffectList::parse_entries(&[s], &r)
            .unwrap_err()
            .1
            .to_string()
    };
    assert!(err("gyro-scal").contains("known effects") || err("gyro-scal").contains("effects:"));
    assert!(err("gyro-scale, gyro-scale").contains("twice"));
    assert!(err("s_gx=1e-3, s_gx=2e-3").contains("twice"));
    assert!(err("gyro-bias-instability=3").contains("T_g"));
    assert!(err("T_g").contains("needs a value"));
    assert!(err("T_g=-5").contains("correlation time"));
    assert!(err("T_g=1e-300").contains("correlation time"));
    assert!(
        err("sigma_bg=1e300").contains("deg/s"),
        "{}",
        err("sigma_bg=1e300")
    );
    assert!(err("sigma_ba=NaN").contains("finite") || err("sigma_ba=NaN").contains("number"));
    assert!(err("heading=0.1").contains("navigation state"));
    assert!(err("kod=abc").contains("not a number"));
    // A platform effect is not a strapdown one.
    assert!(err("gyro-fz").contains("neither"));
    // A fixed value no instrument has is refused by the simulator, with its key.
    let traj = Arc::new(Trajectory::build(&TrajectoryConfig::default()).unwrap());
    let noise = NoiseConfig::default();
    let list = StrapdownEffectList::parse_entries(&["gyro-scale"], &r).unwrap();
    let model = Arc::new(
        StrapdownModel::base(&noise)
            .with_effects(&list, UnitClass::Mems, 1.0)
            .unwrap(),
    );
    let mut fixed = BTreeMap::new();
    fixed.insert("s_gz".to_string(), navkf_dynamics::Prior::fixed(0.5));
    let e = StrapdownSimulator::new(
        model,
        traj,
        10.0,
        1.0,
        UnitClass::Mems.errors(),
        &fixed,
        noise,
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("truth.coefficients.s_gz") && e.contains("real instrument"),
        "{e}"
    );
    // A bias too: a fixed gyro bias of 1e300 rad/s is no gyro's.
    let traj = Arc::new(Trajectory::build(&TrajectoryConfig::default()).unwrap());
    let model = Arc::new(StrapdownModel::base(&noise));
    let mut fixed = BTreeMap::new();
    fixed.insert("bgz".to_string(), navkf_dynamics::Prior::fixed(1e300));
    let e = StrapdownSimulator::new(
        model,
        traj,
        10.0,
        1.0,
        UnitClass::Mems.errors(),
        &fixed,
        noise,
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("truth.coefficients.bgz") && e.contains("real instrument"),
        "{e}"
    );
}
