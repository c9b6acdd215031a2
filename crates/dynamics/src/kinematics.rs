//! The navigation quantities every term of the model is written in, computed once per
//! derivative evaluation and shared by the base model and its effects.

use crate::earth::{meridian_radius, prime_vertical_radius, FLATTENING, RE, WIE};
use crate::state::{LAT, PHI_X, PHI_Y, PHI_Z, V_X, V_Y};

/// Specific force input `f = [fx, fy, fz]` along the platform axes, m/s^2.
pub type Input = [f64; 3];

/// Trigonometry, radii and rates at one state, with their derivatives in latitude (for
/// Jacobians). Field names follow model.md: `w_cmd` is the rate the platform is torqued at.
#[derive(Debug, Clone, Copy, Default)]
pub struct Kinematics {
    /// Specific force input.
    pub f: Input,
    /// Platform error angles.
    pub phi: [f64; 3],
    /// East and North velocity.
    pub v_x: f64,
    /// North velocity.
    pub v_y: f64,
    /// sin L, cos L, tan L.
    pub sin_l: f64,
    /// cos L.
    pub cos_l: f64,
    /// tan L.
    pub tan_l: f64,
    /// 1 / cos L.
    pub inv_cos: f64,
    /// 1 / RM.
    pub inv_rm: f64,
    /// 1 / RN.
    pub inv_rn: f64,
    /// d(1/RM)/dL.
    pub d_inv_rm: f64,
    /// d(1/RN)/dL.
    pub d_inv_rn: f64,
    /// tan L / RN.
    pub tan_over_rn: f64,
    /// d(tan L / RN)/dL.
    pub d_tan_over_rn: f64,
    /// `[-v_y/RM, wie cosL + v_x/RN, wie sinL + v_x tanL/RN]`, rad/s.
    pub w_cmd: [f64; 3],
}

impl Kinematics {
    /// Computes the kinematics of the full state `x` under input `f`.
    #[inline]
    pub fn new(x: &[f64], f: &Input) -> Self {
        let (sin_l, cos_l) = crate::trig::sin_cos(x[LAT]);
        Self::with_trig(x, f, sin_l, cos_l)
    }

    /// As [`Kinematics::new`], with `sin L` and `cos L` already known.
    #[inline]
    pub fn with_trig(x: &[f64], f: &Input, sin_l: f64, cos_l: f64) -> Self {
        let rm = meridian_radius(sin_l);
        let rn = prime_vertical_radius(sin_l);
        let inv_rm = 1.0 / rm;
        let inv_rn = 1.0 / rn;
        let inv_cos = 1.0 / cos_l;
        let tan_l = sin_l * inv_cos;
        // dRM/dL = 6 Re f sinL cosL, dRN/dL = 2 Re f sinL cosL.
        let sc = sin_l * cos_l;
        let d_inv_rm = -6.0 * RE * FLATTENING * sc * inv_rm * inv_rm;
        let d_inv_rn = -2.0 * RE * FLATTENING * sc * inv_rn * inv_rn;
        let tan_over_rn = tan_l * inv_rn;
        let d_tan_over_rn = (1.0 + tan_l * tan_l) * inv_rn + tan_l * d_inv_rn;
        let v_x = x[V_X];
        let v_y = x[V_Y];
        Kinematics {
            f: *f,
            phi: [x[PHI_X], x[PHI_Y], x[PHI_Z]],
            v_x,
            v_y,
            sin_l,
            cos_l,
            tan_l,
            inv_cos,
            inv_rm,
            inv_rn,
            d_inv_rm,
            d_inv_rn,
            tan_over_rn,
            d_tan_over_rn,
            w_cmd: [
                -v_y * inv_rm,
                WIE * cos_l + v_x * inv_rn,
                WIE * sin_l + v_x * tan_over_rn,
            ],
        }
    }
}
