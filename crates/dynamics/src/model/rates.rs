//! The model's rates, written once generic over [`crate::real::Real`]: the sensor errors of
//! docs/model.md eqs. (5), (6), the state equations of docs/model.md eqs. (7)-(11) and the
//! effects' rate terms (docs/model.md eqs. (37)-(44)), for one state or eight lanes.

use super::PlatformModel;
use crate::attitude::{exact_rates, Attitude};
use crate::earth::WIE;
use crate::effect::BlockGroup;
use crate::kinematics::Kinematics;
use crate::real::{Lanes, Real};
use crate::state::*;

impl PlatformModel {
    /// Derivative of the seven navigation states (docs/model.md eqs. (8)-(10) plus effects)
    /// at the full state `x`, given its kinematics, for one state: the truth and the EKF.
    /// [`PlatformModel::base_rates`], the effects' declared linear terms
    /// ([`PlatformModel::add_linear_rates`]) and their generic [`crate::Effect::add_rates`] are
    /// the one source: the UKFs' batches call the first two on [`crate::Lanes`] and the third
    /// through [`PlatformModel::add_effect_rates_blocks`].
    // Inlined into its callers, the result stays in registers: returned through memory, its
    // seven scalar stores were read back as vectors, a store-forwarding stall per call.
    #[inline(always)]
    pub fn nav_rates(&self, x: &[f64], k: &Kinematics) -> [f64; NAV_DIM] {
        if self.attitude == Attitude::Exact {
            return exact_rates(k, &self.platform_terms(x, k));
        }
        let mut r = self.base_rates(x, k);
        if self.has_rate_effects() {
            // Through copies: were `r` or `k` passed by address, neither could stay in
            // registers, effects or not.
            let k = *k;
            let mut with = r;
            self.add_effect_rates(x, &k, &mut with);
            r = with;
        }
        r
    }

    /// Whether any switched-on effect adds rates (declared linear terms or its own code).
    #[inline(always)]
    pub fn has_rate_effects(&self) -> bool {
        !self.rate_effects.is_empty() || !self.linear_rates.is_empty()
    }

    /// Whether any switched-on effect declares linear rate terms ([`crate::linear_rates`]).
    #[inline(always)]
    pub fn has_linear_rates(&self) -> bool {
        !self.linear_rates.is_empty()
    }

    /// Whether any switched-on effect adds rates through its own code
    /// ([`crate::Effect::add_rates`]), which the batch reaches only through its vtable.
    #[inline(always)]
    pub fn has_coded_rate_effects(&self) -> bool {
        !self.rate_effects.is_empty()
    }

    /// The base model's platform terms, in the rate rows' places:
    /// `[eps_x, eps_y, eps_z, nab_x, nab_y, L', lambda']`: docs/model.md eqs. (5), (6), (10)
    /// (the gyro drifts, the accelerometer errors and the position rates). Effects add to
    /// these; the attitude variant maps them to the state ([`crate::attitude`]).
    #[inline(always)]
    pub fn base_terms<T: Real>(&self, x: &[T], k: &Kinematics<T>) -> [T; NAV_DIM] {
        let [fx, fy, _] = k.f;
        // Written out rather than through a closure, which the batch path did not inline.
        let c = &x[..BASE_DIM];
        [
            c[KG0X] + c[KG11X] * fx + c[KG12X] * fy,
            c[KG0Y] + c[KG11X + 3] * fx + c[KG12X + 3] * fy,
            c[KG0Z] + c[KG11X + 6] * fx + c[KG12X + 6] * fy,
            c[KA0X] + c[KA1X] * fx,
            c[KA0Y] + c[KA1Y] * fy,
            k.v_y * k.inv_rm,
            k.v_x * k.inv_rn * k.inv_cos,
        ]
    }

    /// The platform terms of the whole model at one state: [`PlatformModel::base_terms`] plus
    /// every effect's.
    #[inline(always)]
    pub fn platform_terms(&self, x: &[f64], k: &Kinematics) -> [f64; NAV_DIM] {
        let mut t = self.base_terms(x, k);
        self.add_effect_rates(x, k, &mut t);
        t
    }

    /// The base model's navigation-state derivatives in the small-angle form
    /// (docs/model.md eqs. (8)-(10)), on one state or a batch: `x` is the full state, `k` its
    /// kinematics.
    #[inline(always)]
    pub fn base_rates<T: Real>(&self, x: &[T], k: &Kinematics<T>) -> [T; NAV_DIM] {
        let [fx, fy, fz] = k.f;
        let [px, py, pz] = k.phi;
        let [w1, w2, w3] = k.w_cmd;
        let [eps_x, eps_y, eps_z, nab_x, nab_y, lat_rate, lon_rate] = self.base_terms(x, k);
        let coriolis = k.sin_l * (2.0 * WIE) + k.v_x * k.tan_over_rn;
        [
            py * w3 - pz * w2 + eps_x,
            pz * w1 - px * w3 + eps_y,
            px * w2 - py * w1 + eps_z,
            coriolis * k.v_y + nab_x + fx + fy * pz - fz * py,
            -coriolis * k.v_x + nab_y + fy + fz * px - fx * pz,
            lat_rate,
            lon_rate,
        ]
    }

    /// Adds the switched-on effects' rate terms to `r`, at one state: the declared linear
    /// terms, then the effects' own code.
    #[inline(always)]
    pub fn add_effect_rates(&self, x: &[f64], k: &Kinematics, r: &mut [f64; NAV_DIM]) {
        self.add_linear_rates(x, k, r);
        for &i in &self.rate_effects {
            let c = &x[self.ranges[i].clone()];
            self.effects[i].add_rates(k, c, r);
        }
    }

    /// Adds the effects' declared linear rate terms ([`crate::linear_rates`]) to `r`, on one
    /// state or a batch: the batch evaluates them inline, with no call per effect.
    #[inline(always)]
    pub fn add_linear_rates<T: Real>(&self, x: &[T], k: &Kinematics<T>, r: &mut [T; NAV_DIM]) {
        if self.linear_rates.is_empty() {
            return;
        }
        // Through copies, as in `nav_rates`: neither `k` nor `r` has its address taken.
        let k = *k;
        let mut with = *r;
        for t in &self.linear_rates {
            t.add(x, &k, &mut with);
        }
        *r = with;
    }

    /// The effects' own rate code ([`crate::Effect::add_rates`]) on a group of batches, one
    /// call per effect (the declared linear terms are not included).
    #[inline(always)]
    pub fn add_effect_rates_blocks(&self, group: &BlockGroup<'_>, r: &mut [[Lanes; NAV_DIM]]) {
        for &i in &self.rate_effects {
            self.effects[i].add_rates_blocks(group, self.ranges[i].clone(), r);
        }
    }

    pub(super) fn effect_coeffs<'a>(&self, i: usize, x: &'a [f64]) -> &'a [f64] {
        &x[self.ranges[i].clone()]
    }
}
