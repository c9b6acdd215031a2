//! `accel-misalignment`: each accelerometer's sensitive axis leans towards the two others,
//! the off-diagonal entries of `E_a` (docs/model.md eq. (66)): `m_aij` is how much of the
//! force along axis `j` accelerometer `i` reads. `m_axz` and `m_ayz` put a share of gravity
//! into the horizontal readings, where it looks like a bias or a tilt.
//!
//! Sizes as `gyro-misalignment` (Groves, 2013, section 4.4.2).

use super::{Coefficient, PhysicalBound, Places, Slot, StrapdownEffect};

const BOUND: PhysicalBound = PhysicalBound {
    limit: 0.05,
    reason: "50 mrad (3 deg): a sensor axis that far off is mounted to another axis",
};

const fn lean(name: &'static str, i: usize, j: usize) -> Coefficient {
    Coefficient {
        name,
        unit: "rad",
        places: Places::One(Slot::Accel(i, j)),
        sigma: [2e-5, 2e-4, 2e-3],
        bound: BOUND,
    }
}

/// See the module documentation.
pub const ACCEL_MISALIGNMENT: StrapdownEffect = StrapdownEffect {
    name: "accel-misalignment",
    description: "f~_i += m_aij f_j, i != j (accelerometer axis misalignments)",
    coefficients: &[
        lean("m_axy", 0, 1),
        lean("m_axz", 0, 2),
        lean("m_ayx", 1, 0),
        lean("m_ayz", 1, 2),
        lean("m_azx", 2, 0),
        lean("m_azy", 2, 1),
    ],
    instability: None,
    declaration: None,
};
