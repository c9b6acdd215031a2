//! The contract between a model and the filters: a continuous-time state-space model with a
//! known input, additive white process noise on chosen states, and a measurement function.
//!
//! The platform model implements it; so does any test model (a linear one makes every UKF
//! equal to the Kalman filter). Filters are generic over it and never name the platform.

use crate::effect::NoiseChannel;
use crate::integrate::{propagate_one, InputWindow, PropagationScratch};
use crate::kinematics::Input;

/// A continuous-time model `x' = a(x, u) + G w`, `z = h(x) + v` (the platform's:
/// docs/model.md eqs. (12), (13)).
///
/// States `0..dynamic_dim()` have a derivative; the rest are constant between measurements
/// (the error coefficients), except where a noise channel drives them. Buffers are written,
/// never allocated: the caller owns them.
pub trait SystemModel: Send + Sync {
    /// State dimension `n`.
    fn dim(&self) -> usize;
    /// Number of leading states with a non-zero deterministic derivative.
    fn dynamic_dim(&self) -> usize;
    /// The process-noise channels (the columns of `G`).
    fn noise_channels(&self) -> &[NoiseChannel];
    /// Writes the derivative of the dynamic states, `dx.len() == dynamic_dim()`.
    fn rates(&self, x: &[f64], u: &Input, dx: &mut [f64]);
    /// Writes the Jacobian of [`SystemModel::rates`], row-major `dynamic_dim() x dim()`.
    fn rate_jacobian(&self, x: &[f64], u: &Input, jac: &mut [f64]);
    /// [`SystemModel::rates`] and [`SystemModel::rate_jacobian`] at the same point (the EKF
    /// needs both at every RK4 stage), the Jacobian's rows `stride >= dim()` apart in `jac`
    /// (padding columns zeroed). A model may override it to share work between the two.
    fn rates_and_jacobian(
        &self,
        x: &[f64],
        u: &Input,
        dx: &mut [f64],
        jac: &mut [f64],
        stride: usize,
    ) {
        let (d, n) = (self.dynamic_dim(), self.dim());
        assert!(stride >= n && jac.len() >= d * stride);
        self.rates(x, u, dx);
        self.rate_jacobian(x, u, &mut jac[..d * n]);
        // Spread the rows out, last first (they only move right).
        for r in (0..d).rev() {
            jac.copy_within(r * n..(r + 1) * n, r * stride);
            jac[r * stride + n..(r + 1) * stride].fill(0.0);
        }
    }
    /// Measurement dimension.
    fn meas_dim(&self) -> usize;
    /// Writes the noise-free measurement `h(x)`.
    fn measure(&self, x: &[f64], z: &mut [f64]);
    /// Writes `h` of `count = points.len() / dim()` states stored one after another into
    /// `z`, `meas_dim()` values each (a UKF's sigma points). The default calls
    /// [`SystemModel::measure`] point by point; a model may override it with a batched
    /// evaluation that gives the same bits.
    fn measure_points(&self, points: &[f64], z: &mut [f64]) {
        let (n, nz) = (self.dim(), self.meas_dim());
        for (x, z) in points.chunks_exact(n).zip(z.chunks_exact_mut(nz)) {
            self.measure(x, z);
        }
    }
    /// Writes the Jacobian of `h`, row-major `meas_dim() x dim()`.
    fn measurement_jacobian(&self, x: &[f64], h: &mut [f64]);
    /// Whether `h` is linear (then its Jacobian is constant and exact).
    fn measurement_is_linear(&self) -> bool;
    /// Names of the states, for reports and datasets.
    fn state_names(&self) -> Vec<String>;

    /// Scratch length [`SystemModel::propagate_points`] needs for `count` points.
    fn scratch_len(&self, count: usize) -> usize {
        let _ = count;
        4 * self.dynamic_dim() + self.dim()
    }

    /// Scratch for [`SystemModel::propagate_points`] on up to `count` points, allocated now so
    /// that propagating never allocates.
    fn propagation_scratch(&self, count: usize) -> PropagationScratch {
        let mut scratch = PropagationScratch::default();
        scratch.ensure(self.scratch_len(count));
        scratch
    }

    /// Propagates `count = points.len() / dim()` states, stored one after another, across
    /// the input window with RK4 (one sub-step per pair of knots). `noise`, when given, holds
    /// `noise_channels().len()` white-noise values per point, held constant over the window.
    ///
    /// The default runs [`propagate_generic`] point by point; a model may
    /// override it with a faster batched evaluation that must agree to rounding.
    fn propagate_points(
        &self,
        points: &mut [f64],
        noise: Option<&[f64]>,
        window: &InputWindow,
        scratch: &mut PropagationScratch,
    ) {
        let n = self.dim();
        let nw = self.noise_channels().len();
        scratch.ensure(self.scratch_len(1));
        for (i, x) in points.chunks_exact_mut(n).enumerate() {
            let w = noise.map(|w| &w[i * nw..(i + 1) * nw]);
            propagate_generic(self, x, w, window, scratch.as_mut_slice());
        }
    }
}

/// Propagates one state `x` of `model` across `window` with RK4
/// ([`crate::integrate::propagate_one`] with the model's rates). `scratch` must hold at least
/// `4 * dynamic_dim + dim` values. `noise`, when given, holds one value per noise channel.
pub fn propagate_generic<M: SystemModel + ?Sized>(
    model: &M,
    x: &mut [f64],
    noise: Option<&[f64]>,
    window: &InputWindow,
    scratch: &mut [f64],
) {
    debug_assert_eq!(x.len(), model.dim());
    propagate_one(
        |x, u, dx| model.rates(x, u, dx),
        model.dynamic_dim(),
        model.noise_channels(),
        x,
        noise,
        window,
        scratch,
    );
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{NoiseChannel, NoiseConfig, PlatformModel};

    /// The platform model through the trait's default `rates_and_jacobian`.
    struct Defaults(PlatformModel);
    impl SystemModel for Defaults {
        fn dim(&self) -> usize {
            self.0.dim()
        }
        fn dynamic_dim(&self) -> usize {
            self.0.dynamic_dim()
        }
        fn noise_channels(&self) -> &[NoiseChannel] {
            self.0.noise_channels()
        }
        fn rates(&self, x: &[f64], u: &Input, dx: &mut [f64]) {
            self.0.rates(x, u, dx)
        }
        fn rate_jacobian(&self, x: &[f64], u: &Input, jac: &mut [f64]) {
            self.0.rate_jacobian(x, u, jac)
        }
        fn meas_dim(&self) -> usize {
            self.0.meas_dim()
        }
        fn measure(&self, x: &[f64], z: &mut [f64]) {
            self.0.measure(x, z)
        }
        fn measurement_jacobian(&self, x: &[f64], h: &mut [f64]) {
            self.0.measurement_jacobian(x, h)
        }
        fn measurement_is_linear(&self) -> bool {
            true
        }
        fn state_names(&self) -> Vec<String> {
            self.0.state_names()
        }
    }

    #[test]
    fn strided_rates_and_jacobian_match_the_plain_ones() {
        let model = PlatformModel::base(&NoiseConfig::default());
        let (d, n) = (model.dynamic_dim(), model.dim());
        let x: Vec<f64> = (0..n).map(|i| 1e-4 * (i as f64 + 1.0)).collect();
        let u = crate::kinematics::platform_input([0.3, -0.2, 9.8]);
        let mut jac = vec![0.0; d * n];
        let mut dx = vec![0.0; d];
        model.rate_jacobian(&x, &u, &mut jac);
        model.rates(&x, &u, &mut dx);
        let stride = n + 5;
        for m in [
            &model as &dyn SystemModel,
            &Defaults(PlatformModel::base(&NoiseConfig::default())),
        ] {
            let mut js = vec![f64::NAN; d * stride];
            let mut dxs = vec![0.0; d];
            m.rates_and_jacobian(&x, &u, &mut dxs, &mut js, stride);
            assert_eq!(dxs, dx);
            for r in 0..d {
                assert_eq!(&js[r * stride..r * stride + n], &jac[r * n..(r + 1) * n]);
                assert!(js[r * stride + n..(r + 1) * stride]
                    .iter()
                    .all(|&v| v == 0.0));
            }
        }
    }
}
