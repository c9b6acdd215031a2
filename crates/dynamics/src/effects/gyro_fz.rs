//! `gyro-fz`: gyro drift proportional to the vertical specific force,
//! `eps_i += Kg13i fz` for i = x, y, z (a g-sensitive drift along the spin-axis direction).
//!
//! On a level vehicle `fz` is nearly constant (gravity), so on a flat trajectory this term is
//! almost indistinguishable from the constant drift `Kg0i`: the diagnosis reports that.

use crate::effect::{Effect, Partials, Terms};
use crate::kinematics::Kinematics;
use crate::real::Real;
use crate::state::{NAV_DIM, PHI_X};

/// See the module documentation.
#[derive(Debug, Default, Clone)]
pub struct GyroFz;

impl Effect for GyroFz {
    fn name(&self) -> &str {
        "gyro-fz"
    }
    fn description(&self) -> &str {
        "eps_i += Kg13i fz (gyro drift per unit vertical specific force)"
    }
    fn terms(&self) -> Terms {
        Terms::RATES
    }
    fn coefficient_names(&self) -> &[&str] {
        &["Kg13x", "Kg13y", "Kg13z"]
    }
    fn coefficient_units(&self) -> &[&str] {
        &["rad/s/(m/s^2)"; 3]
    }
    fn coefficient_sigma(&self) -> &[f64] {
        // 0.02 deg/h per g.
        &[9.9e-9; 3]
    }
    fn add_rates<T: Real>(&self, k: &Kinematics<T>, c: &[T], rates: &mut [T; NAV_DIM]) {
        for i in 0..3 {
            rates[PHI_X + i] += c[i] * k.f[2];
        }
    }
    fn add_rate_partials(&self, k: &Kinematics, _c: &[f64], offset: usize, p: &mut Partials) {
        for i in 0..3 {
            p.add(PHI_X + i, offset + i, k.f[2]);
        }
    }
}
