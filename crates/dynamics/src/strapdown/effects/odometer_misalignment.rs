//! `odometer-misalignment`: the vehicle's axes are turned from the unit's, by yaw `a_y`
//! (its forward axis to the left of the unit's x) and pitch `a_p` (up): the odometer reads
//! along `u_o`, and the non-holonomic constraint holds along `u_l` and `u_u`
//! (docs/model.md eq. (68)). A unit bolted to a car by hand sits a degree or so off its axes;
//! uncorrected, the constraint then reads the forward speed times `a_y` as a sideslip.
//!
//! Size: 10 mrad (0.6 deg) per angle, for any unit class: it is the mounting's.

use super::{every_class, Coefficient, PhysicalBound, Places, Slot, StrapdownEffect};

const BOUND: PhysicalBound = PhysicalBound {
    limit: 0.2,
    reason: "0.2 rad (11 deg): a unit mounted that far off the vehicle's axes is stated in \
             [initial], not left to be found",
};

/// See the module documentation.
pub const ODOMETER_MISALIGNMENT: StrapdownEffect = StrapdownEffect {
    name: "odometer-misalignment",
    description: "u_o = [cos a_p cos a_y, cos a_p sin a_y, sin a_p] (vehicle axes turned from \
                  the unit's)",
    coefficients: &[
        Coefficient {
            name: "a_y",
            unit: "rad",
            places: Places::One(Slot::OdometerYaw),
            sigma: every_class(1e-2),
            bound: BOUND,
        },
        Coefficient {
            name: "a_p",
            unit: "rad",
            places: Places::One(Slot::OdometerPitch),
            sigma: every_class(1e-2),
            bound: BOUND,
        },
    ],
    instability: None,
    declaration: None,
};
