//! The sensor errors the strapdown effects describe, evaluated once for every number type:
//! where each effect's coefficient sits in the state ([`ErrorLayout`]), the readings the
//! model corrects with them (docs/model.md eqs. (50), (51), (63)-(67)), the readings a unit
//! with those errors gives (the simulator's direction), and the measurement with the
//! odometer's scale and mounting, the antenna's lever arm and the fix's latency
//! (docs/model.md eqs. (59), (60), (68), (70)).
//!
//! Places no effect fills are skipped, not multiplied by zero: a model without effects
//! evaluates exactly the base model's operations, so its results do not change.

use super::attitude::{body_to_nav, rotate, rotate_back};
use super::effects::{Slot, StrapdownEffect, Triad};
use super::rates::ImuReading;
use super::state::*;
use crate::real::Real;

/// The most states a strapdown model holds: the base states, both triads' bias departures
/// (docs/model.md eq. (69)) and one coefficient in each place of [`Slot`] (9 + 9 gyro and accelerometer
/// matrix entries, 3 g-sensitivities, the odometer's 3, the lever arm's 3, the latency).
pub const MAX_DIM: usize = BASE_DIM + 6 + 28;

/// A triad's bias departure (docs/model.md eq. (69)): three states, from `first`, that wander
/// about the constant turn-on bias with rate `-d / T`, and add to it in the readings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Wander {
    /// The state of the x axis' departure; y and z follow.
    pub first: usize,
    /// `1 / T`.
    pub decay: f64,
}

/// A coefficient's state index and the factor it enters a place with.
type Entry = Option<(usize, f64)>;

/// Where each place of the sensor-error description reads its coefficient in the state (and
/// with which factor), and which bias triads wander (docs/model.md eq. (69)). The states after the base
/// ones: the departures (the gyro's, then the accelerometer's, of the triads that wander),
/// then the effects' coefficients in the effects' order.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ErrorLayout {
    gyro: [[Entry; 3]; 3],
    accel: [[Entry; 3]; 3],
    gyro_g: [Entry; 3],
    odometer_scale: Entry,
    odometer_yaw: Entry,
    odometer_pitch: Entry,
    lever_arm: [Entry; 3],
    latency: Entry,
    /// The gyro biases' departure, when they wander.
    pub gyro_wander: Option<Wander>,
    /// The accelerometer biases' departure.
    pub accel_wander: Option<Wander>,
}

impl ErrorLayout {
    /// The layout of `effects`: the departures of the triads an instability makes wander
    /// numbered from [`BASE_DIM`], then the coefficients in order; `decay(triad)` gives
    /// `1 / T` of an instability's law. A coefficient may act in several places (a declared
    /// one), each with its factor. Two coefficients in one place are refused (only a user's
    /// effect can ask for that).
    pub fn new(effects: &[StrapdownEffect], decay: impl Fn(Triad) -> f64) -> Result<Self, String> {
        let mut layout = ErrorLayout::default();
        let mut index = BASE_DIM;
        for triad in [Triad::Gyro, Triad::Accel] {
            let mut wandering = effects
                .iter()
                .filter(|e| e.instability.is_some_and(|l| l.triad == triad));
            if wandering.next().is_none() {
                continue;
            }
            if let Some(second) = wandering.next() {
                return Err(format!("`{}`: that triad already wanders", second.name));
            }
            let wander = Some(Wander {
                first: index,
                decay: decay(triad),
            });
            match triad {
                Triad::Gyro => layout.gyro_wander = wander,
                Triad::Accel => layout.accel_wander = wander,
            }
            index += 3;
        }
        // Who holds each place taken so far, for the refusal.
        let mut holders: Vec<(Slot, &str, &str)> = Vec::new();
        for effect in effects {
            let numbered = effect.coefficients.iter().zip(index..);
            for (c, state, p) in numbered.flat_map(|(c, s)| c.places.iter().map(move |p| (c, s, p)))
            {
                let place = match p.slot {
                    Slot::Gyro(i, j) if i < 3 && j < 3 => &mut layout.gyro[i][j],
                    Slot::Accel(i, j) if i < 3 && j < 3 => &mut layout.accel[i][j],
                    Slot::GyroG(i) if i < 3 => &mut layout.gyro_g[i],
                    Slot::OdometerScale => &mut layout.odometer_scale,
                    Slot::OdometerYaw => &mut layout.odometer_yaw,
                    Slot::OdometerPitch => &mut layout.odometer_pitch,
                    Slot::LeverArm(i) if i < 3 => &mut layout.lever_arm[i],
                    Slot::Latency => &mut layout.latency,
                    other => return Err(format!("`{}`: no such place {other}", c.name)),
                };
                if place.is_some() {
                    let (held_by, of) = holders
                        .iter()
                        .find(|(s, ..)| *s == p.slot)
                        .map_or(("another coefficient", "?"), |(_, c, e)| (*c, *e));
                    return Err(format!(
                        "`{}` of `{}` acts in {}, which `{held_by}` of `{of}` holds already; a \
                         model holds one coefficient in each place",
                        c.name, effect.name, p.slot
                    ));
                }
                *place = Some((state, p.factor));
                holders.push((p.slot, c.name, effect.name));
            }
            index += effect.coefficients.len();
        }
        Ok(layout)
    }

    /// Whether any coefficient changes the readings (then the rates take the corrected path).
    pub fn has_reading_errors(&self) -> bool {
        self.gyro.iter().flatten().any(Option::is_some)
            || self.accel.iter().flatten().any(Option::is_some)
            || self.gyro_g.iter().any(Option::is_some)
    }

    /// Whether any coefficient changes the measurement.
    pub fn has_measurement_errors(&self) -> bool {
        self.odometer_scale.is_some()
            || self.odometer_yaw.is_some()
            || self.odometer_pitch.is_some()
            || self.lever_arm.iter().any(Option::is_some)
            || self.latency.is_some()
    }

    /// Whether a triad's biases wander (docs/model.md eq. (69)).
    pub fn biases_wander(&self) -> bool {
        self.gyro_wander.is_some() || self.accel_wander.is_some()
    }

    /// The departures' states: 3 per triad that wanders.
    pub fn departures(&self) -> usize {
        3 * (usize::from(self.gyro_wander.is_some()) + usize::from(self.accel_wander.is_some()))
    }

    /// The states with a derivative: the navigation states, or, when a triad wanders, the
    /// base states (the biases' derivative is zero) and the departures.
    pub fn dynamic_dim(&self) -> usize {
        if self.biases_wander() {
            BASE_DIM + self.departures()
        } else {
            NAV_DIM
        }
    }

    /// The departures of the triads that wander, the gyros' first.
    pub fn wanders(&self) -> impl Iterator<Item = Wander> {
        [self.gyro_wander, self.accel_wander].into_iter().flatten()
    }

    /// Whether the vehicle's axes are turned from the unit's.
    pub fn has_mounting(&self) -> bool {
        self.odometer_yaw.is_some() || self.odometer_pitch.is_some()
    }

    /// The state index of the GPS latency's coefficient, and its factor.
    pub fn latency_entry(&self) -> Option<(usize, f64)> {
        self.latency
    }
}

/// The value of the place `entry`: its coefficient in `x` times its factor (a factor of 1,
/// every catalogued coefficient's, costs no multiplication).
#[inline(always)]
fn at<T: Real>(x: &[T], entry: Entry) -> Option<T> {
    entry.map(|(i, factor)| {
        if factor == 1.0 {
            x[i]
        } else {
            x[i] * T::splat(factor)
        }
    })
}

/// `I + E` with the entries of `places` taken from `x`.
fn one_plus<T: Real>(x: &[T], places: &[[Entry; 3]; 3]) -> [[T; 3]; 3] {
    std::array::from_fn(|i| {
        std::array::from_fn(|j| {
            let identity = T::splat(if i == j { 1.0 } else { 0.0 });
            at(x, places[i][j]).map_or(identity, |e| identity + e)
        })
    })
}

/// `m^-1` for a 3x3 `m` near the identity (cofactors over the determinant).
fn inverse<T: Real>(m: &[[T; 3]; 3]) -> [[T; 3]; 3] {
    let cof = |r: usize, c: usize| {
        let (r1, r2) = ((r + 1) % 3, (r + 2) % 3);
        let (c1, c2) = ((c + 1) % 3, (c + 2) % 3);
        m[r1][c1] * m[r2][c2] - m[r1][c2] * m[r2][c1]
    };
    let adj: [[T; 3]; 3] = std::array::from_fn(|i| std::array::from_fn(|j| cof(j, i)));
    let det = m[0][0] * adj[0][0] + m[0][1] * adj[1][0] + m[0][2] * adj[2][0];
    let inv_det = T::splat(1.0) / det;
    adj.map(|row| row.map(|a| a * inv_det))
}

/// The true body rate and specific force from `imu` and the state `x` (biases, their
/// departures and effect coefficients): `f = (I + E_a)^-1 (f~ - b_a)`,
/// `w = (I + E_g)^-1 (w~ - b_g - G f)`, each bias the turn-on state plus its departure when
/// the triad wanders (docs/model.md eqs. (51), (63)-(67), (69)). Without reading errors: the
/// readings less the biases.
#[inline(always)]
pub fn corrected_reading<T: Real>(
    layout: &ErrorLayout,
    imu: &ImuReading,
    x: &[T],
) -> ([T; 3], [T; 3]) {
    let mut w: [T; 3] = std::array::from_fn(|i| T::splat(imu.w[i]) - x[BG_X + i]);
    let mut f: [T; 3] = std::array::from_fn(|i| T::splat(imu.f[i]) - x[BA_X + i]);
    if let Some(d) = layout.gyro_wander {
        for (i, w) in w.iter_mut().enumerate() {
            *w -= x[d.first + i];
        }
    }
    if let Some(d) = layout.accel_wander {
        for (i, f) in f.iter_mut().enumerate() {
            *f -= x[d.first + i];
        }
    }
    if layout.accel.iter().flatten().any(Option::is_some) {
        f = rotate(&inverse(&one_plus(x, &layout.accel)), f);
    }
    for (i, g) in layout.gyro_g.iter().enumerate() {
        if let Some(g) = at(x, *g) {
            w[i] -= g * f[i];
        }
    }
    if layout.gyro.iter().flatten().any(Option::is_some) {
        w = rotate(&inverse(&one_plus(x, &layout.gyro)), w);
    }
    (w, f)
}

/// [`corrected_reading`] on `f64` with its partial derivatives: it returns `(w, f)` and calls
/// `column(i, dw/dx_i, df/dx_i)` for each state `i` they depend on (the six biases, their
/// departures and the reading errors' coefficients), once per place of a coefficient acting
/// in several: the
/// caller adds them up. With `A = I + E_a`, `B = I + E_g`: `df = -A^-1 e_i` for `ba_i` and
/// `-A^-1 e_i f_j` for `E_a[i][j]`; `dw = -B^-1 e_i` for `bg_i`, `-B^-1 e_i w_j` for
/// `E_g[i][j]`, `-B^-1 e_i f_i` for `g_i`, and `-B^-1 G df` through `f`; each times the
/// place's factor. A departure's columns are its bias's.
#[inline(always)]
pub fn corrected_reading_partials(
    layout: &ErrorLayout,
    imu: &ImuReading,
    x: &[f64],
    mut column: impl FnMut(usize, [f64; 3], [f64; 3]),
) -> ([f64; 3], [f64; 3]) {
    let (w, f) = corrected_reading(layout, imu, x);
    let a_inv = inverse(&one_plus(x, &layout.accel));
    let b_inv = inverse(&one_plus(x, &layout.gyro));
    let g: [f64; 3] = std::array::from_fn(|i| at(x, layout.gyro_g[i]).unwrap_or(0.0));
    let minus_col =
        |m: &[[f64; 3]; 3], i: usize, s: f64| [-m[0][i] * s, -m[1][i] * s, -m[2][i] * s];
    // A change of f moves w by -B^-1 G df.
    let through_f =
        |df: [f64; 3]| rotate(&b_inv, [g[0] * df[0], g[1] * df[1], g[2] * df[2]]).map(|v| -v);
    for i in 0..3 {
        let dw = minus_col(&b_inv, i, 1.0);
        column(BG_X + i, dw, [0.0; 3]);
        if let Some(d) = layout.gyro_wander {
            column(d.first + i, dw, [0.0; 3]);
        }
        let df = minus_col(&a_inv, i, 1.0);
        column(BA_X + i, through_f(df), df);
        if let Some(d) = layout.accel_wander {
            column(d.first + i, through_f(df), df);
        }
    }
    for i in 0..3 {
        for j in 0..3 {
            if let Some((c, factor)) = layout.accel[i][j] {
                let df = minus_col(&a_inv, i, f[j] * factor);
                column(c, through_f(df), df);
            }
            if let Some((c, factor)) = layout.gyro[i][j] {
                column(c, minus_col(&b_inv, i, w[j] * factor), [0.0; 3]);
            }
        }
        if let Some((c, factor)) = layout.gyro_g[i] {
            column(c, minus_col(&b_inv, i, f[i] * factor), [0.0; 3]);
        }
    }
    (w, f)
}

/// What a unit with the effects' errors of `x` reads when its true body rate and specific
/// force are those of `truth`, biases and white noise aside: `(I + E_g) w + G f` and
/// `(I + E_a) f`. With the biases added, [`corrected_reading`] is its inverse.
pub fn reading_with_errors(layout: &ErrorLayout, truth: &ImuReading, x: &[f64]) -> ImuReading {
    let (g, a) = (one_plus(x, &layout.gyro), one_plus(x, &layout.accel));
    let mut read = ImuReading {
        w: rotate(&g, truth.w),
        f: rotate(&a, truth.f),
    };
    for i in 0..3 {
        read.w[i] += at(x, layout.gyro_g[i]).map_or(0.0, |g| g * truth.f[i]);
    }
    read
}

/// The vehicle's forward, lateral and vertical axes in body axes (docs/model.md eq. (68)):
/// the columns of the vehicle-to-body rotation. `None` when no mounting effect is on.
#[inline(always)]
pub fn vehicle_axes<T: Real>(layout: &ErrorLayout, x: &[T]) -> Option<[[T; 3]; 3]> {
    if !layout.has_mounting() {
        return None;
    }
    let zero = T::splat(0.0);
    let (sy, cy) = at(x, layout.odometer_yaw).map_or((zero, T::splat(1.0)), T::sin_cos);
    let (sp, cp) = at(x, layout.odometer_pitch).map_or((zero, T::splat(1.0)), T::sin_cos);
    Some([
        [cp * cy, cp * sy, sp],
        [-sy, cy, zero],
        [-(sp * cy), -(sp * sy), cp],
    ])
}

/// The measurement with the effects of `layout` (docs/model.md eqs. (59)-(61), (68), (70)):
/// the odometer reads `(1 + kod) u_o . v^b`, the constraint `u_l . v^b` and `u_u . v^b`, the
/// GPS the antenna's position `p + C_b^n l`, `tau` seconds before its stamp.
#[inline(always)]
pub fn measurement_with<T: Real>(layout: &ErrorLayout, x: &[T], z: &mut [T]) {
    if !layout.has_measurement_errors() {
        return super::measurement::measurement(x, z);
    }
    let cbn = body_to_nav([x[ROLL], x[PITCH], x[HEADING]]);
    let zero = T::splat(0.0);
    let v_b = rotate_back(&cbn, [x[V_E], x[V_N], zero]);
    let dot = |u: [T; 3]| u[0] * v_b[0] + u[1] * v_b[1] + u[2] * v_b[2];
    let (forward, lateral, vertical) = match vehicle_axes(layout, x) {
        Some([u_o, u_l, u_u]) => (dot(u_o), dot(u_l), dot(u_u)),
        None => (v_b[0], v_b[1], v_b[2]),
    };
    z[0] = at(x, layout.odometer_scale).map_or(forward, |k| forward + k * forward);
    z[3] = lateral;
    z[4] = vertical;
    let (mut lat, mut lon) = (x[LAT], x[LON]);
    let lever = layout.lever_arm.map(|i| at(x, i).unwrap_or(zero));
    let has_lever = layout.lever_arm.iter().any(Option::is_some);
    if has_lever || layout.latency.is_some() {
        let (sl, cl) = x[LAT].sin_cos();
        let [inv_rm, inv_rn, inv_cos] = T::reciprocals(
            crate::earth::meridian_radius(sl),
            crate::earth::prime_vertical_radius(sl),
            cl,
        );
        let (mut east, mut north) = (zero, zero);
        if has_lever {
            let l_n = rotate(&cbn, lever);
            east += l_n[0];
            north += l_n[1];
        }
        if let Some(tau) = at(x, layout.latency) {
            east -= tau * x[V_E];
            north -= tau * x[V_N];
        }
        lat += north * inv_rm;
        lon += east * inv_rn * inv_cos;
    }
    z[1] = lat;
    z[2] = lon;
    z[5] = x[V_E];
    z[6] = x[V_N];
}
