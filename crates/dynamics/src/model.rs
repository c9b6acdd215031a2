//! The platform model of `docs/model.md`, assembled at run time from the base terms and a
//! list of effects; one implementation serves the truth simulator and every filter.
//!
//! - sensor errors `eps`, `nab`: docs/model.md eqs. (5), (6) ([`PlatformModel::base_terms`]);
//! - state equations: docs/model.md eqs. (7)-(11) ([`PlatformModel::base_rates`]), their
//!   Jacobian `F` (for docs/model.md eq. (19)), the process noise of docs/model.md eq. (12);
//! - the exact-attitude variant instead: docs/model.md eqs. (44)-(47) ([`crate::attitude`]);
//! - measurement: docs/model.md eq. (13); the effects' terms: docs/model.md eqs. (37)-(43).

use crate::attitude::{exact_jacobian, exact_rates, exact_rates_with, Attitude, Rotation};
use crate::batch_propagation;
use crate::earth::WIE;
use crate::effect::{BlockGroup, DynEffect, MeasurementTerm, NoiseChannel, Partials};
use crate::error::DynamicsError;
use crate::integrate::{propagate_generic, InputWindow, PropagationScratch};
use crate::kinematics::{Input, Kinematics};
use crate::linear_rates::StateLinearRate;
use crate::noise::NoiseConfig;
use crate::real::{Lanes, Real};
use crate::state::*;
use crate::system::SystemModel;
use std::collections::HashSet;

/// The base model plus switched-on effects.
#[derive(Debug)]
pub struct PlatformModel {
    effects: Vec<Box<dyn DynEffect>>,
    offsets: Vec<usize>,
    /// The state indices of each effect's coefficients.
    ranges: Vec<std::ops::Range<usize>>,
    /// Effects whose own code adds rates ([`crate::Effect::add_rates`]).
    rate_effects: Vec<usize>,
    /// Every effect's declared linear rate terms, in the model's order.
    linear_rates: Vec<StateLinearRate>,
    meas_effects: Vec<usize>,
    names: Vec<String>,
    units: Vec<String>,
    noise: Vec<NoiseChannel>,
    linear_measurement: bool,
    dim: usize,
    attitude: Attitude,
}

impl PlatformModel {
    /// The 20-state base model with the given process noise.
    pub fn base(noise: &NoiseConfig) -> Self {
        Self::new(Vec::new(), noise).expect("the base model has no effects to conflict")
    }

    /// Assembles the base model with `effects`, in order. Fails on a duplicated effect or
    /// coefficient name, a malformed effect (names, units, sigmas and bounds of unequal
    /// length), or an effect whose code adds a term its [`crate::Effect::terms`] does not
    /// declare.
    pub fn new(
        effects: Vec<Box<dyn DynEffect>>,
        noise: &NoiseConfig,
    ) -> Result<Self, DynamicsError> {
        let mut names: Vec<String> = BASE_NAMES.iter().map(|s| s.to_string()).collect();
        let mut units: Vec<String> = BASE_UNITS.iter().map(|s| s.to_string()).collect();
        let mut seen_effects = HashSet::new();
        let mut offsets = Vec::with_capacity(effects.len());
        for e in &effects {
            if !seen_effects.insert(e.name().to_string()) {
                return Err(DynamicsError::Effect(format!(
                    "effect `{}` is switched on twice",
                    e.name()
                )));
            }
            let c = e.coefficient_names();
            let bounds = e.coefficient_bounds();
            if e.coefficient_units().len() != c.len()
                || e.coefficient_sigma().len() != c.len()
                || !(bounds.is_empty() || bounds.len() == c.len())
                || bounds.iter().any(|b| !(b.limit > 0.0))
            {
                return Err(DynamicsError::Effect(format!(
                    "effect `{}` gives {} coefficient names, {} units, {} sigmas and {} bounds \
                     (none, or one > 0 per coefficient)",
                    e.name(),
                    c.len(),
                    e.coefficient_units().len(),
                    e.coefficient_sigma().len(),
                    bounds.len()
                )));
            }
            offsets.push(names.len());
            for (name, unit) in c.iter().zip(e.coefficient_units()) {
                if names.iter().any(|n| n == name) {
                    return Err(DynamicsError::Effect(format!(
                        "effect `{}` adds coefficient `{name}`, which the model already has",
                        e.name()
                    )));
                }
                names.push(name.to_string());
                units.push(unit.to_string());
            }
        }
        let dim = names.len();
        let mut channels = vec![
            channel("w_gx", PHI_X, noise.gyro_psd),
            channel("w_gy", PHI_Y, noise.gyro_psd),
            channel("w_gz", PHI_Z, noise.gyro_psd),
            channel("w_ax", V_X, noise.accel_psd),
            channel("w_ay", V_Y, noise.accel_psd),
        ];
        for (e, &off) in effects.iter().zip(&offsets) {
            check_declared_terms(e.as_ref(), off, dim)?;
        }
        for e in &effects {
            for ch in e.process_noise() {
                if ch.state >= dim || !(ch.psd.is_finite() && ch.psd >= 0.0) {
                    return Err(DynamicsError::Effect(format!(
                        "effect `{}` declares noise channel `{}` on state {} with density {}",
                        e.name(),
                        ch.name,
                        ch.state,
                        ch.psd
                    )));
                }
                channels.push(ch);
            }
        }
        let rate_effects = (0..effects.len())
            .filter(|&i| effects[i].terms().rates)
            .collect();
        let linear_rates = effects
            .iter()
            .zip(&offsets)
            .flat_map(|(e, &off)| {
                e.terms().linear_rates.iter().map(move |t| StateLinearRate {
                    row: t.row,
                    state: off + t.coefficient,
                    feature: t.feature,
                })
            })
            .collect();
        let meas_effects = (0..effects.len())
            .filter(|&i| effects[i].terms().measurement != MeasurementTerm::None)
            .collect();
        let linear_measurement = effects
            .iter()
            .all(|e| e.terms().measurement != MeasurementTerm::NonLinear);
        let ranges = effects
            .iter()
            .zip(&offsets)
            .map(|(e, &off)| off..off + e.coefficient_names().len())
            .collect();
        Ok(PlatformModel {
            effects,
            offsets,
            ranges,
            rate_effects,
            linear_rates,
            meas_effects,
            names,
            units,
            noise: channels,
            linear_measurement,
            dim,
            attitude: Attitude::SmallAngle,
        })
    }

    /// The same model with the attitude equations `attitude` (the small-angle form unless
    /// set).
    pub fn with_attitude(mut self, attitude: Attitude) -> Self {
        self.attitude = attitude;
        self
    }
    /// Which attitude equations the model uses.
    pub fn attitude(&self) -> Attitude {
        self.attitude
    }

    /// State dimension: 20 plus the effects' coefficients.
    pub fn dim(&self) -> usize {
        self.dim
    }
    /// The switched-on effects, in state order.
    pub fn effects(&self) -> &[Box<dyn DynEffect>] {
        &self.effects
    }
    /// Index of the first coefficient of effect `i`.
    pub fn effect_offset(&self, i: usize) -> usize {
        self.offsets[i]
    }
    /// Names of the effects, in order.
    pub fn effect_names(&self) -> Vec<String> {
        self.effects.iter().map(|e| e.name().to_string()).collect()
    }
    /// Index of a state by name.
    pub fn index_of(&self, name: &str) -> Option<usize> {
        self.names.iter().position(|n| n == name)
    }
    /// Units of every state.
    pub fn units(&self) -> &[String] {
        &self.units
    }
    /// A typical one-sigma of every coefficient (base and effects), indexed like the state;
    /// `None` for the navigation states.
    pub fn effect_coefficient_sigmas(&self) -> Vec<(usize, f64)> {
        let mut out = Vec::new();
        for (e, &off) in self.effects.iter().zip(&self.offsets) {
            for (j, s) in e.coefficient_sigma().iter().enumerate() {
                out.push((off + j, *s));
            }
        }
        out
    }

    /// Derivative of the seven navigation states (docs/model.md eqs. (8)-(10) plus effects)
    /// at the full state `x`, given its kinematics, for one state: the truth and the EKF.
    /// [`PlatformModel::base_rates`], the effects' declared linear terms
    /// ([`PlatformModel::add_linear_rates`]) and their generic [`crate::Effect::add_rates`] are
    /// the one source: the UKFs' batches call the first two on [`crate::Lanes`] and the third
    /// through [`PlatformModel::add_effect_rates_blocks`].
    // Inlined into its callers, the result stays in registers: returned through memory, its
    // seven scalar stores were read back as vectors, a store-forwarding stall per call.
    #[inline(always)]
    pub fn nav_rates(&self, x: &[f64], k: &Kinematics) -> [f64; NAV_DIM] {
        if self.attitude == Attitude::Exact {
            return exact_rates(k, &self.platform_terms(x, k));
        }
        let mut r = self.base_rates(x, k);
        if self.has_rate_effects() {
            // Through copies: were `r` or `k` passed by address, neither could stay in
            // registers, effects or not.
            let k = *k;
            let mut with = r;
            self.add_effect_rates(x, &k, &mut with);
            r = with;
        }
        r
    }

    /// Whether any switched-on effect adds rates (declared linear terms or its own code).
    #[inline(always)]
    pub fn has_rate_effects(&self) -> bool {
        !self.rate_effects.is_empty() || !self.linear_rates.is_empty()
    }

    /// Whether any switched-on effect declares linear rate terms ([`crate::linear_rates`]).
    #[inline(always)]
    pub fn has_linear_rates(&self) -> bool {
        !self.linear_rates.is_empty()
    }

    /// Whether any switched-on effect adds rates through its own code
    /// ([`crate::Effect::add_rates`]), which the batch reaches only through its vtable.
    #[inline(always)]
    pub fn has_coded_rate_effects(&self) -> bool {
        !self.rate_effects.is_empty()
    }

    /// The base model's platform terms, in the rate rows' places:
    /// `[eps_x, eps_y, eps_z, nab_x, nab_y, L', lambda']`: docs/model.md eqs. (5), (6), (10)
    /// (the gyro drifts, the accelerometer errors and the position rates). Effects add to
    /// these; the attitude variant maps them to the state ([`crate::attitude`]).
    #[inline(always)]
    pub fn base_terms<T: Real>(&self, x: &[T], k: &Kinematics<T>) -> [T; NAV_DIM] {
        let [fx, fy, _] = k.f;
        // Written out rather than through a closure, which the batch path did not inline.
        let c = &x[..BASE_DIM];
        [
            c[KG0X] + c[KG11X] * fx + c[KG12X] * fy,
            c[KG0Y] + c[KG11X + 3] * fx + c[KG12X + 3] * fy,
            c[KG0Z] + c[KG11X + 6] * fx + c[KG12X + 6] * fy,
            c[KA0X] + c[KA1X] * fx,
            c[KA0Y] + c[KA1Y] * fy,
            k.v_y * k.inv_rm,
            k.v_x * k.inv_rn * k.inv_cos,
        ]
    }

    /// The platform terms of the whole model at one state: [`PlatformModel::base_terms`] plus
    /// every effect's.
    #[inline(always)]
    pub fn platform_terms(&self, x: &[f64], k: &Kinematics) -> [f64; NAV_DIM] {
        let mut t = self.base_terms(x, k);
        self.add_effect_rates(x, k, &mut t);
        t
    }

    /// The base model's navigation-state derivatives in the small-angle form
    /// (docs/model.md eqs. (8)-(10)), on one state or a batch: `x` is the full state, `k` its
    /// kinematics.
    #[inline(always)]
    pub fn base_rates<T: Real>(&self, x: &[T], k: &Kinematics<T>) -> [T; NAV_DIM] {
        let [fx, fy, fz] = k.f;
        let [px, py, pz] = k.phi;
        let [w1, w2, w3] = k.w_cmd;
        let [eps_x, eps_y, eps_z, nab_x, nab_y, lat_rate, lon_rate] = self.base_terms(x, k);
        let coriolis = k.sin_l * (2.0 * WIE) + k.v_x * k.tan_over_rn;
        [
            py * w3 - pz * w2 + eps_x,
            pz * w1 - px * w3 + eps_y,
            px * w2 - py * w1 + eps_z,
            coriolis * k.v_y + nab_x + fx + fy * pz - fz * py,
            -coriolis * k.v_x + nab_y + fy + fz * px - fx * pz,
            lat_rate,
            lon_rate,
        ]
    }

    /// Adds the switched-on effects' rate terms to `r`, at one state: the declared linear
    /// terms, then the effects' own code.
    #[inline(always)]
    pub fn add_effect_rates(&self, x: &[f64], k: &Kinematics, r: &mut [f64; NAV_DIM]) {
        self.add_linear_rates(x, k, r);
        for &i in &self.rate_effects {
            let c = &x[self.ranges[i].clone()];
            self.effects[i].add_rates(k, c, r);
        }
    }

    /// Adds the effects' declared linear rate terms ([`crate::linear_rates`]) to `r`, on one
    /// state or a batch: the batch evaluates them inline, with no call per effect.
    #[inline(always)]
    pub fn add_linear_rates<T: Real>(&self, x: &[T], k: &Kinematics<T>, r: &mut [T; NAV_DIM]) {
        if self.linear_rates.is_empty() {
            return;
        }
        // Through copies, as in `nav_rates`: neither `k` nor `r` has its address taken.
        let k = *k;
        let mut with = *r;
        for t in &self.linear_rates {
            t.add(x, &k, &mut with);
        }
        *r = with;
    }

    /// The effects' own rate code ([`crate::Effect::add_rates`]) on a group of batches, one
    /// call per effect (the declared linear terms are not included).
    #[inline(always)]
    pub fn add_effect_rates_blocks(&self, group: &BlockGroup<'_>, r: &mut [[Lanes; NAV_DIM]]) {
        for &i in &self.rate_effects {
            self.effects[i].add_rates_blocks(group, self.ranges[i].clone(), r);
        }
    }

    fn effect_coeffs<'a>(&self, i: usize, x: &'a [f64]) -> &'a [f64] {
        &x[self.ranges[i].clone()]
    }

    /// The rate Jacobian `F` (`NAV_DIM` rows `stride >= dim` apart) given the kinematics.
    // Inlined for the same reason as `nav_rates`: `k` then stays in registers.
    #[inline(always)]
    fn jacobian_with(&self, x: &[f64], k: &Kinematics, jac: &mut [f64], stride: usize) {
        if self.attitude == Attitude::Exact {
            let terms = self.platform_terms(x, k);
            self.exact_jacobian_with(x, k, &terms, &Rotation::new(k.phi), jac, stride);
            return;
        }
        assert!(stride >= self.dim);
        let n = stride;
        jac[..NAV_DIM * n].fill(0.0);
        let [fx, fy, fz] = k.f;
        let [px, py, pz] = k.phi;
        let [w1, w2, w3] = k.w_cmd;
        // d(w_cmd)/dL.
        let dw1_dl = -k.v_y * k.d_inv_rm;
        let dw2_dl = -WIE * k.sin_l + k.v_x * k.d_inv_rn;
        let dw3_dl = WIE * k.cos_l + k.v_x * k.d_tan_over_rn;
        // Each base partial is written once onto the zeros, through row slices at least
        // BASE_DIM long (so with no bounds checks left).
        assert!(n >= BASE_DIM);
        {
            let mut rows = jac[..NAV_DIM * n].chunks_exact_mut(n);
            let row: &mut [&mut [f64]; NAV_DIM] =
                &mut std::array::from_fn(|_| rows.next().expect("NAV_DIM rows"));
            // phi_x' = py w3 - pz w2 + eps_x
            row[PHI_X][PHI_Y] = w3;
            row[PHI_X][PHI_Z] = -w2;
            row[PHI_X][V_X] = py * k.tan_over_rn - pz * k.inv_rn;
            row[PHI_X][LAT] = py * dw3_dl - pz * dw2_dl;
            // phi_y' = pz w1 - px w3 + eps_y
            row[PHI_Y][PHI_X] = -w3;
            row[PHI_Y][PHI_Z] = w1;
            row[PHI_Y][V_X] = -px * k.tan_over_rn;
            row[PHI_Y][V_Y] = -pz * k.inv_rm;
            row[PHI_Y][LAT] = pz * dw1_dl - px * dw3_dl;
            // phi_z' = px w2 - py w1 + eps_z
            row[PHI_Z][PHI_X] = w2;
            row[PHI_Z][PHI_Y] = -w1;
            row[PHI_Z][V_X] = px * k.inv_rn;
            row[PHI_Z][V_Y] = py * k.inv_rm;
            row[PHI_Z][LAT] = px * dw2_dl - py * dw1_dl;
            for a in 0..3 {
                row[PHI_X + a][KG0X + 3 * a] = 1.0;
                row[PHI_X + a][KG11X + 3 * a] = fx;
                row[PHI_X + a][KG12X + 3 * a] = fy;
            }
            // v_x' = coriolis v_y + Ka0x + Ka1x fx + fx + fy pz - fz py
            row[V_X][PHI_Z] = fy;
            row[V_X][PHI_Y] = -fz;
            row[V_X][KA0X] = 1.0;
            row[V_X][KA1X] = fx;
            // v_y' = -coriolis v_x + Ka0y + Ka1y fy + fy + fz px - fx pz
            row[V_Y][PHI_X] = fz;
            row[V_Y][PHI_Z] = -fx;
            row[V_Y][KA0Y] = 1.0;
            row[V_Y][KA1Y] = fy;
            for (r, col, v) in transport_partials(k) {
                row[r][col] = v;
            }
        }
        self.add_effect_rate_partials(x, k, jac, n);
    }

    /// The exact variant's rate Jacobian, given the platform terms and the rotation at `x`.
    #[inline(always)]
    fn exact_jacobian_with(
        &self,
        x: &[f64],
        k: &Kinematics,
        terms: &[f64; NAV_DIM],
        rot: &Rotation<f64>,
        jac: &mut [f64],
        stride: usize,
    ) {
        assert!(stride >= self.dim);
        let n = stride;
        jac[..NAV_DIM * n].fill(0.0);
        // The effects' partials of the platform terms first: the variant maps them.
        self.add_effect_rate_partials(x, k, jac, n);
        let transport = transport_partials(k);
        exact_jacobian(k, terms, rot, &transport, self.has_rate_effects(), jac, n);
    }

    /// Adds the rate effects' partials (of their platform terms) to the `NAV_DIM` rows `n`
    /// apart in `jac`.
    #[inline(always)]
    fn add_effect_rate_partials(&self, x: &[f64], k: &Kinematics, jac: &mut [f64], n: usize) {
        if self.has_rate_effects() {
            let mut p = Partials::new(&mut jac[..NAV_DIM * n], n);
            let k = *k; // a copy, as in `nav_rates`
            for t in &self.linear_rates {
                t.add_partials(x, &k, &mut p);
            }
            for &i in &self.rate_effects {
                let c = self.effect_coeffs(i, x);
                self.effects[i].add_rate_partials(&k, c, self.offsets[i], &mut p);
            }
        }
    }
}

/// The partials both attitude variants share, as `(row, column, value)`: the Coriolis and
/// transport terms of the velocity rows (`+-(2 wie sinL + v_x tanL/RN) v`) and the position
/// rows (`L' = v_y/RM`, `lambda' = v_x/(RN cosL)`), docs/model.md eqs. (9), (10).
#[inline(always)]
fn transport_partials(k: &Kinematics) -> [(usize, usize, f64); 9] {
    let (vx, vy) = (k.v_x, k.v_y);
    let coriolis = 2.0 * WIE * k.sin_l + vx * k.tan_over_rn;
    let dcor_dl = 2.0 * WIE * k.cos_l + vx * k.d_tan_over_rn;
    // d/dL (1/(RN cosL)) = d_inv_rn / cosL + tanL / (RN cosL)
    let sec = k.inv_cos;
    [
        (V_X, V_X, k.tan_over_rn * vy),
        (V_X, V_Y, coriolis),
        (V_X, LAT, dcor_dl * vy),
        (V_Y, V_X, -coriolis - k.tan_over_rn * vx),
        (V_Y, LAT, -dcor_dl * vx),
        (LAT, V_Y, k.inv_rm),
        (LAT, LAT, vy * k.d_inv_rm),
        (LON, V_X, k.inv_rn * sec),
        (LON, LAT, vx * sec * (k.d_inv_rn + k.inv_rn * k.tan_l)),
    ]
}

fn channel(name: &str, state: usize, psd: f64) -> NoiseChannel {
    NoiseChannel {
        name: name.to_string(),
        state,
        psd,
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

    fn meas_dim(&self) -> usize {
        MEAS_DIM
    }

    fn measure(&self, x: &[f64], z: &mut [f64]) {
        let mut out = [x[V_X], x[V_Y], x[LAT], x[LON]];
        if !self.meas_effects.is_empty() {
            let k = Kinematics::new(x, &[0.0; 3]);
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
            let k = Kinematics::new(x, &[0.0; 3]);
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

/// Checks an effect's declared [`crate::Terms`] against its code: at a probe state with
/// every quantity non-zero, an effect that declares no rates must add none, one that declares
/// no measurement term must add none, one that declares no noise must bring no channel.
/// Otherwise the model, which calls only what is declared, would silently drop the term.
fn check_declared_terms(e: &dyn DynEffect, offset: usize, dim: usize) -> Result<(), DynamicsError> {
    let terms = e.terms();
    let count = e.coefficient_names().len();
    let mut x: Vec<f64> = (0..dim).map(|i| 1e-3 * (1.0 + i as f64)).collect();
    x[V_X] = 12.0;
    x[V_Y] = -7.0;
    x[LAT] = 0.8;
    x[LON] = 2.2;
    let k = Kinematics::new(&x, &[0.4, -0.3, 9.8]);
    let c = &x[offset..offset + count];
    let undeclared = |what: &str| {
        DynamicsError::Effect(format!(
            "effect `{}` adds {what} that its `terms()` does not declare; declare it, or the \
             model would drop it",
            e.name()
        ))
    };
    for t in terms.linear_rates {
        if t.row >= NAV_DIM || t.coefficient >= count || t.feature.axis() >= 3 {
            return Err(DynamicsError::Effect(format!(
                "effect `{}` declares a linear rate term {t:?}: its row must be a navigation \
                 state (< {NAV_DIM}), its coefficient one of its {count}, its axis 0, 1 or 2",
                e.name()
            )));
        }
    }
    if !terms.rates {
        let mut r = [0.0; NAV_DIM];
        e.add_rates(&k, c, &mut r);
        if r.iter().any(|&v| v != 0.0) {
            return Err(undeclared("rates"));
        }
    }
    if terms.measurement == MeasurementTerm::None {
        let mut z = [0.0; MEAS_DIM];
        e.add_measurement(&k, c, &mut z);
        if z.iter().any(|&v| v != 0.0) {
            return Err(undeclared("a measurement term"));
        }
    }
    if !terms.noise && !e.process_noise().is_empty() {
        return Err(undeclared("process noise"));
    }
    Ok(())
}
