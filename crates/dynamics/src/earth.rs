//! Earth constants, radii of curvature (the paper's section 2.2) and normal gravity:
//! docs/model.md eqs. (1)-(4).
//!
//! `RM = Re (1 - 2f + 3f sin^2 L)` is the meridian radius and `RN = Re (1 + f sin^2 L)` the
//! prime-vertical radius: the paper's first-order forms, kept exactly so that the truth
//! simulator and every filter use one Earth.

use crate::real::Real;

/// Equatorial radius `Re`, metres (docs/model.md eq. (1), as are the next two).
pub const RE: f64 = 6_378_137.0;
/// Flattening `f`.
pub const FLATTENING: f64 = 1.0 / 298.257;
/// Earth rotation rate `wie`, rad/s.
pub const WIE: f64 = 7.292_115e-5;
/// Standard gravity, m/s^2 (the conventional `g`, CGPM 1901): the unit in which accelerometer
/// errors are quoted (micro-g, mg, per g), not the local gravity the model computes.
pub const STANDARD_GRAVITY: f64 = 9.806_65;

/// Meridian radius of curvature `RM` from `sin L`: docs/model.md eq. (2).
#[inline(always)]
pub fn meridian_radius<T: Real>(sin_lat: T) -> T {
    // RE (1 - 2f + 3f sin^2 L), written so that every product rounds as in that order.
    (sin_lat * (3.0 * FLATTENING) * sin_lat + (1.0 - 2.0 * FLATTENING)) * RE
}

/// Prime-vertical radius of curvature `RN` from `sin L`: docs/model.md eq. (3).
#[inline(always)]
pub fn prime_vertical_radius<T: Real>(sin_lat: T) -> T {
    // RE (1 + f sin^2 L).
    (sin_lat * FLATTENING * sin_lat + 1.0) * RE
}

/// Normal gravity at the ellipsoid surface (Somigliana's series, WGS-84 coefficients), m/s^2:
/// docs/model.md eq. (4).
///
/// The model needs gravity only as the level platform's vertical specific force `fz`; the
/// trajectory uses it so that `fz` is what a real platform would read at that latitude.
///
/// ```
/// let g = navkf_dynamics::earth::normal_gravity(45f64.to_radians().sin());
/// assert!((g - 9.8062).abs() < 1e-3);
/// ```
#[inline]
pub fn normal_gravity(sin_lat: f64) -> f64 {
    let s2 = sin_lat * sin_lat;
    9.780_325_335_9 * (1.0 + 0.001_931_852_652_41 * s2) / (1.0 - 0.006_694_379_990_14 * s2).sqrt()
}
