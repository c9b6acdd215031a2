//! `accel-quadratic`: accelerometer second-order scale error,
//! `nab_x += Ka2x fx^2`, `nab_y += Ka2y fy^2`.

use crate::effect::{Effect, Partials, Terms};
use crate::kinematics::Kinematics;
use crate::real::Real;
use crate::state::{NAV_DIM, V_X, V_Y};

/// See the module documentation.
#[derive(Debug, Default, Clone)]
pub struct AccelQuadratic;

impl Effect for AccelQuadratic {
    fn name(&self) -> &str {
        "accel-quadratic"
    }
    fn description(&self) -> &str {
        "nab_x += Ka2x fx^2, nab_y += Ka2y fy^2 (second-order accelerometer scale error)"
    }
    fn terms(&self) -> Terms {
        Terms::RATES
    }
    fn coefficient_names(&self) -> &[&str] {
        &["Ka2x", "Ka2y"]
    }
    fn coefficient_units(&self) -> &[&str] {
        &["1/(m/s^2)"; 2]
    }
    fn coefficient_sigma(&self) -> &[f64] {
        // 50 ug/g^2 = 4.9e-4 m/s^2 per (9.81 m/s^2)^2.
        &[5.1e-6; 2]
    }
    fn add_rates<T: Real>(&self, k: &Kinematics<T>, c: &[T], rates: &mut [T; NAV_DIM]) {
        rates[V_X] += c[0] * k.f[0] * k.f[0];
        rates[V_Y] += c[1] * k.f[1] * k.f[1];
    }
    fn add_rate_partials(&self, k: &Kinematics, _c: &[f64], offset: usize, p: &mut Partials) {
        p.add(V_X, offset, k.f[0] * k.f[0]);
        p.add(V_Y, offset + 1, k.f[1] * k.f[1]);
    }
}
