//! Seeded random streams. Every random number of a run comes from a ChaCha stream keyed by
//! (study seed, purpose) with the run index as its stream number, so a run's data never
//! depend on which thread made it, in what order, or how many other runs there are.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// What a stream is for; each purpose gets an independent key.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Purpose {
    /// The true coefficients' draw.
    Coefficients,
    /// The true initial navigation state (platform tilt).
    InitialState,
    /// Process noise of the truth integration.
    ProcessNoise,
    /// Odometer and GPS noise.
    MeasurementNoise,
    /// Anything a caller needs beyond these, numbered.
    Other(u32),
}

impl Purpose {
    fn code(self) -> u64 {
        match self {
            Purpose::Coefficients => 1,
            Purpose::InitialState => 2,
            Purpose::ProcessNoise => 3,
            Purpose::MeasurementNoise => 4,
            Purpose::Other(k) => 0x1_0000_0000 + k as u64,
        }
    }
}

/// The stream for (`seed`, `run`, `purpose`).
///
/// ```
/// use navkf_dynamics::rng::{stream, Purpose};
/// use rand::Rng;
/// let a: u64 = stream(7, 3, Purpose::ProcessNoise).gen();
/// let b: u64 = stream(7, 3, Purpose::ProcessNoise).gen();
/// let c: u64 = stream(7, 4, Purpose::ProcessNoise).gen();
/// assert_eq!(a, b);
/// assert_ne!(a, c);
/// ```
pub fn stream(seed: u64, run: u64, purpose: Purpose) -> ChaCha8Rng {
    let mut key = [0u8; 32];
    key[..8].copy_from_slice(&seed.to_le_bytes());
    key[8..16].copy_from_slice(&purpose.code().to_le_bytes());
    key[16..24].copy_from_slice(b"navkf-v1");
    let mut rng = ChaCha8Rng::from_seed(key);
    rng.set_stream(run);
    rng
}
