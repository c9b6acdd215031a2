//! `gyro-g-sensitivity`: each gyro reads a rate in proportion to the specific force along
//! its own axis, `w~ += diag(g_x, g_y, g_z) f` (docs/model.md eq. (67)). On a level vehicle
//! `g_z` times gravity is indistinguishable from the z gyro's bias; `g_x` and `g_y` show in
//! accelerations, braking and cornering.
//!
//! Sizes: negligible in ring-laser gyros (0.01 deg/h/g here), about 1 deg/h/g in fibre-optic
//! ones, tens of deg/h/g in compensated MEMS (Groves, 2013, section 4.4.4).

use super::{Coefficient, PhysicalBound, Places, Slot, StrapdownEffect, DEG_PER_H, G0};

const PER_G: f64 = DEG_PER_H / G0;

const BOUND: PhysicalBound = PhysicalBound {
    limit: 3600.0 * PER_G,
    reason: "1 deg/s/g: uncompensated consumer MEMS gyros stay below 0.1 deg/s/g",
};

const fn sensitivity(name: &'static str, axis: usize) -> Coefficient {
    Coefficient {
        name,
        unit: "rad/s/(m/s^2)",
        places: Places::One(Slot::GyroG(axis)),
        sigma: [0.01 * PER_G, 1.0 * PER_G, 30.0 * PER_G],
        bound: BOUND,
    }
}

/// See the module documentation.
pub const GYRO_G_SENSITIVITY: StrapdownEffect = StrapdownEffect {
    name: "gyro-g-sensitivity",
    description: "w~ += diag(g_x, g_y, g_z) f (gyro g-dependent bias)",
    coefficients: &[
        sensitivity("g_x", 0),
        sensitivity("g_y", 1),
        sensitivity("g_z", 2),
    ],
    instability: None,
    declaration: None,
};
