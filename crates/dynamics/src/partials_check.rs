//! The public check of an effect's partial derivatives: the EKF's Jacobians of a model with
//! the effect (docs/model.md eqs. (19), (21)) against central finite differences of its rates
//! and measurement, at random but realistic states, with the worst entry reported.
//!
//! Any effect can be checked this way, catalogued, written in Rust by a user, or declared in
//! TOML: a wrong partial makes the EKF converge to the wrong answer silently, so a user's
//! effect deserves the same test the catalogue's get (`navkf effects --check`,
//! `crates/dynamics/tests/jacobians.rs`).
//!
//! What it catches: a wrong sign, a missing or extra term, a partial written into the wrong
//! row or column (a wrong offset), an entry left unwritten (the buffers are pre-filled with
//! NaN). Each entry is judged against its own size plus the rounding floor of its
//! difference quotient ([`compare`]), so even the smallest terms (the `d(1/RN)/dL` parts,
//! ~1e-5 of their entry) are resolved.
//!
//! ```
//! use navkf_dynamics::partials_check::check_effect;
//! use navkf_dynamics::{NoiseConfig, Registry};
//! let effect = Registry::catalogue().build("gps-latency").unwrap();
//! let report = check_effect(effect, &NoiseConfig::default(), 8, 1).unwrap();
//! assert!(report.passes(), "{report}");
//! ```

use crate::effect::DynEffect;
use crate::error::DynamicsError;
use crate::kinematics::{platform_input, Input};
use crate::model::PlatformModel;
use crate::noise::NoiseConfig;
use crate::state::*;
use crate::system::SystemModel;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::fmt;

/// A value of magnitude `scale * [0.5, 1.5)` with a random sign: never near zero, so that
/// every term it multiplies contributes to the derivatives being checked.
pub fn signed(rng: &mut ChaCha8Rng, scale: f64) -> f64 {
    let m = scale * rng.gen_range(0.5..1.5);
    if rng.gen::<bool>() {
        m
    } else {
        -m
    }
}

/// Typical size of a base coefficient of a navigation-grade platform
/// (docs/model.md, "The state"): gyro drifts 1e-7 rad/s, g-sensitive drifts 1e-8 rad/s per
/// m/s^2, accelerometer bias 5e-4 m/s^2, accelerometer scale factor 5e-5.
pub fn base_coefficient_scale(i: usize) -> f64 {
    match i {
        KG0X | KG0Y | KG0Z => 1e-7,
        KA0X | KA0Y => 5e-4,
        KA1X | KA1Y => 5e-5,
        _ => 1e-8,
    }
}

/// Typical size of every coefficient of `model` (base table, then the effects' sigmas);
/// zero for the navigation states.
pub fn coefficient_scales(model: &PlatformModel) -> Vec<f64> {
    let mut s = vec![0.0; model.dim()];
    for (i, v) in s.iter_mut().enumerate().take(BASE_DIM).skip(NAV_DIM) {
        *v = base_coefficient_scale(i);
    }
    for (i, sigma) in model.effect_coefficient_sigmas() {
        s[i] = sigma;
    }
    s
}

/// A realistic random state: latitude 45 +- 5 deg, longitude 100-130 deg, speeds 2-20 m/s
/// of either sign, attitude errors ~1e-3 rad, every coefficient at its typical size.
pub fn random_state(model: &PlatformModel, rng: &mut ChaCha8Rng) -> Vec<f64> {
    let scales = coefficient_scales(model);
    let mut x = vec![0.0; model.dim()];
    for v in x.iter_mut().take(3) {
        *v = signed(rng, 1e-3);
    }
    x[V_X] = signed(rng, 11.0);
    x[V_Y] = signed(rng, 11.0);
    x[LAT] = (45.0 + rng.gen_range(-5.0..5.0f64)).to_radians();
    x[LON] = rng.gen_range(100.0..130.0f64).to_radians();
    for i in NAV_DIM..model.dim() {
        x[i] = signed(rng, scales[i]);
    }
    x
}

/// A realistic specific force: up to 2 m/s^2 horizontally, ~9.8 vertically; and a time
/// since the record started, up to an hour ([`crate::kinematics::ELAPSED_SLOT`]), for terms
/// shaped in time.
pub fn random_input(rng: &mut ChaCha8Rng) -> Input {
    let mut u = platform_input([
        rng.gen_range(-2.0..2.0),
        rng.gen_range(-2.0..2.0),
        9.8 + rng.gen_range(-0.1..0.1),
    ]);
    u[crate::kinematics::ELAPSED_SLOT] = rng.gen_range(0.0..3600.0);
    u
}

/// Finite-difference steps, one per kind of state.
#[derive(Debug, Clone, Copy)]
pub struct Steps {
    /// Attitude errors, rad.
    pub phi: f64,
    /// Velocities, m/s.
    pub v: f64,
    /// Latitude and longitude, rad.
    pub pos: f64,
    /// Coefficients, as a fraction of their typical size.
    pub coeff_rel: f64,
}

/// Steps for the state equations. Everything there varies on scales of ~1 rad (attitude,
/// latitude through sin/cos/tan), ~1e7 m/s (velocity through v/R) or is linear (coefficients),
/// so the central-difference truncation error `h^2 f'''/6` is below 1e-11 relative with
/// these steps, and the steps are as large as that allows to keep rounding small.
pub const RATE_STEPS: Steps = Steps {
    phi: 1e-6,
    v: 1e-4,
    pos: 1e-6,
    coeff_rel: 1e-3,
};

/// Steps for the measurement. `z_L = L + (effect terms)` carries the whole latitude, ~0.8 rad,
/// so one rounding of `z_L` is ~1e-16 rad and only larger steps resolve the small latitude and
/// velocity partials the effects add there (e.g. `-tau v_y d(1/RM)/dL ~ 3e-9`, resolved to
/// ~1 % by the 1e-4 rad step). The latitude step is capped by truncation: `sec L / RN` has
/// `f'''/f' ~ tan^2 L + 5 sec^2 L`, ~50 at 70 deg, so `h^2/6 * 50 ~ 1e-7` relative.
pub const MEAS_STEPS: Steps = Steps {
    phi: 1e-4,
    v: 1e-2,
    pos: 1e-4,
    coeff_rel: 1e-1,
};

/// The step of every state of `model`.
pub fn steps(model: &PlatformModel, s: Steps) -> Vec<f64> {
    let scales = coefficient_scales(model);
    (0..model.dim())
        .map(|i| match i {
            PHI_X..=PHI_Z => s.phi,
            V_X | V_Y => s.v,
            LAT | LON => s.pos,
            _ => s.coeff_rel * scales[i],
        })
        .collect()
}

/// Relative tolerance of the rate Jacobian check: truncation with [`RATE_STEPS`] is below
/// 1e-11 relative; 1e-9 leaves room without hiding any real error.
pub const RATE_RTOL: f64 = 1e-9;
/// Relative tolerance of the measurement Jacobian check: truncation with [`MEAS_STEPS`] is
/// below ~1e-7 relative up to 70 deg of latitude.
pub const MEAS_RTOL: f64 = 1e-6;

/// Ulps of rounding allowed in each evaluation of a row (see [`compare`]).
pub const ROUNDING_ULPS: f64 = 16.0;

/// A central-difference Jacobian.
pub struct FiniteDiff {
    /// Numerical Jacobian, row-major `rows x n`.
    pub jac: Vec<f64>,
    /// Step actually taken per column, `(x + h) - (x - h)` (exact in floating point).
    pub span: Vec<f64>,
}

/// Central differences of `f: R^n -> R^rows` at `x` with per-state steps `h`.
pub fn central_difference<F>(x: &[f64], h: &[f64], rows: usize, mut f: F) -> FiniteDiff
where
    F: FnMut(&[f64], &mut [f64]),
{
    let n = x.len();
    let mut jac = vec![0.0; rows * n];
    let mut span = vec![0.0; n];
    let mut xp = x.to_vec();
    let mut fp = vec![0.0; rows];
    let mut fm = vec![0.0; rows];
    for c in 0..n {
        xp[c] = x[c] + h[c];
        let hi = xp[c];
        f(&xp, &mut fp);
        xp[c] = x[c] - h[c];
        let lo = xp[c];
        f(&xp, &mut fm);
        xp[c] = x[c];
        span[c] = hi - lo;
        for r in 0..rows {
            jac[r * n + c] = (fp[r] - fm[r]) / span[c];
        }
    }
    FiniteDiff { jac, span }
}

/// Which Jacobian an entry belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Jacobian {
    /// The state equations' (rows: navigation-state derivatives).
    Rates,
    /// The measurement's (rows: measurement channels).
    Measurement,
}

/// One entry of a Jacobian, analytic beside numeric.
#[derive(Debug, Clone, PartialEq)]
pub struct Entry {
    /// Row index.
    pub row: usize,
    /// Column (state) index.
    pub col: usize,
    /// What the model's code gives.
    pub analytic: f64,
    /// What finite differences give.
    pub numeric: f64,
    /// How far apart they may be: `rtol * |entry| + rounding floor`.
    pub tolerance: f64,
}

impl Entry {
    /// `|analytic - numeric| / tolerance`: at most 1 passes; NaN (an unwritten entry) is
    /// infinite.
    pub fn ratio(&self) -> f64 {
        let difference = (self.analytic - self.numeric).abs();
        if difference.is_nan() {
            f64::INFINITY
        } else if difference == 0.0 {
            0.0
        } else {
            difference / self.tolerance
        }
    }
}

/// Entries compared: the worst one, and every one that fails.
#[derive(Debug, Clone, Default)]
pub struct Comparison {
    /// The entry with the largest [`Entry::ratio`] (among entries with a tolerance).
    pub worst: Option<Entry>,
    /// Every entry beyond its tolerance.
    pub failures: Vec<Entry>,
    /// Every entry, row-major.
    pub entries: Vec<Entry>,
}

/// Compares `analytic` with `fd` entry by entry.
///
/// Tolerance of entry `(r, c)`: `rtol * |J(r, c)| + floor(r, c)`. Units differ from row to
/// row, so each entry is judged against its own size, not the largest of its column. The
/// floor: each evaluation of row `r` is a sum of terms whose magnitudes add up to at most
/// `m[r]`, so it is off by a few ulp of `m[r]`, and the quotient divides that by the step:
/// `floor = ROUNDING_ULPS * eps * m[r] / span[c]`. `rtol` covers truncation.
pub fn compare(analytic: &[f64], fd: &FiniteDiff, m: &[f64], rtol: f64) -> Comparison {
    let n = fd.span.len();
    let rows = m.len();
    assert_eq!(analytic.len(), rows * n, "analytic Jacobian size");
    let mut out = Comparison::default();
    for r in 0..rows {
        for c in 0..n {
            let a = analytic[r * n + c];
            let d = fd.jac[r * n + c];
            let floor = ROUNDING_ULPS * f64::EPSILON * m[r] / fd.span[c];
            let entry = Entry {
                row: r,
                col: c,
                analytic: a,
                numeric: d,
                tolerance: rtol * a.abs().max(d.abs()) + floor,
            };
            let ratio = entry.ratio();
            if ratio > 1.0 {
                out.failures.push(entry.clone());
            }
            if entry.tolerance > 0.0 && out.worst.as_ref().is_none_or(|w| ratio > w.ratio()) {
                out.worst = Some(entry.clone());
            }
            out.entries.push(entry);
        }
    }
    out
}

/// The rate Jacobian of `model` at `(x, u)` against central differences of its rates.
pub fn check_rate_jacobian(model: &PlatformModel, x: &[f64], u: &Input) -> Comparison {
    let n = model.dim();
    let d = model.dynamic_dim();
    // Filled with NaN: an entry the analytic code leaves unwritten fails the comparison.
    let mut jac = vec![f64::NAN; d * n];
    model.rate_jacobian(x, u, &mut jac);
    let fd = central_difference(x, &steps(model, RATE_STEPS), d, |xx, out| {
        model.rates(xx, u, out)
    });
    // Term magnitudes of each row: the rate itself, every linear term J(r, c) x_c, the
    // specific force, which enters v_x' and v_y' directly (a term the Jacobian does not see),
    // and in the attitude rows the Earth's and the transport rates, which enter through the
    // attitude's rotation and may cancel to a rate far smaller than either (the exact
    // variant at large angles).
    let mut r0 = vec![0.0; d];
    model.rates(x, u, &mut r0);
    let transport = (x[V_X].abs() + x[V_Y].abs()) / 6.3e6 * (1.0 + x[LAT].tan().abs());
    let m: Vec<f64> = (0..d)
        .map(|r| {
            let lin: f64 = (0..n).map(|c| (jac[r * n + c] * x[c]).abs()).sum();
            let force = if r == V_X || r == V_Y {
                u.iter().map(|f| f.abs()).sum()
            } else {
                0.0
            };
            let turning = if r < 3 {
                crate::earth::WIE + transport
            } else {
                0.0
            };
            r0[r].abs() + lin + force + turning
        })
        .collect();
    compare(&jac, &fd, &m, RATE_RTOL)
}

/// `[v_x, v_y, L, lambda]`: the base measurement, written independently of the model.
pub fn base_measurement(x: &[f64]) -> [f64; MEAS_DIM] {
    [x[V_X], x[V_Y], x[LAT], x[LON]]
}

/// The measurement Jacobian of `model` at `x` against central differences of its
/// measurement.
///
/// The base part `[v_x, v_y, L, lambda]` is subtracted from both sides before comparing (its
/// Jacobian is the identity's, exact): the effects' partials there are ~1e-9 next to the
/// identity's 1, and a tolerance relative to the whole entry would hide them. The difference
/// of two nearby floats is exact, so the subtraction adds no error; the rounding of `z`
/// itself is in the floor through `|z_r|`.
pub fn check_measurement_jacobian(model: &PlatformModel, x: &[f64]) -> Comparison {
    let n = model.dim();
    let rows = model.meas_dim();
    let mut h = vec![f64::NAN; rows * n];
    model.measurement_jacobian(x, &mut h);
    let mut h_eff = h.clone();
    for (r, c) in [V_X, V_Y, LAT, LON].into_iter().enumerate() {
        h_eff[r * n + c] -= 1.0;
    }
    let fd = central_difference(x, &steps(model, MEAS_STEPS), rows, |xx, out| {
        model.measure(xx, out);
        for (o, b) in out.iter_mut().zip(base_measurement(xx)) {
            *o -= b;
        }
    });
    let mut z0 = vec![0.0; rows];
    model.measure(x, &mut z0);
    let m: Vec<f64> = (0..rows)
        .map(|r| {
            let lin: f64 = (0..n).map(|c| (h[r * n + c] * x[c]).abs()).sum();
            z0[r].abs() + lin
        })
        .collect();
    compare(&h_eff, &fd, &m, MEAS_RTOL)
}

/// What [`check_effect`] found: the worst entry over every state checked, named.
#[derive(Debug, Clone)]
pub struct PartialsReport {
    /// The effect checked.
    pub effect: String,
    /// Random states checked.
    pub states: usize,
    /// Entries beyond their tolerance, over all states.
    pub failures: usize,
    /// The worst entry: its Jacobian, row name, column name and the entry.
    pub worst: Option<(Jacobian, String, String, Entry)>,
}

impl PartialsReport {
    /// Whether every entry was within its tolerance.
    pub fn passes(&self) -> bool {
        self.failures == 0
    }

    /// Counts `c`'s failures and keeps its worst entry that the effect touches, if worse than
    /// the worst so far: an entry in the effect's own columns (from `base_dim` on), or one
    /// where the model with it differs from the base model's Jacobian `base_jac` (`rows x
    /// base_dim`, its rows the first of the model's), by its code or by the finite differences. So the report is about the
    /// effect, not the base model the test suite checks already.
    pub(crate) fn record(
        &mut self,
        jacobian: Jacobian,
        c: &Comparison,
        base_jac: &[f64],
        base_dim: usize,
        row_name: impl Fn(usize) -> String,
        state_names: &[String],
    ) {
        self.failures += c.failures.len();
        // A row the base model lacks (a bias made dynamic by the effect) is the effect's too.
        let touched = |e: &&Entry| {
            e.col >= base_dim
                || base_jac
                    .get(e.row * base_dim + e.col)
                    .is_none_or(|&b| e.analytic != b || (e.numeric - b).abs() > e.tolerance)
        };
        let Some(w) = c
            .entries
            .iter()
            .filter(touched)
            .filter(|e| e.tolerance > 0.0)
            .max_by(|a, b| a.ratio().total_cmp(&b.ratio()))
            .cloned()
        else {
            return;
        };
        if self
            .worst
            .as_ref()
            .is_none_or(|(_, _, _, e)| w.ratio() > e.ratio())
        {
            self.worst = Some((jacobian, row_name(w.row), state_names[w.col].clone(), w));
        }
    }
}

impl fmt::Display for PartialsReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let verdict = if self.passes() {
            "partials agree with finite differences".to_string()
        } else {
            format!("{} entries DISAGREE with finite differences", self.failures)
        };
        write!(
            f,
            "{}: {verdict} at {} random states",
            self.effect, self.states
        )?;
        if let Some((jacobian, row, col, e)) = &self.worst {
            let row = match jacobian {
                Jacobian::Rates => format!("{row}'"),
                Jacobian::Measurement => format!("z_{row}"),
            };
            write!(
                f,
                "; worst entry d({row})/d({col}): analytic {:.6e}, numeric {:.6e}, {:.3} of \
                 its tolerance {:.1e}",
                e.analytic,
                e.numeric,
                e.ratio(),
                e.tolerance
            )?;
        }
        Ok(())
    }
}

/// Checks `effect`'s partials: a model with the base states and this effect alone, at
/// `states` random realistic states ([`random_state`], [`random_input`]; seeded by `seed`),
/// its rate and measurement Jacobians against central differences. Every entry counts
/// towards [`PartialsReport::failures`]; the worst entry reported is the worst among those
/// the effect touches (its own coefficients' columns, and the entries where the model with
/// it differs from the base model, by its code or by the finite differences), so that the
/// report is about the effect, not the base model the test suite checks already.
pub fn check_effect(
    effect: Box<dyn DynEffect>,
    noise: &NoiseConfig,
    states: usize,
    seed: u64,
) -> Result<PartialsReport, DynamicsError> {
    let name = effect.name().to_string();
    let model = PlatformModel::new(vec![effect], noise)?;
    let base = PlatformModel::base(noise);
    let names = model.state_names();
    let nb = base.dim();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut report = PartialsReport {
        effect: name,
        states,
        failures: 0,
        worst: None,
    };
    for _ in 0..states {
        let x = random_state(&model, &mut rng);
        let u = random_input(&mut rng);
        let rows = (model.dynamic_dim(), model.meas_dim());
        let mut base_rates = vec![0.0; rows.0 * nb];
        base.rate_jacobian(&x[..nb], &u, &mut base_rates);
        let mut base_measurement = vec![0.0; rows.1 * nb];
        base.measurement_jacobian(&x[..nb], &mut base_measurement);
        // The measurement comparison is of the effects' part (the identity removed).
        for (r, c) in [V_X, V_Y, LAT, LON].into_iter().enumerate() {
            base_measurement[r * nb + c] -= 1.0;
        }
        for (jacobian, c, base_jac) in [
            (
                Jacobian::Rates,
                check_rate_jacobian(&model, &x, &u),
                &base_rates,
            ),
            (
                Jacobian::Measurement,
                check_measurement_jacobian(&model, &x),
                &base_measurement,
            ),
        ] {
            let row_name = |r: usize| match jacobian {
                Jacobian::Rates => names[r].clone(),
                Jacobian::Measurement => MEASUREMENT_NAMES[r].to_string(),
            };
            report.record(jacobian, &c, base_jac, nb, row_name, &names);
        }
    }
    Ok(report)
}
