//! Horizontal accelerometer biases settling after switch-on, outside the catalogue: the
//! second rival `gyro-bias-walk` must beat before it is named ([`super`]).
//!
//! An instrument warming up moves its biases along a curve that flattens: `nab += A (1 -
//! exp(-t / tau))`, `t` the seconds since the record started. With the constant biases
//! `Ka0x`, `Ka0y` beside it, the model holds `Ka0 + B exp(-t / tau)` for any `B`, so a
//! record that starts before or after the switch-on is covered alike. On a platform INS a
//! slowly changing horizontal accelerometer bias is held off by the tilt it causes, and the
//! velocity then shows it as a changing gyro drift would: a random walk of the drifts
//! follows it, and neither the accelerometer walk nor the halves' constancy test refuses
//! that walk. On the error-rate study the walk was named, `explained`, on 11 of 60
//! accelerometer warm-ups (docs/diagnosis.md, "Where the targets are missed").
//!
//! A function of time, which no coefficient (a random constant) of the model can carry: the
//! rates read the time from the input ([`navkf_dynamics::kinematics::ELAPSED_SLOT`]), which
//! the diagnosis writes on its own copy of the dataset ([`with_elapsed_time`]). The time
//! constant is the effect's parameter, fitted around the filter as a noise term's density is
//! ([`crate::fit::time_constant`]); the two amplitudes are coefficients.

use navkf_dynamics::dataset::Dataset;
use navkf_dynamics::effect::{Effect, Partials, PhysicalBound, Terms};
use navkf_dynamics::kinematics::{Kinematics, ELAPSED_SLOT};
use navkf_dynamics::real::Real;
use navkf_dynamics::state::{NAV_DIM, V_X, V_Y};

/// See the module documentation. Coefficients: the settled change of the East and North
/// biases, m/s^2.
#[derive(Debug, Clone)]
pub struct AccelSettling {
    /// The time constant, s.
    pub time_constant_s: f64,
}

impl AccelSettling {
    /// The name it is fitted under (never named: it is not in the catalogue).
    pub const NAME: &'static str = "accel-settling";

    /// How far the settling has gone `elapsed_s` seconds after the record started.
    fn settled(&self, elapsed_s: f64) -> f64 {
        -(-elapsed_s.max(0.0) / self.time_constant_s).exp_m1()
    }
}

impl Default for AccelSettling {
    /// Ten minutes: a warm-up's common length (the fit tries others).
    fn default() -> Self {
        AccelSettling {
            time_constant_s: 600.0,
        }
    }
}

/// A copy of `ds` whose inputs carry the seconds since its first input in
/// [`ELAPSED_SLOT`] (the platform's inputs leave it zero), for [`AccelSettling`].
pub fn with_elapsed_time(ds: &Dataset) -> Dataset {
    let mut timed = ds.clone();
    let t0 = ds.inputs.first().map_or(0.0, |s| s.t);
    for s in &mut timed.inputs {
        s.f[ELAPSED_SLOT] = s.t - t0;
    }
    timed
}

impl Effect for AccelSettling {
    fn name(&self) -> &str {
        Self::NAME
    }
    fn description(&self) -> &str {
        "the horizontal accelerometer biases settle by A (1 - exp(-t / tau)) after the record \
         starts (outside the catalogue)"
    }
    fn terms(&self) -> Terms {
        Terms::RATES
    }
    fn coefficient_names(&self) -> &[&str] {
        &["settle_ax", "settle_ay"]
    }
    fn coefficient_units(&self) -> &[&str] {
        &["m/s^2", "m/s^2"]
    }
    fn coefficient_sigma(&self) -> &[f64] {
        // Four times a navigation-grade bias (50 micro-g): the fit profiles the amplitudes,
        // so the prior only keeps the first steps linear.
        &[2e-3, 2e-3]
    }
    fn coefficient_bounds(&self) -> &[PhysicalBound] {
        &[]
    }
    fn add_rates<T: Real>(&self, k: &Kinematics<T>, c: &[T], rates: &mut [T; NAV_DIM]) {
        let s = self.settled(k.elapsed_s);
        rates[V_X] += c[0] * s;
        rates[V_Y] += c[1] * s;
    }
    fn add_rate_partials(&self, k: &Kinematics, _c: &[f64], offset: usize, p: &mut Partials) {
        let s = self.settled(k.elapsed_s);
        p.add(V_X, offset, s);
        p.add(V_Y, offset + 1, s);
    }
    fn set_parameter(&mut self, value: f64) -> Result<(), String> {
        if value.is_finite() && value > 0.0 {
            self.time_constant_s = value;
            Ok(())
        } else {
            Err(format!(
                "accel-settling time constant {value} s: expected a finite tau > 0"
            ))
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
            let report = check_effect(
                Box::new(AccelSettling::default()),
                &NoiseConfig::default(),
                16,
                seed,
            )
            .unwrap();
            assert!(report.passes(), "{report:?}");
        }
    }

    #[test]
    fn it_starts_at_zero_and_settles_to_its_amplitude() {
        let e = AccelSettling {
            time_constant_s: 300.0,
        };
        let at = |t: f64| {
            let k = Kinematics {
                elapsed_s: t,
                ..Kinematics::default()
            };
            let mut r = [0.0; NAV_DIM];
            e.add_rates(&k, &[1e-3, -2e-3], &mut r);
            (r[V_X], r[V_Y])
        };
        assert_eq!(at(0.0), (0.0, 0.0));
        let (x, y) = at(300.0);
        let s = 1.0 - (-1.0f64).exp();
        assert!((x - 1e-3 * s).abs() < 1e-18 && (y + 2e-3 * s).abs() < 1e-18);
        let (x, _) = at(1e5);
        assert!((x - 1e-3).abs() < 1e-15);
    }
}
