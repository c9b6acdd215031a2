//! The Jacobian `F` of the rates (for docs/model.md eq. (19)), analytic, in both attitude
//! variants (docs/model.md eqs. (8), (9) and (45)-(48)), with the effects' partials.

use super::PlatformModel;
use crate::attitude::{exact_jacobian, Attitude, Rotation};
use crate::earth::WIE;
use crate::effect::Partials;
use crate::kinematics::Kinematics;
use crate::state::*;

impl PlatformModel {
    /// The rate Jacobian `F` (`NAV_DIM` rows `stride >= dim` apart) given the kinematics.
    // Inlined for the same reason as `nav_rates`: `k` then stays in registers.
    #[inline(always)]
    pub(super) fn jacobian_with(&self, x: &[f64], k: &Kinematics, jac: &mut [f64], stride: usize) {
        if self.attitude == Attitude::Exact {
            let terms = self.platform_terms(x, k);
            self.exact_jacobian_with(x, k, &terms, &Rotation::new(k.phi), jac, stride);
            return;
        }
        assert!(stride >= self.dim);
        let n = stride;
        zero(&mut jac[..NAV_DIM * n]);
        let [fx, fy, fz] = k.f;
        let [px, py, pz] = k.phi;
        let [w1, w2, w3] = k.w_cmd;
        // d(w_cmd)/dL.
        let dw1_dl = -k.v_y * k.d_inv_rm;
        let dw2_dl = -WIE * k.sin_l + k.v_x * k.d_inv_rn;
        let dw3_dl = WIE * k.cos_l + k.v_x * k.d_tan_over_rn;
        // Each base partial is written once onto the zeros, through row slices at least
        // BASE_DIM long (so with no bounds checks left).
        assert!(n >= BASE_DIM);
        {
            let mut rows = jac[..NAV_DIM * n].chunks_exact_mut(n);
            let row: &mut [&mut [f64]; NAV_DIM] =
                &mut std::array::from_fn(|_| rows.next().expect("NAV_DIM rows"));
            // phi_x' = py w3 - pz w2 + eps_x
            row[PHI_X][PHI_Y] = w3;
            row[PHI_X][PHI_Z] = -w2;
            row[PHI_X][V_X] = py * k.tan_over_rn - pz * k.inv_rn;
            row[PHI_X][LAT] = py * dw3_dl - pz * dw2_dl;
            // phi_y' = pz w1 - px w3 + eps_y
            row[PHI_Y][PHI_X] = -w3;
            row[PHI_Y][PHI_Z] = w1;
            row[PHI_Y][V_X] = -px * k.tan_over_rn;
            row[PHI_Y][V_Y] = -pz * k.inv_rm;
            row[PHI_Y][LAT] = pz * dw1_dl - px * dw3_dl;
            // phi_z' = px w2 - py w1 + eps_z
            row[PHI_Z][PHI_X] = w2;
            row[PHI_Z][PHI_Y] = -w1;
            row[PHI_Z][V_X] = px * k.inv_rn;
            row[PHI_Z][V_Y] = py * k.inv_rm;
            row[PHI_Z][LAT] = px * dw2_dl - py * dw1_dl;
            for a in 0..3 {
                row[PHI_X + a][KG0X + 3 * a] = 1.0;
                row[PHI_X + a][KG11X + 3 * a] = fx;
                row[PHI_X + a][KG12X + 3 * a] = fy;
            }
            // v_x' = coriolis v_y + Ka0x + Ka1x fx + fx + fy pz - fz py
            row[V_X][PHI_Z] = fy;
            row[V_X][PHI_Y] = -fz;
            row[V_X][KA0X] = 1.0;
            row[V_X][KA1X] = fx;
            // v_y' = -coriolis v_x + Ka0y + Ka1y fy + fy + fz px - fx pz
            row[V_Y][PHI_X] = fz;
            row[V_Y][PHI_Z] = -fx;
            row[V_Y][KA0Y] = 1.0;
            row[V_Y][KA1Y] = fy;
            for (r, col, v) in transport_partials(k) {
                row[r][col] = v;
            }
        }
        self.add_effect_rate_partials(x, k, jac, n);
    }

    /// The exact variant's rate Jacobian, given the platform terms and the rotation at `x`.
    #[inline(always)]
    pub(super) fn exact_jacobian_with(
        &self,
        x: &[f64],
        k: &Kinematics,
        terms: &[f64; NAV_DIM],
        rot: &Rotation<f64>,
        jac: &mut [f64],
        stride: usize,
    ) {
        assert!(stride >= self.dim);
        let n = stride;
        zero(&mut jac[..NAV_DIM * n]);
        // The effects' partials of the platform terms first: the variant maps them.
        self.add_effect_rate_partials(x, k, jac, n);
        let transport = transport_partials(k);
        exact_jacobian(k, terms, rot, &transport, self.has_rate_effects(), jac, n);
    }

    /// Adds the rate effects' partials (of their platform terms) to the `NAV_DIM` rows `n`
    /// apart in `jac`.
    #[inline(always)]
    pub(super) fn add_effect_rate_partials(
        &self,
        x: &[f64],
        k: &Kinematics,
        jac: &mut [f64],
        n: usize,
    ) {
        if self.has_rate_effects() {
            let mut p = Partials::new(&mut jac[..NAV_DIM * n], n);
            let k = *k; // a copy, as in `nav_rates`
            for t in &self.linear_rates {
                t.add_partials(x, &k, &mut p);
            }
            for &i in &self.rate_effects {
                let c = self.effect_coeffs(i, x);
                self.effects[i].add_rate_partials(&k, c, self.offsets[i], &mut p);
            }
        }
    }
}

/// Zeroes `a` as a `memset` of whole 64-byte lines and a short tail. A `memset` whose end is
/// not on a 64-byte line finishes with stores that straddle two lines; with AVX-512 stores
/// that stalled: the EKF's 7 x 20 rows (1120 bytes) took 6 % of its step in the portable
/// build, against 2 % for the native build's 7 x 24 (1344 bytes, whole lines).
#[inline(always)]
fn zero(a: &mut [f64]) {
    let (lines, tail) = a.split_at_mut(a.len() / 8 * 8);
    lines.fill(0.0);
    for v in tail {
        *v = 0.0;
    }
}

/// The partials both attitude variants share, as `(row, column, value)`: the Coriolis and
/// transport terms of the velocity rows (`+-(2 wie sinL + v_x tanL/RN) v`) and the position
/// rows (`L' = v_y/RM`, `lambda' = v_x/(RN cosL)`), docs/model.md eqs. (9), (10).
#[inline(always)]
pub(super) fn transport_partials(k: &Kinematics) -> [(usize, usize, f64); 9] {
    let (vx, vy) = (k.v_x, k.v_y);
    let coriolis = 2.0 * WIE * k.sin_l + vx * k.tan_over_rn;
    let dcor_dl = 2.0 * WIE * k.cos_l + vx * k.d_tan_over_rn;
    // d/dL (1/(RN cosL)) = d_inv_rn / cosL + tanL / (RN cosL)
    let sec = k.inv_cos;
    [
        (V_X, V_X, k.tan_over_rn * vy),
        (V_X, V_Y, coriolis),
        (V_X, LAT, dcor_dl * vy),
        (V_Y, V_X, -coriolis - k.tan_over_rn * vx),
        (V_Y, LAT, -dcor_dl * vx),
        (LAT, V_Y, k.inv_rm),
        (LAT, LAT, vy * k.d_inv_rm),
        (LON, V_X, k.inv_rn * sec),
        (LON, LAT, vx * sec * (k.d_inv_rn + k.inv_rn * k.tan_l)),
    ]
}
