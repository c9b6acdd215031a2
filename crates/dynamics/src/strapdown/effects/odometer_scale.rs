//! `odometer-scale`: the odometer reads `s = (1 + kod) u_o . v^b` (docs/model.md eq. (68)):
//! a wheel whose rolling radius is not the one assumed.
//!
//! Size: 0.2 % (a tyre's radius changes by a few per cent over its life; a calibrated
//! odometer is within tenths of one). The same for every unit class: it is the vehicle's.

use super::{every_class, Coefficient, PhysicalBound, Places, Slot, StrapdownEffect};

/// See the module documentation.
pub const ODOMETER_SCALE: StrapdownEffect = StrapdownEffect {
    name: "odometer-scale",
    description: "s = (1 + kod) u_o . v^b (odometer scale error)",
    coefficients: &[Coefficient {
        name: "kod",
        unit: "1",
        places: Places::One(Slot::OdometerScale),
        sigma: every_class(2e-3),
        bound: PhysicalBound {
            limit: 0.2,
            reason: "20 %: a tyre's rolling radius varies by a few per cent (wear, pressure, load)",
        },
    }],
    instability: None,
    declaration: None,
};
