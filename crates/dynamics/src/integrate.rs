//! Fourth-order Runge-Kutta over an input window: the one integrator that the truth
//! simulator and every filter use.
//!
//! A window is a list of input knots `t_0 < t_1 < ... < t_m` with the specific force at each
//! knot and at each sub-step's midpoint. Each pair of knots is one RK4 sub-step, with stage
//! inputs `f(t_j)`, `f_mid_j`, `f_mid_j`, `f(t_{j+1})`. Filters fill the midpoint with the
//! average of the two knots (linear interpolation of sampled data); the truth simulator fills
//! it with the trajectory's exact value.
//!
//! White noise is held constant over the window (`w ~ N(0, q / T)` gives the right integrated
//! variance `q T`). A noise channel on a constant state (a coefficient random walk) moves that
//! state linearly in time, which RK4 reproduces exactly.

use crate::kinematics::Input;
use crate::system::SystemModel;

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
    pub fn push_linear(&mut self, t: f64, f: Input) {
        if let Some(prev) = self.f.last() {
            self.f_mid.push([
                0.5 * (prev[0] + f[0]),
                0.5 * (prev[1] + f[1]),
                0.5 * (prev[2] + f[2]),
            ]);
        }
        self.t.push(t);
        self.f.push(f);
    }
    /// Appends a knot with an explicit midpoint input for the sub-step it closes.
    pub fn push_with_mid(&mut self, t: f64, f: Input, f_mid: Input) {
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

/// Reusable scratch memory for propagation, grown once and then reused.
#[derive(Debug, Clone, Default)]
pub struct PropagationScratch {
    buf: Vec<f64>,
}

impl PropagationScratch {
    /// Scratch of `len` values.
    pub fn new(len: usize) -> Self {
        PropagationScratch {
            buf: vec![0.0; len],
        }
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

/// Propagates one state `x` across `window` with RK4. `scratch` must hold at least
/// `4 * dynamic_dim + dim` values. `noise`, when given, holds one value per noise channel.
pub fn propagate_generic<M: SystemModel + ?Sized>(
    model: &M,
    x: &mut [f64],
    noise: Option<&[f64]>,
    window: &InputWindow,
    scratch: &mut [f64],
) {
    let n = model.dim();
    let d = model.dynamic_dim();
    let (k, rest) = scratch.split_at_mut(4 * d);
    let (k1, k) = k.split_at_mut(d);
    let (k2, k) = k.split_at_mut(d);
    let (k3, k4) = k.split_at_mut(d);
    let tmp = &mut rest[..n];
    let channels = model.noise_channels();

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
        let (f0, fm, f1) = (&window.f[j], &window.f_mid[j], &window.f[j + 1]);

        model.rates(x, f0, k1);
        add_noise(k1);

        tmp.copy_from_slice(x);
        for i in 0..d {
            tmp[i] = x[i] + 0.5 * h * k1[i];
        }
        drift_constants(tmp, x, 0.5 * h);
        model.rates(tmp, fm, k2);
        add_noise(k2);

        for i in 0..d {
            tmp[i] = x[i] + 0.5 * h * k2[i];
        }
        model.rates(tmp, fm, k3);
        add_noise(k3);

        for i in 0..d {
            tmp[i] = x[i] + h * k3[i];
        }
        drift_constants(tmp, x, h);
        model.rates(tmp, f1, k4);
        add_noise(k4);

        for i in 0..d {
            x[i] += h / 6.0 * (k1[i] + 2.0 * (k2[i] + k3[i]) + k4[i]);
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
