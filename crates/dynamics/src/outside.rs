//! Physics outside the catalogue: terms a platform user meets that neither the base model nor
//! any catalogued effect carries. They exist to be hidden in simulated truth, so that the
//! diagnosis can be measured on misfits it has no candidate for (it must then name nothing,
//! not the nearest catalogued effect). None of them is in [`crate::Registry::catalogue`].
//!
//! - [`Drag`]: a velocity-proportional acceleration error, `v' -= kd v` (the walk-through's
//!   user effect in `navkf-study`'s `user_effect` example).
//! - [`AccelWarmUp`]: horizontal accelerometer biases that drift while the instrument warms
//!   up, `nab += A (1 - exp(-t / tau))`: a function of time, which no coefficient (a random
//!   constant) can carry. The truth simulator adds it to the specific force it integrates
//!   ([`crate::Simulator::with_specific_force_error`]); the recorded input lacks it.

use crate::effect::{Effect, Partials, Terms};
use crate::kinematics::{Kinematics, SpecificForce};
use crate::real::Real;
use crate::state::{NAV_DIM, V_X, V_Y};

/// `v' -= kd v`: a velocity-proportional acceleration error (not in the catalogue).
#[derive(Debug, Clone, Copy, Default)]
pub struct Drag;

impl Drag {
    /// The effect's name.
    pub const NAME: &'static str = "drag";
    /// Typical size of `kd`, 1/s: 5e-5, 7.5e-4 m/s^2 (75 micro-g) at 15 m/s.
    pub const TYPICAL: f64 = 5e-5;
}

impl Effect for Drag {
    fn name(&self) -> &str {
        Self::NAME
    }
    fn description(&self) -> &str {
        "v' -= kd v (velocity-proportional acceleration error; outside the catalogue)"
    }
    fn terms(&self) -> Terms {
        Terms::RATES
    }
    fn coefficient_names(&self) -> &[&str] {
        &["kd"]
    }
    fn coefficient_units(&self) -> &[&str] {
        &["1/s"]
    }
    fn coefficient_sigma(&self) -> &[f64] {
        &[Self::TYPICAL]
    }
    fn add_rates<T: Real>(&self, k: &Kinematics<T>, c: &[T], r: &mut [T; NAV_DIM]) {
        r[V_X] -= c[0] * k.v_x;
        r[V_Y] -= c[0] * k.v_y;
    }
    fn add_rate_partials(&self, k: &Kinematics, c: &[f64], offset: usize, p: &mut Partials) {
        p.add(V_X, V_X, -c[0]);
        p.add(V_Y, V_Y, -c[0]);
        p.add(V_X, offset, -k.v_x);
        p.add(V_Y, offset, -k.v_y);
    }
}

/// Horizontal accelerometer biases that settle after switch-on:
/// `nab(t) = amplitude (1 - exp(-t / time_constant_s))` on the East and North axes.
///
/// ```
/// use navkf_dynamics::outside::AccelWarmUp;
/// let w = AccelWarmUp { amplitude: [4.9e-4, -2e-4], time_constant_s: 600.0 };
/// assert_eq!(w.at(0.0), [0.0, 0.0, 0.0]);
/// let late = w.at(1e6);
/// assert!((late[0] - 4.9e-4).abs() < 1e-15 && late[2] == 0.0);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AccelWarmUp {
    /// Settled change of the East and North biases, m/s^2.
    pub amplitude: [f64; 2],
    /// Time constant of the warm-up, s.
    pub time_constant_s: f64,
}

impl AccelWarmUp {
    /// Typical settled change, m/s^2: 50 micro-g, the size of the bias itself.
    pub const TYPICAL: f64 = 4.9e-4;

    /// The bias change at time `t` (s since the record started), as a specific-force error.
    pub fn at(&self, t: f64) -> SpecificForce {
        let s = 1.0 - (-t.max(0.0) / self.time_constant_s).exp();
        [self.amplitude[0] * s, self.amplitude[1] * s, 0.0]
    }
}
