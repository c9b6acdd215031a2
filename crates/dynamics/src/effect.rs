//! The effect trait: one physical term the base model leaves out, switchable at run time.
//!
//! An effect owns named coefficients (random constants that join the state after the 20 base
//! states when the effect is switched on), and may add to the navigation-state derivatives,
//! to the measurement, or to the process noise; it says which in [`Effect::terms`]. Its rates
//! are written once, generic over the number type ([`Real`]): the truth simulator and the EKF
//! evaluate them on `f64`, the UKFs' batched propagation on eight sigma points at once
//! ([`Lanes`]). It supplies the partial derivatives of what it adds, which the EKF needs; the
//! test suite checks every effect's partials against finite differences.
//!
//! The catalogue (docs/model.md eqs. (37)-(44)) lives in [`crate::effects`]; a user writes a
//! new effect by implementing [`Effect`] in their own crate and passing it to
//! [`crate::PlatformModel::new`] or registering it in an [`crate::effects::Registry`]. The
//! model holds effects as [`DynEffect`] objects, which every [`Effect`] is.

use crate::kinematics::{Input, Kinematics, LatitudeTerms};
use crate::linear_rates::LinearRate;
pub use crate::partials::Partials;
use crate::real::{Lanes, Real};
pub use crate::sensor_classes::PhysicalBound;
use crate::state::{MEAS_DIM, NAV_DIM};
use std::fmt;

/// A combination of an effect's coefficients that the base model's own states take up on a
/// vehicle test, however large: no filter can tell it from them, so no diagnosis can name the
/// effect for it. `weights` has one entry per coefficient, each coefficient measured in its
/// typical sigma ([`Effect::coefficient_sigma`]); its length does not matter. A diagnosis
/// study measures an effect's detection on the part of its hidden size outside these
/// combinations.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UnseenCombination {
    /// The combination, one weight per coefficient (in typical sigmas).
    pub weights: &'static [f64],
    /// Which combination it is and what takes it up, for reports: "`Ka12x = -Ka12y`, ...".
    pub why: &'static str,
}

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

/// How an effect's measurement term depends on the state.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum MeasurementTerm {
    /// It adds nothing to the measurement.
    #[default]
    None,
    /// It adds a term linear in the state (its Jacobian is constant).
    Linear,
    /// It adds a term non-linear in the state (the simplified UKF then takes its
    /// sigma-point measurement path).
    NonLinear,
}

/// What an effect contributes: the one declaration the model reads to decide which of its
/// methods to call. [`crate::PlatformModel::new`] checks it against the code (an effect that
/// adds rates or a measurement term it did not declare, or noise channels it did not declare,
/// is refused), so a term is never silently dropped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Terms {
    /// It adds to the navigation-state derivatives through its own code
    /// ([`Effect::add_rates`]).
    pub rates: bool,
    /// Rate terms linear in one coefficient, which the model evaluates itself (no
    /// [`Effect::add_rates`] needed; see [`crate::linear_rates`] for why). They are added
    /// before any effect's [`Effect::add_rates`].
    pub linear_rates: &'static [LinearRate],
    /// Its measurement term ([`Effect::add_measurement`]).
    pub measurement: MeasurementTerm,
    /// It brings process-noise channels ([`Effect::process_noise`]).
    pub noise: bool,
}

impl Terms {
    /// Rates only.
    pub const RATES: Terms = Terms {
        rates: true,
        linear_rates: &[],
        measurement: MeasurementTerm::None,
        noise: false,
    };
    /// Linear rate terms only.
    pub const fn linear(terms: &'static [LinearRate]) -> Terms {
        Terms {
            rates: false,
            linear_rates: terms,
            measurement: MeasurementTerm::None,
            noise: false,
        }
    }
    /// A measurement term only.
    pub const fn measurement(kind: MeasurementTerm) -> Terms {
        Terms {
            rates: false,
            linear_rates: &[],
            measurement: kind,
            noise: false,
        }
    }
    /// Process noise only.
    pub const NOISE: Terms = Terms {
        rates: false,
        linear_rates: &[],
        measurement: MeasurementTerm::None,
        noise: true,
    };
}

/// One switchable term of the model.
///
/// An effect declares what it adds in [`Effect::terms`] and implements those methods; the
/// others default to adding nothing. Rate terms that are a coefficient times a kinematic
/// quantity ([`crate::Feature`]) are better declared as data in [`Terms::linear_rates`], with
/// no code: the model evaluates and differentiates them, and the UKFs' batch evaluates them
/// inline ([`crate::linear_rates`]); `add_rates` is for the rest. `c` is always the slice of
/// the state holding this effect's own coefficients, in the order of
/// [`Effect::coefficient_names`]; `offset` is the index of the first of them in the full state
/// (for writing partials).
///
/// ```
/// use navkf_dynamics::{Effect, Kinematics, Partials, PlatformModel, NoiseConfig, Real, Terms};
/// use navkf_dynamics::state::{V_X, NAV_DIM};
/// use navkf_dynamics::SystemModel;
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
///     fn terms(&self) -> Terms { Terms::RATES }
///     fn add_rates<T: Real>(&self, k: &Kinematics<T>, c: &[T], rates: &mut [T; NAV_DIM]) {
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
pub trait Effect: Send + Sync + fmt::Debug + 'static {
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
    /// The largest magnitude each coefficient takes in any real instrument, with the reason
    /// (same order as the names; [`crate::sensor_classes`] says where the bounds come from).
    /// A diagnosis does not name the effect when its fitted coefficients lie beyond, and the
    /// simulator refuses such a value. Empty: no bound declared (a user's effect may leave it
    /// so; then nothing is refused).
    fn coefficient_bounds(&self) -> &[PhysicalBound] {
        &[]
    }
    /// The combinations of the coefficients the base model takes up on any vehicle test
    /// ([`UnseenCombination`]); empty when the data can see every one.
    fn unseen_combinations(&self) -> &[UnseenCombination] {
        &[]
    }
    /// What the effect adds (required: the model calls only what is declared here).
    fn terms(&self) -> Terms;
    /// Adds the effect's terms to the navigation-state derivatives `[phi, v_x, v_y, L, lambda]`,
    /// on one state (`T = f64`) or a batch of them ([`Lanes`]). Rates read the kinematics'
    /// values, never their `d_` latitude derivatives (left zero in the batch).
    ///
    /// The `phi` rows are platform-axis gyro errors (they join `eps`) and the `v` rows
    /// platform-axis accelerometer errors (they join `nab`): the small-angle model adds them to
    /// the derivatives as they are, the exact-attitude variant maps them through the rotation
    /// ([`crate::attitude`]), so an effect is written once for both.
    fn add_rates<T: Real>(&self, _k: &Kinematics<T>, _c: &[T], _rates: &mut [T; NAV_DIM]) {}
    /// Adds the partial derivatives of [`Effect::add_rates`] (rows: navigation states).
    fn add_rate_partials(&self, _k: &Kinematics, _c: &[f64], _offset: usize, _p: &mut Partials) {}
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
    /// The TOML declaration the effect was built from, when it was declared rather than
    /// written in Rust ([`crate::declared`]): a simulated dataset writes it into its
    /// `dataset.toml`, so that the folder reads back with the effect known.
    fn declaration(&self) -> Option<&crate::declared::EffectDeclaration> {
        None
    }
}

/// An [`Effect`] as the model holds it: the same methods, with the generic rates
/// instantiated for each number type the model evaluates (a trait object cannot carry a
/// generic method). Every [`Effect`] is one; nobody implements this by hand.
pub trait DynEffect: Send + Sync + fmt::Debug {
    /// [`Effect::name`].
    fn name(&self) -> &str;
    /// [`Effect::description`].
    fn description(&self) -> &str;
    /// [`Effect::coefficient_names`].
    fn coefficient_names(&self) -> &[&str];
    /// [`Effect::coefficient_units`].
    fn coefficient_units(&self) -> &[&str];
    /// [`Effect::coefficient_sigma`].
    fn coefficient_sigma(&self) -> &[f64];
    /// [`Effect::coefficient_bounds`].
    fn coefficient_bounds(&self) -> &[PhysicalBound];
    /// [`Effect::unseen_combinations`].
    fn unseen_combinations(&self) -> &[UnseenCombination];
    /// [`Effect::terms`].
    fn terms(&self) -> Terms;
    /// [`Effect::add_rates`] on one state.
    fn add_rates(&self, k: &Kinematics, c: &[f64], rates: &mut [f64; NAV_DIM]);
    /// [`Effect::add_rates`] on each block of a group of batches of eight (`rates` holds one
    /// entry per block), the effect's coefficients being at `coefficients` in each block's
    /// state. One call serves the group,
    /// so the dynamic dispatch is paid once per group and stage, not per block.
    fn add_rates_blocks(
        &self,
        group: &BlockGroup<'_>,
        coefficients: std::ops::Range<usize>,
        rates: &mut [[Lanes; NAV_DIM]],
    );
    /// [`Effect::add_rate_partials`].
    fn add_rate_partials(&self, k: &Kinematics, c: &[f64], offset: usize, p: &mut Partials);
    /// [`Effect::add_measurement`].
    fn add_measurement(&self, k: &Kinematics, c: &[f64], z: &mut [f64; MEAS_DIM]);
    /// [`Effect::add_measurement_partials`].
    fn add_measurement_partials(&self, k: &Kinematics, c: &[f64], offset: usize, p: &mut Partials);
    /// [`Effect::process_noise`].
    fn process_noise(&self) -> Vec<NoiseChannel>;
    /// [`Effect::set_parameter`].
    fn set_parameter(&mut self, value: f64) -> Result<(), String>;
    /// [`Effect::declaration`].
    fn declaration(&self) -> Option<&crate::declared::EffectDeclaration>;
}

impl<E: Effect> DynEffect for E {
    fn name(&self) -> &str {
        Effect::name(self)
    }
    fn description(&self) -> &str {
        Effect::description(self)
    }
    fn coefficient_names(&self) -> &[&str] {
        Effect::coefficient_names(self)
    }
    fn coefficient_units(&self) -> &[&str] {
        Effect::coefficient_units(self)
    }
    fn coefficient_sigma(&self) -> &[f64] {
        Effect::coefficient_sigma(self)
    }
    fn coefficient_bounds(&self) -> &[PhysicalBound] {
        Effect::coefficient_bounds(self)
    }
    fn unseen_combinations(&self) -> &[UnseenCombination] {
        Effect::unseen_combinations(self)
    }
    fn terms(&self) -> Terms {
        Effect::terms(self)
    }
    #[inline]
    fn add_rates(&self, k: &Kinematics, c: &[f64], rates: &mut [f64; NAV_DIM]) {
        Effect::add_rates(self, k, c, rates)
    }
    fn add_rates_blocks(
        &self,
        group: &BlockGroup<'_>,
        coefficients: std::ops::Range<usize>,
        rates: &mut [[Lanes; NAV_DIM]],
    ) {
        debug_assert_eq!(rates.len(), group.len());
        for (b, r) in rates.iter_mut().enumerate() {
            // Built here, inlined with the effect's rates: only what they read is computed.
            let k = group.kinematics(b);
            Effect::add_rates(self, &k, &group.state(b)[coefficients.clone()], r)
        }
    }
    fn add_rate_partials(&self, k: &Kinematics, c: &[f64], offset: usize, p: &mut Partials) {
        Effect::add_rate_partials(self, k, c, offset, p)
    }
    fn add_measurement(&self, k: &Kinematics, c: &[f64], z: &mut [f64; MEAS_DIM]) {
        Effect::add_measurement(self, k, c, z)
    }
    fn add_measurement_partials(&self, k: &Kinematics, c: &[f64], offset: usize, p: &mut Partials) {
        Effect::add_measurement_partials(self, k, c, offset, p)
    }
    fn process_noise(&self) -> Vec<NoiseChannel> {
        Effect::process_noise(self)
    }
    fn set_parameter(&mut self, value: f64) -> Result<(), String> {
        Effect::set_parameter(self, value)
    }
    fn declaration(&self) -> Option<&crate::declared::EffectDeclaration> {
        Effect::declaration(self)
    }
}

/// A group of batches of eight states as the effects see them during the batched
/// propagation: each block's full state (`stride` lanes apart), its latitude's functions, and
/// the stage's input. An effect builds from these the kinematics it reads
/// ([`Kinematics::from_latitude`]), bit for bit the values the base model used. Passing the
/// whole kinematics instead, which a call through the effect's vtable must take through
/// memory, cost the propagation half again its time: a CPU that stores one vector register
/// every other cycle spent it storing 23 vectors per derivative where 5 do.
#[derive(Debug, Clone)]
pub struct BlockGroup<'a> {
    states: &'a [Lanes],
    stride: usize,
    latitude: &'a [LatitudeTerms<Lanes>],
    f: &'a Input,
}

impl<'a> BlockGroup<'a> {
    /// `latitude.len()` blocks whose states lie in `states`, `stride` lanes apart, under the
    /// input `f`.
    pub fn new(
        states: &'a [Lanes],
        stride: usize,
        latitude: &'a [LatitudeTerms<Lanes>],
        f: &'a Input,
    ) -> Self {
        assert!(states.len() >= latitude.len() * stride);
        BlockGroup {
            states,
            stride,
            latitude,
            f,
        }
    }
    /// Number of blocks.
    #[inline(always)]
    pub fn len(&self) -> usize {
        self.latitude.len()
    }
    /// Whether the group has no block.
    pub fn is_empty(&self) -> bool {
        self.latitude.is_empty()
    }
    /// Block `b`'s full state.
    #[inline(always)]
    pub fn state(&self, b: usize) -> &'a [Lanes] {
        &self.states[b * self.stride..(b + 1) * self.stride]
    }
    /// Block `b`'s kinematics.
    #[inline(always)]
    pub fn kinematics(&self, b: usize) -> Kinematics<Lanes> {
        Kinematics::from_latitude(self.state(b), self.f, &self.latitude[b])
    }
}
