//! The base model integrated with `propagate_generic` in cases with a known solution.
//!
//! Windows are 100 knots one second apart, built with `InputWindow::push_linear` (or
//! `push_with_mid` where the input varies). Where the solution is a polynomial in time of
//! degree <= 4, RK4 reproduces it exactly and the checks are to rounding.

use crate::common;

use common::*;
use navkf_dynamics::earth::{
    meridian_radius, normal_gravity, prime_vertical_radius, FLATTENING, RE, WIE,
};
use navkf_dynamics::effects::GyroBiasWalk;
use navkf_dynamics::state::*;
use navkf_dynamics::{InputWindow, NoiseConfig, PlatformModel, SystemModel};

const T: f64 = 100.0;
const H: f64 = 1.0;
const LON0: f64 = 2.2;
/// Rounding accumulated on a longitude of ~2 rad over 100 RK4 steps: one ulp per step.
const LON_ROUNDING: f64 = (T / H) * f64::EPSILON * LON0;

fn base() -> PlatformModel {
    PlatformModel::base(&NoiseConfig::default())
}

fn assert_close(what: &str, got: f64, want: f64, tol: f64) {
    assert!(
        (got - want).abs() <= tol,
        "{what}: got {got:e}, want {want:e}, |diff| {:e} > {tol:e}",
        (got - want).abs()
    );
}

/// (a) At rest on the equator with only `Ka0x`: `sin L = 0`, so there is no Coriolis
/// coupling and `v_x' = Ka0x` exactly; `v_y`, `L` and the attitude stay exactly zero, and
/// `lambda` advances by `Ka0x T^2 / (2 RN)`.
/// Catches: the accelerometer bias entering the wrong axis, with a wrong sign or gain; a
/// Coriolis term that does not vanish at the equator; a wrong radius in `lambda'`.
#[test]
fn accel_bias_at_rest_on_equator_grows_v_x_at_ka0x() {
    let model = base();
    let a = 5e-4;
    let mut x = rest_state(model.dim(), 0.0, LON0);
    x[KA0X] = a;
    let g = normal_gravity(0.0);
    propagate(&model, &mut x, None, &constant_window([0.0, 0.0, g], H, T));
    assert_close("v_x", x[V_X], a * T, 1e-14 * a * T);
    for (i, name) in [(PHI_X, "phi_x"), (PHI_Y, "phi_y"), (PHI_Z, "phi_z")] {
        assert_eq!(x[i], 0.0, "{name} must stay zero");
    }
    assert_eq!(x[V_Y], 0.0, "v_y: no Coriolis at the equator");
    assert_eq!(x[LAT], 0.0, "L must stay zero");
    let dlon = a * T * T / (2.0 * prime_vertical_radius(0.0));
    assert_close(
        "lambda - lambda0",
        x[LON] - LON0,
        dlon,
        1e-12 * dlon + LON_ROUNDING,
    );
    assert_eq!(x[KA0X], a, "coefficients are constant");
}

/// (a) At rest at 45 deg with only `Ka0x = a`: the velocity turns under the Coriolis term
/// `Omega = 2 wie sin L`, `v_x' = Omega v_y + a`, `v_y' = -Omega v_x`, whose solution is
/// `v_x = (a/Omega) sin(Omega t)`, `v_y = (a/Omega)(cos(Omega t) - 1)`. The transport part
/// `v_x tanL/RN` of the Coriolis factor adds, to first order in `tau = tanL/RN`,
/// `dv_y = -tau a^2 t^3/3` and `dv_x = -(5/24) Omega tau a^2 t^4` (1.3e-8 and 8e-11 m/s here),
/// included; what remains is ~1e-12 m/s (relative (Omega t)^2 ~ 1e-4 of those terms;
/// `L` moves by ~1e-12 rad).
/// Catches: a wrong sign or a missing factor 2 of the Coriolis term (v_y off by ~1e-4 m/s),
/// a missing or wrong transport term (1.3e-8 m/s), a wrong bias gain.
#[test]
fn accel_bias_at_rest_at_45_deg_turns_with_coriolis() {
    let model = base();
    let a = 5e-4;
    let lat = 45f64.to_radians();
    let mut x = rest_state(model.dim(), lat, LON0);
    x[KA0X] = a;
    let (s, c) = lat.sin_cos();
    let g = normal_gravity(s);
    propagate(&model, &mut x, None, &constant_window([0.0, 0.0, g], H, T));
    let om = 2.0 * WIE * s;
    let tau = s / c / prime_vertical_radius(s);
    let vx = a / om * (om * T).sin() - 5.0 / 24.0 * om * tau * a * a * T.powi(4);
    let vy = a / om * ((om * T).cos() - 1.0) - tau * a * a * T.powi(3) / 3.0;
    assert_close("v_x", x[V_X], vx, 1e-13);
    assert_close("v_y", x[V_Y], vy, 2e-12);
    // The Coriolis coupling is visible: v_y is -a Omega T^2 / 2 ~ -2.6e-4 m/s.
    assert!(x[V_Y] < -2e-4, "v_y = {}", x[V_Y]);
    for i in [PHI_X, PHI_Y, PHI_Z] {
        assert_eq!(x[i], 0.0, "attitude must stay zero without drift");
    }
}

/// (b) A constant north-gyro drift `Kg0y = e` at rest on the equator: `phi_y = e t`,
/// `v_x = -g e t^2/2`, `lambda - lambda0 = -g e t^3 / (6 RN)`; the other states stay zero
/// (at L = 0 the Earth-rate couplings that could move them are `wie sin L = 0` and `v_y/RM`
/// with `v_y = 0`). Polynomials of degree <= 3: RK4 is exact.
/// Catches: the drift on the wrong axis or with a wrong sign, a wrong sign or a missing `g`
/// in the `-fz phi_y` tilt term, a cross-coupling that should vanish at the equator.
#[test]
fn north_gyro_drift_on_equator_tilts_phi_y_and_accelerates_v_x() {
    let model = base();
    let e = 1e-7;
    let mut x = rest_state(model.dim(), 0.0, LON0);
    x[KG0Y] = e;
    let g = normal_gravity(0.0);
    propagate(&model, &mut x, None, &constant_window([0.0, 0.0, g], H, T));
    assert_close("phi_y", x[PHI_Y], e * T, 1e-14 * e * T);
    let vx = -g * e * T * T / 2.0;
    assert_close("v_x", x[V_X], vx, 1e-13 * vx.abs());
    let dlon = -g * e * T.powi(3) / (6.0 * prime_vertical_radius(0.0));
    assert_close(
        "lambda - lambda0",
        x[LON] - LON0,
        dlon,
        1e-12 * dlon.abs() + LON_ROUNDING,
    );
    for (i, name) in [(PHI_X, "phi_x"), (PHI_Z, "phi_z"), (V_Y, "v_y"), (LAT, "L")] {
        assert_eq!(x[i], 0.0, "{name} must stay zero on the equator");
    }
}

/// (b) The same drift at 45 deg. To first order in the Earth rate (`W3 = wie sin L`,
/// `W2 = wie cos L`, `Omega = 2 W3`):
/// `phi_y = e t`, `phi_x = W3 e t^2/2`, `phi_z = W2 W3 e t^3/6`, `v_x = -g e t^2/2`,
/// `v_y = g e (W3 + Omega) t^3/6 = g e W3 t^3/2`.
/// The next terms are relative `(W3 t)^2/6`, `(W2 t)^2/12`, `Omega W3 t^2/4`, ... all below
/// `(wie T)^2 = 5.3e-5`, the bound used (velocity-dependent terms `v/R` are ~1e-9 smaller).
/// Catches: a wrong sign of any Earth-rate attitude coupling (phi_x, phi_z flip), of the
/// Coriolis term or of the `fz phi_x` tilt term in `v_y'` (v_y off by 1/3 or more).
#[test]
fn north_gyro_drift_at_45_deg_within_earth_rate_bounds() {
    let model = base();
    let e = 1e-7;
    let lat = 45f64.to_radians();
    let mut x = rest_state(model.dim(), lat, LON0);
    x[KG0Y] = e;
    let (s, c) = lat.sin_cos();
    let g = normal_gravity(s);
    propagate(&model, &mut x, None, &constant_window([0.0, 0.0, g], H, T));
    let (w2, w3) = (WIE * c, WIE * s);
    let rel = (WIE * T).powi(2);
    let want = [
        ("phi_y", PHI_Y, e * T),
        ("phi_x", PHI_X, w3 * e * T * T / 2.0),
        ("phi_z", PHI_Z, w2 * w3 * e * T.powi(3) / 6.0),
        ("v_x", V_X, -g * e * T * T / 2.0),
        ("v_y", V_Y, g * e * w3 * T.powi(3) / 2.0),
    ];
    for (name, i, v) in want {
        assert_close(name, x[i], v, rel * v.abs());
    }
}

/// `L(t)` and its first two time derivatives' coefficients for a constant velocity:
/// returns `(L(t), lambda(t))` to second order in `t`.
fn positions_second_order(lat0: f64, lon0: f64, vx: f64, vy: f64, t: f64) -> (f64, f64) {
    let (s, c) = lat0.sin_cos();
    let rm = meridian_radius(s);
    let rn = prime_vertical_radius(s);
    // d(1/RM)/dL = -dRM/dL / RM^2, dRM/dL = 6 Re f sinL cosL.
    let d_inv_rm = -6.0 * RE * FLATTENING * s * c / (rm * rm);
    // g = 1/(RN cosL), dg/dL = (RN sinL - dRN/dL cosL) / (RN cosL)^2, dRN/dL = 2 Re f sinL cosL.
    let drn = 2.0 * RE * FLATTENING * s * c;
    let gl = 1.0 / (rn * c);
    let dgl = (rn * s - drn * c) / (rn * c).powi(2);
    let l_dot = vy / rm;
    let lat = lat0 + l_dot * t + 0.5 * vy * d_inv_rm * l_dot * t * t;
    let lon = lon0 + vx * gl * t + 0.5 * vx * dgl * l_dot * t * t;
    (lat, lon)
}

/// (c) Positions follow velocities. The vehicle moves at constant `v = (vx, vy)`: the input
/// cancels the Coriolis term exactly (`fx = -c(L) vy`, `fy = c(L) vx`, `c = 2 wie sinL +
/// vx tanL/RN`, evaluated along the expected latitude, midpoints exact), attitude and
/// coefficients are zero. Then `L' = vy/RM(L)`, `lambda' = vx/(RN(L) cosL)`, and to second
/// order `L(T) = L0 + vy T/RM + (1/2) vy^2 d(1/RM)/dL T^2 / RM`, similarly for lambda.
/// Third-order remainders: `(T^3/6) vx g'' L'^2 ~ 2e-11 rad` for lambda, below 1e-13 rad for
/// L (`d^2(1/RM)/dL^2` is of order f/RM); tolerances are 1e-10 and 3e-13 rad.
/// Catches: RM and RN swapped (1e-6 rad), a missing sec L (1e-4 rad), a wrong sign, a
/// missing latitude dependence of the radii (second-order terms: 5e-13 and 7e-8 rad).
#[test]
fn positions_follow_constant_velocities() {
    let model = base();
    for &(vx, vy) in &[(20.0, 15.0), (-12.0, 20.0), (18.0, -20.0), (-20.0, -7.0)] {
        let lat0 = 45f64.to_radians();
        let mut x = rest_state(model.dim(), lat0, LON0);
        x[V_X] = vx;
        x[V_Y] = vy;
        let force = |t: f64| {
            let (lat, _) = positions_second_order(lat0, LON0, vx, vy, t);
            let (s, c) = lat.sin_cos();
            let cor = 2.0 * WIE * s + vx * s / c / prime_vertical_radius(s);
            [-cor * vy, cor * vx, normal_gravity(s)]
        };
        let mut w = InputWindow::default();
        let n = (T / H) as usize;
        for j in 0..=n {
            let t = j as f64 * H;
            w.push_with_mid(t, force(t), force(t - 0.5 * H));
        }
        propagate(&model, &mut x, None, &w);
        assert_close("v_x constant", x[V_X], vx, 1e-9);
        assert_close("v_y constant", x[V_Y], vy, 1e-9);
        let (lat, lon) = positions_second_order(lat0, LON0, vx, vy, T);
        assert_close("L", x[LAT], lat, 3e-13);
        assert_close("lambda", x[LON], lon, 1e-10);
        // First-order sanity, independent of the expansion: ~2 km in 100 s.
        let north_m = (x[LAT] - lat0) * meridian_radius(lat0.sin());
        assert_close("north distance", north_m, vy * T, 1e-3 * (vy * T).abs());
    }
}

/// (d) Noise: with `gyro-bias-walk`, a noise value `w` on channel `w_bx` held over the
/// window moves `Kg0x` by exactly `w T`, and moves it *within* every RK4 step, so that the
/// attitude integrates the ramp: at rest on the equator `phi_x' = K0 + w t - W2 phi_z`,
/// `phi_z' = W2 phi_x` (W2 = wie), solved by
/// `phi_x = (K0/W2) sin(W2 t) + (w/W2^2)(1 - cos(W2 t))`,
/// `phi_z = (K0/W2)(1 - cos(W2 t)) + (w/W2^2)(W2 t - sin(W2 t))`.
/// The couplings this neglects (through `v_y ~ 1e-2 m/s`, `L ~ 5e-8 rad`) are below 1e-9
/// relative. Catches: a noise channel that misses its state, is scaled (e.g. by `h`), is
/// held at the start-of-step value inside the RK4 stages (phi_x off by ~2e-4 relative), or is
/// applied to the wrong index; also that the other coefficients stay put.
#[test]
fn gyro_bias_walk_noise_adds_w_t_to_kg0x() {
    let model = PlatformModel::new(
        vec![Box::new(GyroBiasWalk::default())],
        &NoiseConfig::default(),
    )
    .unwrap();
    let channels = model.noise_channels();
    assert_eq!(channels.len(), 8);
    let bx = channels.iter().position(|c| c.state == KG0X).unwrap();
    let (k0, w) = (2e-7, 1e-10);
    let mut noise = vec![0.0; channels.len()];
    noise[bx] = w;
    let mut x = rest_state(model.dim(), 0.0, LON0);
    x[KG0X] = k0;
    x[KA0Y] = 1e-4; // a constant that no channel drives must not move
    let g = normal_gravity(0.0);
    propagate(
        &model,
        &mut x,
        Some(&noise),
        &constant_window([0.0, 0.0, g], H, T),
    );
    assert_close("Kg0x", x[KG0X], k0 + w * T, 1e-13 * (k0 + w * T));
    assert_eq!(x[KG0Y], 0.0);
    assert_eq!(x[KG0Z], 0.0);
    assert_eq!(x[KA0Y], 1e-4);
    let om = WIE;
    let (sn, cs) = (om * T).sin_cos();
    let phi_x = k0 / om * sn + w / (om * om) * (1.0 - cs);
    let phi_z = k0 / om * (1.0 - cs) + w / (om * om) * (om * T - sn);
    assert_close("phi_x", x[PHI_X], phi_x, 1e-9 * phi_x.abs());
    assert_close("phi_z", x[PHI_Z], phi_z, 1e-8 * phi_z.abs());
}

/// (d) A noise value on the navigation channel `w_ax` at rest on the equator is an
/// acceleration: `v_x = w T` exactly, nothing else moves but `lambda`.
/// Catches: the navigation noise channels added to the wrong derivative or scaled.
#[test]
fn accel_noise_channel_adds_w_t_to_v_x() {
    let model = base();
    let channels = model.noise_channels();
    let ax = channels.iter().position(|c| c.name == "w_ax").unwrap();
    let mut noise = vec![0.0; channels.len()];
    let w = 3e-4;
    noise[ax] = w;
    let mut x = rest_state(model.dim(), 0.0, LON0);
    let g = normal_gravity(0.0);
    propagate(
        &model,
        &mut x,
        Some(&noise),
        &constant_window([0.0, 0.0, g], H, T),
    );
    assert_close("v_x", x[V_X], w * T, 1e-14 * w * T);
    for i in [PHI_X, PHI_Y, PHI_Z, V_Y, LAT] {
        assert_eq!(x[i], 0.0, "state {i}");
    }
    assert!(x[NAV_DIM..].iter().all(|&k| k == 0.0));
}
