//! `torquer-scale`: scale error of the platform's torquing commands,
//! `phi' += diag(kt) w_cmd`, `w_cmd = [-v_y/RM, wie cosL + v_x/RN, wie sinL + v_x tanL/RN]`.
//!
//! This is where the navigation-frame rate terms of the printed eqs 6-8 come back (model.md):
//! the platform follows the commanded rate only up to the torquer's scale factor.

use crate::earth::WIE;
use crate::effect::{Effect, Partials, Terms};
use crate::kinematics::Kinematics;
use crate::real::Real;
use crate::state::{LAT, NAV_DIM, PHI_X, PHI_Y, PHI_Z, V_X, V_Y};

/// See the module documentation.
#[derive(Debug, Default, Clone)]
pub struct TorquerScale;

impl Effect for TorquerScale {
    fn name(&self) -> &str {
        "torquer-scale"
    }
    fn description(&self) -> &str {
        "phi' += diag(kt) w_cmd (scale error of the torquing commands)"
    }
    fn terms(&self) -> Terms {
        Terms::RATES
    }
    fn coefficient_names(&self) -> &[&str] {
        &["ktx", "kty", "ktz"]
    }
    fn coefficient_units(&self) -> &[&str] {
        &["1"; 3]
    }
    fn coefficient_sigma(&self) -> &[f64] {
        // 300 ppm torquer scale error.
        &[3.0e-4; 3]
    }
    fn add_rates<T: Real>(&self, k: &Kinematics<T>, c: &[T], rates: &mut [T; NAV_DIM]) {
        for i in 0..3 {
            rates[PHI_X + i] += c[i] * k.w_cmd[i];
        }
    }
    fn add_rate_partials(&self, k: &Kinematics, c: &[f64], offset: usize, p: &mut Partials) {
        for i in 0..3 {
            p.add(PHI_X + i, offset + i, k.w_cmd[i]);
        }
        // w1 = -v_y / RM
        p.add(PHI_X, V_Y, -c[0] * k.inv_rm);
        p.add(PHI_X, LAT, -c[0] * k.v_y * k.d_inv_rm);
        // w2 = wie cosL + v_x / RN
        p.add(PHI_Y, V_X, c[1] * k.inv_rn);
        p.add(PHI_Y, LAT, c[1] * (-WIE * k.sin_l + k.v_x * k.d_inv_rn));
        // w3 = wie sinL + v_x tanL / RN
        p.add(PHI_Z, V_X, c[2] * k.tan_over_rn);
        p.add(PHI_Z, LAT, c[2] * (WIE * k.cos_l + k.v_x * k.d_tan_over_rn));
    }
}
