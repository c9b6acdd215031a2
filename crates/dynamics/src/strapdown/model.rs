//! The strapdown family's base model as a [`SystemModel`], so the filters run it as they run
//! the platform: the 13 states, the rates of docs/model.md eqs. (51)-(58) driven by the unit's
//! readings, and the measurement of docs/model.md eqs. (59), (60) (odometer speed, GPS
//! position, and the non-holonomic constraint).
//!
//! **Input.** Each [`Input`] sample holds the body rate `w` (rad/s) in its first three numbers
//! and the specific force `f` (m/s^2) in the next three, body FLU axes, as `imu.csv` does.
//!
//! **Process noise.** The gyro and accelerometer white noises enter through the corrected
//! rate and force (docs/model.md eq. (50)). Resolved in n, an accelerometer noise of density
//! `q_a` per body axis is `q_a` per horizontal axis whatever the attitude (a rotation keeps an
//! isotropic covariance), so `v_e`, `v_n` each get a channel of density `q_a`. The gyro noise
//! reaches the angle rates through the Euler-rate map of docs/model.md eqs. (54), (55), which is
//! `D` (a sign per axis) at level and turns the noise by the tilt's size otherwise; the model
//! gives roll, pitch and heading a channel of density `q_g` each, exact at level and off by
//! terms of the order of the squared tilt for a road vehicle's few degrees.
//!
//! **Jacobians.** The rates and the measurement are written once over [`Real`]. The
//! measurement's Jacobian is that source on dual numbers ([`crate::dual`]); the rates', taken
//! at every RK4 stage of the EKF's step, is written out ([`super::jacobian`]) and held to the
//! dual-number one by the tests.

use super::attitude::angle_trig;
use super::effect_list::StrapdownEffectList;
use super::effect_rates::rates_with_effects;
use super::effects::{StrapdownEffect, Triad};
use super::errors::{measurement_with, ErrorLayout};
use super::jacobian::{nav_rate_jacobian_analytic, nav_rate_jacobian_with};
pub use super::measurement::{measurement, MEASUREMENT_NAMES, MEAS_DIM};
use super::rates::{imu_of, nav_rates, nav_rates_with};
use super::state::*;
use super::tangent;
use super::unit_class::{UnitClass, UnitErrors};
use crate::dual::Dual;
use crate::effect::NoiseChannel;
use crate::error::DynamicsError;
use crate::integrate::{InputWindow, PropagationScratch};
use crate::kinematics::Input;
use crate::noise::NoiseConfig;
use crate::system::SystemModel;

/// The strapdown model (module documentation): the base states and the coefficients of
/// its effects ([`super::effects`]).
#[derive(Debug, Clone)]
pub struct StrapdownModel {
    noise: Vec<NoiseChannel>,
    unit: UnitErrors,
    effects: Vec<StrapdownEffect>,
    layout: ErrorLayout,
    /// Typical one-sigma of each state after the base ones (the bias departures' steady
    /// sigma, then each effect coefficient's), in state order.
    coefficient_sigma: Vec<f64>,
    /// The unit class's typical steady sigma of each bias departure, in state order.
    departure_typical: Vec<f64>,
}

impl StrapdownModel {
    /// The base model with the process noise of `noise` (`gyro_psd`, `accel_psd`).
    pub fn base(noise: &NoiseConfig) -> Self {
        let channel = |name: &str, state, psd| NoiseChannel {
            name: name.into(),
            state,
            psd,
        };
        StrapdownModel {
            noise: vec![
                channel("w_roll", ROLL, noise.gyro_psd),
                channel("w_pitch", PITCH, noise.gyro_psd),
                channel("w_heading", HEADING, noise.gyro_psd),
                channel("w_ve", V_E, noise.accel_psd),
                channel("w_vn", V_N, noise.accel_psd),
            ],
            unit: UnitClass::default().errors(),
            effects: Vec::new(),
            layout: ErrorLayout::default(),
            coefficient_sigma: Vec::new(),
            departure_typical: Vec::new(),
        }
    }

    /// The model with the bias sizes of `unit` as its typical biases (the priors a study
    /// draws and filters start from; the dynamics do not depend on them).
    pub fn with_unit(mut self, unit: UnitErrors) -> Self {
        self.unit = unit;
        self
    }

    /// The model with `list`'s effects switched on: their coefficients join the state after
    /// the base states, typical sizes those of `class` times `scale`; a bias instability
    /// adds its triad's three departures from the turn-on biases, which follow a Gauss-Markov
    /// law (docs/model.md eq. (69)) with the list's parameters or the class's defaults, their
    /// typical size the law's steady sigma (not scaled: it is the law's, not a prior's).
    pub fn with_effects(
        mut self,
        list: &StrapdownEffectList,
        class: UnitClass,
        scale: f64,
    ) -> Result<Self, DynamicsError> {
        let law = |triad| list.instability(triad, class);
        let layout = ErrorLayout::new(&list.effects, |t| 1.0 / law(t).map_or(1.0, |l| l.0))
            .map_err(DynamicsError::Effect)?;
        let mut sigmas = Vec::new();
        let mut typical = Vec::new();
        for (triad, wander) in [
            (Triad::Gyro, layout.gyro_wander),
            (Triad::Accel, layout.accel_wander),
        ] {
            if let (Some(w), Some((time_s, sigma))) = (wander, law(triad)) {
                let class_sigma = list
                    .effects
                    .iter()
                    .filter_map(|e| e.instability)
                    .find(|l| l.triad == triad)
                    .map(|l| l.sigma_for(class));
                let prefix = match triad {
                    Triad::Gyro => "w_dbg",
                    Triad::Accel => "w_dba",
                };
                for (a, axis) in ["x", "y", "z"].iter().enumerate() {
                    self.noise.push(NoiseChannel {
                        name: format!("{prefix}{axis}"),
                        state: w.first + a,
                        psd: 2.0 * sigma * sigma / time_s,
                    });
                    sigmas.push(sigma);
                    typical.extend(class_sigma);
                }
            }
        }
        sigmas.extend(
            list.effects
                .iter()
                .flat_map(|e| e.coefficients.iter().map(|c| c.sigma_for(class) * scale)),
        );
        self.coefficient_sigma = sigmas;
        self.departure_typical = typical;
        self.effects = list.effects.clone();
        self.layout = layout;
        Ok(self)
    }

    /// The typical bias sizes.
    pub fn unit(&self) -> UnitErrors {
        self.unit
    }

    /// The effects switched on, in state order.
    pub fn effects(&self) -> &[StrapdownEffect] {
        &self.effects
    }

    /// The user's declarations among the effects, in state order.
    pub fn declarations(&self) -> Vec<crate::declared::EffectDeclaration> {
        self.effects
            .iter()
            .filter_map(|e| e.declaration.as_deref().cloned())
            .collect()
    }

    /// Where the effects' coefficients act.
    pub fn layout(&self) -> &ErrorLayout {
        &self.layout
    }

    /// The unit class's typical steady sigma when state `i` is a bias departure: the
    /// departure's prior in a fit ([`crate::family::FamilyModel::typical_sigma`]). A fit
    /// that tries densities keeps it whatever the density tried: at the start a departure
    /// cannot be told from its turn-on bias, whose own prior covers how far off the bias
    /// is, so the density measures how fast the bias wanders, not how far it starts. Tied to
    /// the density instead, a correlation time far from the one declared made the two halves
    /// of a drive fit densities four times apart (a true instability withdrawn as a
    /// stand-in, `crates/diagnose/tests/strapdown_diagnosis.rs`).
    pub fn departure_typical(&self, i: usize) -> Option<f64> {
        i.checked_sub(BASE_DIM)
            .and_then(|k| self.departure_typical.get(k).copied())
    }

    /// Typical one-sigma of state `i` when it is a bias departure (its law's steady sigma, the
    /// simulator's draw) or an effect coefficient.
    pub fn coefficient_sigma(&self, i: usize) -> Option<f64> {
        i.checked_sub(BASE_DIM)
            .and_then(|k| self.coefficient_sigma.get(k).copied())
    }

    /// The names of the bias departures the model carries, in state order.
    pub fn departure_names(&self) -> impl Iterator<Item = &'static str> {
        let gyro = self.layout.gyro_wander.map(|_| GYRO_DEPARTURE_NAMES.iter());
        let accel = self
            .layout
            .accel_wander
            .map(|_| ACCEL_DEPARTURE_NAMES.iter());
        gyro.into_iter().chain(accel).flatten().copied()
    }

    fn plain(&self) -> bool {
        self.effects.is_empty()
    }
}

impl StrapdownModel {
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
        let imu = imu_of(u);
        if !self.plain() {
            rates_with_effects(&self.layout, x, &imu, dx);
            let dynamic = self.dynamic_dim();
            return tangent::rate_jacobian(&self.layout, dynamic, x, &imu, jac, stride);
        }
        let trig = angle_trig([x[ROLL], x[PITCH], x[HEADING]]);
        let lat = crate::trig::sin_cos_angle(x[LAT]);
        nav_rates_with(x, &imu, &trig, lat, dx);
        nav_rate_jacobian_with(x, &imu, &trig, lat, jac, stride);
    }
}

impl SystemModel for StrapdownModel {
    fn dim(&self) -> usize {
        BASE_DIM + self.coefficient_sigma.len()
    }
    fn dynamic_dim(&self) -> usize {
        self.layout.dynamic_dim()
    }
    fn noise_channels(&self) -> &[NoiseChannel] {
        &self.noise
    }
    fn rates(&self, x: &[f64], u: &Input, dx: &mut [f64]) {
        if self.plain() {
            nav_rates(x, &imu_of(u), dx);
        } else {
            rates_with_effects(&self.layout, x, &imu_of(u), dx);
        }
    }
    fn rate_jacobian(&self, x: &[f64], u: &Input, jac: &mut [f64]) {
        if self.plain() {
            nav_rate_jacobian_analytic(x, &imu_of(u), jac);
        } else {
            let dynamic = self.dynamic_dim();
            tangent::rate_jacobian(&self.layout, dynamic, x, &imu_of(u), jac, x.len());
        }
    }
    /// The rates and their Jacobian from one evaluation of the angles' and the latitude's
    /// sines and cosines (the EKF asks for both at every RK4 stage).
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
        measurement_with(&self.layout, x, z);
    }
    fn measure_points(&self, points: &[f64], z: &mut [f64]) {
        super::batch_measurement::measure_blocks(&self.layout, self.dim(), points, z);
    }
    fn measurement_jacobian(&self, x: &[f64], h: &mut [f64]) {
        if !self.plain() {
            return tangent::measurement_jacobian(&self.layout, x, h);
        }
        let xd: [Dual<BASE_DIM>; BASE_DIM] = std::array::from_fn(|i| Dual::variable(x[i], i));
        let mut z = [Dual::<BASE_DIM>::constant(0.0); MEAS_DIM];
        measurement(&xd, &mut z);
        for (r, row) in z.iter().enumerate() {
            h[r * BASE_DIM..(r + 1) * BASE_DIM].copy_from_slice(&row.d);
        }
    }
    fn measurement_is_linear(&self) -> bool {
        false
    }
    fn state_names(&self) -> Vec<String> {
        let coefficients = self.effects.iter().flat_map(|e| e.coefficients.iter());
        STATE_NAMES
            .iter()
            .copied()
            .chain(self.departure_names())
            .map(|s| s.to_string())
            .chain(coefficients.map(|c| c.name.to_string()))
            .collect()
    }
    fn propagate_points(
        &self,
        points: &mut [f64],
        noise: Option<&[f64]>,
        window: &InputWindow,
        _scratch: &mut PropagationScratch,
    ) {
        if self.plain() {
            super::batch::propagate_blocks(points, noise, &self.noise, window);
        } else {
            let dim = self.dim();
            super::batch::propagate_blocks_with(
                &self.layout,
                dim,
                points,
                noise,
                &self.noise,
                window,
            );
        }
    }
}
