//! `accel-cross-axis`: accelerometer cross-axis sensitivity (input-axis misalignment),
//! `nab_x += Ka12x fy`, `nab_y += Ka12y fx`.

use crate::effect::{Effect, Partials, Terms};
use crate::kinematics::Kinematics;
use crate::real::Real;
use crate::state::{NAV_DIM, V_X, V_Y};

/// See the module documentation.
#[derive(Debug, Default, Clone)]
pub struct AccelCrossAxis;

impl Effect for AccelCrossAxis {
    fn name(&self) -> &str {
        "accel-cross-axis"
    }
    fn description(&self) -> &str {
        "nab_x += Ka12x fy, nab_y += Ka12y fx (accelerometer cross-axis coupling)"
    }
    fn terms(&self) -> Terms {
        Terms::RATES
    }
    fn coefficient_names(&self) -> &[&str] {
        &["Ka12x", "Ka12y"]
    }
    fn coefficient_units(&self) -> &[&str] {
        &["1"; 2]
    }
    fn coefficient_sigma(&self) -> &[f64] {
        // 20 arcsec of input-axis misalignment.
        &[1.0e-4; 2]
    }
    fn add_rates<T: Real>(&self, k: &Kinematics<T>, c: &[T], rates: &mut [T; NAV_DIM]) {
        rates[V_X] += c[0] * k.f[1];
        rates[V_Y] += c[1] * k.f[0];
    }
    fn add_rate_partials(&self, k: &Kinematics, _c: &[f64], offset: usize, p: &mut Partials) {
        p.add(V_X, offset, k.f[1]);
        p.add(V_Y, offset + 1, k.f[0]);
    }
}
