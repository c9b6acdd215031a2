//! `odometer-scale`: the odometer's scale error, measured `v = (1 + kod) v_true`:
//! docs/model.md eq. (41).
//!
//! The product `kod v` makes the measurement non-linear in the state, so the simplified UKF
//! takes its sigma-point measurement path when this effect is on.

use crate::effect::{Effect, MeasurementTerm, Partials, PhysicalBound, Terms};
use crate::kinematics::Kinematics;
use crate::state::{MEAS_DIM, V_X, V_Y};

/// See the module documentation.
#[derive(Debug, Default, Clone)]
pub struct OdometerScale;

impl Effect for OdometerScale {
    fn name(&self) -> &str {
        "odometer-scale"
    }
    fn description(&self) -> &str {
        "z_v = (1 + kod) v (odometer scale error; non-linear measurement)"
    }
    fn terms(&self) -> Terms {
        Terms::measurement(MeasurementTerm::NonLinear)
    }
    fn coefficient_names(&self) -> &[&str] {
        &["kod"]
    }
    fn coefficient_units(&self) -> &[&str] {
        &["1"]
    }
    fn coefficient_sigma(&self) -> &[f64] {
        // 0.2 % wheel-radius uncertainty.
        &[2.0e-3]
    }
    fn coefficient_bounds(&self) -> &[PhysicalBound] {
        // A tyre's rolling radius changes by a few per cent with wear (8 mm of tread on a
        // 300 mm radius: 2.7 %), pressure and load (1-2 %) and between the sizes a vehicle is
        // approved for; 20 % is no odometer of that wheel.
        &[PhysicalBound {
            limit: 0.2,
            reason: "20 %: a tyre's rolling radius varies by a few per cent (wear, pressure, load)",
        }]
    }
    fn add_measurement(&self, k: &Kinematics, c: &[f64], z: &mut [f64; MEAS_DIM]) {
        z[0] += c[0] * k.v_x;
        z[1] += c[0] * k.v_y;
    }
    fn add_measurement_partials(&self, k: &Kinematics, c: &[f64], offset: usize, p: &mut Partials) {
        p.add(0, V_X, c[0]);
        p.add(1, V_Y, c[0]);
        p.add(0, offset, k.v_x);
        p.add(1, offset, k.v_y);
    }
}
