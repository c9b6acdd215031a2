//! The strapdown state equations, docs/model.md eqs. (51)-(58), written once over
//! [`Real`]: one state on `f64`, eight sigma points on [`crate::real::Lanes`], and their
//! exact Jacobian on [`Dual`] numbers ([`nav_rate_jacobian`]), which checks the written-out
//! one the EKF runs ([`super::jacobian`]).

use super::attitude::{angle_trig, body_to_nav_of, euler_rates_of, rotate, rotate_back};
use super::state::*;
use crate::dual::Dual;
use crate::earth::{meridian_radius, prime_vertical_radius, WIE};
use crate::kinematics::Input;
use crate::real::Real;

/// One reading of the unit, body (forward-left-up) axes: rate `w` (rad/s, relative to
/// inertial space) and specific force `f` (m/s^2), as `imu.csv` holds them.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ImuReading {
    /// Body rate, rad/s.
    pub w: [f64; 3],
    /// Specific force, m/s^2.
    pub f: [f64; 3],
}

/// The unit's reading held in an input sample (body rate in the first three numbers, specific force in the next three).
pub fn imu_of(u: &Input) -> ImuReading {
    ImuReading {
        w: [u[0], u[1], u[2]],
        f: [u[3], u[4], u[5]],
    }
}

/// An input sample holding the unit's reading.
pub fn input_of(imu: &ImuReading) -> Input {
    [imu.w[0], imu.w[1], imu.w[2], imu.f[0], imu.f[1], imu.f[2]]
}

/// Writes the derivatives of the [`NAV_DIM`] navigation states of `x` (the base states at
/// least) under `imu`: docs/model.md eqs. (51)-(58) with no error matrices (the base model).
#[inline(always)]
pub fn nav_rates<T: Real>(x: &[T], imu: &ImuReading, dx: &mut [T]) {
    let trig = angle_trig([x[ROLL], x[PITCH], x[HEADING]]);
    nav_rates_with(x, imu, &trig, x[LAT].sin_cos(), dx);
}

/// [`nav_rates`] with the sines and cosines of the angles ([`angle_trig`]) and of the
/// latitude already evaluated (the EKF shares them with the Jacobian).
#[inline(always)]
pub fn nav_rates_with<T: Real>(
    x: &[T],
    imu: &ImuReading,
    trig: &[(T, T); 3],
    (sin_l, cos_l): (T, T),
    dx: &mut [T],
) {
    let c = |v: f64| T::splat(v);
    // docs/model.md eq. (51): the readings corrected by the biases.
    let w: [T; 3] = std::array::from_fn(|i| c(imu.w[i]) - x[BG_X + i]);
    let f: [T; 3] = std::array::from_fn(|i| c(imu.f[i]) - x[BA_X + i]);
    nav_rates_corrected(x, w, f, trig, (sin_l, cos_l), dx);
}

/// The navigation states' derivatives under the true body rate `w` and specific force `f`
/// (the readings already corrected: docs/model.md eqs. (52)-(58)).
#[inline(always)]
pub fn nav_rates_corrected<T: Real>(
    x: &[T],
    w: [T; 3],
    f: [T; 3],
    trig: &[(T, T); 3],
    (sin_l, cos_l): (T, T),
    dx: &mut [T],
) {
    let (v_e, v_n) = (x[V_E], x[V_N]);
    let [inv_rm, inv_rn, inv_cos] =
        T::reciprocals(meridian_radius(sin_l), prime_vertical_radius(sin_l), cos_l);
    let tan_l = sin_l * inv_cos;
    let cbn = body_to_nav_of(trig);
    // docs/model.md eqs. (52), (53): the rate of n relative to inertial space, taken out in body axes.
    let w_in = [
        -(v_n * inv_rm),
        cos_l * WIE + v_e * inv_rn,
        sin_l * WIE + v_e * tan_l * inv_rn,
    ];
    let w_in_b = rotate_back(&cbn, w_in);
    let w_nb = [w[0] - w_in_b[0], w[1] - w_in_b[1], w[2] - w_in_b[2]];
    // docs/model.md eqs. (54), (55).
    let angle_rates = euler_rates_of(trig, w_nb);
    // docs/model.md eqs. (56), (57).
    let f_n = rotate(&cbn, f);
    let turn = sin_l * (2.0 * WIE) + v_e * tan_l * inv_rn;
    dx[ROLL] = angle_rates[0];
    dx[PITCH] = angle_rates[1];
    dx[HEADING] = angle_rates[2];
    dx[V_E] = f_n[0] + turn * v_n;
    dx[V_N] = f_n[1] - turn * v_e;
    // docs/model.md eq. (58).
    dx[LAT] = v_n * inv_rm;
    dx[LON] = v_e * inv_rn * inv_cos;
}

/// Writes `d(nav_rates)/dx`, row-major `NAV_DIM x BASE_DIM`, at `x` (the [`BASE_DIM`] base
/// states): [`nav_rates`] evaluated on dual numbers, exact to rounding.
pub fn nav_rate_jacobian(x: &[f64], imu: &ImuReading, jac: &mut [f64]) {
    let xd: [Dual<BASE_DIM>; BASE_DIM] = std::array::from_fn(|i| Dual::variable(x[i], i));
    let mut dx = [Dual::<BASE_DIM>::constant(0.0); NAV_DIM];
    nav_rates(&xd, imu, &mut dx);
    for (r, row) in dx.iter().enumerate() {
        jac[r * BASE_DIM..(r + 1) * BASE_DIM].copy_from_slice(&row.d);
    }
}
