//! The paper's vehicle test (section 4): a closed O-A-B-C-O path with acceleration, cruise,
//! deceleration and turns, and the specific force that makes the model reproduce it.
//!
//! The path is a sequence of segments on which speed `s` and heading `psi` (from North,
//! clockwise) are analytic: standstill, speed changes and 90-degree right turns follow a
//! `sin^2` profile (acceleration and turn rate rise and fall smoothly, as a driver's do), and
//! cruises hold speed and heading. From `v_E = s sin psi`, `v_N = s cos psi` the input is
//!
//! ```text
//! fx = a_E - (2 wie sinL + v_E tanL / RN) v_N
//! fy = a_N + (2 wie sinL + v_E tanL / RN) v_E
//! fz = g(L)
//! ```
//!
//! which is docs/model.md eq. (9) solved for `f` with every error zero, `g` from
//! docs/model.md eq. (4), so that the error-free model reproduces the path exactly. Latitude
//! and longitude follow the model's own docs/model.md eq. (10) along the path; the lengths
//! of the last two legs are solved so that the path closes on itself under that equation.

mod config;
mod segment;

pub use config::TrajectoryConfig;
use config::{check_fits, config_err, Fit, PATH_FITS, SEGMENTS_FIT};
pub use segment::{phase_thresholds, Motion, Phase, Segment};

use crate::earth::{meridian_radius, normal_gravity, prime_vertical_radius, WIE};
use crate::error::DynamicsError;
use crate::kinematics::SpecificForce;
use std::f64::consts::{FRAC_PI_2, PI};

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathState {
    /// East and North velocity, m/s.
    pub v: [f64; 2],
    /// East and North acceleration, m/s^2.
    pub a: [f64; 2],
    /// Latitude and longitude, rad.
    pub pos: [f64; 2],
    /// Heading from North, positive towards East (clockwise seen from above), rad.
    pub heading: f64,
    /// Signed speed along the heading, m/s.
    pub speed: f64,
    /// Heading rate, rad/s.
    pub turn_rate: f64,
    /// Upward acceleration on a grade, m/s^2 (the vertical velocity itself is not modelled).
    pub a_up: f64,
    /// Motion phase.
    pub phase: Phase,
}

/// The built path: segments plus the integrated nominal latitude and longitude.
#[derive(Debug, Clone)]
pub struct Trajectory {
    config: TrajectoryConfig,
    segments: Vec<Segment>,
    /// Nominal `[L, lambda]` at `k * GRID` seconds.
    grid: Vec<[f64; 2]>,
}

/// Spacing of the stored nominal positions, s. Positions in between come from cubic Hermite
/// interpolation with the exact derivatives, accurate to far below a millimetre.
const GRID: f64 = 0.5;
/// RK4 sub-steps per grid interval when integrating the nominal position.
const SUBSTEPS: usize = 10;

impl Trajectory {
    /// Builds the O-A-B-C-O path of `config`, solving the last two legs for closure.
    pub fn build(config: &TrajectoryConfig) -> Result<Self, DynamicsError> {
        config.validate()?;
        if !config.segments.is_empty() {
            return Self::from_segments(config);
        }
        let lat0 = config.start_lat_deg.to_radians();
        // Leg 3 (South) must undo leg 1 plus the northward part of two turns; leg 4 (West)
        // must undo leg 2 plus the eastward parts. Start from flat-Earth guesses and correct
        // with the model's own position equations (the problem is almost linear).
        let turn_t = 2.0 * FRAC_PI_2 / config.peak_turn_rate_deg.to_radians();
        let radius_like = config.turn_speed * turn_t * 2.0 / PI; // chord offset of a 90-deg arc
        let mut south = config.leg_north_m + radius_like;
        let mut west = config.leg_east_m + radius_like;
        let mut traj = Self::with_legs(config, south, west)?;
        for _ in 0..6 {
            let end = traj.end_position();
            let d_north = (end[0] - lat0) * meridian_radius(lat0.sin());
            let d_east = (end[1] - config.start_lon_deg.to_radians())
                * prime_vertical_radius(end[0].sin())
                * end[0].cos();
            if d_north.abs() < 1e-9 && d_east.abs() < 1e-9 {
                break;
            }
            south += d_north;
            west += d_east;
            traj = Self::with_legs(config, south, west)?;
        }
        Ok(traj)
    }

    fn with_legs(config: &TrajectoryConfig, south: f64, west: f64) -> Result<Self, DynamicsError> {
        let c = config;
        let mut b = SegmentList::default();
        let speed_change = |from: f64, to: f64| 2.0 * (to - from).abs() / c.peak_accel;
        let dist_change = |from: f64, to: f64| 0.5 * (from + to) * speed_change(from, to);
        let turn_t = 2.0 * FRAC_PI_2 / c.peak_turn_rate_deg.to_radians();
        if c.initial_standstill_s > 0.0 {
            b.push(c.initial_standstill_s, Motion::Standstill, "O");
        }
        let legs: [(&'static str, &'static str, f64); 4] = [
            ("O-A", "turn A", c.leg_north_m),
            ("A-B", "turn B", c.leg_east_m),
            ("B-C", "turn C", south),
            ("C-O", "O", west),
        ];
        for (i, (leg, corner, length)) in legs.into_iter().enumerate() {
            let first = i == 0;
            let last = i == 3;
            let v_in = if first { 0.0 } else { c.turn_speed };
            let v_out = if last { 0.0 } else { c.turn_speed };
            let cruise =
                length - dist_change(v_in, c.cruise_speed) - dist_change(c.cruise_speed, v_out);
            if cruise <= 0.0 {
                return Err(config_err(
                    if i % 2 == 0 { "leg_north_m" } else { "leg_east_m" },
                    format!(
                        "leg {leg} is {length:.1} m, too short to reach cruise_speed and slow down again: expected a longer leg or a higher peak_accel"
                    ),
                ));
            }
            b.push(
                speed_change(v_in, c.cruise_speed),
                Motion::SpeedChange {
                    from: v_in,
                    to: c.cruise_speed,
                },
                leg,
            );
            b.push(
                cruise / c.cruise_speed,
                Motion::Cruise {
                    speed: c.cruise_speed,
                },
                leg,
            );
            b.push(
                speed_change(c.cruise_speed, v_out),
                Motion::SpeedChange {
                    from: c.cruise_speed,
                    to: v_out,
                },
                leg,
            );
            if !last {
                b.push(
                    turn_t,
                    Motion::Turn {
                        speed: c.turn_speed,
                        delta: FRAC_PI_2,
                    },
                    corner,
                );
            }
        }
        Self::finish(c, b, PATH_FITS, "O")
    }

    /// The user's segment list, from rest at the start, heading North; after the last segment
    /// the vehicle holds or cruises until `duration_s`.
    fn from_segments(c: &TrajectoryConfig) -> Result<Self, DynamicsError> {
        let laid = crate::segments::lay_out(&c.segments, "trajectory.segment")?;
        let mut b = SegmentList::default();
        for l in laid {
            b.push_climbing(l.duration, l.motion, l.label, l.climb);
        }
        Self::finish(c, b, SEGMENTS_FIT, "hold")
    }

    /// The path of segments `b` until `duration_s`: refused if they take longer (`fit` says
    /// so), otherwise continued by what the vehicle does at their end (a cruise at its speed,
    /// or a hold labelled `rest_label`), with the nominal position integrated.
    fn finish(
        c: &TrajectoryConfig,
        mut b: SegmentList,
        fit: Fit,
        rest_label: &'static str,
    ) -> Result<Self, DynamicsError> {
        let t = b.t;
        check_fits(c, t, fit)?;
        if c.duration_s > t {
            let end_speed = b.segs.last().map_or(0.0, |s| s.kinematics(s.duration).0);
            if end_speed > 0.0 {
                b.push(
                    c.duration_s - t,
                    Motion::Cruise { speed: end_speed },
                    "cruise",
                );
            } else {
                b.push(c.duration_s - t, Motion::Standstill, rest_label);
            }
        }
        let mut traj = Trajectory {
            config: c.clone(),
            segments: b.segs,
            grid: Vec::new(),
        };
        crate::memory::check(
            "trajectory.duration_s",
            "the trajectory's position grid",
            (traj.config.duration_s / GRID).ceil() + 1.0,
            std::mem::size_of::<[f64; 2]>(),
        )?;
        traj.integrate_positions();
        Ok(traj)
    }

    /// Integrates `L' = v_N / RM`, `lambda' = v_E / (RN cos L)` along the path with RK4.
    fn integrate_positions(&mut self) {
        let n = (self.config.duration_s / GRID).ceil() as usize;
        let mut pos = [
            self.config.start_lat_deg.to_radians(),
            self.config.start_lon_deg.to_radians(),
        ];
        let mut grid = Vec::with_capacity(n + 1);
        grid.push(pos);
        let h = GRID / SUBSTEPS as f64;
        let rate = |t: f64, p: [f64; 2]| {
            let v = self.velocity(t);
            position_rate(v, p[0])
        };
        for k in 0..n {
            for j in 0..SUBSTEPS {
                let t = k as f64 * GRID + j as f64 * h;
                let k1 = rate(t, pos);
                let k2 = rate(
                    t + 0.5 * h,
                    [pos[0] + 0.5 * h * k1[0], pos[1] + 0.5 * h * k1[1]],
                );
                let k3 = rate(
                    t + 0.5 * h,
                    [pos[0] + 0.5 * h * k2[0], pos[1] + 0.5 * h * k2[1]],
                );
                let k4 = rate(t + h, [pos[0] + h * k3[0], pos[1] + h * k3[1]]);
                for i in 0..2 {
                    pos[i] += h / 6.0 * (k1[i] + 2.0 * (k2[i] + k3[i]) + k4[i]);
                }
            }
            grid.push(pos);
        }
        self.grid = grid;
    }

    fn segment_at(&self, t: f64) -> &Segment {
        let i = self
            .segments
            .partition_point(|s| s.start <= t)
            .saturating_sub(1);
        &self.segments[i]
    }

    fn velocity(&self, t: f64) -> [f64; 2] {
        let seg = self.segment_at(t);
        let (s, _, psi, _) = seg.kinematics(t - seg.start);
        [s * psi.sin(), s * psi.cos()]
    }

    /// The configuration it was built from.
    pub fn config(&self) -> &TrajectoryConfig {
        &self.config
    }
    /// The segments, in time order.
    pub fn segments(&self) -> &[Segment] {
        &self.segments
    }
    /// Total duration, s.
    pub fn duration(&self) -> f64 {
        self.config.duration_s
    }
    /// Nominal position at the end of the test, `[L, lambda]` in rad.
    pub fn end_position(&self) -> [f64; 2] {
        self.state(self.duration()).pos
    }

    /// Nominal motion at time `t` (clamped to the test's span).
    pub fn state(&self, t: f64) -> PathState {
        let t = t.clamp(0.0, self.duration());
        let seg = self.segment_at(t);
        let (s, ds, psi, dpsi) = seg.kinematics(t - seg.start);
        let (sp, cp) = psi.sin_cos();
        let v = [s * sp, s * cp];
        let a = [ds * sp + s * dpsi * cp, ds * cp - s * dpsi * sp];
        // Cubic Hermite between grid points, with the exact position rates at both ends.
        let k = ((t / GRID).floor() as usize).min(self.grid.len() - 2);
        let t0 = k as f64 * GRID;
        let t1 = t0 + GRID;
        let (p0, p1) = (self.grid[k], self.grid[k + 1]);
        let (m0, m1) = (
            position_rate(self.velocity(t0), p0[0]),
            position_rate(self.velocity(t1), p1[0]),
        );
        let u = (t - t0) / GRID;
        let (h00, h10, h01, h11) = (
            (1.0 + 2.0 * u) * (1.0 - u) * (1.0 - u),
            u * (1.0 - u) * (1.0 - u),
            u * u * (3.0 - 2.0 * u),
            u * u * (u - 1.0),
        );
        let pos = [
            h00 * p0[0] + h10 * GRID * m0[0] + h01 * p1[0] + h11 * GRID * m1[0],
            h00 * p0[1] + h10 * GRID * m0[1] + h01 * p1[1] + h11 * GRID * m1[1],
        ];
        // The road's rise h(u) = climb (u - sin(2 pi u) / (2 pi)) over the segment.
        let a_up = if seg.climb != 0.0 {
            let u = ((t - seg.start) / seg.duration).clamp(0.0, 1.0);
            seg.climb * 2.0 * PI * (2.0 * PI * u).sin() / (seg.duration * seg.duration)
        } else {
            0.0
        };
        PathState {
            v,
            a,
            pos,
            heading: psi,
            speed: s,
            turn_rate: dpsi,
            a_up,
            phase: seg.phase(),
        }
    }

    /// The specific force `[fx, fy, fz]` at time `t` that makes the error-free model follow
    /// the path (module documentation).
    pub fn specific_force(&self, t: f64) -> SpecificForce {
        let st = self.state(t);
        specific_force_for(&st)
    }
}

/// The specific force of a path state (module documentation).
pub fn specific_force_for(st: &PathState) -> SpecificForce {
    let (s, c) = st.pos[0].sin_cos();
    let tan_over_rn = s / c / prime_vertical_radius(s);
    let cor = 2.0 * WIE * s + st.v[0] * tan_over_rn;
    [
        st.a[0] - cor * st.v[1],
        st.a[1] + cor * st.v[0],
        normal_gravity(s) + st.a_up,
    ]
}

/// Segments laid end to end.
#[derive(Default)]
struct SegmentList {
    segs: Vec<Segment>,
    t: f64,
    heading: f64,
}

impl SegmentList {
    fn push(&mut self, duration: f64, motion: Motion, label: &'static str) {
        self.push_climbing(duration, motion, label, 0.0)
    }

    fn push_climbing(&mut self, duration: f64, motion: Motion, label: &'static str, climb: f64) {
        let s = Segment {
            start: self.t,
            duration,
            heading: self.heading,
            motion,
            label,
            climb,
        };
        self.t += duration;
        self.heading = s.end_heading();
        self.segs.push(s);
    }
}

fn position_rate(v: [f64; 2], lat: f64) -> [f64; 2] {
    let (s, c) = lat.sin_cos();
    [
        v[1] / meridian_radius(s),
        v[0] / (prime_vertical_radius(s) * c),
    ]
}
