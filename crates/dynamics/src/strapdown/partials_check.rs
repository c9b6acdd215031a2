//! The check of a strapdown effect's partial derivatives, as `navkf effects --model strapdown
//! --check` runs it: the Jacobians the EKF uses (the chain rule through each place,
//! [`super::jacobian`]) of a model with the effect alone, against central finite differences
//! of its rates and measurement (docs/model.md eqs. (57), (61)), at random states far from
//! level, at speed, with readings of turns and accelerations.
//!
//! A strapdown effect has no partials of its own to get wrong: a declaration says where its
//! coefficients sit and the model differentiates through those places. The check is still
//! worth a user's minute: it proves, for the effects in their file, that each place reaches
//! the rates and the measurement the way docs/model.md writes it, and it reports in the
//! platform check's words ([`crate::partials_check::PartialsReport`]).
//!
//! ```
//! use navkf_dynamics::strapdown::effects::StrapdownRegistry;
//! use navkf_dynamics::strapdown::partials_check::check_effect;
//! use navkf_dynamics::strapdown::unit_class::UnitClass;
//! let registry = StrapdownRegistry::catalogue();
//! let report = check_effect(&registry, "gps-lever-arm", UnitClass::Mems, 8, 1).unwrap();
//! assert!(report.passes(), "{report}");
//! ```

use super::effect_list::StrapdownEffectList;
use super::effects::StrapdownRegistry;
use super::model::{StrapdownModel, MEASUREMENT_NAMES, MEAS_DIM};
use super::rates::{input_of, ImuReading};
use super::state::*;
use super::unit_class::UnitClass;
use crate::error::DynamicsError;
use crate::family::FamilyModel;
use crate::noise::NoiseConfig;
use crate::partials_check::{central_difference, compare, Jacobian, PartialsReport, ROUNDING_ULPS};
use crate::system::SystemModel;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Truncation allowance of a central difference at the steps of [`steps`], relative.
const RTOL: f64 = 1e-6;

/// Ulps of a row's largest term that one evaluation of it may be off: the attitude's sines
/// and cosines and the Earth's radii make a strapdown row a longer sum than a platform one.
const STRAPDOWN_ULPS: f64 = 256.0;

/// A state far from level and at speed, its coefficients drawn at up to four typical sigmas.
pub fn random_state(model: &StrapdownModel, rng: &mut ChaCha8Rng) -> Vec<f64> {
    let mut x = vec![0.0; model.dim()];
    x[ROLL] = rng.gen_range(-0.5..0.5);
    x[PITCH] = rng.gen_range(-0.5..0.5);
    x[HEADING] = rng.gen_range(-3.1..3.1);
    x[V_E] = rng.gen_range(-40.0..40.0);
    x[V_N] = rng.gen_range(-40.0..40.0);
    x[LAT] = rng.gen_range(-1.3..1.3);
    x[LON] = rng.gen_range(-3.1..3.1);
    for (i, xi) in x.iter_mut().enumerate().skip(NAV_DIM) {
        *xi = rng.gen_range(-4.0..4.0) * model.typical_sigma(i);
    }
    x
}

/// Readings of a turning, accelerating unit.
pub fn random_reading(rng: &mut ChaCha8Rng) -> ImuReading {
    ImuReading {
        w: std::array::from_fn(|_| rng.gen_range(-0.5..0.5)),
        f: [
            rng.gen_range(-3.0..3.0),
            rng.gen_range(-3.0..3.0),
            rng.gen_range(8.0..11.0),
        ],
    }
}

/// Each state's difference step: small against its scale, large against its rounding.
pub fn steps(model: &StrapdownModel) -> Vec<f64> {
    const BASE: [f64; BASE_DIM] = [
        1e-6, 1e-6, 1e-6, 1e-4, 1e-4, 1e-7, 1e-7, 1e-8, 1e-8, 1e-8, 1e-5, 1e-5, 1e-5,
    ];
    (0..model.dim())
        .map(|i| {
            BASE.get(i)
                .copied()
                .unwrap_or(1e-3 * model.typical_sigma(i))
        })
        .collect()
}

/// Each row's term magnitude for the rounding floor: the row's value, its linear terms
/// `|J(r, c) x_c|` and `unseen` (the size of what enters the row but not through the state:
/// the readings and the Earth's rate in a rate row), scaled so that [`compare`]'s floor is
/// [`STRAPDOWN_ULPS`] ulps.
fn magnitudes(jac: &[f64], x: &[f64], f0: &[f64], unseen: f64) -> Vec<f64> {
    let n = x.len();
    f0.iter()
        .enumerate()
        .map(|(r, v)| {
            let linear: f64 = (0..n).map(|c| (jac[r * n + c] * x[c]).abs()).sum();
            (v.abs() + linear + unseen) * STRAPDOWN_ULPS / ROUNDING_ULPS
        })
        .collect()
}

/// What enters a rate row besides the state, m/s^2 or rad/s: readings up to 11 m/s^2.
const READINGS: f64 = 10.0;

/// Checks the partials of `registry`'s effect `name`: a model of `class` with that effect
/// alone, at `states` random states and readings (seeded by `seed`), its rate and measurement
/// Jacobians against central differences. Every entry counts towards
/// [`PartialsReport::failures`]; the worst entry reported is the worst the effect touches
/// ([`PartialsReport`]'s rule, as on the platform).
pub fn check_effect(
    registry: &StrapdownRegistry,
    name: &str,
    class: UnitClass,
    states: usize,
    seed: u64,
) -> Result<PartialsReport, DynamicsError> {
    let noise = NoiseConfig::default();
    let list = StrapdownEffectList::parse_entries(&[name], registry).map_err(|(_, e)| e)?;
    let model = StrapdownModel::base(&noise).with_effects(&list, class, 1.0)?;
    let base = StrapdownModel::base(&noise);
    let names = model.state_names();
    let (n, nb, d) = (model.dim(), base.dim(), model.dynamic_dim());
    let h = steps(&model);
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut report = PartialsReport {
        effect: name.to_string(),
        states,
        failures: 0,
        worst: None,
    };
    for _ in 0..states {
        let x = random_state(&model, &mut rng);
        let u = input_of(&random_reading(&mut rng));
        // Rates: filled with NaN, so an entry the code leaves unwritten fails.
        let mut jac = vec![f64::NAN; d * n];
        model.rate_jacobian(&x, &u, &mut jac);
        let mut f0 = vec![0.0; d];
        model.rates(&x, &u, &mut f0);
        let fd = central_difference(&x, &h, d, |xx, out| model.rates(xx, &u, out));
        let rates = compare(&jac, &fd, &magnitudes(&jac, &x, &f0, READINGS), RTOL);
        let mut base_jac = vec![0.0; base.dynamic_dim() * nb];
        base.rate_jacobian(&x[..nb], &u, &mut base_jac);
        report.record(
            Jacobian::Rates,
            &rates,
            &base_jac,
            nb,
            |r| names[r].clone(),
            &names,
        );
        // The measurement. Its latitude and longitude rows are near 1 rad, so an entry of a
        // navigation state's column there is resolved to about 1e-7 only; the coefficients'
        // columns, differenced over their own sizes, are resolved far finer.
        let mut hm = vec![f64::NAN; MEAS_DIM * n];
        model.measurement_jacobian(&x, &mut hm);
        let mut z0 = vec![0.0; MEAS_DIM];
        model.measure(&x, &mut z0);
        let fd = central_difference(&x, &h, MEAS_DIM, |xx, out| model.measure(xx, out));
        let measurement = compare(&hm, &fd, &magnitudes(&hm, &x, &z0, 0.0), RTOL);
        let mut base_h = vec![0.0; MEAS_DIM * nb];
        base.measurement_jacobian(&x[..nb], &mut base_h);
        report.record(
            Jacobian::Measurement,
            &measurement,
            &base_h,
            nb,
            |r| MEASUREMENT_NAMES[r].to_string(),
            &names,
        );
    }
    Ok(report)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::declared::parse_declarations;

    #[test]
    fn every_catalogued_effect_passes() {
        let registry = StrapdownRegistry::catalogue();
        for name in registry.names() {
            let report = check_effect(&registry, name, UnitClass::Mems, 6, 3).unwrap();
            assert!(report.passes(), "{report}");
            assert!(report.worst.is_some(), "{report}");
        }
    }

    /// The check can fail: a model whose measurement Jacobian is perturbed in one entry of
    /// the effect's column is caught, and the report `navkf effects --check` prints fails
    /// and names that entry.
    #[test]
    fn a_wrong_entry_is_caught_and_named() {
        let registry = StrapdownRegistry::catalogue();
        let list = StrapdownEffectList::parse_entries(&["odometer-scale"], &registry).unwrap();
        let model = StrapdownModel::base(&NoiseConfig::default())
            .with_effects(&list, UnitClass::Mems, 1.0)
            .unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let x = random_state(&model, &mut rng);
        let n = model.dim();
        let mut hm = vec![f64::NAN; MEAS_DIM * n];
        model.measurement_jacobian(&x, &mut hm);
        let fd = central_difference(&x, &steps(&model), MEAS_DIM, |xx, out| {
            model.measure(xx, out)
        });
        let mut z0 = vec![0.0; MEAS_DIM];
        model.measure(&x, &mut z0);
        let m = magnitudes(&hm, &x, &z0, 0.0);
        assert!(compare(&hm, &fd, &m, RTOL).failures.is_empty());
        // The speed row's kod entry, 0.1 % off.
        hm[n - 1] *= 1.001;
        let c = compare(&hm, &fd, &m, RTOL);
        assert_eq!(c.failures.len(), 1);
        assert_eq!((c.failures[0].row, c.failures[0].col), (0, n - 1));
        let base = StrapdownModel::base(&NoiseConfig::default());
        let nb = base.dim();
        let mut base_h = vec![0.0; MEAS_DIM * nb];
        base.measurement_jacobian(&x[..nb], &mut base_h);
        let mut report = PartialsReport {
            effect: "odometer-scale".into(),
            states: 1,
            failures: 0,
            worst: None,
        };
        let names = model.state_names();
        report.record(
            Jacobian::Measurement,
            &c,
            &base_h,
            nb,
            |r| MEASUREMENT_NAMES[r].to_string(),
            &names,
        );
        let text = report.to_string();
        assert!(!report.passes(), "{text}");
        assert!(
            text.contains("1 entries DISAGREE") && text.contains("d(z_speed)/d(kod)"),
            "{text}"
        );
    }

    #[test]
    fn a_declared_effect_is_checked_through_its_places() {
        let mut registry = StrapdownRegistry::catalogue();
        let text = r#"
[[effect]]
name = "mast-check"
coefficients = [{ name = "h_check", unit = "m", sigma = 1.0 }]
places = [
    { coefficient = "h_check", place = "l[z]" },
    { coefficient = "h_check", place = "l[x]", factor = 0.5 },
]
"#;
        registry
            .declare(&parse_declarations(text).unwrap())
            .unwrap();
        let report = check_effect(&registry, "mast-check", UnitClass::Mems, 6, 4).unwrap();
        assert!(report.passes() && report.worst.is_some(), "{report}");
    }
}
