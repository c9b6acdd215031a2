//! Where a model fails: NIS against its chi-square bounds overall, in sliding windows and by
//! motion phase, and the whiteness of each innovation channel.
//!
//! A consistent model's normalised innovations are white with unit variance: NIS
//! (docs/model.md eq. (18)) averages to the measurement dimension, and each channel's
//! autocorrelation stays inside `+-1.96/sqrt(N)` at every lag. The Ljung-Box statistic
//! `Q = N (N + 2) sum_l r_l^2 / (N - l)` over `L` lags is then chi-square with `L` degrees of
//! freedom.

use navkf_dynamics::trajectory::Phase;
use navkf_report::stats::{
    chi2_quantile, mean_chi2_band, normal_quantile, Band, Consistency, MeanChi2,
};
use serde::{Deserialize, Serialize};

use navkf_dynamics::trajectory::phase_thresholds as thresholds;

/// The motion phase at one step, from the mean horizontal specific force over the step and
/// the odometer velocity. Gravity and Coriolis are below the thresholds' resolution.
pub fn classify(f_mean: [f64; 2], velocity: Option<[f64; 2]>) -> Phase {
    let Some(v) = velocity else {
        return Phase::Cruising;
    };
    let speed = v[0].hypot(v[1]);
    if speed < thresholds::STILL_SPEED {
        return Phase::Standstill;
    }
    let (ux, uy) = (v[0] / speed, v[1] / speed);
    let along = f_mean[0] * ux + f_mean[1] * uy;
    let cross = -f_mean[0] * uy + f_mean[1] * ux;
    moving_phase(cross / speed, along)
}

/// The phase of a vehicle in motion from its turn rate (rad/s) and its acceleration along
/// the track (m/s^2).
pub fn moving_phase(turn_rate: f64, along: f64) -> Phase {
    if turn_rate.abs() > thresholds::TURN_RATE_DEG_S.to_radians() {
        Phase::Turning
    } else if along > thresholds::ALONG_ACCEL {
        Phase::Accelerating
    } else if along < -thresholds::ALONG_ACCEL {
        Phase::Decelerating
    } else {
        Phase::Cruising
    }
}

/// Name of a phase in reports.
pub fn phase_name(p: Phase) -> &'static str {
    match p {
        Phase::Standstill => "standstill",
        Phase::Accelerating => "accelerating",
        Phase::Cruising => "cruising",
        Phase::Turning => "turning",
        Phase::Decelerating => "decelerating",
    }
}

/// NIS statistics over a set of updates: the mean of chi-square variables with its bounds
/// ([`MeanChi2`], the one type of that idea, which [`NisStat::chi2`] returns), with the count
/// and the mean dimension kept for the report.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NisStat {
    /// Number of updates.
    pub count: usize,
    /// Mean NIS.
    pub mean: f64,
    /// Mean measurement dimension (the expected mean NIS).
    pub dof: f64,
    /// 95 % bounds of the mean for a consistent model.
    pub bounds: [f64; 2],
    /// Where the mean lies against its bounds.
    pub verdict: Consistency,
}

impl NisStat {
    /// From NIS values and their dimensions.
    pub fn of(nis: &[f64], dims: &[usize]) -> Self {
        let count = nis.len();
        let total_dof: usize = dims.iter().sum();
        if count == 0 || total_dof == 0 {
            return NisStat {
                count,
                mean: f64::NAN,
                dof: f64::NAN,
                bounds: [f64::NAN; 2],
                verdict: Consistency::NoVerdict,
            };
        }
        let chi2 = MeanChi2::of_sum(nis.iter().sum(), total_dof as f64, count as f64);
        NisStat {
            count,
            mean: chi2.mean,
            dof: total_dof as f64 / count as f64,
            bounds: chi2.bounds,
            verdict: chi2.verdict(),
        }
    }

    /// The mean with its 95 % bounds.
    pub fn chi2(&self) -> MeanChi2 {
        MeanChi2 {
            mean: self.mean,
            bounds: self.bounds,
        }
    }
}

impl NisStat {
    /// The `band` the mean of a consistent model lies in; `None` without updates.
    fn band(&self, band: Band) -> Option<[f64; 2]> {
        (self.count > 0)
            .then(|| mean_chi2_band(band, self.dof * self.count as f64, self.count as f64))
    }

    /// Whether the mean lies inside `band` (false without updates).
    pub fn within(&self, band: Band) -> bool {
        self.band(band)
            .is_some_and(|[lo, hi]| self.mean >= lo && self.mean <= hi)
    }

    /// Whether the mean lies below `band`: the model predicts larger innovations than it
    /// gets (false without updates).
    pub fn below(&self, band: Band) -> bool {
        self.band(band).is_some_and(|[lo, _]| self.mean < lo)
    }
}

/// Whiteness of one innovation channel.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Whiteness {
    /// Channel name.
    pub channel: String,
    /// Number of innovations.
    pub count: usize,
    /// Normalised autocorrelation at lags 1..=L.
    pub autocorrelation: Vec<f64>,
    /// 95 % band for white noise, `1.96 / sqrt(N)`.
    pub band: f64,
    /// Ljung-Box statistic over the lags.
    pub ljung_box: f64,
    /// Its critical value (chi-square, L dof, at the test's level).
    pub critical: f64,
    /// Mean of the normalised innovation (a bias shows here).
    pub mean: f64,
    /// Variance of the normalised innovation (1 when consistent).
    pub variance: f64,
    /// Updates per block of the slow-drift test.
    pub block: usize,
    /// Variance of the block sums of the normalised innovations over the block length (1
    /// when white; a slow drift the short lags cannot see makes it larger).
    pub block_variance: f64,
    /// Its critical value at the test's level.
    pub block_critical: f64,
    /// Whether the channel passes every test.
    pub white: bool,
    /// Why it fails, in words (empty when white).
    pub problems: Vec<String>,
}

/// Updates per block of the slow-drift test (a minute at 1 Hz: a misfit that changes over the
/// legs of a test, minutes long, shows; the Ljung-Box lags cover seconds).
pub const BLOCK: usize = 60;
/// Tests per channel, for the Bonferroni division of the family-wise level: Ljung-Box, mean,
/// variance, slow drift.
pub const TESTS_PER_CHANNEL: usize = 4;

/// Whiteness of a sequence of normalised innovations `nu / sqrt(S_ii)`. Each of its four
/// tests is made at level `alpha`; the caller divides its family-wise level among channels
/// and tests (Bonferroni):
///
/// - **autocorrelation**: Ljung-Box over `lags` lags;
/// - **bias**: the mean against `N(0, 1/N)`;
/// - **variance**: the mean square against `chi2(N) / N`;
/// - **slow drift**: the block sums `sum / sqrt(B)` over blocks of [`BLOCK`] updates are
///   `N(0, 1)` for white innovations; their mean square is tested against `chi2(M) / M`
///   (upper tail). A misfit that a filter tracks with inflated noise (a drag, a warming-up
///   bias) leaves innovations white over seconds but correlated over minutes: this is the
///   test that sees it.
pub fn whiteness(channel: &str, e: &[f64], lags: usize, alpha: f64) -> Whiteness {
    let n = e.len();
    let nf = n as f64;
    let mean = if n > 0 {
        e.iter().sum::<f64>() / nf
    } else {
        f64::NAN
    };
    let var = if n > 1 {
        e.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / nf
    } else {
        f64::NAN
    };
    let lags = lags.min(n.saturating_sub(2));
    let mut ac = Vec::with_capacity(lags);
    let mut q = 0.0;
    for l in 1..=lags {
        let c: f64 = (l..n)
            .map(|i| (e[i] - mean) * (e[i - l] - mean))
            .sum::<f64>()
            / nf;
        let r = if var > 0.0 { c / var } else { 0.0 };
        ac.push(r);
        q += r * r / (nf - l as f64);
    }
    q *= nf * (nf + 2.0);
    let critical = if lags > 0 {
        chi2_quantile(1.0 - alpha, lags as f64)
    } else {
        f64::NAN
    };
    // Raw second moment about zero tests the unit variance (chi-square with n dof).
    let m2 = if n > 0 {
        e.iter().map(|v| v * v).sum::<f64>() / nf
    } else {
        f64::NAN
    };
    let var_ok = n > 10 && {
        let lo = chi2_quantile(0.5 * alpha, nf) / nf;
        let hi = chi2_quantile(1.0 - 0.5 * alpha, nf) / nf;
        m2 >= lo && m2 <= hi
    };
    let mean_ok = mean.abs() <= normal_quantile(1.0 - 0.5 * alpha) / nf.sqrt();
    let blocks = n / BLOCK;
    let (block_variance, block_critical) = if blocks >= 2 {
        let b = BLOCK as f64;
        let sum_sq: f64 = e
            .chunks_exact(BLOCK)
            .map(|c| {
                let s = c.iter().sum::<f64>();
                s * s / b
            })
            .sum();
        let m = blocks as f64;
        (sum_sq / m, chi2_quantile(1.0 - alpha, m) / m)
    } else {
        (f64::NAN, f64::NAN)
    };
    let drift_ok = !(block_variance > block_critical);
    let mut w = Whiteness {
        channel: channel.into(),
        count: n,
        autocorrelation: ac,
        band: 1.96 / nf.sqrt(),
        ljung_box: q,
        critical,
        mean,
        variance: m2,
        block: BLOCK,
        block_variance,
        block_critical,
        white: lags > 0 && q <= critical && mean_ok && var_ok && drift_ok,
        problems: Vec::new(),
    };
    w.problems = problems(&w, mean_ok, var_ok);
    w
}

/// The sentence form of the tests' failures.
fn problems(w: &Whiteness, mean_ok: bool, var_ok: bool) -> Vec<String> {
    let mut why = Vec::new();
    if w.ljung_box > w.critical {
        why.push(format!(
            "correlated in time (Ljung-Box {:.0} > {:.0})",
            w.ljung_box, w.critical
        ));
    }
    if !mean_ok {
        why.push(format!("biased (mean {:+.2} sigma)", w.mean));
    }
    if !var_ok {
        why.push(format!("variance {:.2} of the predicted", w.variance));
    }
    if w.block_variance > w.block_critical {
        why.push(format!(
            "drifting slowly (sums over {} updates vary {:.1} times as much as white noise's)",
            w.block, w.block_variance
        ));
    }
    why
}

/// NIS in sliding windows of `width` updates, stepping by `width / 2`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NisWindow {
    /// Start and end time of the window, s.
    pub t: [f64; 2],
    /// The statistic.
    pub stat: NisStat,
}

/// Sliding-window NIS.
pub fn nis_windows(t: &[f64], nis: &[f64], dims: &[usize], width: usize) -> Vec<NisWindow> {
    let width = width.max(2);
    let mut out = Vec::new();
    let mut start = 0;
    while start + width <= nis.len() {
        let end = start + width;
        out.push(NisWindow {
            t: [t[start], t[end - 1]],
            stat: NisStat::of(&nis[start..end], &dims[start..end]),
        });
        start += width / 2;
    }
    out
}
