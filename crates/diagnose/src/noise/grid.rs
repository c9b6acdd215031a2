//! The process-noise grid of a noise check ([`super`]): restarts that find the gyro and
//! accelerometer levels when they are stated far from the truth.
//!
//! Noise stated far off leaves local optima along the ridge where one process noise stands in
//! for the other. On a MEMS recording diagnosed with navigation-grade levels (the densities
//! 100-1000 times larger in sigma), a gyro density raised 10^4 times explains the velocity
//! misfit of the accelerometer's, through the tilt it lets wander (`g phi` of
//! docs/model.md eq. (9)); from there the accelerometer's own level is flat, and Newton stays
//! (`examples/noise_from_afar.rs` measures it). So when a check found a process noise off,
//! the pair is also tried on a grid of absolute levels, and Newton restarts from the best
//! point of each of the best few gyro levels.
//!
//! The grid is 10x apart in the gyro's sigma and sqrt(10)x apart in the accelerometer's: the
//! accelerometer's level is resolved far more sharply (it drives the measured velocity
//! directly), so a coarse step in it lands outside the basin of the truth, while the gyro's
//! likelihood is broad. Each point is tried at the measurement levels found and at the start's
//! (a measurement noise raised to absorb a process noise's misfit tilts the grid towards a
//! wrong pair).

use super::levels::{Theta, MAX_SOURCES};
use crate::error::DiagnoseError;

/// The gyro density's levels: 1 to 10^4 times the stated sigma, 10x apart (log-variance).
const GYRO: [f64; 5] = [
    0.0,
    4.605_170_185_988_092,
    9.210_340_371_976_184,
    13.815_510_557_964_274,
    18.420_680_743_952_367,
];
/// Steps of the accelerometer density's levels: 1 to 10^4 times the stated sigma,
/// sqrt(10)x apart (log-variance `ln 10` each).
const ACCEL_STEPS: usize = 9;
/// Gyro levels Newton restarts from (the best ones, each at its best accelerometer level).
const RESTARTS: usize = 3;

/// The Hessian of the log-likelihood over the log-scales.
pub(super) type Hessian = [[f64; MAX_SOURCES]; MAX_SOURCES];

/// What the grid needs of the search ([`super::search`] implements it): the log-likelihood at
/// points, and Newton's climb from one.
pub(super) trait Landscape {
    /// The log-likelihood at each point.
    fn values(&self, points: &[Theta]) -> Result<Vec<f64>, DiagnoseError>;
    /// Newton's method from `start` (value `value`) with a fresh pass budget, over `active`
    /// and any source that becomes significant; leaves its last derivatives in `g`, `hess`.
    fn climb(
        &self,
        start: Theta,
        value: f64,
        active: &mut Vec<usize>,
        g: &mut Theta,
        hess: &mut Hessian,
    ) -> Result<(Theta, f64), DiagnoseError>;
}

/// How far (in log-variance) a restart's gyro or accelerometer level must end from the local
/// optimum for the restart to be kept: a factor of 10 in variance.
pub(super) const BASIN: f64 = std::f64::consts::LN_10;

/// Whether a restart that ended at `t` left the basin of the local optimum `theta`: its gyro
/// or accelerometer level moved by at least [`BASIN`].
///
/// The grid exists to escape a wrong basin, not to refine the local optimum. A restart that
/// ends in the same basin only polishes the noise-only fit, which the structured candidates
/// of the contest ([`crate::naming`]) are not given; kept, it let a white gyro noise 78x
/// (against 45x) outbid a hidden gyro bias walk (pairs of `studies/diagnosis.toml`: both
/// effects named above their limits fell from 53 to 50 of 72).
pub(super) fn another_basin(t: &Theta, theta: &Theta) -> bool {
    (t[0] - theta[0]).abs() >= BASIN || (t[1] - theta[1]).abs() >= BASIN
}

/// Tries the grid from the optimum `theta` (value `f`) of a check that started at
/// `theta_start`; when a grid point beats `f` by more than `gain`, Newton restarts from the
/// best few and the highest end that left the local optimum's basin ([`another_basin`]) is
/// returned, with its active sources and last derivatives in
/// `active`, `g` and `hess`. Otherwise everything is left as it was.
#[allow(clippy::too_many_arguments)]
pub(super) fn restart(
    surface: &impl Landscape,
    gain: f64,
    theta: Theta,
    f: f64,
    theta_start: Theta,
    active: &mut Vec<usize>,
    g: &mut Theta,
    hess: &mut Hessian,
) -> Result<(Theta, f64), DiagnoseError> {
    let mut at_start = theta_start;
    at_start[0] = theta[0];
    at_start[1] = theta[1];
    let bases: Vec<Theta> = if at_start == theta {
        vec![theta]
    } else {
        vec![theta, at_start]
    };
    let accel: Vec<f64> = (0..ACCEL_STEPS)
        .map(|i| i as f64 * std::f64::consts::LN_10)
        .collect();
    let mut points: Vec<(usize, Theta)> = Vec::new();
    for base in &bases {
        for (row, &gyro) in GYRO.iter().enumerate() {
            for &a in &accel {
                let mut t = *base;
                t[0] = gyro;
                t[1] = a;
                points.push((row, t));
            }
        }
    }
    let values = surface.values(&points.iter().map(|p| p.1).collect::<Vec<_>>())?;
    // The best point of each gyro level, best levels first.
    let mut rows: Vec<(f64, Theta)> = GYRO
        .iter()
        .enumerate()
        .filter_map(|(row, _)| {
            points
                .iter()
                .zip(&values)
                .filter(|((r, _), v)| *r == row && v.is_finite())
                .max_by(|a, b| a.1.total_cmp(b.1))
                .map(|((_, t), v)| (*v, *t))
        })
        .collect();
    rows.sort_by(|a, b| b.0.total_cmp(&a.0));
    let mut best = (f, theta, active.clone(), *g, *hess);
    for &(value, start) in rows.iter().take(RESTARTS) {
        if value - f <= gain {
            break;
        }
        let mut a = active.clone();
        for j in [0, 1] {
            if !a.contains(&j) {
                a.push(j);
            }
        }
        a.sort_unstable();
        let (mut gi, mut hi) = (*g, *hess);
        let (t, fi) = surface.climb(start, value, &mut a, &mut gi, &mut hi)?;
        if fi > best.0 && another_basin(&t, &theta) {
            best = (fi, t, a, gi, hi);
        }
    }
    let (fb, tb, ab, gb, hb) = best;
    *active = ab;
    *g = gb;
    *hess = hb;
    Ok((tb, fb))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_restart_is_another_basin_only_when_a_process_level_moved_tenfold() {
        let theta: Theta = [7.6, 2.0, 0.0, 0.0, 0.0, 0.0];
        let mut t = theta;
        t[0] = 8.7; // 78x against 45x in sigma: the same basin refined
        assert!(!another_basin(&t, &theta));
        t[2] = 5.0; // a measurement level's move does not count
        assert!(!another_basin(&t, &theta));
        t[0] = 7.6 + 2.4;
        assert!(another_basin(&t, &theta));
        let mut t = theta;
        t[1] = 2.0 - 2.5;
        assert!(another_basin(&t, &theta));
    }
}
