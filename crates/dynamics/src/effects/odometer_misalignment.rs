//! `odometer-misalignment`: the odometer's velocity turned by a small angle, measured
//! `[v_x, v_y]` become `R(a_y) [v_x, v_y]`: docs/model.md eq. (43). An odometer mounted a little
//! crooked (a fraction of a degree about the vertical) is one of the commonest defects of a
//! real vehicle test.
//!
//! Like every effect, its term adds to the measurement, `(R(a_y) - I) v`; with
//! `odometer-scale` on as well the model measures `(1 + kod) v + (R(a_y) - I) v`, which
//! differs from `(1 + kod) R(a_y) v` by `kod (R(a_y) - I) v`: a product of two small
//! coefficients (3e-3 x 3e-3 x 20 m/s = 2e-4 m/s), far below any odometer's noise. The
//! rotation makes the measurement non-linear in the state, so the simplified UKF takes its
//! sigma-point measurement path when this effect is on.

use crate::effect::{Effect, MeasurementTerm, Partials, PhysicalBound, Terms};
use crate::kinematics::Kinematics;
use crate::state::{MEAS_DIM, V_X, V_Y};

/// See the module documentation.
#[derive(Debug, Default, Clone)]
pub struct OdometerMisalignment;

impl Effect for OdometerMisalignment {
    fn name(&self) -> &str {
        "odometer-misalignment"
    }
    fn description(&self) -> &str {
        "z_v = R(a_y) v (odometer turned about the vertical; non-linear measurement)"
    }
    fn terms(&self) -> Terms {
        Terms::measurement(MeasurementTerm::NonLinear)
    }
    fn coefficient_names(&self) -> &[&str] {
        &["a_y"]
    }
    fn coefficient_units(&self) -> &[&str] {
        &["rad"]
    }
    fn coefficient_sigma(&self) -> &[f64] {
        // 3 mrad (0.17 deg): what careful mounting against the vehicle's body leaves.
        &[3.0e-3]
    }
    fn coefficient_bounds(&self) -> &[PhysicalBound] {
        // A wheel turned by more than about 5 deg from the vehicle's axis is steering, and an
        // inertial unit bolted that far off its vehicle's axis is seen by anyone installing it.
        &[PhysicalBound {
            limit: 0.1,
            reason: "0.1 rad (5.7 deg): an odometer or unit mounted that far off the vehicle's axis is seen at installation",
        }]
    }
    fn add_measurement(&self, k: &Kinematics, c: &[f64], z: &mut [f64; MEAS_DIM]) {
        let (s, co) = c[0].sin_cos();
        let cm1 = co - 1.0;
        z[0] += cm1 * k.v_x - s * k.v_y;
        z[1] += s * k.v_x + cm1 * k.v_y;
    }
    fn add_measurement_partials(&self, k: &Kinematics, c: &[f64], offset: usize, p: &mut Partials) {
        let (s, co) = c[0].sin_cos();
        let cm1 = co - 1.0;
        p.add(0, V_X, cm1);
        p.add(0, V_Y, -s);
        p.add(1, V_X, s);
        p.add(1, V_Y, cm1);
        p.add(0, offset, -s * k.v_x - co * k.v_y);
        p.add(1, offset, co * k.v_x - s * k.v_y);
    }
}
