//! The vehicle body's small motion about its path: sideslip and bounce.
//!
//! **Why.** The strapdown truth is a rigid vehicle held to its road: level, heading along its
//! velocity, so its lateral and vertical body velocities are exactly zero. A real car's are
//! not: its body slides a little sideways on its tyres and pitches on its springs. The
//! non-holonomic constraint's stated sigma `nhc_m_s` (docs/model.md eq. (60)) stands for that
//! motion. A study's runs meet it as drawn constraint readings ([`crate::dataset::Measurement::nhc`]),
//! but a file has no column for them: a recording's constraint readings are zero, and the
//! vehicle must carry the motion itself. Without it, a written dataset's constraint holds to
//! the millimetre, and a diagnosis rightly finds the stated sigma thousands of times too
//! large. [`BodyMotion`] is that motion, for the datasets the simulator writes.
//!
//! **What.** Two random body velocities, lateral `u(t)` and vertical `w(t)`, each a
//! uniform cubic B-spline whose coefficients, [`KNOT_S`] apart, are independent normal
//! draws, scaled so that its mean square is `sigma^2`. Such a spline's autocorrelation is the
//! seventh-order B-spline, zero beyond four knot spacings: with knots a quarter second apart
//! its content lies below about 1.5 Hz (a car body's modes on its tyres and springs), and its
//! samples one second apart, the odometer's, are independent. The constraint's readings then
//! meet exactly the white noise its sigma describes. (A sum of a few sinusoids would not do:
//! those near a multiple of 1 Hz alias to near zero frequency, and the samples stay
//! correlated for minutes; nor would a white-noise-driven oscillator: its acceleration is
//! rough, and readings sampled at 100 Hz integrate to an attitude that wanders off the
//! truth's.) The spline is twice differentiable, so readings sampled well above its content
//! (100 Hz) integrate back to its angles to micro-radians.
//!
//! The body turns to carry the velocities: a heading offset `beta = u k(v)` (sideslip) and a
//! pitch `theta = w k(v)` (bounce), where `v` is the speed and `k(v) = v / (v^2 + v_c^2)`,
//! `v_c` [`TAPER_M_S`]. When cruising the body velocities are nearly `u` and `w` (0.9 of
//! them at 15 m/s, half at `v_c`); a standing car neither slides nor pitches; and the angles
//! are largest at `v_c`, `sigma / (2 v_c)`, 0.6 deg at the default 0.1 m/s. A steeper taper
//! (`1/v` above 5 m/s, `v / v_c^2` below) doubled that peak, and 100 Hz readings integrated
//! (linearly interpolated, as the filters take them) to a pitch and roll off by 5e-5 rad and a
//! position 66 m off the path in 900 s; this one leaves 1.4e-5 rad and 3 m, an acceleration
//! error of 1e-5 m/s^2, far below any unit's bias. The path itself (position, velocity) is
//! unchanged; the unit's readings are
//! those of the turned body ([`super::simulate`]). Every number comes from one stream of the
//! run, so the motion is as reproducible as the rest of the run, and the same whatever the
//! IMU's rate.

use crate::trajectory::PathState;
use rand::Rng;
use rand_distr::StandardNormal;

/// The spacing of the splines' knots, s: a quarter of the odometer's second, so that its
/// samples are independent.
pub const KNOT_S: f64 = 0.25;
/// The speed at which the body's angles are largest, m/s; well above it the body velocities
/// are `u` and `w`, below it they fall off with the square of the speed.
pub const TAPER_M_S: f64 = 5.0;
/// The largest root-mean-square body velocity a simulator takes, m/s. A car's sideslip and
/// bounce are centimetres a second; beyond a metre a second the angles (up to
/// `sigma / (2 TAPER_M_S)`, 0.1 rad here) are no longer small, and a value this large is
/// more likely a unit's mistake (cm/s given as m/s) than a vehicle.
pub const MAX_SIGMA_M_S: f64 = 1.0;

/// `integral of B3(x)^2 dx` for the uniform cubic B-spline `B3`: a spline with coefficients
/// of unit variance has this mean square.
const MEAN_SQUARE: f64 = 151.0 / 315.0;

/// One drawn velocity: a uniform cubic B-spline's coefficients, the first at `-2 KNOT_S`.
#[derive(Debug, Clone)]
struct Spline(Vec<f64>);

impl Spline {
    /// Draws coefficients covering `[0, duration]`, for a mean square `sigma^2`.
    fn draw(sigma: f64, duration: f64, rng: &mut impl Rng) -> Self {
        let scale = sigma / MEAN_SQUARE.sqrt();
        let knots = (duration.max(0.0) / KNOT_S).ceil() as usize + 5;
        Spline(
            (0..knots)
                .map(|_| scale * rng.sample::<f64, _>(StandardNormal))
                .collect(),
        )
    }

    /// The value and its time derivative at `t` (clamped to the drawn span).
    fn at(&self, t: f64) -> (f64, f64) {
        let last = self.0.len() - 4;
        // Coefficient k is centred on (k - 2) KNOT_S; the segment [j, j + 1) KNOT_S is
        // shaped by those centred on j - 1 .. j + 2, coefficients j + 1 .. j + 4.
        let x = (t / KNOT_S).max(0.0) + 1.0;
        let k = (x.floor() as usize).min(last);
        let s = (x - k as f64).min(1.0);
        let r = 1.0 - s;
        let (s2, s3) = (s * s, s * s * s);
        let basis = [
            r * r * r / 6.0,
            (3.0 * s3 - 6.0 * s2 + 4.0) / 6.0,
            (-3.0 * s3 + 3.0 * s2 + 3.0 * s + 1.0) / 6.0,
            s3 / 6.0,
        ];
        let slope = [
            -r * r / 2.0,
            (3.0 * s2 - 4.0 * s) / 2.0,
            (-3.0 * s2 + 2.0 * s + 1.0) / 2.0,
            s2 / 2.0,
        ];
        let c = &self.0[k..k + 4];
        let value = (0..4).map(|i| c[i] * basis[i]).sum();
        let rate = (0..4).map(|i| c[i] * slope[i]).sum::<f64>() / KNOT_S;
        (value, rate)
    }
}

/// The body's offsets from the rigid vehicle at one time.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct BodyOffsets {
    /// Pitch (bounce), rad, positive nose up.
    pub pitch: f64,
    /// The heading's offset from the path's (sideslip), rad, clockwise from above.
    pub heading: f64,
    /// `pitch`'s rate, rad/s.
    pub pitch_rate: f64,
    /// `heading`'s rate, rad/s.
    pub heading_rate: f64,
}

/// One run's sideslip and bounce (module documentation).
#[derive(Debug, Clone)]
pub struct BodyMotion {
    lateral: Spline,
    vertical: Spline,
}

impl BodyMotion {
    /// Draws the motion over `[0, duration]` s from `rng`, with body velocities of
    /// root-mean-square `sigma_m_s` each at cruising speed.
    pub fn draw(sigma_m_s: f64, duration: f64, rng: &mut impl Rng) -> Self {
        BodyMotion {
            lateral: Spline::draw(sigma_m_s, duration, rng),
            vertical: Spline::draw(sigma_m_s, duration, rng),
        }
    }

    /// The body's offsets at time `t`, where the path's state is `st`.
    pub fn offsets(&self, t: f64, st: &PathState) -> BodyOffsets {
        let speed = st.speed.abs();
        // d|speed|/dt: the acceleration along the track, signed with the speed.
        let (sh, ch) = st.heading.sin_cos();
        let along = (st.a[0] * sh + st.a[1] * ch) * st.speed.signum();
        let (v2, c2) = (speed * speed, TAPER_M_S * TAPER_M_S);
        let k = speed / (v2 + c2);
        let dk = (c2 - v2) / (v2 + c2).powi(2);
        let (u, du) = self.lateral.at(t);
        let (w, dw) = self.vertical.at(t);
        BodyOffsets {
            pitch: w * k,
            heading: u * k,
            pitch_rate: dw * k + w * dk * along,
            heading_rate: du * k + u * dk * along,
        }
    }
}
