//! How the platform error angles enter the model: the paper's small-angle form, or the exact
//! variant for large misalignment (docs/model.md, "Variant: exact attitude").
//!
//! The base model (docs/model.md eqs. (8), (9)) keeps only first-order terms of the rotation
//! between the platform frame p and the navigation frame n: `phi' = phi x w_in + eps`, and
//! the specific force reaches the velocity as `f + nab + f x phi`. That is right for angles of
//! arcminutes; an unaligned platform starts with azimuth errors of degrees, where it is not.
//! The exact variant keeps the same 20 states and measurement, takes `phi` as Euler angles
//! (docs/model.md eqs. (45)-(48)),
//!
//! ```text
//! C_n^p = Ry(phi_y) Rx(phi_x) Rz(phi_z)
//! Om    = (C_n^p - I) w_in + eps                          (Om = -w_np)
//! phi_x' = Om_x cos(phi_y) - Om_z sin(phi_y)
//! phi_z' = (Om_x sin(phi_y) + Om_z cos(phi_y)) / cos(phi_x)
//! phi_y' = Om_y + phi_z' sin(phi_x)
//! [v_x', v_y'] = first two rows of C_p^n (f + nab) + the Coriolis and transport terms
//! ```
//!
//! Effects contribute platform-axis errors in both variants: what an effect adds to the
//! `phi` rows of its rates is a gyro error (it joins `eps`), what it adds to the `v` rows an
//! accelerometer error (it joins `nab`), and the variant maps both to the state (the identity
//! for the small-angle form). So every effect works with either, unchanged in meaning.
//!
//! Process noise drives the derivatives of its states directly in both variants: the gyro
//! noise enters `phi'` rather than `Om` (docs/model.md eq. (47)). The two differ by
//! `E(phi) - I` (below), which depends only on the level angles `phi_x`, `phi_y`, and so is
//! of their size (1e-4 rad in the paper's test); the noise itself is a random walk of 1e-7
//! rad/sqrt(s).
//!
//! The rates are generic over [`Real`]: the truth and the EKF evaluate them on `f64`, the UKFs'
//! batches on [`crate::Lanes`], with the same sines ([`crate::trig::sin_cos_angle`]). The EKF's
//! Jacobian ([`exact_jacobian`]) is analytic; `tests/attitude.rs` checks it against finite
//! differences and pins the three checks of docs/model.md, "Variant: exact attitude".

use crate::kinematics::Kinematics;
use crate::real::Real;
use crate::state::*;
use serde::{Deserialize, Serialize};
use std::fmt;
use std::str::FromStr;

/// Which attitude equations a model uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Attitude {
    /// The paper's first-order equations (docs/model.md eqs. (8), (9)).
    #[default]
    SmallAngle,
    /// Euler angles and the exact rotation (docs/model.md eqs. (45)-(48)).
    Exact,
}

impl Attitude {
    /// Every variant, in the order help texts list them.
    pub const ALL: [Attitude; 2] = [Attitude::SmallAngle, Attitude::Exact];

    /// The name written in study files and on command lines.
    pub fn name(self) -> &'static str {
        match self {
            Attitude::SmallAngle => "small-angle",
            Attitude::Exact => "exact",
        }
    }

    /// The largest initial tilt sigma (rad) these equations take.
    ///
    /// The small-angle form keeps `sin x ~ x` and `cos x ~ 1`: the term it drops beside the
    /// first-order one it keeps is `(1 - cos x) / sin x = tan(x/2)`, which reaches a tenth at
    /// `x = 2 atan(0.1)` = 0.199 rad (11.4 deg). Beyond that the model is not an approximation
    /// of the rotation at one sigma (the diagnosis already warns from 0.5 deg, where its EKF
    /// starts to lose consistency in `studies/misalignment.toml`). Euler angles repeat after
    /// half a turn: the exact form takes up to pi.
    pub fn max_tilt_sigma(self) -> f64 {
        match self {
            Attitude::SmallAngle => 2.0 * 0.1f64.atan(),
            Attitude::Exact => std::f64::consts::PI,
        }
    }

    /// Checks an initial tilt sigma `value` given as `key` against
    /// [`Attitude::max_tilt_sigma`]; the error names the key and, for the small-angle form,
    /// says to use the exact one.
    pub fn check_tilt_sigma(self, key: &str, value: f64) -> Result<(), String> {
        let max = self.max_tilt_sigma();
        if value <= max {
            return Ok(());
        }
        Err(match self {
            Attitude::SmallAngle => format!(
                "{key} {value}: beyond what the small-angle model holds ({max:.3} rad = {:.1} \
                 deg, where the term it drops reaches a tenth of the one it keeps); use \
                 --attitude exact for a platform misaligned by more",
                max.to_degrees()
            ),
            Attitude::Exact => {
                format!("{key} {value}: beyond pi; Euler angles repeat after half a turn")
            }
        })
    }
}

impl fmt::Display for Attitude {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Attitude {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        Attitude::ALL
            .into_iter()
            .find(|a| a.name() == s)
            .ok_or_else(|| format!("unknown attitude `{s}`; expected `small-angle` or `exact`"))
    }
}

/// The rotation `C_n^p` at Euler angles `phi`, with what the rates and their partials need.
#[derive(Debug, Clone, Copy)]
pub struct Rotation<T> {
    /// `C_n^p`, row-major: `c[i][j]` is row i, column j.
    pub c: [[T; 3]; 3],
    /// sin and cos of phi_x and phi_y, and 1 / cos(phi_x).
    sx: T,
    cx: T,
    sy: T,
    cy: T,
    inv_cx: T,
}

impl<T: Real> Rotation<T> {
    /// `C_n^p = Ry(phi_y) Rx(phi_x) Rz(phi_z)`: docs/model.md eq. (45).
    #[inline(always)]
    pub fn new(phi: [T; 3]) -> Self {
        let (sx, cx) = phi[0].sin_cos();
        let (sy, cy) = phi[1].sin_cos();
        let (sz, cz) = phi[2].sin_cos();
        // Rx Rz = [[cz, -sz, 0], [cx sz, cx cz, -sx], [sx sz, sx cz, cx]], then Ry on the left.
        let (sxsz, sxcz) = (sx * sz, sx * cz);
        let c = [
            [
                cy.mul_add(cz, sy * sxsz),
                sy.mul_add(sxcz, -(cy * sz)),
                sy * cx,
            ],
            [cx * sz, cx * cz, -sx],
            [
                cy.mul_add(sxsz, -(sy * cz)),
                sy.mul_add(sz, cy * sxcz),
                cy * cx,
            ],
        ];
        Rotation {
            c,
            sx,
            cx,
            sy,
            cy,
            inv_cx: T::splat(1.0) / cx,
        }
    }

    /// `C_n^p v`: a navigation-frame vector in platform axes.
    #[inline(always)]
    pub fn to_platform(&self, v: [T; 3]) -> [T; 3] {
        let c = &self.c;
        // Written out, not by `std::array::from_fn`, whose closure the inliner can leave as a
        // call (see `crate::real`).
        let row = |i: usize| c[i][0].mul_add(v[0], c[i][1].mul_add(v[1], c[i][2] * v[2]));
        [row(0), row(1), row(2)]
    }

    /// `C_p^n a = (C_n^p)^T a`: a platform-axis vector in navigation axes.
    #[inline(always)]
    pub fn to_navigation(&self, a: [T; 3]) -> [T; 3] {
        let c = &self.c;
        let column = |j: usize| c[0][j].mul_add(a[0], c[1][j].mul_add(a[1], c[2][j] * a[2]));
        [column(0), column(1), column(2)]
    }

    /// The Euler-angle rates `(phi_x', phi_y', phi_z')` for the rate `Om`, without the noise:
    /// docs/model.md eq. (47).
    #[inline(always)]
    pub fn euler_rates(&self, om: [T; 3]) -> [T; 3] {
        let dx = om[0].mul_add(self.cy, -(om[2] * self.sy));
        let dz = om[0].mul_add(self.sy, om[2] * self.cy) * self.inv_cx;
        let dy = dz.mul_add(self.sx, om[1]);
        [dx, dy, dz]
    }
}

/// The exact variant's navigation-state derivatives, docs/model.md eqs. (46)-(48), (10).
/// `terms` holds, in the rate rows' places, the platform terms:
/// `[eps_x, eps_y, eps_z, nab_x, nab_y, L', lambda']` (the base coefficients' plus every
/// effect's; see the module documentation).
#[inline(always)]
pub fn exact_rates<T: Real>(k: &Kinematics<T>, terms: &[T; NAV_DIM]) -> [T; NAV_DIM] {
    exact_rates_with(k, terms, &Rotation::new(k.phi))
}

/// [`exact_rates`] with the rotation at `k.phi` already built (the EKF shares it with the
/// Jacobian).
#[inline(always)]
pub fn exact_rates_with<T: Real>(
    k: &Kinematics<T>,
    terms: &[T; NAV_DIM],
    rot: &Rotation<T>,
) -> [T; NAV_DIM] {
    let w = k.w_cmd;
    let cw = rot.to_platform(w);
    let om = |i: usize| (cw[i] - w[i]) + terms[PHI_X + i];
    let [dx, dy, dz] = rot.euler_rates([om(0), om(1), om(2)]);
    let [fx, fy, fz] = k.f;
    let a = rot.to_navigation([fx + terms[V_X], fy + terms[V_Y], fz]);
    let coriolis = k.sin_l * (2.0 * crate::earth::WIE) + k.v_x * k.tan_over_rn;
    [
        dx,
        dy,
        dz,
        coriolis * k.v_y + a[0],
        -coriolis * k.v_x + a[1],
        terms[LAT],
        terms[LON],
    ]
}

/// `a x b`.
#[inline(always)]
fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// The exact variant's rate Jacobian (of docs/model.md eqs. (47), (48)): `NAV_DIM` rows `n`
/// apart in `jac`, the first `n` columns of each written. On entry the rows hold the effects'
/// partials of the platform terms (zeros without rate effects; `mapped_effects` says whether
/// to map them), and `terms` their values (as for [`exact_rates`]), `rot` the rotation at
/// `k.phi`; `transport` the partials the variants share ([`crate::model`]'s Coriolis,
/// transport and position terms), added as they are.
///
/// With `E` the Euler map (`phi' = E Om`) and `u_j` the axis of Euler angle j
/// (`dC/dphi_j = [u_j x] C`: `u_x = Ry e_x`, `u_y = e_y`, `u_z = Ry Rx e_z`):
///
/// ```text
/// dphi'/dphi_j = (dE/dphi_j) Om + E (u_j x C w)        dphi'/d(v, L) = E (C - I) dw/d(v, L)
/// dv'/dphi_j   = C^T (a x u_j)                          dphi'/dK = E deps/dK,  dv'/dK = C^T dnab/dK
/// ```
pub fn exact_jacobian(
    k: &Kinematics,
    terms: &[f64; NAV_DIM],
    rot: &Rotation<f64>,
    transport: &[(usize, usize, f64)],
    mapped_effects: bool,
    jac: &mut [f64],
    n: usize,
) {
    assert!(n >= BASE_DIM && jac.len() >= NAV_DIM * n);
    let c = rot.c;
    let (sx, sy, cy, inv_cx) = (rot.sx, rot.sy, rot.cy, rot.inv_cx);
    // E, rows phi_x', phi_y', phi_z'.
    let e = [
        [cy, 0.0, -sy],
        [sx * sy * inv_cx, 1.0, sx * cy * inv_cx],
        [sy * inv_cx, 0.0, cy * inv_cx],
    ];
    let w = k.w_cmd;
    let cw = rot.to_platform(w);
    let om: [f64; 3] = std::array::from_fn(|i| (cw[i] - w[i]) + terms[PHI_X + i]);
    let [dx, _, dz] = rot.euler_rates(om);
    let [fx, fy, fz] = k.f;
    let a = [fx + terms[V_X], fy + terms[V_Y], fz];
    let e_times = |v: [f64; 3]| -> [f64; 3] {
        std::array::from_fn(|i| e[i][0] * v[0] + e[i][1] * v[1] + e[i][2] * v[2])
    };
    let mut rows = jac[..NAV_DIM * n].chunks_exact_mut(n);
    let row: &mut [&mut [f64]; NAV_DIM] =
        &mut std::array::from_fn(|_| rows.next().expect("NAV_DIM rows"));
    // The effects' partials of eps and nab, through E and C^T.
    if mapped_effects {
        for j in 0..n {
            let p = e_times([row[PHI_X][j], row[PHI_Y][j], row[PHI_Z][j]]);
            let q = [row[V_X][j], row[V_Y][j]];
            for i in 0..3 {
                row[PHI_X + i][j] = p[i];
            }
            row[V_X][j] = c[0][0] * q[0] + c[1][0] * q[1];
            row[V_Y][j] = c[0][1] * q[0] + c[1][1] * q[1];
        }
    }
    // The base coefficients: eps_a = Kg0a + Kg11a fx + Kg12a fy, nab = Ka0 + Ka1 f.
    for axis in 0..3 {
        for i in 0..3 {
            let r = &mut row[PHI_X + i];
            r[KG0X + 3 * axis] += e[i][axis];
            r[KG11X + 3 * axis] += e[i][axis] * fx;
            r[KG12X + 3 * axis] += e[i][axis] * fy;
        }
    }
    for (axis, (bias, scale, f)) in [(KA0X, KA1X, fx), (KA0Y, KA1Y, fy)].into_iter().enumerate() {
        for (r, out) in [V_X, V_Y].into_iter().enumerate() {
            row[out][bias] += c[axis][r];
            row[out][scale] += c[axis][r] * f;
        }
    }
    // w_in through (C - I): d(w)/d(v_x, v_y, L).
    let dw = [
        (V_X, [0.0, k.inv_rn, k.tan_over_rn]),
        (V_Y, [-k.inv_rm, 0.0, 0.0]),
        (
            LAT,
            [
                -k.v_y * k.d_inv_rm,
                -crate::earth::WIE * k.sin_l + k.v_x * k.d_inv_rn,
                crate::earth::WIE * k.cos_l + k.v_x * k.d_tan_over_rn,
            ],
        ),
    ];
    for (col, d) in dw {
        let cd = rot.to_platform(d);
        let m = e_times(std::array::from_fn(|i| cd[i] - d[i]));
        for i in 0..3 {
            row[PHI_X + i][col] += m[i];
        }
    }
    // The Euler angles: through E, through C w and through C^T a.
    let tx = sx * inv_cx;
    let t = om[0] * sy + om[2] * cy;
    let de_om = [
        [0.0, dz * inv_cx, dz * tx],
        [-t, dx * tx, dx * inv_cx],
        [0.0; 3],
    ];
    let u = [
        [cy, 0.0, -sy],
        [0.0, 1.0, 0.0],
        [sy * rot.cx, -sx, cy * rot.cx],
    ];
    for j in 0..3 {
        let m = e_times(cross(u[j], cw));
        for i in 0..3 {
            row[PHI_X + i][PHI_X + j] += m[i] + de_om[j][i];
        }
        let dv = rot.to_navigation(cross(a, u[j]));
        row[V_X][PHI_X + j] += dv[0];
        row[V_Y][PHI_X + j] += dv[1];
    }
    for &(r, col, v) in transport {
        row[r][col] += v;
    }
}
