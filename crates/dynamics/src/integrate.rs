//! Fourth-order Runge-Kutta over an input window: the one integrator that the truth
//! simulator and every filter use, as one table of stages ([`RK4`]) that the one-state path
//! here, the UKFs' batches ([`crate::batch_propagation`]) and the EKF's tangent step through:
//! docs/model.md eq. (15).
//!
//! A window is a list of input knots `t_0 < t_1 < ... < t_m` with the specific force at each
//! knot and at each sub-step's midpoint. Each pair of knots is one RK4 sub-step, with stage
//! inputs `f(t_j)`, `f_mid_j`, `f_mid_j`, `f(t_{j+1})`. Filters fill the midpoint with the
//! average of the two knots (linear interpolation of sampled data); the truth simulator fills
//! it with the trajectory's exact value.
//!
//! White noise is held constant over the window (`w ~ N(0, q / T)` gives the right integrated
//! variance `q T`; docs/model.md eq. (16)). A noise channel on a constant state (a coefficient
//! random walk) moves that state linearly in time, which RK4 reproduces exactly.

use crate::kinematics::{Input, IntoInput};
use crate::real::{Lanes, Real};

/// Input knots over one propagation interval. Reused across steps: `clear` keeps capacity.
#[derive(Debug, Clone, Default)]
pub struct InputWindow {
    /// Knot times, strictly increasing, seconds.
    pub t: Vec<f64>,
    /// Input at each knot.
    pub f: Vec<Input>,
    /// Input at each sub-step's midpoint (`t.len() - 1` entries).
    pub f_mid: Vec<Input>,
}

impl InputWindow {
    /// An empty window with room for `knots` knots.
    pub fn with_capacity(knots: usize) -> Self {
        InputWindow {
            t: Vec::with_capacity(knots),
            f: Vec::with_capacity(knots),
            f_mid: Vec::with_capacity(knots),
        }
    }
    /// Empties the window, keeping its storage.
    pub fn clear(&mut self) {
        self.t.clear();
        self.f.clear();
        self.f_mid.clear();
    }
    /// Appends a knot; the midpoint input of the new sub-step is the average of its ends.
    pub fn push_linear(&mut self, t: f64, f: impl IntoInput) {
        let f = f.into_input();
        if let Some(prev) = self.f.last() {
            self.f_mid
                .push(std::array::from_fn(|i| 0.5 * (prev[i] + f[i])));
        }
        self.t.push(t);
        self.f.push(f);
    }
    /// Appends a knot with an explicit midpoint input for the sub-step it closes.
    pub fn push_with_mid(&mut self, t: f64, f: impl IntoInput, f_mid: impl IntoInput) {
        let (f, f_mid) = (f.into_input(), f_mid.into_input());
        if !self.t.is_empty() {
            self.f_mid.push(f_mid);
        }
        self.t.push(t);
        self.f.push(f);
    }
    /// Number of RK4 sub-steps.
    pub fn substeps(&self) -> usize {
        self.t.len().saturating_sub(1)
    }
    /// Duration covered, seconds.
    pub fn duration(&self) -> f64 {
        match (self.t.first(), self.t.last()) {
            (Some(a), Some(b)) => b - a,
            _ => 0.0,
        }
    }
}

/// Reusable scratch memory for propagation, grown once and then reused: numbers for the
/// one-state path, lanes for the batched one.
#[derive(Debug, Clone, Default)]
pub struct PropagationScratch {
    buf: Vec<f64>,
    lanes: Vec<Lanes>,
}

impl PropagationScratch {
    /// Scratch of `len` values.
    pub fn new(len: usize) -> Self {
        PropagationScratch {
            buf: vec![0.0; len],
            lanes: Vec::new(),
        }
    }
    /// `len` lanes of scratch (allocates only when growing).
    pub fn lanes(&mut self, len: usize) -> &mut [Lanes] {
        if self.lanes.len() < len {
            self.lanes.resize(len, Lanes::default());
        }
        &mut self.lanes[..len]
    }
    /// Makes sure at least `len` values are available (allocates only when growing).
    pub fn ensure(&mut self, len: usize) {
        if self.buf.len() < len {
            self.buf.resize(len, 0.0);
        }
    }
    /// The whole buffer.
    pub fn as_mut_slice(&mut self) -> &mut [f64] {
        &mut self.buf
    }
}

/// Which input a stage of a sub-step sees.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Knot {
    /// The input at the sub-step's start.
    Start,
    /// The input at its midpoint.
    Mid,
    /// The input at its end.
    End,
}

/// One stage of the RK4 table: stage `s` evaluates the rates at `x + offset h k_{s-1}` (the
/// start state for the first) with the input at `knot`, and enters the sum with weight
/// `h / divisor`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rk4Stage {
    /// The input it sees.
    pub knot: Knot,
    /// Fraction of the sub-step at which its state lies.
    pub offset: f64,
    /// Its weight in the sum is `h / divisor`.
    pub divisor: f64,
}

impl Rk4Stage {
    /// Its input in sub-step `j` of `window`.
    #[inline(always)]
    pub fn input<'a>(&self, window: &'a InputWindow, j: usize) -> &'a Input {
        match self.knot {
            Knot::Start => &window.f[j],
            Knot::Mid => &window.f_mid[j],
            Knot::End => &window.f[j + 1],
        }
    }
    /// `offset h`: how far along the sub-step of length `h` its state lies.
    #[inline(always)]
    pub fn offset(&self, h: f64) -> f64 {
        self.offset * h
    }
    /// `h / divisor`: its weight in the sum over a sub-step of length `h`.
    #[inline(always)]
    pub fn weight(&self, h: f64) -> f64 {
        h / self.divisor
    }
}

/// The classical fourth-order Runge-Kutta table, which the truth simulator, the UKFs' batches
/// and the EKF's tangent all step through.
pub const RK4: [Rk4Stage; 4] = [
    Rk4Stage {
        knot: Knot::Start,
        offset: 0.0,
        divisor: 6.0,
    },
    Rk4Stage {
        knot: Knot::Mid,
        offset: 0.5,
        divisor: 3.0,
    },
    Rk4Stage {
        knot: Knot::Mid,
        offset: 0.5,
        divisor: 3.0,
    },
    Rk4Stage {
        knot: Knot::End,
        offset: 1.0,
        divisor: 6.0,
    },
];

/// The step of one sub-step from the stage rates, `h/6 (k1 + 2 (k2 + k3) + k4)`: the table's
/// weights grouped so that the one-state and the batched paths round alike.
#[inline(always)]
pub fn rk4_step<T: Real>(h: f64, k: [T; 4]) -> T {
    (k[0] + (k[1] + k[2]) * 2.0 + k[3]) * (h / 6.0)
}

/// Propagates one state `x` (of `x.len()` states, the first `d` dynamic) across `window`
/// with RK4 ([`RK4`]), the derivative of the dynamic states given by `rates(x, u, dx)`.
/// `scratch` must hold at least `4 * d + x.len()` values. `noise`, when given, holds one value
/// per channel of `channels`. A model's one-state path is
/// [`crate::system::propagate_generic`], which calls this with its own rates.
pub fn propagate_one<R: Fn(&[f64], &Input, &mut [f64])>(
    rates: R,
    d: usize,
    channels: &[crate::effect::NoiseChannel],
    x: &mut [f64],
    noise: Option<&[f64]>,
    window: &InputWindow,
    scratch: &mut [f64],
) {
    let n = x.len();
    let (k, rest) = scratch.split_at_mut(4 * d);
    let tmp = &mut rest[..n];

    let add_noise = |dx: &mut [f64]| {
        if let Some(w) = noise {
            for (c, wi) in channels.iter().zip(w) {
                if c.state < d {
                    dx[c.state] += wi;
                }
            }
        }
    };
    // Constant states driven by noise move linearly: x_s(tau) = x_s + w tau.
    let drift_constants = |tmp: &mut [f64], x: &[f64], tau: f64| {
        if let Some(w) = noise {
            for (c, wi) in channels.iter().zip(w) {
                if c.state >= d {
                    tmp[c.state] = x[c.state] + wi * tau;
                }
            }
        }
    };

    for j in 0..window.substeps() {
        let h = window.t[j + 1] - window.t[j];
        for (s, stage) in RK4.iter().enumerate() {
            let (done, todo) = k.split_at_mut(s * d);
            let ks = &mut todo[..d];
            let u = stage.input(window, j);
            if s == 0 {
                rates(x, u, ks);
            } else {
                if s == 1 {
                    tmp[d..].copy_from_slice(&x[d..]);
                }
                let c = stage.offset(h);
                let prev = &done[(s - 1) * d..];
                for i in 0..d {
                    tmp[i] = x[i] + c * prev[i];
                }
                drift_constants(tmp, x, c);
                rates(tmp, u, ks);
            }
            add_noise(ks);
        }
        for i in 0..d {
            x[i] += rk4_step(h, [k[i], k[d + i], k[2 * d + i], k[3 * d + i]]);
        }
        drift_constants_final(channels, noise, d, x, h);
    }
}

fn drift_constants_final(
    channels: &[crate::effect::NoiseChannel],
    noise: Option<&[f64]>,
    d: usize,
    x: &mut [f64],
    h: f64,
) {
    if let Some(w) = noise {
        for (c, wi) in channels.iter().zip(w) {
            if c.state >= d {
                x[c.state] += wi * h;
            }
        }
    }
}
