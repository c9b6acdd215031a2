//! `gps-latency`: the fix refers to `tau` seconds before its time stamp, read as
//! `L - tau v_n / RM`, `lambda - tau v_e / (RN cosL)` to first order in `tau`
//! (docs/model.md eq. (70)), as the platform's `gps-latency`.
//!
//! Size: 0.1 s for any unit class (a receiver's unmodelled output delay: tens to a few
//! hundred milliseconds).

use super::{every_class, Coefficient, PhysicalBound, Places, Slot, StrapdownEffect};

/// See the module documentation.
pub const GPS_LATENCY: StrapdownEffect = StrapdownEffect {
    name: "gps-latency",
    description: "GPS reads the position tau seconds before its stamp (time-stamp latency)",
    coefficients: &[Coefficient {
        name: "tau",
        unit: "s",
        places: Places::One(Slot::Latency),
        sigma: every_class(0.1),
        bound: PhysicalBound {
            limit: 2.0,
            reason: "2 s: a receiver delivers its fix within its output interval (1 s at 1 \
                     Hz), a logger's stamp adds at most as much",
        },
    }],
    instability: None,
    declaration: None,
};
