//! Small statistics: chi-square quantiles for consistency bounds.

/// Standard normal quantile (Acklam's rational approximation, relative error < 1.2e-9).
#[allow(clippy::excessive_precision)] // the published coefficients, as printed
pub fn normal_quantile(p: f64) -> f64 {
    const A: [f64; 6] = [
        -3.969683028665376e+01,
        2.209460984245205e+02,
        -2.759285104469687e+02,
        1.383577518672690e+02,
        -3.066479806614716e+01,
        2.506628277459239e+00,
    ];
    const B: [f64; 5] = [
        -5.447609879822406e+01,
        1.615858368580409e+02,
        -1.556989798598866e+02,
        6.680131188771972e+01,
        -1.328068155288572e+01,
    ];
    const C: [f64; 6] = [
        -7.784894002430293e-03,
        -3.223964580411365e-01,
        -2.400758277161838e+00,
        -2.549732539343734e+00,
        4.374664141464968e+00,
        2.938163982698783e+00,
    ];
    const D: [f64; 4] = [
        7.784695709041462e-03,
        3.224671290700398e-01,
        2.445134137142996e+00,
        3.754408661907416e+00,
    ];
    let pl = 0.02425;
    if p < pl {
        let q = (-2.0 * p.ln()).sqrt();
        (((((C[0] * q + C[1]) * q + C[2]) * q + C[3]) * q + C[4]) * q + C[5])
            / ((((D[0] * q + D[1]) * q + D[2]) * q + D[3]) * q + 1.0)
    } else if p <= 1.0 - pl {
        let q = p - 0.5;
        let r = q * q;
        (((((A[0] * r + A[1]) * r + A[2]) * r + A[3]) * r + A[4]) * r + A[5]) * q
            / (((((B[0] * r + B[1]) * r + B[2]) * r + B[3]) * r + B[4]) * r + 1.0)
    } else {
        -normal_quantile(1.0 - p)
    }
}

/// Chi-square quantile with `dof` degrees of freedom (Wilson-Hilferty; within 0.5 % for
/// dof >= 10, which every bound here has).
///
/// ```
/// let q = navkf_report::stats::chi2_quantile(0.975, 100.0);
/// assert!((q - 129.56).abs() < 0.2);
/// ```
pub fn chi2_quantile(p: f64, dof: f64) -> f64 {
    let z = normal_quantile(p);
    let a = 2.0 / (9.0 * dof);
    dof * (1.0 - a + z * a.sqrt()).powi(3)
}

/// Two-sided 95 % bounds of the average of `count` chi-square variables with `dof` degrees
/// of freedom each (total degrees `count * dof`), divided by `count`.
pub fn mean_chi2_bounds(dof_total: f64, count: f64) -> [f64; 2] {
    mean_chi2_band(Band::Percent95, dof_total, count)
}

/// A two-sided band of a chi-square statistic: 95 % (what reports show) or 99 % (what a
/// verdict that runs several tests at once may use, so that a consistent model is rarely
/// called inconsistent).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Band {
    /// 2.5 % in each tail.
    Percent95,
    /// 0.5 % in each tail.
    Percent99,
}

impl Band {
    /// The lower and upper tail probabilities, written out (`(1 - 0.95) / 2` is not 0.025
    /// in floating point).
    pub fn tails(self) -> (f64, f64) {
        match self {
            Band::Percent95 => (0.025, 0.975),
            Band::Percent99 => (0.005, 0.995),
        }
    }
}

/// The `band` of the average of `count` chi-square variables with `dof_total` degrees of
/// freedom in all, divided by `count`.
pub fn mean_chi2_band(band: Band, dof_total: f64, count: f64) -> [f64; 2] {
    let (lo, hi) = band.tails();
    [
        chi2_quantile(lo, dof_total) / count,
        chi2_quantile(hi, dof_total) / count,
    ]
}

/// Where an average of chi-square variables (a mean NEES or NIS) lies against its 95 %
/// bounds. The one consistency verdict of the crate: the study report, the diagnosis's NIS
/// statistics and its fit summaries all say it with this type.
///
/// ```
/// use navkf_report::stats::Consistency;
/// assert_eq!(Consistency::of(30.0, [10.0, 20.0]), Consistency::Optimistic);
/// assert_eq!(Consistency::of(15.0, [10.0, 20.0]), Consistency::Consistent);
/// assert_eq!(Consistency::of(5.0, [10.0, 20.0]).to_string(), "pessimistic");
/// assert_eq!(Consistency::of(f64::NAN, [10.0, 20.0]), Consistency::NoVerdict);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Consistency {
    /// Inside the bounds.
    Consistent,
    /// Above: the errors (or innovations) are larger than the covariance claims.
    Optimistic,
    /// Below: the covariance claims more than the errors show (noise set too high?).
    Pessimistic,
    /// No finite mean or bounds (no data, or no run finished).
    NoVerdict,
}

impl Consistency {
    /// The verdict on `mean` against `bounds = [low, high]`.
    pub fn of(mean: f64, bounds: [f64; 2]) -> Self {
        if !(mean.is_finite() && bounds[0].is_finite() && bounds[1].is_finite()) {
            Consistency::NoVerdict
        } else if mean > bounds[1] {
            Consistency::Optimistic
        } else if mean < bounds[0] {
            Consistency::Pessimistic
        } else {
            Consistency::Consistent
        }
    }

    /// The verdict as one word (`consistent`, `optimistic`, `pessimistic`, `no verdict`).
    pub fn as_str(self) -> &'static str {
        match self {
            Consistency::Consistent => "consistent",
            Consistency::Optimistic => "optimistic",
            Consistency::Pessimistic => "pessimistic",
            Consistency::NoVerdict => "no verdict",
        }
    }
}

impl std::fmt::Display for Consistency {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// A mean of chi-square variables (a mean NEES or NIS) with its two-sided 95 % bounds for a
/// consistent filter: the one shape of such a statistic, whose verdict is computed in one
/// place ([`Consistency::of`]).
///
/// ```
/// use navkf_report::stats::{Consistency, MeanChi2};
/// // 100 NIS values of 2 degrees of freedom each, summing to 260: mean 2.6, above the band.
/// let nis = MeanChi2::of_sum(260.0, 200.0, 100.0);
/// assert!((nis.mean - 2.6).abs() < 1e-12);
/// assert!(nis.bounds[0] < 2.0 && 2.0 < nis.bounds[1] && nis.bounds[1] < 2.6);
/// assert_eq!(nis.verdict(), Consistency::Optimistic);
/// assert_eq!(MeanChi2::of_sum(0.0, 0.0, 0.0).verdict(), Consistency::NoVerdict);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct MeanChi2 {
    /// The mean (NaN without data).
    pub mean: f64,
    /// Its 95 % bounds for a consistent filter (NaN without data).
    pub bounds: [f64; 2],
}

impl MeanChi2 {
    /// The mean of `count` variables whose values sum to `sum` and whose degrees of freedom
    /// sum to `dof_total`, with [`mean_chi2_bounds`].
    pub fn of_sum(sum: f64, dof_total: f64, count: f64) -> Self {
        if !(count > 0.0 && dof_total > 0.0) {
            return MeanChi2 {
                mean: f64::NAN,
                bounds: [f64::NAN; 2],
            };
        }
        MeanChi2 {
            mean: sum / count,
            bounds: mean_chi2_bounds(dof_total, count),
        }
    }

    /// Where the mean lies against its bounds.
    pub fn verdict(&self) -> Consistency {
        Consistency::of(self.mean, self.bounds)
    }
}

/// `ln Gamma(x)` for `x > 0` (Lanczos, g = 7, nine terms; relative error below 1e-14).
#[allow(clippy::excessive_precision)] // the published coefficients, as printed
pub fn ln_gamma(x: f64) -> f64 {
    const G: f64 = 7.0;
    const C: [f64; 9] = [
        0.999_999_999_999_809_93,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_13,
        -176.615_029_162_140_59,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_571_6e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        // Reflection: Gamma(x) Gamma(1 - x) = pi / sin(pi x).
        let pi = std::f64::consts::PI;
        return (pi / (pi * x).sin()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let mut a = C[0];
    let t = x + G + 0.5;
    for (i, c) in C.iter().enumerate().skip(1) {
        a += c / (x + i as f64);
    }
    0.5 * (2.0 * std::f64::consts::PI).ln() + (x + 0.5) * t.ln() - t + a.ln()
}

/// Upper regularised incomplete gamma function `Q(a, x) = Gamma(a, x) / Gamma(a)`: the series
/// of `P` below `x = a + 1`, Lentz's continued fraction above (the textbook split, each where
/// it converges fast).
pub fn gamma_q(a: f64, x: f64) -> f64 {
    if !(a > 0.0) || x.is_nan() {
        return f64::NAN;
    }
    if x <= 0.0 {
        return 1.0;
    }
    if x.is_infinite() {
        return 0.0;
    }
    let ln_front = a * x.ln() - x - ln_gamma(a);
    if x < a + 1.0 {
        let (mut term, mut sum, mut n) = (1.0 / a, 1.0 / a, a);
        for _ in 0..10_000 {
            n += 1.0;
            term *= x / n;
            sum += term;
            if term.abs() < sum.abs() * 1e-16 {
                break;
            }
        }
        (1.0 - sum * ln_front.exp()).max(0.0)
    } else {
        let tiny = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / tiny;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..10_000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < tiny {
                d = tiny;
            }
            c = b + an / c;
            if c.abs() < tiny {
                c = tiny;
            }
            d = 1.0 / d;
            let delta = d * c;
            h *= delta;
            if (delta - 1.0).abs() < 1e-16 {
                break;
            }
        }
        (ln_front.exp() * h).clamp(0.0, 1.0)
    }
}

/// Survival function of the chi-square distribution: `P(X > x)` for `dof` degrees of freedom.
///
/// ```
/// use navkf_report::stats::chi2_sf;
/// assert!((chi2_sf(3.841_458_820_694_124, 1.0) - 0.05).abs() < 1e-12);
/// assert!((chi2_sf(18.307_038_053_275_146, 10.0) - 0.05).abs() < 1e-12);
/// assert_eq!(chi2_sf(0.0, 3.0), 1.0);
/// ```
pub fn chi2_sf(x: f64, dof: f64) -> f64 {
    gamma_q(0.5 * dof, 0.5 * x)
}
