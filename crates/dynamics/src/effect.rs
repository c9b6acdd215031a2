//! The effect trait: one physical term the base model leaves out, switchable at run time.
//!
//! An effect owns named coefficients (random constants that join the state after the 20 base
//! states when the effect is switched on), and may add to the navigation-state derivatives,
//! to the measurement, or to the process noise. It supplies the partial derivatives of what it
//! adds, which the EKF needs; the test suite checks every effect's partials against finite
//! differences. The catalogue of model.md lives in [`crate::effects`]; a user writes a new
//! effect by implementing this trait in their own crate and passing it to
//! [`crate::PlatformModel::new`] or registering it in an [`crate::effects::Registry`].

use crate::kinematics::Kinematics;
use crate::state::{MEAS_DIM, NAV_DIM};
use std::fmt;

/// A white process-noise channel: it drives the derivative of one state with the given
/// spectral density.
#[derive(Debug, Clone, PartialEq)]
pub struct NoiseChannel {
    /// Name used in reports, e.g. `w_gx`.
    pub name: String,
    /// Index of the state whose derivative it drives.
    pub state: usize,
    /// Spectral density, (state unit)^2 / s.
    pub psd: f64,
}

/// Rows of partial derivatives with respect to the full state, row-major, `cols` wide.
///
/// For rate partials the rows are the 7 navigation-state derivatives; for measurement partials
/// they are the 4 measurement channels.
pub struct Partials<'a> {
    data: &'a mut [f64],
    cols: usize,
}

impl<'a> Partials<'a> {
    /// Wraps a row-major buffer of `data.len() / cols` rows.
    pub fn new(data: &'a mut [f64], cols: usize) -> Self {
        debug_assert_eq!(data.len() % cols, 0);
        Partials { data, cols }
    }
    /// Adds `value` to the partial of row `row` with respect to state `col`.
    #[inline]
    pub fn add(&mut self, row: usize, col: usize, value: f64) {
        self.data[row * self.cols + col] += value;
    }
    /// Reads one entry.
    #[inline]
    pub fn get(&self, row: usize, col: usize) -> f64 {
        self.data[row * self.cols + col]
    }
    /// Number of columns: the row stride, at least the state dimension.
    pub fn cols(&self) -> usize {
        self.cols
    }
}

/// One switchable term of the model.
///
/// Every method that adds something has a default that adds nothing, so an effect implements
/// only what it touches. `c` is always the slice of the state holding this effect's own
/// coefficients, in the order of [`Effect::coefficient_names`]; `offset` is the index of the
/// first of them in the full state (for writing partials).
///
/// ```
/// use navkf_dynamics::{Effect, Kinematics, Partials, PlatformModel, NoiseConfig, SystemModel};
/// use navkf_dynamics::state::{V_X, NAV_DIM};
///
/// /// A drag-like East velocity damping `v_x' += -kd v_x` (not in the catalogue).
/// #[derive(Debug)]
/// struct Damping;
/// impl Effect for Damping {
///     fn name(&self) -> &str { "damping" }
///     fn description(&self) -> &str { "v_x' += -kd v_x" }
///     fn coefficient_names(&self) -> &[&str] { &["kd"] }
///     fn coefficient_units(&self) -> &[&str] { &["1/s"] }
///     fn coefficient_sigma(&self) -> &[f64] { &[1e-5] }
///     fn add_rates(&self, k: &Kinematics, c: &[f64], rates: &mut [f64; NAV_DIM]) {
///         rates[V_X] -= c[0] * k.v_x;
///     }
///     fn add_rate_partials(&self, k: &Kinematics, c: &[f64], offset: usize, p: &mut Partials) {
///         p.add(V_X, V_X, -c[0]);
///         p.add(V_X, offset, -k.v_x);
///     }
/// }
///
/// let model = PlatformModel::new(vec![Box::new(Damping)], &NoiseConfig::default()).unwrap();
/// assert_eq!(model.dim(), 21);
/// assert_eq!(model.state_names()[20], "kd");
/// ```
pub trait Effect: Send + Sync + fmt::Debug {
    /// The effect's name, as written on command lines and in study files (`gyro-fz`).
    fn name(&self) -> &str;
    /// One line: what the effect adds, as a formula.
    fn description(&self) -> &str;
    /// Names of the coefficients it adds to the state (may be empty).
    fn coefficient_names(&self) -> &[&str] {
        &[]
    }
    /// Units of those coefficients, for reports.
    fn coefficient_units(&self) -> &[&str] {
        &[]
    }
    /// A typical one-sigma size of each coefficient for a navigation-grade platform: the
    /// default spread of the truth's draw and of a filter's initial uncertainty.
    fn coefficient_sigma(&self) -> &[f64] {
        &[]
    }
    /// Adds the effect's terms to the navigation-state derivatives `[phi, v_x, v_y, L, lambda]`.
    fn add_rates(&self, _k: &Kinematics, _c: &[f64], _rates: &mut [f64; NAV_DIM]) {}
    /// Adds the partial derivatives of [`Effect::add_rates`] (rows: navigation states).
    fn add_rate_partials(&self, _k: &Kinematics, _c: &[f64], _offset: usize, _p: &mut Partials) {}
    /// Whether [`Effect::add_rates`] adds anything (lets the model skip the call).
    fn adds_rates(&self) -> bool {
        true
    }
    /// Adds the effect's terms to the predicted measurement `[v_x, v_y, L, lambda]`.
    fn add_measurement(&self, _k: &Kinematics, _c: &[f64], _z: &mut [f64; MEAS_DIM]) {}
    /// Adds the partial derivatives of [`Effect::add_measurement`] (rows: measurement channels).
    fn add_measurement_partials(
        &self,
        _k: &Kinematics,
        _c: &[f64],
        _offset: usize,
        _p: &mut Partials,
    ) {
    }
    /// Whether the effect touches the measurement at all.
    fn adds_measurement(&self) -> bool {
        false
    }
    /// Whether the measurement stays linear in the state with this effect switched on.
    fn measurement_is_linear(&self) -> bool {
        !self.adds_measurement()
    }
    /// Extra white-noise channels the effect brings (indices into the full state).
    fn process_noise(&self) -> Vec<NoiseChannel> {
        Vec::new()
    }
    /// Sets the effect's own parameter (not a coefficient), when it has one: the spectral
    /// density of `gyro-bias-walk`, for instance. Effects without one refuse.
    fn set_parameter(&mut self, _value: f64) -> Result<(), String> {
        Err(format!(
            "effect `{}` has no parameter; its value sets its coefficients",
            self.name()
        ))
    }
}
