//! The GPS antenna mounted away from the platform, outside the catalogue: the rival
//! `gps-latency` must beat before it is named ([`super`]).
//!
//! A fix refers to the antenna, `a` metres ahead of the platform and `b` to its right, so
//! it reads the platform's position moved by `a f + b r`, with `f` the unit vector of travel
//! and `r` the one to its right. At a constant speed `v` a forward antenna shifts the fix
//! along the track by `a`, exactly as a latency `tau = -a / v` does (docs/model.md eq. (42)):
//! on the error-rate study a lever arm of 0.5-1.9 m was named `gps-latency` in 26 of 60
//! drives, with the verdict `explained`. The two differ only where the speed changes: the
//! latency's shift grows with the speed, the antenna's does not.
//!
//! The platform model has no heading state, so the direction of travel comes from the
//! velocity states, `f = (v_x, v_y) / s` with `s = sqrt(v_x^2 + v_y^2 + V0^2)`: the offset
//! fades below walking speed, where the direction is unknown, and is smooth everywhere, so
//! the filters differentiate it like any measurement term. (A real antenna keeps its offset
//! at a standstill; there the model leaves it to the position states, as it does a
//! latency's.)

use navkf_dynamics::effect::{Effect, MeasurementTerm, Partials, PhysicalBound, Terms};
use navkf_dynamics::kinematics::Kinematics;
use navkf_dynamics::state::{LAT, MEAS_DIM, V_X, V_Y};

/// The speed below which the direction of travel, and with it the offset, fades, m/s.
pub const V0: f64 = 1.0;

/// See the module documentation. Coefficients: `a` (forward) and `b` (right), metres.
#[derive(Debug, Default, Clone)]
pub struct GpsAntennaOffset;

impl GpsAntennaOffset {
    /// The name it is fitted under (never named: it is not in the catalogue).
    pub const NAME: &'static str = "gps-antenna-offset";
}

/// The direction of travel `(f_E, f_N)` and its derivatives `d f_i / d v_j` (`j`: east,
/// north).
fn travel(k: &Kinematics) -> ([f64; 2], [[f64; 2]; 2]) {
    let (vx, vy) = (k.v_x, k.v_y);
    let s2 = vx * vx + vy * vy + V0 * V0;
    let s = s2.sqrt();
    let s3 = s2 * s;
    let f = [vx / s, vy / s];
    let df = [
        [1.0 / s - vx * vx / s3, -vx * vy / s3],
        [-vx * vy / s3, 1.0 / s - vy * vy / s3],
    ];
    (f, df)
}

impl Effect for GpsAntennaOffset {
    fn name(&self) -> &str {
        Self::NAME
    }
    fn description(&self) -> &str {
        "the fix refers to an antenna a m ahead and b m right of the platform (outside the \
         catalogue)"
    }
    fn terms(&self) -> Terms {
        Terms::measurement(MeasurementTerm::NonLinear)
    }
    fn coefficient_names(&self) -> &[&str] {
        &["a_fwd", "b_right"]
    }
    fn coefficient_units(&self) -> &[&str] {
        &["m", "m"]
    }
    fn coefficient_sigma(&self) -> &[f64] {
        // An antenna on a car's roof or a van's: a metre or two from the unit.
        &[1.5, 1.5]
    }
    fn coefficient_bounds(&self) -> &[PhysicalBound] {
        const VEHICLE: PhysicalBound = PhysicalBound {
            limit: 10.0,
            reason: "10 m: an antenna on the vehicle",
        };
        &[VEHICLE, VEHICLE]
    }
    fn add_measurement(&self, k: &Kinematics, c: &[f64], z: &mut [f64; MEAS_DIM]) {
        let ([fe, fn_], _) = travel(k);
        let (a, b) = (c[0], c[1]);
        let (de, dn) = (a * fe + b * fn_, a * fn_ - b * fe);
        z[2] += dn * k.inv_rm;
        z[3] += de * k.inv_rn * k.inv_cos;
    }
    fn add_measurement_partials(&self, k: &Kinematics, c: &[f64], offset: usize, p: &mut Partials) {
        let ([fe, fn_], df) = travel(k);
        let (a, b) = (c[0], c[1]);
        let (de, dn) = (a * fe + b * fn_, a * fn_ - b * fe);
        let lam = k.inv_rn * k.inv_cos;
        p.add(2, offset, fn_ * k.inv_rm);
        p.add(2, offset + 1, -fe * k.inv_rm);
        p.add(3, offset, fe * lam);
        p.add(3, offset + 1, fn_ * lam);
        for (j, state) in [V_X, V_Y].into_iter().enumerate() {
            let ddn = a * df[1][j] - b * df[0][j];
            let dde = a * df[0][j] + b * df[1][j];
            p.add(2, state, ddn * k.inv_rm);
            p.add(3, state, dde * lam);
        }
        p.add(2, LAT, dn * k.d_inv_rm);
        p.add(3, LAT, de * k.inv_cos * (k.d_inv_rn + k.inv_rn * k.tan_l));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use navkf_dynamics::partials_check::check_effect;
    use navkf_dynamics::NoiseConfig;

    #[test]
    fn its_partials_agree_with_finite_differences() {
        for seed in [1, 2, 3] {
            let report = check_effect(
                Box::new(GpsAntennaOffset),
                &NoiseConfig::default(),
                16,
                seed,
            )
            .unwrap();
            assert!(report.passes(), "{report:?}");
        }
    }

    #[test]
    fn ahead_of_a_moving_platform_it_shifts_the_fix_along_the_track_and_fades_at_rest() {
        let mut k = Kinematics {
            v_y: 15.0,
            inv_rm: 1.0 / 6.4e6,
            inv_rn: 1.0 / 6.4e6,
            inv_cos: 1.0,
            ..Kinematics::default()
        };
        let mut z = [0.0; MEAS_DIM];
        GpsAntennaOffset.add_measurement(&k, &[2.0, 0.0], &mut z);
        // North at 15 m/s: 2 m ahead is 2 m north (less the fading, 15/sqrt(15^2 + 1)).
        let ahead = 2.0 * 15.0 / (15.0f64 * 15.0 + V0 * V0).sqrt();
        assert!((z[2] * 6.4e6 - ahead).abs() < 1e-9, "{z:?}");
        assert!(z[3].abs() < 1e-18);
        k.v_y = 0.01;
        let mut z = [0.0; MEAS_DIM];
        GpsAntennaOffset.add_measurement(&k, &[2.0, 0.0], &mut z);
        assert!(z[2] * 6.4e6 < 0.021, "{z:?}");
    }
}
