//! The navigation quantities every term of the model is written in, computed once per
//! derivative evaluation and shared by the base model and its effects: the radii of
//! docs/model.md eqs. (2), (3) and the commanded rate `w_cmd` of docs/model.md eq. (7).

use crate::earth::{meridian_radius, prime_vertical_radius, FLATTENING, RE, WIE};
use crate::real::Real;
use crate::state::{LAT, PHI_X, PHI_Y, PHI_Z, V_X, V_Y};

/// What a model's state equations are driven by, one sample: up to [`INPUT_WIDTH`] numbers,
/// each model family reading its own. The platform reads the specific force
/// `f = [fx, fy, fz]` along its axes (m/s^2) from the first three and leaves the rest zero
/// ([`platform_input`]); a strapdown unit reads its body rates, then its specific forces
/// (`crate::strapdown::rates::ImuReading`). One fixed width keeps the input window, the
/// filters and `dyn Filter` the same for every family.
pub type Input = [f64; INPUT_WIDTH];

/// A specific force `[fx, fy, fz]`, m/s^2: what the platform's input holds.
pub type SpecificForce = [f64; 3];

/// Numbers in one [`Input`] sample.
pub const INPUT_WIDTH: usize = 6;

/// What an input window takes as a knot's input: a whole [`Input`], or a platform's specific
/// force ([`platform_input`]).
pub trait IntoInput {
    /// The input sample.
    fn into_input(self) -> Input;
}

impl IntoInput for Input {
    #[inline(always)]
    fn into_input(self) -> Input {
        self
    }
}

impl IntoInput for SpecificForce {
    #[inline(always)]
    fn into_input(self) -> Input {
        platform_input(self)
    }
}

/// The platform's input: the specific force `f` in the first three numbers.
#[inline(always)]
pub fn platform_input(f: SpecificForce) -> Input {
    [f[0], f[1], f[2], 0.0, 0.0, 0.0]
}

/// Where a platform input may carry the seconds since its record started
/// ([`Kinematics::elapsed_s`]). Recorded and simulated inputs leave it zero; the diagnosis
/// writes the time there on its own copy of a dataset when it fits a term shaped in time (an
/// accelerometer bias settling after switch-on), which no catalogued effect is.
pub const ELAPSED_SLOT: usize = 3;

/// Trigonometry, radii and rates at one state, with their derivatives in latitude (for
/// Jacobians). Field names follow `docs/model.md`: `w_cmd` is the rate the platform is
/// torqued at.
///
/// Generic over the number type ([`Real`]): `Kinematics<f64>` (the default) for one state,
/// `Kinematics<Lanes>` for eight. Built by [`Kinematics::with_trig`] from `sin L` and `cos L`,
/// which each caller evaluates its own way (see [`crate::trig`] and
/// [`crate::batch_propagation`]); everything after that is one source for every number type.
#[derive(Debug, Clone, Copy, Default)]
pub struct Kinematics<T = f64> {
    /// Specific force input.
    pub f: [T; 3],
    /// Platform error angles.
    pub phi: [T; 3],
    /// East velocity.
    pub v_x: T,
    /// North velocity.
    pub v_y: T,
    /// sin L.
    pub sin_l: T,
    /// cos L.
    pub cos_l: T,
    /// tan L.
    pub tan_l: T,
    /// 1 / cos L.
    pub inv_cos: T,
    /// 1 / RM.
    pub inv_rm: T,
    /// 1 / RN.
    pub inv_rn: T,
    /// d(1/RM)/dL. This and the other `d_` fields are for Jacobians only: the batched
    /// propagation builds [`Kinematics::values`], which leaves them zero, so rates must not
    /// read them.
    pub d_inv_rm: T,
    /// d(1/RN)/dL.
    pub d_inv_rn: T,
    /// tan L / RN.
    pub tan_over_rn: T,
    /// d(tan L / RN)/dL.
    pub d_tan_over_rn: T,
    /// `[-v_y/RM, wie cosL + v_x/RN, wie sinL + v_x tanL/RN]`, rad/s: docs/model.md eq. (7).
    pub w_cmd: [T; 3],
    /// The input's [`ELAPSED_SLOT`]: seconds since the record started where the caller put
    /// them there, zero otherwise. The same for every lane of a batch.
    pub elapsed_s: f64,
}

impl Kinematics<f64> {
    /// Computes the kinematics of the full state `x` under input `f`.
    // Always inlined: returned through memory, the kinematics cost the EKF step 3 % (a call
    // LLVM stopped inlining into `rates_and_jacobian` once the exact variant joined it).
    #[inline(always)]
    pub fn new(x: &[f64], f: &Input) -> Self {
        let (sin_l, cos_l) = crate::trig::sin_cos(x[LAT]);
        Self::with_trig(x, f, sin_l, cos_l)
    }
}

impl<T: Real> Kinematics<T> {
    /// As [`Kinematics::new`], with `sin L` and `cos L` already known. `x` holds at least the
    /// navigation states.
    #[inline(always)]
    pub fn with_trig(x: &[T], f: &Input, sin_l: T, cos_l: T) -> Self {
        Self::values(x, f, sin_l, cos_l).with_slopes()
    }

    /// The latitude derivatives (`d_inv_rm`, `d_inv_rn`, `d_tan_over_rn`), which only
    /// Jacobians need, from the values.
    #[inline(always)]
    pub fn with_slopes(mut self) -> Self {
        // dRM/dL = 6 Re f sinL cosL, dRN/dL = 2 Re f sinL cosL.
        let sc = self.sin_l * self.cos_l;
        self.d_inv_rm = sc * (-6.0 * RE * FLATTENING) * self.inv_rm * self.inv_rm;
        self.d_inv_rn = sc * (-2.0 * RE * FLATTENING) * self.inv_rn * self.inv_rn;
        self.d_tan_over_rn =
            (self.tan_l * self.tan_l + 1.0) * self.inv_rn + self.tan_l * self.d_inv_rn;
        self
    }

    /// The values without the latitude derivatives (left zero): what the rates need. The
    /// batched propagation builds these, never a Jacobian.
    #[inline(always)]
    pub fn values(x: &[T], f: &Input, sin_l: T, cos_l: T) -> Self {
        Self::from_latitude(x, f, &LatitudeTerms::new(sin_l, cos_l))
    }

    /// [`Kinematics::values`] from the latitude's functions already evaluated: a few
    /// multiplications, bit for bit the same values.
    #[inline(always)]
    pub fn from_latitude(x: &[T], f: &Input, lat: &LatitudeTerms<T>) -> Self {
        let LatitudeTerms {
            sin_l,
            cos_l,
            inv_rm,
            inv_rn,
            inv_cos,
        } = *lat;
        let tan_l = sin_l * inv_cos;
        let tan_over_rn = tan_l * inv_rn;
        let zero = T::splat(0.0);
        let v_x = x[V_X];
        let v_y = x[V_Y];
        Kinematics {
            f: [T::splat(f[0]), T::splat(f[1]), T::splat(f[2])],
            phi: [x[PHI_X], x[PHI_Y], x[PHI_Z]],
            v_x,
            v_y,
            sin_l,
            cos_l,
            tan_l,
            inv_cos,
            inv_rm,
            inv_rn,
            d_inv_rm: zero,
            d_inv_rn: zero,
            tan_over_rn,
            d_tan_over_rn: zero,
            w_cmd: [
                -v_y * inv_rm,
                cos_l * WIE + v_x * inv_rn,
                sin_l * WIE + v_x * tan_over_rn,
            ],
            elapsed_s: f[ELAPSED_SLOT],
        }
    }
}

/// The costly part of [`Kinematics`]: the latitude's sine and cosine and the three
/// reciprocals (one division in a batch). Everything else follows by a few multiplications
/// ([`Kinematics::from_latitude`]). The batched propagation keeps these per block for its
/// effects, five values where the whole kinematics are twenty-three: on a CPU that stores one
/// vector register every other cycle, storing all of them cost a fifth of the propagation.
#[derive(Debug, Clone, Copy, Default)]
pub struct LatitudeTerms<T = f64> {
    /// sin L.
    pub sin_l: T,
    /// cos L.
    pub cos_l: T,
    /// 1 / RM.
    pub inv_rm: T,
    /// 1 / RN.
    pub inv_rn: T,
    /// 1 / cos L.
    pub inv_cos: T,
}

impl<T: Real> LatitudeTerms<T> {
    /// The radii's and the cosine's reciprocals at the latitude with these sine and cosine.
    #[inline(always)]
    pub fn new(sin_l: T, cos_l: T) -> Self {
        let rm = meridian_radius(sin_l);
        let rn = prime_vertical_radius(sin_l);
        let [inv_rm, inv_rn, inv_cos] = T::reciprocals(rm, rn, cos_l);
        LatitudeTerms {
            sin_l,
            cos_l,
            inv_rm,
            inv_rn,
            inv_cos,
        }
    }
}
