//! Rate terms linear in one coefficient, declared as data: `rates[row] += c * feature`, the
//! form of the catalogue's rate effects (docs/model.md eqs. (37)-(40)).
//!
//! Most effects that add rates are a coefficient times a kinematic quantity: a cross-axis
//! accelerometer error `Ka12x f_y`, a torquer scale error `c w_cmd`, a g-sensitive drift
//! `c f_z`. An effect declares such terms in [`crate::Terms::linear_rates`] instead of writing
//! [`crate::Effect::add_rates`], and the model evaluates them itself: generic over the number
//! type like the base model (the truth and the EKF on `f64`, the UKFs' batch on
//! [`crate::Lanes`]), with the partials the EKF needs written here once per feature.
//!
//! Why data and not code: the batch reaches an effect's own code only through its vtable, and
//! that boundary (the kinematics and the rates through memory, every block of a stage waiting
//! for the call) cost the UKFs 1.15-1.25x their step with two effects. Evaluated inline in
//! the batch's loop, with `accel-cross-axis` and `torquer-scale` the simplified UKF's step
//! went from 20.3 to 19.0 us against 13.2 us for the base model (`step_timing`, Zen 4; the
//! same terms hard-coded in the loop: 17.8). An effect whose terms are not of this form (a drag
//! `c v |v|`, say) still writes [`crate::Effect::add_rates`].

use crate::earth::WIE;
use crate::kinematics::Kinematics;
use crate::partials::Partials;
use crate::real::Real;
use crate::state::{LAT, NAV_DIM, V_X, V_Y};

/// A kinematic quantity a linear rate term multiplies its coefficient by.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Feature {
    /// The specific force along a platform axis (0 = x, 1 = y, 2 = z).
    SpecificForce(usize),
    /// The square of the specific force along an axis.
    SpecificForceSquared(usize),
    /// The rate the platform is torqued at about an axis, `w_cmd` (docs/model.md eq. (7)).
    CommandedRate(usize),
}

impl Feature {
    /// The axis the feature is about.
    pub fn axis(self) -> usize {
        match self {
            Feature::SpecificForce(a)
            | Feature::SpecificForceSquared(a)
            | Feature::CommandedRate(a) => a,
        }
    }

    /// Its value at kinematics `k`.
    // Every field is named statically (a match on the axis, not an index): indexed by a
    // number known only at run time, the kinematics would have to live in memory, and the
    // batch's derivative with them.
    #[inline(always)]
    pub fn value<T: Real>(self, k: &Kinematics<T>) -> T {
        let [fx, fy, fz] = k.f;
        let [w1, w2, w3] = k.w_cmd;
        match self {
            Feature::SpecificForce(a) => pick(a, fx, fy, fz),
            Feature::SpecificForceSquared(a) => pick(a, fx * fx, fy * fy, fz * fz),
            Feature::CommandedRate(a) => pick(a, w1, w2, w3),
        }
    }

    /// Adds the partials of `c * feature` with respect to the navigation states to row `row`
    /// (the specific force is an input: only the commanded rate depends on the state).
    #[inline(always)]
    pub fn add_state_partials(self, k: &Kinematics, c: f64, row: usize, p: &mut Partials) {
        match self {
            Feature::SpecificForce(_) | Feature::SpecificForceSquared(_) => {}
            // w1 = -v_y / RM
            Feature::CommandedRate(0) => {
                p.add(row, V_Y, -c * k.inv_rm);
                p.add(row, LAT, -c * k.v_y * k.d_inv_rm);
            }
            // w2 = wie cosL + v_x / RN
            Feature::CommandedRate(1) => {
                p.add(row, V_X, c * k.inv_rn);
                p.add(row, LAT, c * (-WIE * k.sin_l + k.v_x * k.d_inv_rn));
            }
            // w3 = wie sinL + v_x tanL / RN
            Feature::CommandedRate(_) => {
                p.add(row, V_X, c * k.tan_over_rn);
                p.add(row, LAT, c * (WIE * k.cos_l + k.v_x * k.d_tan_over_rn));
            }
        }
    }
}

/// `rates[row] += c[coefficient] * feature`: one rate term linear in one of the effect's
/// coefficients (`coefficient` indexes [`crate::Effect::coefficient_names`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LinearRate {
    /// The navigation-state derivative it adds to (a `phi` row joins the gyro errors, a `v`
    /// row the accelerometer errors, as for [`crate::Effect::add_rates`]).
    pub row: usize,
    /// Which of the effect's coefficients multiplies the feature.
    pub coefficient: usize,
    /// The kinematic quantity.
    pub feature: Feature,
}

/// A model's linear rate terms, every effect's in the model's order, with the coefficient
/// as its index in the full state.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct StateLinearRate {
    pub row: usize,
    pub state: usize,
    pub feature: Feature,
}

impl StateLinearRate {
    /// Adds the term to `rates`, at the full state `x` with kinematics `k`.
    #[inline(always)]
    pub fn add<T: Real>(&self, x: &[T], k: &Kinematics<T>, rates: &mut [T; NAV_DIM]) {
        let c = x[self.state];
        let term = match self.feature {
            // `(c f) f`, the order the catalogue's effects always wrote it in.
            Feature::SpecificForceSquared(a) => {
                let f = pick(a, k.f[0], k.f[1], k.f[2]);
                c * f * f
            }
            feature => c * feature.value(k),
        };
        // A static row for each arm, for the same reason as in `Feature::value`.
        let [r0, r1, r2, r3, r4, r5, r6] = rates;
        match self.row {
            0 => *r0 += term,
            1 => *r1 += term,
            2 => *r2 += term,
            3 => *r3 += term,
            4 => *r4 += term,
            5 => *r5 += term,
            _ => *r6 += term,
        }
    }

    /// Adds its partials (with respect to its coefficient and to the navigation states).
    #[inline(always)]
    pub fn add_partials(&self, x: &[f64], k: &Kinematics, p: &mut Partials) {
        p.add(self.row, self.state, self.feature.value(k));
        self.feature
            .add_state_partials(k, x[self.state], self.row, p);
    }
}

/// `a`, `b` or `c` for axis 0, 1 or 2 (the model checks axes at assembly).
#[inline(always)]
fn pick<T: Real>(axis: usize, a: T, b: T, c: T) -> T {
    match axis {
        0 => a,
        1 => b,
        _ => c,
    }
}
