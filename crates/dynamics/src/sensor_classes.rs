//! What real sensors and vehicles can be: the bounds beyond which a stated noise level, a
//! coefficient or a reading belongs to no instrument, so that the diagnosis refuses to name
//! it and the simulator refuses to make it.
//!
//! The bounds are not tuned to any dataset: each is the extreme of a class of real sensors,
//! taken from the grade tables of Groves, *Principles of GNSS, Inertial, and Multisensor
//! Integrated Navigation Systems* (2nd ed., 2013), ch. 4 (sections 4.4.1-4.4.3: biases, scale
//! factors, g-dependent biases and random noise by grade, from marine/aviation to consumer),
//! and El-Sheimy & Youssef, *Inertial sensors technologies for navigation applications*,
//! Satellite Navigation 1 (2020), Table 1 (strategic to commercial grade), with consumer MEMS
//! datasheets for the coarse end:
//!
//! - **Stated noise** ([`NOISE_BOUNDS`]) may lie [`FAR`] times (in sigma) beyond the class
//!   extremes: below the quietest navigation-grade sensor or above the noisiest consumer one.
//!   A user who mis-states a level by the 2-30x the diagnosis is built to find stays far
//!   inside; `accel_psd = 1e300` or a GPS of 1e-12 m does not.
//! - **Coefficients** ([`PhysicalBound`], declared beside each effect by
//!   [`crate::Effect::coefficient_bounds`] and for the base ones by
//!   [`base_coefficient_bound`]) may reach about twice (scale factors) to ten times (biases)
//!   the worst real sensor's: a fitted value beyond is a symptom of data that are not what
//!   they claim, not a finding about the instrument.

use crate::state::*;
use std::f64::consts::PI;

/// Standard gravity, m/s^2 (the unit "g" of the datasheets).
const G: f64 = crate::earth::STANDARD_GRAVITY;
/// One degree per hour, rad/s.
const DEG_PER_H: f64 = PI / 180.0 / 3600.0;
/// One degree per root hour (angle random walk), rad/sqrt(s).
const DEG_PER_ROOT_H: f64 = PI / 180.0 / 60.0;
/// One micro-g per root hertz (accelerometer noise density), m/s/sqrt(s).
const MICRO_G_PER_ROOT_HZ: f64 = 1e-6 * G;

/// How far beyond a sensor class's extreme a stated noise level (in sigma) must lie to be no
/// sensor's: two orders of magnitude, against the 2-30x by which a real level is mis-stated.
pub const FAR: f64 = 100.0;

/// One `[noise]` key's bounds: the quietest and the noisiest real sensor, as one-sigma (or
/// root-PSD) values; the key's own value is compared as such (a PSD through its square root).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NoiseBound {
    /// The `[noise]` key.
    pub key: &'static str,
    /// Its unit.
    pub unit: &'static str,
    /// Whether the key is a spectral density (compared through its square root).
    pub psd: bool,
    /// The quietest real sensor's sigma (or root density).
    pub quietest: f64,
    /// The noisiest real sensor's sigma (or root density).
    pub noisiest: f64,
    /// The classes, in words.
    pub classes: &'static str,
}

impl NoiseBound {
    /// The smallest plausible value of the key (in its own unit): [`FAR`] below the quietest.
    pub fn min(&self) -> f64 {
        let s = self.quietest / FAR;
        if self.psd {
            s * s
        } else {
            s
        }
    }
    /// The largest plausible value of the key: [`FAR`] above the noisiest.
    pub fn max(&self) -> f64 {
        let s = self.noisiest * FAR;
        if self.psd {
            s * s
        } else {
            s
        }
    }
}

/// The bounds of every `[noise]` key (module documentation).
pub const NOISE_BOUNDS: [NoiseBound; 5] = [
    NoiseBound {
        key: "gyro_psd",
        unit: "rad^2/s",
        psd: true,
        // 1e-4 deg/sqrt(h): below strategic grade (< 0.002 deg/sqrt(h), El-Sheimy & Youssef)
        // and the project's navigation-grade default (3.4e-4); 10 deg/sqrt(h): consumer MEMS
        // ("several deg/sqrt(h)").
        quietest: 1e-4 * DEG_PER_ROOT_H,
        noisiest: 10.0 * DEG_PER_ROOT_H,
        classes: "angle random walk of 1e-4 deg/sqrt(h) (strategic grade) to 10 deg/sqrt(h) \
                  (consumer MEMS)",
    },
    NoiseBound {
        key: "accel_psd",
        unit: "(m/s^2)^2/s",
        psd: true,
        // 1 ug/sqrt(Hz): navigation-grade servo accelerometers; 1000 ug/sqrt(Hz): the
        // noisiest consumer MEMS datasheets (100-1000).
        quietest: 1.0 * MICRO_G_PER_ROOT_HZ,
        noisiest: 1000.0 * MICRO_G_PER_ROOT_HZ,
        classes: "1 ug/sqrt(Hz) (navigation-grade servo accelerometer) to 1 mg/sqrt(Hz) \
                  (consumer MEMS)",
    },
    NoiseBound {
        key: "odometer_rel",
        unit: "1",
        psd: false,
        // A survey distance-measuring wheel (0.01 %) to a coarse wheel-pulse count (10 %).
        quietest: 1e-4,
        noisiest: 0.1,
        classes: "0.01 % (survey measuring wheel) to 10 % (coarse wheel-pulse count)",
    },
    NoiseBound {
        key: "odometer_floor",
        unit: "m/s",
        psd: false,
        // An encoder's resolution over a second (1 mm/s) to one wheel pulse per second (1 m/s).
        quietest: 1e-3,
        noisiest: 1.0,
        classes: "1 mm/s (encoder resolution) to 1 m/s (one wheel pulse per second)",
    },
    NoiseBound {
        key: "gps_m",
        unit: "m",
        psd: false,
        // RTK carrier phase (1 cm) to stand-alone code positioning in its worst days
        // (selective availability, about 100 m).
        quietest: 0.01,
        noisiest: 100.0,
        classes: "1 cm (RTK) to 100 m (stand-alone GPS under selective availability)",
    },
];

/// The value of `key` in `noise` (a key of [`NOISE_BOUNDS`]).
pub fn noise_value(noise: &crate::NoiseConfig, key: &str) -> Option<f64> {
    Some(match key {
        "gyro_psd" => noise.gyro_psd,
        "accel_psd" => noise.accel_psd,
        "odometer_rel" => noise.odometer_rel,
        "odometer_floor" => noise.odometer_floor,
        "gps_m" => noise.gps_m,
        _ => return None,
    })
}

/// The levels of `noise` that no real sensor has: each bound it leaves, with its value.
pub fn noise_out_of_bounds(
    noise: &crate::NoiseConfig,
) -> impl Iterator<Item = (&'static NoiseBound, f64)> + '_ {
    NOISE_BOUNDS.iter().filter_map(|b| {
        let value = noise_value(noise, b.key)?;
        (!(b.min()..=b.max()).contains(&value)).then_some((b, value))
    })
}

/// Fastest speed (m/s) an odometer of a road vehicle reads: the fastest production road car
/// measured 136 m/s (490 km/h); a wheel turning faster belongs to no road vehicle (and a speed
/// in mm/s or a stuck counter shows as one).
pub const ROAD_SPEED_MAX: f64 = 150.0;

/// The largest magnitude a coefficient takes in any real instrument, with the reason:
/// `|c| <= limit`. Declared beside each effect ([`crate::Effect::coefficient_bounds`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PhysicalBound {
    /// The largest magnitude, in the coefficient's unit.
    pub limit: f64,
    /// Why, in a few words (shown when a value is refused).
    pub reason: &'static str,
}

impl PhysicalBound {
    /// Whether `value` is a real instrument's (false for NaN).
    pub fn contains(&self, value: f64) -> bool {
        value.abs() <= self.limit
    }
}

/// A scale factor, cross-axis coupling or torquer scale (dimensionless): twice the widest
/// tolerance a datasheet gives, +-10 % on a consumer MEMS accelerometer's sensitivity
/// (cross-axis +-2-5 %, gyro sensitivity +-3-6 %); a "scale factor of 100 %" is no sensor's.
pub const SCALE: PhysicalBound = PhysicalBound {
    limit: 0.2,
    reason: "twice the widest datasheet tolerance, +-10 % of a consumer MEMS sensitivity",
};

/// A gyro's constant drift, rad/s: ten times the commercial grade's 0.1 deg/s.
pub const GYRO_DRIFT: PhysicalBound = PhysicalBound {
    limit: 1.0 * 3600.0 * DEG_PER_H,
    reason: "1 deg/s, ten times a commercial-grade MEMS gyro's drift (0.1 deg/s)",
};

/// A gyro's g-dependent drift, rad/s per m/s^2: ten times a consumer MEMS gyro's
/// g-sensitivity (about 0.1 deg/s/g).
pub const GYRO_G_SENSITIVITY: PhysicalBound = PhysicalBound {
    limit: 1.0 * 3600.0 * DEG_PER_H / G,
    reason: "1 deg/s per g, ten times a consumer MEMS gyro's g-sensitivity",
};

/// An accelerometer's bias, m/s^2: the worst datasheet zero-g offset (uncalibrated consumer
/// MEMS, up to about +-150 mg), rounded up to 0.2 g.
pub const ACCEL_BIAS: PhysicalBound = PhysicalBound {
    limit: 0.2 * G,
    reason: "0.2 g, beyond the worst zero-g offset of an uncalibrated consumer MEMS (+-150 mg)",
};

/// An accelerometer's second-order scale error, 1/(m/s^2): 2 % of the reading at 1 g, twice
/// the worst datasheet non-linearity (1 % of full scale).
pub const ACCEL_NONLINEARITY: PhysicalBound = PhysicalBound {
    limit: 0.02 / G,
    reason: "2 % of the reading at 1 g, twice the worst MEMS non-linearity (1 % of full scale)",
};

/// The bound of base coefficient `index` (the 13 constants of docs/model.md eq. (11)), `None`
/// for a navigation state.
pub fn base_coefficient_bound(index: usize) -> Option<PhysicalBound> {
    match index {
        KG0X | KG0Y | KG0Z => Some(GYRO_DRIFT),
        KA0X | KA0Y => Some(ACCEL_BIAS),
        KA1X | KA1Y => Some(SCALE),
        i if (KG0X..KA0X).contains(&i) => Some(GYRO_G_SENSITIVITY),
        _ => None,
    }
}
