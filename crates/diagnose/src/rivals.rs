//! Explanations outside the catalogue that a candidate must beat before it is named: a walk
//! of the other sensor and, on the platform, accelerometer biases settling after switch-on
//! ([`AccelSettling`]) for a noise-only term, a GPS antenna away from the platform for a
//! latency ([`GpsAntennaOffset`]), and an acceleration error depending on the velocity for the
//! refitted noise levels ([`VelocityDependentAcceleration`]).
//!
//! A noise-only term fitted by maximum likelihood can soak up any slow misfit: a random walk
//! of the gyro drifts (`gyro-bias-walk`) tracks a drag, a warming-up accelerometer bias, a
//! torquer scale error. Whether the data single out the *gyros* is a question the data can
//! answer, because a gyro drift reaches the velocity through the tilt (`g phi`, one more
//! integration) and an accelerometer error reaches it directly: the two random walks give
//! velocity errors of different spectral shapes. So before naming `gyro-bias-walk`, the
//! diagnosis fits the same walk on the accelerometer biases ([`AccelBiasWalk`], not in the
//! catalogue, never named), and names the gyro walk only if it fits decisively better. When
//! it does not, the report says that a slow drift is there and that the data cannot say
//! where it comes from. A walk also follows a bias that changes along a smooth curve, as an
//! instrument warming up does, and the accelerometer walk does not always fit that as well;
//! so the settling itself is fitted too, and the gyro walk must beat it on the BIC.
//!
//! Refitted noise levels cover more still: a gyro noise put hundreds of times above its
//! stated level lets the tilt wander wherever the velocity errors ask. On the platform's
//! error-rate study, 22 of 60 drags (`v' -= kd v`, 3-29 times a tenth of the accelerometer
//! bias at 15 m/s) ended `consistent` with the gyro noise refitted at 82-711 times the level
//! the data were made with. So before the levels are named, an acceleration error that
//! depends on the velocity ([`VelocityDependentAcceleration`]: linear in it along any
//! direction, a bias growing with speed, a quadratic drag) is fitted as their rival, and the
//! levels must beat it on the BIC. Rivals of fewer laws let errors of the other laws through
//! (its module has the measurement). It does not cover every shape: out of sample, a North
//! error proportional to the East velocity times the speed still passed for noise once in
//! two (docs/diagnosis.md, "Rounds"). A noise truly mis-stated leaves little for seven
//! coefficients of structure to take (docs/diagnosis.md has the measurement on the study's
//! MEMS units).

mod accel_settling;
mod gps_antenna_offset;
mod velocity_dependent_acceleration;

pub use accel_settling::{with_elapsed_time, AccelSettling};
pub use gps_antenna_offset::GpsAntennaOffset;
pub use velocity_dependent_acceleration::VelocityDependentAcceleration;

use navkf_dynamics::effect::Terms;
use navkf_dynamics::state::{KA0X, KA0Y};
use navkf_dynamics::{Effect, NoiseChannel};

/// Random walks of the accelerometer biases `Ka0x`, `Ka0y` of density `q` ((m/s^2)^2/s).
#[derive(Debug, Clone)]
pub struct AccelBiasWalk {
    /// The density.
    pub psd: f64,
}

impl AccelBiasWalk {
    /// The catalogue name.
    pub const NAME: &'static str = "accel-bias-walk";
    /// Typical density: the bias wanders by `sqrt(q T)` = 1e-4 m/s^2 (10 micro-g) over a
    /// 2400 s test.
    pub const DEFAULT_PSD: f64 = 4.0e-12;
}

impl Default for AccelBiasWalk {
    fn default() -> Self {
        AccelBiasWalk {
            psd: Self::DEFAULT_PSD,
        }
    }
}

impl Effect for AccelBiasWalk {
    fn name(&self) -> &str {
        Self::NAME
    }
    fn description(&self) -> &str {
        "Ka0x, Ka0y wander as random walks of density q ((m/s^2)^2/s) (outside the catalogue)"
    }
    fn terms(&self) -> Terms {
        Terms::NOISE
    }
    fn process_noise(&self) -> Vec<NoiseChannel> {
        [("w_ax0", KA0X), ("w_ay0", KA0Y)]
            .iter()
            .map(|(name, state)| NoiseChannel {
                name: name.to_string(),
                state: *state,
                psd: self.psd,
            })
            .collect()
    }
    fn set_parameter(&mut self, value: f64) -> Result<(), String> {
        if value.is_finite() && value >= 0.0 {
            self.psd = value;
            Ok(())
        } else {
            Err(format!(
                "accel-bias-walk density {value}: expected a finite q >= 0"
            ))
        }
    }
}
