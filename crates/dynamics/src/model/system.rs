//! The platform model as a [`SystemModel`]: what every filter and the simulator call
//! (docs/model.md eqs. (12), (13)).

use super::PlatformModel;
use crate::attitude::{exact_rates_with, Attitude, Rotation};
use crate::batch_propagation;
use crate::effect::{NoiseChannel, Partials};
use crate::integrate::{InputWindow, PropagationScratch};
use crate::kinematics::{Input, Kinematics};
use crate::state::*;
use crate::system::propagate_generic;
use crate::system::SystemModel;

impl PlatformModel {
    /// [`SystemModel::rates_and_jacobian`], inlined into both copies of
    /// [`crate::dispatch!`].
    #[inline(always)]
    fn rates_and_jacobian_inline(
        &self,
        x: &[f64],
        u: &Input,
        dx: &mut [f64],
        jac: &mut [f64],
        stride: usize,
    ) {
        // One evaluation of the kinematics (a sin_cos and three divisions) for both, and in
        // the exact variant of the platform terms and the rotation.
        let k = Kinematics::new(x, u);
        if self.attitude == Attitude::Exact {
            let terms = self.platform_terms(x, &k);
            let rot = Rotation::new(k.phi);
            dx[..NAV_DIM].copy_from_slice(&exact_rates_with(&k, &terms, &rot));
            self.exact_jacobian_with(x, &k, &terms, &rot, jac, stride);
            return;
        }
        dx[..NAV_DIM].copy_from_slice(&self.nav_rates(x, &k));
        self.jacobian_with(x, &k, jac, stride);
    }
}

impl SystemModel for PlatformModel {
    fn dim(&self) -> usize {
        self.dim
    }
    fn dynamic_dim(&self) -> usize {
        NAV_DIM
    }
    fn noise_channels(&self) -> &[NoiseChannel] {
        &self.noise
    }
    #[inline]
    fn rates(&self, x: &[f64], u: &Input, dx: &mut [f64]) {
        let k = Kinematics::new(x, u);
        dx[..NAV_DIM].copy_from_slice(&self.nav_rates(x, &k));
    }

    fn rate_jacobian(&self, x: &[f64], u: &Input, jac: &mut [f64]) {
        self.jacobian_with(x, &Kinematics::new(x, u), jac, self.dim);
    }

    fn rates_and_jacobian(
        &self,
        x: &[f64],
        u: &Input,
        dx: &mut [f64],
        jac: &mut [f64],
        stride: usize,
    ) {
        // The EKF's 40 evaluations per step, compiled for the CPU (crate::instruction_set).
        crate::dispatch!(self.rates_and_jacobian_inline(x, u, dx, jac, stride))
    }

    fn meas_dim(&self) -> usize {
        MEAS_DIM
    }

    fn measure(&self, x: &[f64], z: &mut [f64]) {
        let mut out = [x[V_X], x[V_Y], x[LAT], x[LON]];
        if !self.meas_effects.is_empty() {
            let k = Kinematics::new(x, &[0.0; crate::kinematics::INPUT_WIDTH]);
            for &i in &self.meas_effects {
                let c = self.effect_coeffs(i, x);
                self.effects[i].add_measurement(&k, c, &mut out);
            }
        }
        z[..MEAS_DIM].copy_from_slice(&out);
    }

    fn measurement_jacobian(&self, x: &[f64], h: &mut [f64]) {
        let n = self.dim;
        h[..MEAS_DIM * n].fill(0.0);
        let mut p = Partials::new(&mut h[..MEAS_DIM * n], n);
        p.add(0, V_X, 1.0);
        p.add(1, V_Y, 1.0);
        p.add(2, LAT, 1.0);
        p.add(3, LON, 1.0);
        if !self.meas_effects.is_empty() {
            let k = Kinematics::new(x, &[0.0; crate::kinematics::INPUT_WIDTH]);
            for &i in &self.meas_effects {
                let c = self.effect_coeffs(i, x);
                self.effects[i].add_measurement_partials(&k, c, self.offsets[i], &mut p);
            }
        }
    }

    fn measurement_is_linear(&self) -> bool {
        self.linear_measurement
    }

    fn state_names(&self) -> Vec<String> {
        self.names.clone()
    }

    fn propagation_scratch(&self, count: usize) -> PropagationScratch {
        let mut scratch = PropagationScratch::default();
        scratch.ensure(self.scratch_len(count));
        scratch.lanes(batch_propagation::scratch_lanes(self.dim));
        scratch
    }

    fn propagate_points(
        &self,
        points: &mut [f64],
        noise: Option<&[f64]>,
        window: &InputWindow,
        scratch: &mut PropagationScratch,
    ) {
        let n = self.dim;
        if points.len() >= n && batch_propagation::applicable(points, n, window, points[LAT]) {
            batch_propagation::propagate(self, points, noise, window, scratch);
        } else {
            let nw = self.noise.len();
            scratch.ensure(self.scratch_len(1));
            for (i, x) in points.chunks_exact_mut(n).enumerate() {
                let w = noise.map(|w| &w[i * nw..(i + 1) * nw]);
                propagate_generic(self, x, w, window, scratch.as_mut_slice());
            }
        }
    }
}
