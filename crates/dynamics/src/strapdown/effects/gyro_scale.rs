//! `gyro-scale`: each gyro's scale-factor error, `E_g += diag(s_gx, s_gy, s_gz)`
//! (docs/model.md eq. (63)). A rate about a body axis is read `1 + s` times too large; on a
//! vehicle that turns mostly about its up axis, `s_gz` is what shows (as a heading error that
//! grows with the angle turned).
//!
//! Sizes: a few ppm for ring-laser gyros, hundreds for fibre-optic ones, tenths of a per cent
//! for calibrated MEMS (Groves, 2013, section 4.4.2, as the unit classes cite it).

use super::{Coefficient, Places, Slot, StrapdownEffect};
use crate::sensor_classes::SCALE as BOUND;

const fn scale(name: &'static str, axis: usize) -> Coefficient {
    Coefficient {
        name,
        unit: "1",
        places: Places::One(Slot::Gyro(axis, axis)),
        sigma: [1e-5, 3e-4, 3e-3],
        bound: BOUND,
    }
}

/// See the module documentation.
pub const GYRO_SCALE: StrapdownEffect = StrapdownEffect {
    name: "gyro-scale",
    description: "w~ = (I + diag(s_gx, s_gy, s_gz)) w + ... (gyro scale-factor errors)",
    coefficients: &[scale("s_gx", 0), scale("s_gy", 1), scale("s_gz", 2)],
    instability: None,
    declaration: None,
};
