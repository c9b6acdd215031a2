//! Roll, pitch and heading: the rotation `C_b^n` they stand for (docs/model.md eq. (49)) and
//! their rates under a body rate (docs/model.md eqs. (53)-(55)), generic over the number type.
//!
//! `C_b^n = T Rz(psi) Ry(theta) Rx(phi) D` is the usual North-East-Down / forward-right-down
//! matrix with its rows taken to East-North-Up (`T`) and its columns to forward-left-up (`D`):
//!
//! ```
//! use navkf_dynamics::strapdown::attitude::body_to_nav;
//! let c = body_to_nav([0.0, 0.0, 90f64.to_radians()]);
//! // Heading East: the forward axis (first column) points East.
//! assert!((c[0][0] - 1.0).abs() < 1e-15 && c[1][0].abs() < 1e-15 && c[2][0].abs() < 1e-15);
//! ```

use crate::real::Real;

/// The sines and cosines of `[roll, pitch, heading]`, evaluated once for both
/// [`body_to_nav_of`] and [`euler_rates_of`].
#[inline(always)]
pub fn angle_trig<T: Real>(euler: [T; 3]) -> [(T, T); 3] {
    // Written out: `array::map`'s closure stayed a call per angle on the batch path.
    [euler[0].sin_cos(), euler[1].sin_cos(), euler[2].sin_cos()]
}

/// `C_b^n` from `[roll, pitch, heading]`: rows East, North, Up; columns forward, left, up.
#[inline(always)]
pub fn body_to_nav<T: Real>(euler: [T; 3]) -> [[T; 3]; 3] {
    body_to_nav_of(&angle_trig(euler))
}

/// [`body_to_nav`] from the angles' sines and cosines ([`angle_trig`]).
#[inline(always)]
pub fn body_to_nav_of<T: Real>(trig: &[(T, T); 3]) -> [[T; 3]; 3] {
    let [(sf, cf), (st, ct), (sp, cp)] = *trig;
    // Rz(psi) Ry(theta) Rx(phi), NED rows and FRD columns.
    let c = [
        [ct * cp, sf * st * cp - cf * sp, cf * st * cp + sf * sp],
        [ct * sp, sf * st * sp + cf * cp, cf * st * sp - sf * cp],
        [-st, sf * ct, cf * ct],
    ];
    // T: East is NED's second row, North its first, Up minus its third. D: left and up are
    // minus right and minus down.
    [
        [c[1][0], -c[1][1], -c[1][2]],
        [c[0][0], -c[0][1], -c[0][2]],
        [-c[2][0], c[2][1], c[2][2]],
    ]
}

/// `C a`.
#[inline(always)]
pub fn rotate<T: Real>(c: &[[T; 3]; 3], a: [T; 3]) -> [T; 3] {
    std::array::from_fn(|i| c[i][0] * a[0] + c[i][1] * a[1] + c[i][2] * a[2])
}

/// `C^T a`.
#[inline(always)]
pub fn rotate_back<T: Real>(c: &[[T; 3]; 3], a: [T; 3]) -> [T; 3] {
    std::array::from_fn(|i| c[0][i] * a[0] + c[1][i] * a[1] + c[2][i] * a[2])
}

/// `[roll', pitch', heading']` under the body rate relative to n, `w_nb` in FLU axes
/// (docs/model.md eqs. (53)-(55)). Singular at pitch +-90 deg.
#[inline(always)]
pub fn euler_rates<T: Real>(euler: [T; 3], w_nb: [T; 3]) -> [T; 3] {
    euler_rates_of(&angle_trig(euler), w_nb)
}

/// [`euler_rates`] from the angles' sines and cosines ([`angle_trig`]).
#[inline(always)]
pub fn euler_rates_of<T: Real>(trig: &[(T, T); 3], w_nb: [T; 3]) -> [T; 3] {
    // Forward-right-down components: D w_nb.
    let (p, q, r) = (w_nb[0], -w_nb[1], -w_nb[2]);
    let [(sf, cf), (st, ct), _] = *trig;
    let inv_ct = T::splat(1.0) / ct;
    let turn = q * sf + r * cf;
    [p + turn * st * inv_ct, q * cf - r * sf, turn * inv_ct]
}

/// `[roll, pitch, heading]` of a rotation `C_b^n` (heading in (-pi, pi]); the inverse of
/// [`body_to_nav`] away from pitch +-90 deg.
pub fn euler_of(c: &[[f64; 3]; 3]) -> [f64; 3] {
    // Back to NED rows and FRD columns: n[i][j] of Rz Ry Rx.
    let ned = [
        [c[1][0], -c[1][1], -c[1][2]],
        [c[0][0], -c[0][1], -c[0][2]],
        [-c[2][0], c[2][1], c[2][2]],
    ];
    let pitch = (-ned[2][0]).clamp(-1.0, 1.0).asin();
    let roll = ned[2][1].atan2(ned[2][2]);
    let heading = ned[1][0].atan2(ned[0][0]);
    [roll, pitch, heading]
}
