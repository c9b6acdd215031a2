//! `gps-lever-arm`: the GPS antenna sits at `l` (body axes) from the unit, so the fix is the
//! position of `p + C_b^n l` (docs/model.md eq. (70)). A roof antenna is a metre or more
//! from a unit in the boot; uncorrected, each turn swings the fix by `|l|` across the track.
//!
//! Size: 0.5 m per axis for any unit class (it is the installation's).

use super::{every_class, Coefficient, PhysicalBound, Places, Slot, StrapdownEffect};

const BOUND: PhysicalBound = PhysicalBound {
    limit: 10.0,
    reason: "10 m: an antenna farther than that from the unit is on another vehicle",
};

const fn arm(name: &'static str, axis: usize) -> Coefficient {
    Coefficient {
        name,
        unit: "m",
        places: Places::One(Slot::LeverArm(axis)),
        sigma: every_class(0.5),
        bound: BOUND,
    }
}

/// See the module documentation.
pub const GPS_LEVER_ARM: StrapdownEffect = StrapdownEffect {
    name: "gps-lever-arm",
    description: "GPS reads p + C_b^n l, l = [l_x, l_y, l_z] in body axes (antenna lever arm)",
    coefficients: &[arm("l_x", 0), arm("l_y", 1), arm("l_z", 2)],
    instability: None,
    declaration: None,
};
