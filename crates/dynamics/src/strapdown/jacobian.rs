//! The strapdown rates' Jacobian written out, for the EKF's tangent at every RK4 stage:
//! `d(rates)/dX` of docs/model.md eqs. (51)-(58), `NAV_DIM x BASE_DIM`, row-major.
//!
//! The same Jacobian is the rates on dual numbers ([`super::rates::nav_rate_jacobian`]),
//! exact and from the one source; that one is the check (the tests hold the two within
//! rounding), this one the speed: the dual evaluation carries 13 derivatives through every
//! operation, which made the EKF's strapdown step 3x the platform's.
//!
//! With `u = D w_nb` the forward-right-down body rate and `E` the Z-Y-X angle-rate matrix of
//! docs/model.md eqs. (54), (55), the angle rates are `E u`, `w_nb = w - C^T w_in`, and the
//! velocity rates `C f` plus the Coriolis and transport terms. The derivatives of `C` are
//! those of its three rotations, `dRz/dpsi = Rz K_z` and alike (`K` the cross-product
//! matrices of the axes).

use super::attitude::angle_trig;
use super::rates::ImuReading;
use super::state::*;
use crate::earth::{meridian_radius, prime_vertical_radius, FLATTENING, RE, WIE};

type M3 = [[f64; 3]; 3];

fn mul(a: &M3, b: &M3) -> M3 {
    std::array::from_fn(|i| std::array::from_fn(|j| (0..3).map(|k| a[i][k] * b[k][j]).sum()))
}

/// A North-East-Down / forward-right-down matrix in East-North-Up rows and forward-left-up
/// columns (docs/model.md eq. (49): `T m D`).
fn enu_flu(m: &M3) -> M3 {
    [
        [m[1][0], -m[1][1], -m[1][2]],
        [m[0][0], -m[0][1], -m[0][2]],
        [-m[2][0], m[2][1], m[2][2]],
    ]
}

fn t_mul(c: &M3, a: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|i| c[0][i] * a[0] + c[1][i] * a[1] + c[2][i] * a[2])
}

fn mul_v(c: &M3, a: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|i| c[i][0] * a[0] + c[i][1] * a[1] + c[i][2] * a[2])
}

/// Writes `d(nav_rates)/dx` at `x` under `imu` into `jac` (`NAV_DIM x BASE_DIM`, row-major).
/// Inlined into [`super::tangent::rate_jacobian`], and so into both copies of
/// [`crate::dispatch!`].
#[inline(always)]
pub fn nav_rate_jacobian_analytic(x: &[f64], imu: &ImuReading, jac: &mut [f64]) {
    let trig = angle_trig([x[ROLL], x[PITCH], x[HEADING]]);
    let lat = crate::trig::sin_cos_angle(x[LAT]);
    nav_rate_jacobian_with(x, imu, &trig, lat, jac, BASE_DIM);
}

/// [`nav_rate_jacobian_analytic`] with the sines and cosines of the angles and of the
/// latitude already evaluated (shared with the rates at the same point), its rows `stride >=
/// BASE_DIM` apart in `jac` (padding zeroed), as the EKF's tangent lays them out. Inlined, so
/// that the EKF's copy for the CPU ([`crate::instruction_set`]) compiles it too.
#[inline(always)]
pub fn nav_rate_jacobian_with(
    x: &[f64],
    imu: &ImuReading,
    trig: &[(f64, f64); 3],
    (sl, cl): (f64, f64),
    jac: &mut [f64],
    stride: usize,
) {
    assert!(stride >= BASE_DIM && jac.len() >= NAV_DIM * stride);
    jac[..NAV_DIM * stride].fill(0.0);
    let [(sf, cf), (st, ct), (sp, cp)] = *trig;
    let rx: M3 = [[1.0, 0.0, 0.0], [0.0, cf, -sf], [0.0, sf, cf]];
    let ry: M3 = [[ct, 0.0, st], [0.0, 1.0, 0.0], [-st, 0.0, ct]];
    let rz: M3 = [[cp, -sp, 0.0], [sp, cp, 0.0], [0.0, 0.0, 1.0]];
    let kx: M3 = [[0.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]];
    let ky: M3 = [[0.0, 0.0, 1.0], [0.0, 0.0, 0.0], [-1.0, 0.0, 0.0]];
    let kz: M3 = [[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 0.0]];
    let zy = mul(&rz, &ry);
    let r = mul(&zy, &rx);
    let c = enu_flu(&r);
    let dc = [
        enu_flu(&mul(&zy, &mul(&rx, &kx))),
        enu_flu(&mul(&mul(&rz, &mul(&ry, &ky)), &rx)),
        enu_flu(&mul(&mul(&rz, &kz), &mul(&ry, &rx))),
    ];
    let w: [f64; 3] = std::array::from_fn(|i| imu.w[i] - x[BG_X + i]);
    let f: [f64; 3] = std::array::from_fn(|i| imu.f[i] - x[BA_X + i]);
    let (v_e, v_n) = (x[V_E], x[V_N]);
    let (rm, rn) = (meridian_radius(sl), prime_vertical_radius(sl));
    let tl = sl / cl;
    // d RM / dL and d RN / dL.
    let drm = 6.0 * RE * FLATTENING * sl * cl;
    let drn = 2.0 * RE * FLATTENING * sl * cl;
    let d_inv_rm = -drm / (rm * rm);
    let d_inv_rn = -drn / (rn * rn);
    let d_tan_rn = 1.0 / (cl * cl * rn) + tl * d_inv_rn;
    let w_in = [-v_n / rm, WIE * cl + v_e / rn, WIE * sl + v_e * tl / rn];
    // d w_in / d(v_e, v_n, L).
    let dw_in: [[f64; 3]; 3] = [
        [0.0, 1.0 / rn, tl / rn],
        [-1.0 / rm, 0.0, 0.0],
        [
            -v_n * d_inv_rm,
            -WIE * sl + v_e * d_inv_rn,
            WIE * cl + v_e * d_tan_rn,
        ],
    ];
    let w_in_b = t_mul(&c, w_in);
    let w_nb = [w[0] - w_in_b[0], w[1] - w_in_b[1], w[2] - w_in_b[2]];
    let u = [w_nb[0], -w_nb[1], -w_nb[2]];
    let (tt, sec) = (st / ct, 1.0 / ct);
    let e: M3 = [
        [1.0, sf * tt, cf * tt],
        [0.0, cf, -sf],
        [0.0, sf * sec, cf * sec],
    ];
    let de_droll: M3 = [
        [0.0, cf * tt, -sf * tt],
        [0.0, -sf, -cf],
        [0.0, cf * sec, -sf * sec],
    ];
    let de_dpitch: M3 = [
        [0.0, sf * sec * sec, cf * sec * sec],
        [0.0, 0.0, 0.0],
        [0.0, sf * tt * sec, cf * tt * sec],
    ];
    // E D: the angle rates per unit of w_nb.
    let ed: M3 = std::array::from_fn(|i| [e[i][0], -e[i][1], -e[i][2]]);
    let set = |jac: &mut [f64], r: usize, col: usize, v: f64| jac[r * stride + col] = v;
    // Angle rows: through E (roll, pitch) and through w_nb (every angle, v, L, bg).
    for (a, col) in [ROLL, PITCH, HEADING].into_iter().enumerate() {
        let d_wnb = t_mul(&dc[a], w_in).map(|v| -v);
        let through = mul_v(&ed, d_wnb);
        let direct = match a {
            0 => mul_v(&de_droll, u),
            1 => mul_v(&de_dpitch, u),
            _ => [0.0; 3],
        };
        for row in 0..3 {
            set(jac, row, col, through[row] + direct[row]);
        }
    }
    for (k, col) in [V_E, V_N, LAT].into_iter().enumerate() {
        let d_wnb = t_mul(&c, dw_in[k]).map(|v| -v);
        let through = mul_v(&ed, d_wnb);
        for row in 0..3 {
            set(jac, row, col, through[row]);
        }
    }
    for i in 0..3 {
        for row in 0..3 {
            set(jac, row, BG_X + i, -ed[row][i]);
        }
    }
    // Velocity rows: C f and the Coriolis and transport terms.
    for (a, col) in [ROLL, PITCH, HEADING].into_iter().enumerate() {
        let d = mul_v(&dc[a], f);
        set(jac, V_E, col, d[0]);
        set(jac, V_N, col, d[1]);
    }
    for i in 0..3 {
        set(jac, V_E, BA_X + i, -c[0][i]);
        set(jac, V_N, BA_X + i, -c[1][i]);
    }
    let turn = 2.0 * WIE * sl + v_e * tl / rn;
    let dturn_dve = tl / rn;
    let dturn_dl = 2.0 * WIE * cl + v_e * d_tan_rn;
    set(jac, V_E, V_E, dturn_dve * v_n);
    set(jac, V_E, V_N, turn);
    set(jac, V_E, LAT, dturn_dl * v_n);
    set(jac, V_N, V_E, -(dturn_dve * v_e + turn));
    set(jac, V_N, LAT, -dturn_dl * v_e);
    // Position rows.
    set(jac, LAT, V_N, 1.0 / rm);
    set(jac, LAT, LAT, v_n * d_inv_rm);
    set(jac, LON, V_E, 1.0 / (rn * cl));
    set(jac, LON, LAT, v_e * (d_inv_rn / cl + sl / (rn * cl * cl)));
}
