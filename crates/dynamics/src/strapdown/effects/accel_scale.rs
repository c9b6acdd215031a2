//! `accel-scale`: each accelerometer's scale-factor error, `E_a += diag(s_ax, s_ay, s_az)`
//! (docs/model.md eq. (64)). On a level vehicle `s_az` multiplies gravity, which the
//! horizontal model does not integrate: it shows only through tilt; `s_ax` shows in
//! accelerations and braking.
//!
//! Sizes: tens of ppm for navigation-grade accelerometers, hundreds for tactical ones,
//! tenths of a per cent for calibrated MEMS (Groves, 2013, section 4.4.2).

use super::{Coefficient, Places, Slot, StrapdownEffect};
use crate::sensor_classes::SCALE as BOUND;

const fn scale(name: &'static str, axis: usize) -> Coefficient {
    Coefficient {
        name,
        unit: "1",
        places: Places::One(Slot::Accel(axis, axis)),
        sigma: [2e-5, 3e-4, 3e-3],
        bound: BOUND,
    }
}

/// See the module documentation.
pub const ACCEL_SCALE: StrapdownEffect = StrapdownEffect {
    name: "accel-scale",
    description: "f~ = (I + diag(s_ax, s_ay, s_az)) f + ... (accelerometer scale-factor errors)",
    coefficients: &[scale("s_ax", 0), scale("s_ay", 1), scale("s_az", 2)],
    instability: None,
    declaration: None,
};
