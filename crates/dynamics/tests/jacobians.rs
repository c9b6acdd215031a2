//! The analytic Jacobians (`rate_jacobian`, `measurement_jacobian`) against central finite
//! differences of `rates` and `measure`, for the base model, each catalogue effect alone and
//! all of them together, at several random but realistic states (see `common::random_state`).
//!
//! What the checks catch: a wrong sign, a missing or extra term, a partial written into the
//! wrong row or column (e.g. a wrong effect offset), an entry left unwritten (the buffers are
//! pre-filled with NaN), or a partial that disagrees with the equations it derives from.
//! Tolerances are explained in `common::compare`: each entry is judged against its own size
//! plus the rounding floor of the difference quotient, so even the smallest terms (the
//! `d(1/RN)/dL` parts, ~1e-5 of their entry) are resolved.

use crate::common;

use common::*;
use navkf_dynamics::effect::Partials;
use navkf_dynamics::effects::TorquerScale;
use navkf_dynamics::state::*;
use navkf_dynamics::{Effect, Kinematics, NoiseConfig, PlatformModel, Registry};

/// Random states per configuration.
const STATES: usize = 8;

fn model_with(names: &[&str]) -> PlatformModel {
    let effects = Registry::catalogue()
        .build_all(names)
        .expect("catalogue names");
    PlatformModel::new(effects, &NoiseConfig::default()).expect("model assembles")
}

fn all_effects_model() -> PlatformModel {
    let reg = Registry::catalogue();
    let effects = reg.build_all(&reg.names()).expect("catalogue builds");
    PlatformModel::new(effects, &NoiseConfig::default()).expect("model assembles")
}

fn check_rates(model: &PlatformModel, seed: u64) {
    let mut rng = rng(seed);
    for k in 0..STATES {
        let x = random_state(model, &mut rng);
        let u = random_input(&mut rng);
        if let Err(e) = check_rate_jacobian(model, &x, &u) {
            panic!(
                "rate Jacobian of {:?}, state #{k} (x = {x:?}, f = {u:?}):\n{e}",
                model.effect_names()
            );
        }
    }
}

fn check_measurement(model: &PlatformModel, seed: u64) {
    let mut rng = rng(seed);
    for k in 0..STATES {
        let x = random_state(model, &mut rng);
        if let Err(e) = check_measurement_jacobian(model, &x) {
            panic!(
                "measurement Jacobian of {:?}, state #{k} (x = {x:?}):\n{e}",
                model.effect_names()
            );
        }
    }
}

#[test]
fn base_rate_jacobian_matches_finite_differences() {
    check_rates(&PlatformModel::base(&NoiseConfig::default()), 1);
}

#[test]
fn base_measurement_jacobian_matches_finite_differences() {
    check_measurement(&PlatformModel::base(&NoiseConfig::default()), 2);
}

/// Also at the speed and latitude extremes the brief names (20 m/s both signs, high
/// latitude where tan L and sec L grow), with the full catalogue.
#[test]
fn all_effects_jacobians_at_extreme_speeds_and_latitudes() {
    let model = all_effects_model();
    let mut rng = rng(3);
    for &lat_deg in &[0.5f64, 30.0, 45.0, 70.0, -60.0] {
        for &(vx, vy) in &[(20.0, 20.0), (-20.0, 20.0), (20.0, -20.0), (-20.0, -20.0)] {
            let mut x = random_state(&model, &mut rng);
            x[LAT] = lat_deg.to_radians();
            x[V_X] = vx;
            x[V_Y] = vy;
            let u = random_input(&mut rng);
            check_rate_jacobian(&model, &x, &u)
                .unwrap_or_else(|e| panic!("rates at L = {lat_deg}, v = ({vx}, {vy}):\n{e}"));
            check_measurement_jacobian(&model, &x)
                .unwrap_or_else(|e| panic!("measurement at L = {lat_deg}, v = ({vx}, {vy}):\n{e}"));
        }
    }
}

/// One module per catalogue effect switched on alone, plus `all` with the whole catalogue.
macro_rules! effect_jacobian_tests {
    ($($module:ident => $names:expr, $seed:expr;)*) => {$(
        mod $module {
            use super::*;
            #[test]
            fn rate_jacobian_matches_finite_differences() {
                check_rates(&model_with($names), $seed);
            }
            #[test]
            fn measurement_jacobian_matches_finite_differences() {
                check_measurement(&model_with($names), $seed + 1000);
            }
        }
    )*};
}

effect_jacobian_tests! {
    gyro_fz => &["gyro-fz"], 10;
    accel_quadratic => &["accel-quadratic"], 11;
    accel_cross_axis => &["accel-cross-axis"], 12;
    torquer_scale => &["torquer-scale"], 13;
    odometer_scale => &["odometer-scale"], 14;
    odometer_misalignment => &["odometer-misalignment"], 17;
    gps_latency => &["gps-latency"], 15;
    gyro_bias_walk => &["gyro-bias-walk"], 16;
}

#[test]
fn all_catalogue_effects_rate_jacobian_matches_finite_differences() {
    let model = all_effects_model();
    assert_eq!(model.effects().len(), 8, "the catalogue has eight effects");
    check_rates(&model, 20);
}

#[test]
fn all_catalogue_effects_measurement_jacobian_matches_finite_differences() {
    check_measurement(&all_effects_model(), 21);
}

/// The same catalogue in reverse order: offsets change, the check must still pass (catches
/// an effect that writes its partials at a fixed column instead of at `offset`).
#[test]
fn all_catalogue_effects_in_reverse_order_match_finite_differences() {
    let reg = Registry::catalogue();
    let mut names = reg.names();
    names.reverse();
    let model =
        PlatformModel::new(reg.build_all(&names).unwrap(), &NoiseConfig::default()).unwrap();
    check_rates(&model, 22);
    check_measurement(&model, 23);
}

/// The checker itself: the torquer-scale effect with its smallest partial dropped (the
/// `v_x d(1/RN)/dL` part of `d phi_y'/dL`, about 1e-5 of its entry) must be reported.
/// Guards against a tolerance so loose that the Jacobian tests could not fail.
#[derive(Debug)]
struct TorquerScaleMissingTerm;

impl Effect for TorquerScaleMissingTerm {
    fn terms(&self) -> navkf_dynamics::Terms {
        navkf_dynamics::Terms {
            rates: true,
            linear_rates: &[],
            measurement: navkf_dynamics::MeasurementTerm::None,
            noise: false,
        }
    }
    fn name(&self) -> &str {
        "torquer-scale-broken"
    }
    fn description(&self) -> &str {
        "torquer-scale with one partial term dropped"
    }
    fn coefficient_names(&self) -> &[&str] {
        TorquerScale.coefficient_names()
    }
    fn coefficient_units(&self) -> &[&str] {
        TorquerScale.coefficient_units()
    }
    fn coefficient_sigma(&self) -> &[f64] {
        TorquerScale.coefficient_sigma()
    }
    fn add_rates<T: navkf_dynamics::Real>(
        &self,
        k: &Kinematics<T>,
        c: &[T],
        rates: &mut [T; NAV_DIM],
    ) {
        TorquerScale.add_rates(k, c, rates)
    }
    fn add_rate_partials(&self, k: &Kinematics, c: &[f64], offset: usize, p: &mut Partials) {
        TorquerScale.add_rate_partials(k, c, offset, p);
        // Remove c_y v_x d(1/RN)/dL from d phi_y' / dL.
        p.add(PHI_Y, LAT, -c[1] * k.v_x * k.d_inv_rn);
    }
}

#[test]
fn checker_reports_a_dropped_small_partial() {
    let model = PlatformModel::new(
        vec![Box::new(TorquerScaleMissingTerm)],
        &NoiseConfig::default(),
    )
    .unwrap();
    let mut rng = rng(30);
    let x = random_state(&model, &mut rng);
    let u = random_input(&mut rng);
    let err = check_rate_jacobian(&model, &x, &u).expect_err("the dropped term must be found");
    assert!(err.contains("d(row 1)/d(L)"), "reported: {err}");
    // The public check a user runs on their own effect finds it too, and names it.
    let report = navkf_dynamics::partials_check::check_effect(
        Box::new(TorquerScaleMissingTerm),
        &NoiseConfig::default(),
        4,
        30,
    )
    .unwrap();
    assert!(!report.passes(), "{report}");
    let (_, row, col, _) = report.worst.as_ref().unwrap();
    assert_eq!((row.as_str(), col.as_str()), ("phi_y", "L"), "{report}");
    assert!(report.to_string().contains("DISAGREE"), "{report}");
}
