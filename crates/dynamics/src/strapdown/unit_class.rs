//! Classes of strapdown inertial unit, with the sizes of their sensor errors: what
//! `navkf simulate --model strapdown --unit mems` and a study's `[model] unit` draw from.
//!
//! The values are chosen inside the ranges by grade that Groves, *Principles of GNSS,
//! Inertial, and Multisensor Integrated Navigation Systems*, 2nd ed. (2013), chapter 4
//! (inertial sensors: biases, scale factors and noise by grade), and Titterton & Weston,
//! *Strapdown Inertial Navigation Technology*, 2nd ed. (2004), give. The books were cited
//! from memory; the table below checks the values against two public sets of error sizes by
//! grade that can be read line by line: the IMU error models of the MATLAB demonstrations
//! Groves publishes with the book (BSD licence; `Inertial_Demo_2` aviation grade,
//! `Inertial_Demo_1NED` tactical, `Inertial_Demo_3` consumer), and the built-in models of
//! gnss-ins-sim (`gnss_ins_sim/sim/imu_model.py`: `high-accuracy` from the HG9900,
//! `mid-accuracy` from the IMU381, `low-accuracy` from the AHRS380 data sheets; it models
//! bias *instability*, not a turn-on bias). A user with a data sheet should state its
//! figures (a dataset's `[noise]` and `[prior]`) rather than trust a class. Where a range is
//! wide, the class takes a value a unit of that class meets after its factory calibration:
//!
//! | class | gyro bias | angle random walk | accel bias | velocity random walk |
//! |---|---|---|---|---|
//! | navigation (ring-laser, aviation) | 0.01 deg/h | 0.002 deg/sqrt(h) | 50 ug | 30 ug/sqrt(Hz) |
//! | tactical (fibre-optic) | 1 deg/h | 0.05 deg/sqrt(h) | 1 mg | 100 ug/sqrt(Hz) |
//! | MEMS (industrial) | 50 deg/h | 0.3 deg/sqrt(h) | 5 mg | 200 ug/sqrt(Hz) |
//!
//! Checked against the public models (the demos' biases are fixed per axis, given here as
//! their range):
//!
//! | class | Groves's demonstration | gnss-ins-sim |
//! |---|---|---|
//! | navigation | aviation: gyro 0.0008-0.0013 deg/h, ARW 0.002 deg/sqrt(h), accel 26-45 ug, 20 ug/sqrt(Hz) | high: instability 0.1 deg/h, ARW 0.002 deg/sqrt(h), accel instability 0.37 ug, VRW 0.04 ug/sqrt(Hz) |
//! | tactical | gyro 8-13 deg/h, ARW 0.01 deg/sqrt(h), accel 0.8-1.3 mg, 100 ug/sqrt(Hz) | mid: instability 3.5 deg/h, ARW 0.25 deg/sqrt(h), accel instability 5 ug, VRW 51 ug/sqrt(Hz) |
//! | MEMS | consumer: gyro 160-260 deg/h, ARW 1 deg/sqrt(h), accel 8-13 mg, 1000 ug/sqrt(Hz) | low: instability 10 deg/h, ARW 0.75 deg/sqrt(h), accel instability 20 ug, VRW 85 ug/sqrt(Hz) |
//!
//! So: the navigation class is near the aviation demo's noise and accelerometer bias (ARW
//! equal, VRW 30 against 20 ug/sqrt(Hz), bias 50 against 26-45 ug) and takes a gyro bias ten
//! times the demo's (0.01 deg/h, the usual data-sheet figure); the
//! tactical class matches the demo's accelerometer bias and VRW, takes an ARW between the
//! two sources and a gyro bias below both (1 deg/h against the demo's 8-13 deg/h and the mid
//! model's 3.5 deg/h instability: the better, fibre-optic end of the grade); the MEMS class is an *industrial* unit, between the
//! consumer demo and the tactical grade: a quarter of the consumer demo's gyro bias and a
//! third of its ARW, half its accelerometer bias, a fifth of its VRW.
//!
//! A bias here is the one-sigma of its turn-on value (a random constant over the test, the
//! state of docs/model.md eq. (58)); the random walks are the white noises `q_g`, `q_a` of
//! docs/model.md eq. (50), as densities: `q_g = ARW^2`, `q_a = VRW^2`.

use crate::noise::NoiseConfig;
use serde::{Deserialize, Serialize};

/// Standard gravity, m/s^2 (the unit of `g` in accelerometer data sheets).
const G0: f64 = crate::earth::STANDARD_GRAVITY;

/// A class of inertial unit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum UnitClass {
    /// Ring-laser or high-end fibre-optic gyros, navigation-grade accelerometers.
    Navigation,
    /// Fibre-optic gyros, tactical-grade accelerometers.
    Tactical,
    /// Industrial MEMS: what most vehicle recordings come from.
    #[default]
    Mems,
}

/// The error sizes of a [`UnitClass`], SI units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UnitErrors {
    /// One-sigma gyro bias per axis, rad/s.
    pub gyro_bias: f64,
    /// One-sigma accelerometer bias per axis, m/s^2.
    pub accel_bias: f64,
    /// Gyro white-noise density `q_g`, rad^2/s.
    pub gyro_psd: f64,
    /// Accelerometer white-noise density `q_a`, (m/s^2)^2/s.
    pub accel_psd: f64,
}

impl UnitErrors {
    /// `aids` (the odometer's, GPS's and constraint's sigmas) with this unit's reading-noise
    /// densities.
    pub fn noise(&self, aids: NoiseConfig) -> NoiseConfig {
        NoiseConfig {
            gyro_psd: self.gyro_psd,
            accel_psd: self.accel_psd,
            ..aids
        }
    }
}

impl UnitClass {
    /// Every class, best first.
    pub const ALL: [UnitClass; 3] = [UnitClass::Navigation, UnitClass::Tactical, UnitClass::Mems];

    /// The class's name as files write it.
    pub fn name(self) -> &'static str {
        match self {
            UnitClass::Navigation => "navigation",
            UnitClass::Tactical => "tactical",
            UnitClass::Mems => "mems",
        }
    }

    /// The class's error sizes (module documentation).
    pub fn errors(self) -> UnitErrors {
        let deg_per_h = 1f64.to_radians() / 3600.0;
        // deg/sqrt(h) -> rad/sqrt(s): one sqrt(h) is 60 sqrt(s).
        let arw = |v: f64| v.to_radians() / 60.0;
        let ug = 1e-6 * G0;
        let (bias_g, arw_deg, bias_a_ug, vrw_ug) = match self {
            UnitClass::Navigation => (0.01, 0.002, 50.0, 30.0),
            UnitClass::Tactical => (1.0, 0.05, 1000.0, 100.0),
            UnitClass::Mems => (50.0, 0.3, 5000.0, 200.0),
        };
        UnitErrors {
            gyro_bias: bias_g * deg_per_h,
            accel_bias: bias_a_ug * ug,
            gyro_psd: arw(arw_deg).powi(2),
            accel_psd: (vrw_ug * ug).powi(2),
        }
    }
}

impl std::str::FromStr for UnitClass {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        UnitClass::ALL
            .into_iter()
            .find(|c| c.name() == s)
            .ok_or_else(|| {
                format!("unknown unit class `{s}`; expected navigation, tactical or mems")
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_classes_convert_their_data_sheet_units() {
        let mems = UnitClass::Mems.errors();
        // 50 deg/h = 2.42e-4 rad/s; 0.3 deg/sqrt(h) = 8.73e-5 rad/sqrt(s).
        assert!((mems.gyro_bias - 2.424e-4).abs() < 1e-7);
        assert!((mems.gyro_psd.sqrt() - 8.727e-5).abs() < 1e-8);
        // 5 mg; 200 ug/sqrt(Hz).
        assert!((mems.accel_bias - 0.049033).abs() < 1e-6);
        assert!((mems.accel_psd.sqrt() - 1.9613e-3).abs() < 1e-7);
        // Each class is worse than the one before it in every figure.
        for pair in UnitClass::ALL.windows(2) {
            let (a, b) = (pair[0].errors(), pair[1].errors());
            assert!(a.gyro_bias < b.gyro_bias && a.accel_bias < b.accel_bias);
            assert!(a.gyro_psd < b.gyro_psd && a.accel_psd < b.accel_psd);
        }
        assert_eq!("tactical".parse::<UnitClass>(), Ok(UnitClass::Tactical));
        assert!("consumer".parse::<UnitClass>().is_err());
    }
}
