//! `gps-latency`: the GPS fix refers to `tau` seconds before its time stamp,
//! measured `L - tau v_y / RM`, `lambda - tau v_x / (RN cosL)` (a non-linear measurement):
//! docs/model.md eq. (42).

use crate::effect::{Effect, MeasurementTerm, Partials, PhysicalBound, Terms};
use crate::kinematics::Kinematics;
use crate::state::{LAT, MEAS_DIM, V_X, V_Y};

/// See the module documentation.
#[derive(Debug, Default, Clone)]
pub struct GpsLatency;

impl Effect for GpsLatency {
    fn name(&self) -> &str {
        "gps-latency"
    }
    fn description(&self) -> &str {
        "z_L -= tau v_y/RM, z_lambda -= tau v_x/(RN cosL) (GPS time-stamp latency)"
    }
    fn terms(&self) -> Terms {
        Terms::measurement(MeasurementTerm::NonLinear)
    }
    fn coefficient_names(&self) -> &[&str] {
        &["tau"]
    }
    fn coefficient_units(&self) -> &[&str] {
        &["s"]
    }
    fn coefficient_sigma(&self) -> &[f64] {
        // A receiver's unmodelled output delay: tens to a few hundred milliseconds.
        &[0.1]
    }
    fn coefficient_bounds(&self) -> &[PhysicalBound] {
        // A receiver delivers a fix within its output interval (1 s at the usual 1 Hz; the
        // slowest serial NMEA output takes about that to send), or it would fall behind its own
        // fixes; a logger that stamps either stream on arrival adds at most as much. tau is
        // the offset between the two clocks, so it takes either sign (inertial samples stamped
        // late make the fix look early): |tau| <= 2 s. A latency of minutes is no receiver's.
        &[PhysicalBound {
            limit: 2.0,
            reason: "2 s: a receiver delivers its fix within its output interval (1 s at 1 Hz), \
                     a logger's stamp adds at most as much",
        }]
    }
    fn add_measurement(&self, k: &Kinematics, c: &[f64], z: &mut [f64; MEAS_DIM]) {
        z[2] -= c[0] * k.v_y * k.inv_rm;
        z[3] -= c[0] * k.v_x * k.inv_rn * k.inv_cos;
    }
    fn add_measurement_partials(&self, k: &Kinematics, c: &[f64], offset: usize, p: &mut Partials) {
        let tau = c[0];
        let sec = k.inv_cos;
        p.add(2, offset, -k.v_y * k.inv_rm);
        p.add(2, V_Y, -tau * k.inv_rm);
        p.add(2, LAT, -tau * k.v_y * k.d_inv_rm);
        p.add(3, offset, -k.v_x * k.inv_rn * sec);
        p.add(3, V_X, -tau * k.inv_rn * sec);
        p.add(
            3,
            LAT,
            -tau * k.v_x * sec * (k.d_inv_rn + k.inv_rn * k.tan_l),
        );
    }
}
