//! `gyro-misalignment`: each gyro's sensitive axis leans towards the two others, the
//! off-diagonal entries of `E_g` (docs/model.md eq. (65)): `m_gij` is how much of the rate
//! about axis `j` gyro `i` reads. With `m_gxz` and `m_gyz`, a vehicle's turns (about z) leak
//! into roll and pitch.
//!
//! Sizes: tens of microradians in a navigation unit, tenths of a milliradian in a tactical
//! one, milliradians in a MEMS package (Groves, 2013, section 4.4.2, cross-coupling).

use super::{Coefficient, PhysicalBound, Places, Slot, StrapdownEffect};

const BOUND: PhysicalBound = PhysicalBound {
    limit: 0.05,
    reason: "50 mrad (3 deg): a sensor axis that far off is mounted to another axis",
};

const fn lean(name: &'static str, i: usize, j: usize) -> Coefficient {
    Coefficient {
        name,
        unit: "rad",
        places: Places::One(Slot::Gyro(i, j)),
        sigma: [2e-5, 2e-4, 2e-3],
        bound: BOUND,
    }
}

/// See the module documentation.
pub const GYRO_MISALIGNMENT: StrapdownEffect = StrapdownEffect {
    name: "gyro-misalignment",
    description: "w~_i += m_gij w_j, i != j (gyro axis misalignments)",
    coefficients: &[
        lean("m_gxy", 0, 1),
        lean("m_gxz", 0, 2),
        lean("m_gyx", 1, 0),
        lean("m_gyz", 1, 2),
        lean("m_gzx", 2, 0),
        lean("m_gzy", 2, 1),
    ],
    instability: None,
    declaration: None,
};
