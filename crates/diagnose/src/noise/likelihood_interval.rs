//! The 95 % interval of a fitted noise level, by likelihood ratio: the log-scales either side
//! of the optimum where the log-likelihood has fallen by `chi2(1, 0.95) / 2`.
//!
//! Why not the curvature at the optimum: a level the data inform only weakly has a likelihood
//! far from quadratic in its log-scale. A MEMS unit's gyro noise beside an accelerometer noise
//! several times larger (both stated at navigation grade) is the measured case
//! (`examples/noise_from_afar.rs`): the accelerometer's noise drives the measured velocity
//! directly and swamps the gyro's, so the likelihood keeps rising gently towards larger gyro
//! levels and is flat below them. The curvature at its optimum then claimed a factor of 2
//! either side, and missed the truth on 16 of 90 datasets where a 95 % interval may miss it on
//! about 5: the fitted gyro level was 2 to 4.7 times the truth while the log-likelihood at the
//! truth was less than 1 below the optimum. The likelihood-ratio interval follows the
//! likelihood's own shape, and is open where it never falls far enough.
//!
//! The interval is the profile likelihood's along the ridge the curvature predicts: as the
//! source's log-scale moves by `d`, each other fitted source moves by `d cov_kj / cov_jj`, its
//! best level given the first's if the likelihood were quadratic (a true profile would refit
//! them at every point, at many more filter passes). Held at their optimum instead, the others
//! would make the interval too narrow where levels trade off: a gyro level that the
//! accelerometer's can partly stand in for missed its truth on 14 of 100 MEMS datasets along
//! its own axis.

use super::grid::Landscape;
use super::levels::Theta;
use crate::error::DiagnoseError;

/// The log-likelihood fall that bounds the interval: `chi2(1, 0.95) / 2`.
pub const LR_DROP: f64 = 1.920_729_410_347_062;
/// Farthest a bound is sought from the optimum, in log-variance: a factor 10^4 in sigma, the
/// process-noise grid's reach (`noise::grid`).
pub const FARTHEST: f64 = 18.420_680_743_952_367;
/// Doublings of the step before a side is called open.
const DOUBLINGS: usize = 6;
/// Passes at the interpolated crossing once a side is bracketed.
const REFINEMENTS: usize = 2;

/// One side's search: the farthest offset known inside the interval and the nearest known
/// outside, each with its log-likelihood fall.
#[derive(Clone, Copy)]
struct Side {
    sign: f64,
    inside: (f64, f64),
    outside: Option<(f64, f64)>,
}

impl Side {
    /// Where the fall crosses [`LR_DROP`] between the two points known, interpolated in the
    /// square root of the fall (linear in the offset for a quadratic log-likelihood, so
    /// exact there).
    fn crossing(&self) -> Option<f64> {
        let ((a, fa), (b, fb)) = (self.inside, self.outside?);
        let (ra, rb) = (fa.max(0.0).sqrt(), fb.sqrt());
        let w = ((LR_DROP.sqrt() - ra) / (rb - ra)).clamp(0.0, 1.0);
        Some(a + w * (b - a))
    }

    fn learn(&mut self, offset: f64, fall: f64) {
        // A failed filter (no value) is beyond any level the data allow.
        let fall = if fall.is_nan() { f64::INFINITY } else { fall };
        if fall >= LR_DROP {
            if self.outside.is_none_or(|(o, _)| offset < o) {
                self.outside = Some((offset, fall));
            }
        } else if offset > self.inside.0 {
            self.inside = (offset, fall);
        }
    }
}

/// The 95 % likelihood-ratio bounds of log-scale `j` about the optimum `theta` (value `f`),
/// as log-scales; `None` on a side where the log-likelihood does not fall far enough within
/// [`FARTHEST`]. The search moves along `ridge` (`ridge[j] = 1`; the others' moves per unit of
/// `j`'s, module documentation); `se` (the curvature's standard error) sizes the first step.
pub(super) fn bounds(
    surface: &dyn Landscape,
    theta: Theta,
    f: f64,
    j: usize,
    ridge: Theta,
    se: f64,
) -> Result<[Option<f64>; 2], DiagnoseError> {
    let mut sides = [-1.0, 1.0].map(|sign| Side {
        sign,
        inside: (0.0, 0.0),
        outside: None,
    });
    let at = |side: &Side, offset: f64| -> Theta {
        std::array::from_fn(|k| theta[k] + ridge[k] * side.sign * offset)
    };
    // Bracket: step out from 1.96 se, doubling, on both sides at once.
    let mut step = (1.96 * se).clamp(0.2, 4.0);
    for _ in 0..DOUBLINGS {
        let open: Vec<usize> = (0..2)
            .filter(|&s| sides[s].outside.is_none() && sides[s].inside.0 < FARTHEST)
            .collect();
        if open.is_empty() {
            break;
        }
        let offsets: Vec<f64> = open.iter().map(|_| step.min(FARTHEST)).collect();
        let points: Vec<Theta> = open
            .iter()
            .zip(&offsets)
            .map(|(&s, &o)| at(&sides[s], o))
            .collect();
        for ((&s, &o), v) in open.iter().zip(&offsets).zip(surface.values(&points)?) {
            sides[s].learn(o, f - v);
        }
        step *= 2.0;
    }
    // Refine: passes at each bracketed side's interpolated crossing.
    for _ in 0..REFINEMENTS {
        let bracketed: Vec<(usize, f64)> = (0..2)
            .filter_map(|s| sides[s].crossing().map(|c| (s, c)))
            .collect();
        let points: Vec<Theta> = bracketed.iter().map(|&(s, c)| at(&sides[s], c)).collect();
        for (&(s, c), v) in bracketed.iter().zip(surface.values(&points)?) {
            sides[s].learn(c, f - v);
        }
    }
    Ok(sides.map(|side| side.crossing().map(|c| theta[j] + side.sign * c)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::noise::grid::Hessian;

    /// A log-likelihood of known shape.
    struct Known(fn(&Theta) -> f64);

    const AXIS: Theta = [1.0, 0.0, 0.0, 0.0, 0.0, 0.0];

    impl Landscape for Known {
        fn values(&self, points: &[Theta]) -> Result<Vec<f64>, DiagnoseError> {
            Ok(points.iter().map(self.0).collect())
        }
        fn climb(
            &self,
            start: Theta,
            value: f64,
            _: &mut Vec<usize>,
            _: &mut Theta,
            _: &mut Hessian,
        ) -> Result<(Theta, f64), DiagnoseError> {
            Ok((start, value))
        }
    }

    /// A quadratic log-likelihood of standard error 0.5 gives +-1.96 x 0.5, whatever the
    /// first step; a plateau on one side leaves that side open; a filter failing far out
    /// bounds it there.
    #[test]
    fn bounds_follow_the_likelihoods_shape() {
        let quadratic = Known(|t| -0.5 * ((t[0] - 1.0) / 0.5).powi(2));
        for se in [0.05, 0.5, 3.0] {
            let [lo, hi] =
                bounds(&quadratic, [1.0, 0.0, 0.0, 0.0, 0.0, 0.0], 0.0, 0, AXIS, se).unwrap();
            let (lo, hi) = (lo.unwrap(), hi.unwrap());
            assert!((lo - (1.0 - 0.98)).abs() < 1e-3, "{se}: {lo}");
            assert!((hi - (1.0 + 0.98)).abs() < 1e-3, "{se}: {hi}");
        }
        // Flat below 0, falling above: the lower side is open.
        let plateau = Known(|t| if t[0] < 0.0 { 0.0 } else { -t[0] * t[0] });
        let [lo, hi] = bounds(
            &plateau,
            [0.0; crate::noise::MAX_SOURCES],
            0.0,
            0,
            AXIS,
            0.5,
        )
        .unwrap();
        assert_eq!(lo, None);
        assert!((hi.unwrap() - LR_DROP.sqrt()).abs() < 0.05, "{hi:?}");
        let failing = Known(|t| if t[0] > 3.0 { f64::NAN } else { 0.0 });
        let [lo, hi] = bounds(
            &failing,
            [0.0; crate::noise::MAX_SOURCES],
            0.0,
            0,
            AXIS,
            0.5,
        )
        .unwrap();
        assert_eq!(lo, None);
        assert!(hi.unwrap() <= 3.2 && hi.unwrap() >= 0.0, "{hi:?}");
    }

    /// Two log-scales that trade off (correlation 0.9, standard errors 1 and 2): along the
    /// ridge the interval is the marginal one, +-1.96 x 1; along the axis, the conditional
    /// one, +-1.96 x sqrt(1 - 0.81), too narrow.
    #[test]
    fn the_ridge_gives_the_profile_interval() {
        // -0.5 [x y] C^-1 [x y]^T, C = [[1, 1.8], [1.8, 4]].
        let pair = Known(|t| -0.5 * (4.0 * t[0] * t[0] - 3.6 * t[0] * t[1] + t[1] * t[1]) / 0.76);
        let ridge = [1.0, 1.8, 0.0, 0.0, 0.0, 0.0];
        let [lo, hi] = bounds(&pair, [0.0; crate::noise::MAX_SOURCES], 0.0, 0, ridge, 1.0).unwrap();
        assert!((hi.unwrap() - 1.96).abs() < 1e-3 && (lo.unwrap() + 1.96).abs() < 1e-3);
        let [_, hi] = bounds(&pair, [0.0; crate::noise::MAX_SOURCES], 0.0, 0, AXIS, 1.0).unwrap();
        assert!((hi.unwrap() - 1.96 * 0.19f64.sqrt()).abs() < 1e-3, "{hi:?}");
    }
}
