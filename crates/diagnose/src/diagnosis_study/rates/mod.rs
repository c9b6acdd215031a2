//! From outcomes to error rates: the confusion matrix, false attribution on clean and
//! out-of-catalogue data, per-effect detection curves and their 90 % sizes, and pairs.
//!
//! Every rate comes with its 95 % Wilson interval, so that "2 of 200" reads as what it is.
//! The detection curve of an effect is a logistic regression of "named" on the log of its
//! size over the datasets that hid it alone; its detection limit is the size named 90 % of
//! the time on the fitted curve, and the rate above the limit is counted directly (a curve
//! that falls again at large sizes, the symptom of a capping prior, shows there).

use super::hidden::{Class, Hidden, MEMS_NOISE_LABEL};
use super::Record;
use crate::Verdict;
use navkf_dynamics::effect::UnseenCombination;
use navkf_dynamics::Registry;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// `k` of `n` with its 95 % Wilson interval.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Rate {
    /// Events.
    pub k: usize,
    /// Trials.
    pub n: usize,
    /// `k / n` (NaN when `n = 0`).
    pub rate: f64,
    /// 95 % Wilson interval.
    pub interval: [f64; 2],
}

impl Rate {
    /// `k` of `n`.
    pub fn of(k: usize, n: usize) -> Rate {
        if n == 0 {
            return Rate {
                k,
                n,
                rate: f64::NAN,
                interval: [f64::NAN; 2],
            };
        }
        let z = 1.959_963_984_540_054_f64;
        let (kf, nf) = (k as f64, n as f64);
        let p = kf / nf;
        let denom = 1.0 + z * z / nf;
        let centre = (p + z * z / (2.0 * nf)) / denom;
        let half = z * (p * (1.0 - p) / nf + z * z / (4.0 * nf * nf)).sqrt() / denom;
        Rate {
            k,
            n,
            rate: p,
            interval: [(centre - half).max(0.0), (centre + half).min(1.0)],
        }
    }
}

impl std::fmt::Display for Rate {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.n == 0 {
            return write!(f, "-");
        }
        write!(
            f,
            "{:.1} % ({} of {}; 95 % {:.1}-{:.1} %)",
            100.0 * self.rate,
            self.k,
            self.n,
            100.0 * self.interval[0],
            100.0 * self.interval[1]
        )
    }
}

/// How a dataset's named set compares with the catalogued effects it hid.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Match {
    /// Nothing named.
    NothingNamed,
    /// Exactly the hidden catalogued effects.
    Exact,
    /// Every hidden one, and more.
    HiddenAndMore,
    /// Some but not all of the hidden ones.
    PartOfHidden,
    /// Only effects that were not hidden.
    OnlyOthers,
    /// The diagnosis stopped with an error.
    Error,
}

/// The match of one record.
pub fn matching(r: &Record) -> Match {
    if r.error.is_some() {
        return Match::Error;
    }
    let hidden: Vec<&str> = r.hidden.iter().filter_map(Hidden::effect).collect();
    if r.named.is_empty() {
        return Match::NothingNamed;
    }
    let found = hidden
        .iter()
        .filter(|h| r.named.iter().any(|n| n == *h))
        .count();
    let extra = r
        .named
        .iter()
        .filter(|n| !hidden.contains(&n.as_str()))
        .count();
    match (found, extra) {
        (0, _) => Match::OnlyOthers,
        (f, 0) if f == hidden.len() => Match::Exact,
        (f, _) if f == hidden.len() => Match::HiddenAndMore,
        _ => Match::PartOfHidden,
    }
}

/// One row of the confusion matrix: a kind of hidden content and what the diagnoses said.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ConfusionRow {
    /// The hidden content.
    pub hidden: String,
    /// Datasets.
    pub n: usize,
    /// By how the named set matched.
    pub matches: BTreeMap<String, usize>,
    /// By verdict.
    pub verdicts: BTreeMap<String, usize>,
    /// How often each effect was named (any round).
    pub named: BTreeMap<String, usize>,
    /// How often the noise levels were refitted.
    pub noise_refitted: usize,
}

/// A bin of a detection curve.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Bin {
    /// Size bounds, multiples of typical.
    pub multiples: [f64; 2],
    /// Named rate in the bin.
    pub named: Rate,
}

/// One catalogued effect's detection curve.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Detection {
    /// The effect.
    pub effect: String,
    /// Its first coefficient's typical sigma (the unit of the multiples), and its unit.
    pub typical: f64,
    /// Unit of `typical`.
    pub unit: String,
    /// Datasets hiding it alone whose size a test can see (those in [`Detection::unseen`] left out).
    pub n: usize,
    /// Logistic fit `P(named) = 1 / (1 + exp(-(a + b ln m)))`, when it could be fitted.
    pub logistic: Option<[f64; 2]>,
    /// Size named 90 % of the time, multiple of typical: `None` when not reached within the
    /// sizes drawn.
    pub limit_multiple: Option<f64>,
    /// Why there is no limit, in words.
    pub no_limit: Option<String>,
    /// Named rate among the datasets above the limit.
    pub above_limit: Option<Rate>,
    /// Named rate in log-spaced bins.
    pub bins: Vec<Bin>,
    /// Every dataset: (multiple, named); the multiple is of the part a test can see
    /// ([`EffectScale::seen_multiple`]).
    pub points: Vec<(f64, bool)>,
    /// The datasets left out because they hid only what no test sees; `None` when the effect
    /// has no such combination.
    #[serde(default)]
    pub unseen: Option<UnseenDraws>,
}

/// A target of the issue, measured.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Target {
    /// What.
    pub what: String,
    /// The target, in words.
    pub target: String,
    /// The measurement, in words.
    pub measured: String,
    /// Whether it is met.
    pub met: bool,
}

/// Everything the report shows.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Rates {
    /// Datasets.
    pub datasets: usize,
    /// Diagnoses that stopped with an error.
    pub errors: usize,
    /// Clean data: any effect named.
    pub clean_named: Rate,
    /// Clean data: the noise refitted.
    pub clean_noise_refitted: Rate,
    /// Clean data: verdict other than consistent.
    pub clean_not_consistent: Rate,
    /// Outside the catalogue, pooled: any catalogued effect named.
    pub outside_named: Rate,
    /// Per outside effect.
    pub outside_by_effect: BTreeMap<String, Rate>,
    /// Mis-stated noise: any effect named.
    pub noise_named: Rate,
    /// Mis-stated noise: the noise refitted.
    pub noise_found: Rate,
    /// Single effects: the hidden effect named, over all sizes.
    pub single_found: Rate,
    /// Single effects: something else named too, or instead.
    pub single_extra: Rate,
    /// Per catalogued effect.
    pub detection: Vec<Detection>,
    /// Pairs with both sizes above their limits: both named.
    pub pairs_both_above: Rate,
    /// All pairs: both named.
    pub pairs_both: Rate,
    /// The confusion matrix.
    pub confusion: Vec<ConfusionRow>,
    /// Single effects: hidden effect (rows) by named effect or "nothing" (columns).
    pub effect_matrix: BTreeMap<String, BTreeMap<String, usize>>,
    /// Named hidden effects' coefficients: share with |estimate - truth| < 3 sigma.
    pub estimates_within_3_sigma: Rate,
    /// Their RMS of (estimate - truth) / sigma (1 when the sigmas are honest).
    pub estimate_error_rms: f64,
    /// The targets.
    pub targets: Vec<Target>,
    /// Data of another kind than the model's, nothing catalogued hidden: any effect named,
    /// by row label (MEMS noise stated at navigation grade, misaligned platforms by the
    /// attitude equations diagnosed with, wrong units).
    #[serde(default)]
    pub other_kind_named: BTreeMap<String, Rate>,
    /// MEMS noise stated at navigation grade: each source's fitted level within 20 % of the
    /// truth, by source; and the levels the data could not fix (said so).
    #[serde(default)]
    pub mems_levels_within_20: BTreeMap<String, Rate>,
    /// The same, pooled over the sources.
    #[serde(default)]
    pub mems_levels_pooled: Option<Rate>,
    /// MEMS noise: levels left unresolved, pooled.
    #[serde(default)]
    pub mems_levels_unresolved: Option<Rate>,
    /// MEMS noise: levels the report calls fixed (a fitted level whose 95 % interval lies
    /// within 20 % of the truth wherever the truth is in it; `SourceFit::fixed`), pooled.
    #[serde(default)]
    pub mems_levels_fixed: Option<Rate>,
    /// MEMS noise: of the levels called fixed, those within 20 % of the truth.
    #[serde(default)]
    pub mems_fixed_within_20: Option<Rate>,
    /// MEMS noise: levels whose reported 95 % interval holds the truth, pooled (records that
    /// keep their intervals only).
    #[serde(default)]
    pub mems_intervals_cover: Option<Rate>,
    /// Wrong units: the warning that names the unit fired, by unit.
    #[serde(default)]
    pub wrong_units_warned: BTreeMap<String, Rate>,
}

/// Per noise source of `r` (gyro, accelerometer, odometer, GPS): the fitted level over the
/// truth, `None` where unresolved; for a MEMS-noise record.
fn mems_level_errors(r: &Record) -> Vec<Option<f64>> {
    r.noise_ratios
        .iter()
        .enumerate()
        .map(|(j, ratio)| ratio.map(|q| q / mems_truth(r, j)))
        .collect()
}

/// The truth's sigma over the stated one of source `j` of a MEMS-noise record (1 for the
/// sources the class leaves as stated).
fn mems_truth(r: &Record, j: usize) -> f64 {
    r.hidden
        .iter()
        .find_map(|h| match h {
            Hidden::MemsNoise { factors } => factors.get(j).copied(),
            _ => None,
        })
        .unwrap_or(1.0)
}

/// Names of the noise sources in a record's `noise_ratios` order.
const SOURCE_LABELS: [&str; 6] = [
    "gyro",
    "accelerometer",
    "odometer",
    "GPS",
    "constraint",
    "standstill",
];

/// `v` with `digits` significant digits, without an exponent between 1e-3 and 1e5.
pub fn sig(v: f64, digits: usize) -> String {
    if !v.is_finite() || v == 0.0 {
        return format!("{v}");
    }
    let mag = v.abs().log10().floor() as i32;
    if (-3..5).contains(&mag) {
        let decimals = (digits as i32 - 1 - mag).max(0) as usize;
        format!("{v:.decimals$}")
    } else {
        format!("{v:.*e}", digits.saturating_sub(1))
    }
}

/// `log(1 / (1 - 0.9) - 1)`: the logit of 0.9.
const LOGIT_90: f64 = 2.197_224_577_336_219_6;

/// Logistic regression of `y` on `x` by Newton's method (a small ridge keeps separable data
/// finite). `None` when `y` is all one value.
fn logistic(points: &[(f64, bool)]) -> Option<[f64; 2]> {
    let ones = points.iter().filter(|p| p.1).count();
    if ones == 0 || ones == points.len() {
        return None;
    }
    let (mut a, mut b) = (0.0f64, 0.0f64);
    for _ in 0..100 {
        let (mut g0, mut g1, mut h00, mut h01, mut h11) = (0.0, 0.0, 1e-6, 0.0, 1e-6);
        for &(x, y) in points {
            let p = 1.0 / (1.0 + (-(a + b * x)).exp());
            let r = f64::from(u8::from(y)) - p;
            let w = p * (1.0 - p);
            g0 += r;
            g1 += r * x;
            h00 += w;
            h01 += w * x;
            h11 += w * x * x;
        }
        g0 -= 1e-6 * a;
        g1 -= 1e-6 * b;
        let det = h00 * h11 - h01 * h01;
        if !(det > 0.0) {
            break;
        }
        let da = (h11 * g0 - h01 * g1) / det;
        let db = (h00 * g1 - h01 * g0) / det;
        a += da;
        b += db;
        if da.abs().max(db.abs()) < 1e-10 {
            break;
        }
    }
    (a.is_finite() && b.is_finite()).then_some([a, b])
}

/// A catalogued effect with the size its detection curve is scaled by: its first
/// coefficient's typical sigma (a noise-only term's `sqrt(density)`), and that one's unit;
/// and the combinations of its coefficients no test sees, which its curve leaves out.
#[derive(Debug, Clone, PartialEq)]
pub struct EffectScale {
    /// The effect's name.
    pub name: String,
    /// Its typical size (NaN when unknown).
    pub typical: f64,
    /// The unit of `typical`.
    pub unit: String,
    /// Each coefficient's name and typical sigma, in the order of the combinations' weights.
    pub sigmas: Vec<(String, f64)>,
    /// [`navkf_dynamics::effect::Effect::unseen_combinations`].
    pub unseen: Vec<UnseenCombination>,
}

impl EffectScale {
    /// The size of the hidden coefficients `values` that a test can see, as a multiple of
    /// their typical sizes: the root mean square over the coefficients, each in its typical
    /// sigma, of what is left once the unseen combinations are taken out. With none, or
    /// without a value for every coefficient, the size drawn (`multiple`).
    pub fn seen_multiple(&self, multiple: f64, values: &BTreeMap<String, f64>) -> f64 {
        if self.unseen.is_empty() || self.sigmas.is_empty() {
            return multiple;
        }
        let Some(mut x) = self
            .sigmas
            .iter()
            .map(|(name, sigma)| values.get(name).map(|v| v / sigma))
            .collect::<Option<Vec<f64>>>()
        else {
            return multiple;
        };
        // Gram-Schmidt on the combinations, each taken out of `x` once it is orthonormal.
        let mut basis: Vec<Vec<f64>> = Vec::new();
        for c in &self.unseen {
            let mut w: Vec<f64> = (0..x.len())
                .map(|i| c.weights.get(i).copied().unwrap_or(0.0))
                .collect();
            for b in &basis {
                let d: f64 = w.iter().zip(b).map(|(a, b)| a * b).sum();
                w.iter_mut().zip(b).for_each(|(a, b)| *a -= d * b);
            }
            let norm = w.iter().map(|a| a * a).sum::<f64>().sqrt();
            if norm > 1e-12 {
                w.iter_mut().for_each(|a| *a /= norm);
                let d: f64 = x.iter().zip(&w).map(|(a, b)| a * b).sum();
                x.iter_mut().zip(&w).for_each(|(a, b)| *a -= d * b);
                basis.push(w);
            }
        }
        (x.iter().map(|a| a * a).sum::<f64>() / x.len() as f64).sqrt()
    }

    /// [`EffectScale::seen_multiple`] of a hidden effect (its drawn size for anything else).
    fn seen(&self, h: &Hidden) -> f64 {
        match h {
            Hidden::Effect {
                multiple, values, ..
            } => self.seen_multiple(*multiple, values),
            other => other.multiple(),
        }
    }
}

/// A hidden size whose seen part is below this share of the size drawn lay wholly in an
/// unseen combination (the study draws each coefficient at the same size, so the seen part is
/// then zero to rounding).
const UNSEEN_SHARE: f64 = 1e-6;

/// The datasets of a detection curve whose hidden effect lay wholly in a combination no test
/// sees ([`EffectScale::unseen`]): left out of the curve, and counted.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct UnseenDraws {
    /// The combinations, in words.
    pub why: String,
    /// How often the effect was named on them (a name the data cannot have given).
    pub named: Rate,
}

/// The effects of `catalogue` (the platform's, with a study's declared ones) with their
/// typical sizes.
pub fn platform_scales(catalogue: &Registry) -> Vec<EffectScale> {
    catalogue
        .names()
        .into_iter()
        .map(|name| {
            let built = catalogue.build(&name).ok();
            let (sigmas, unseen) = built.as_ref().map_or((Vec::new(), Vec::new()), |e| {
                let sigmas = e
                    .coefficient_names()
                    .iter()
                    .zip(e.coefficient_sigma())
                    .map(|(n, s)| (n.to_string(), *s))
                    .collect();
                (sigmas, e.unseen_combinations().to_vec())
            });
            let (typical, unit) = built
                .map(|e| {
                    let t = e.coefficient_sigma().first().copied().unwrap_or_else(|| {
                        e.process_noise().first().map_or(f64::NAN, |c| c.psd.sqrt())
                    });
                    let u = e
                        .coefficient_units()
                        .first()
                        .map_or("sqrt(density)".to_string(), |u| u.to_string());
                    (t, u)
                })
                .unwrap_or((f64::NAN, String::new()));
            EffectScale {
                name,
                typical,
                unit,
                sigmas,
                unseen,
            }
        })
        .collect()
}

/// The detection curve of `scale`'s effect from the single-effect records.
fn detection(scale: &EffectScale, records: &[&Record]) -> Detection {
    let effect = scale.name.as_str();
    let (typical, unit) = (scale.typical, scale.unit.clone());
    let all: Vec<(f64, f64, bool)> = records
        .iter()
        .filter_map(|r| {
            let h = r.hidden.first()?;
            (h.effect() == Some(effect) && r.error.is_none()).then(|| {
                let named = r.named.iter().any(|n| n == effect);
                (h.multiple(), scale.seen(h), named)
            })
        })
        .collect();
    let is_unseen = |&(drawn, seen, _): &(f64, f64, bool)| seen < UNSEEN_SHARE * drawn;
    let points: Vec<(f64, bool)> = all
        .iter()
        .filter(|p| !is_unseen(p))
        .map(|&(_, seen, named)| (seen, named))
        .collect();
    let unseen = (!scale.unseen.is_empty()).then(|| {
        let hid: Vec<bool> = all.iter().filter(|p| is_unseen(p)).map(|p| p.2).collect();
        UnseenDraws {
            why: scale
                .unseen
                .iter()
                .map(|c| c.why)
                .collect::<Vec<_>>()
                .join("; "),
            named: Rate::of(hid.iter().filter(|&&y| y).count(), hid.len()),
        }
    });
    let xs: Vec<(f64, bool)> = points.iter().map(|&(m, y)| (m.ln(), y)).collect();
    let fit = logistic(&xs);
    let (lo, hi) = points.iter().fold((f64::INFINITY, 0.0f64), |(l, h), p| {
        (l.min(p.0), h.max(p.0))
    });
    // Named at least 90 % of the time over every size drawn: the limit is the smallest size
    // drawn, whatever the curve's slope (a miss or two among the largest sizes would tilt a
    // logistic fit the wrong way and read as "no size dependence").
    let named = points.iter().filter(|p| p.1).count();
    let named_from_the_smallest = !points.is_empty() && named as f64 >= 0.9 * points.len() as f64;
    let (limit, no_limit) = match fit {
        _ if named_from_the_smallest => (Some(lo), None),
        Some([a, b]) if b > 0.0 => {
            let m = ((LOGIT_90 - a) / b).exp();
            if m > hi {
                (
                    None,
                    Some(format!(
                        "not reached: named at most {:.0} % of the time up to {} x typical",
                        100.0 * (1.0 / (1.0 + (-(a + b * hi.ln())).exp())),
                        sig(hi, 3)
                    )),
                )
            } else {
                (Some(m.max(lo)), None)
            }
        }
        _ => (
            None,
            Some(if points.iter().any(|p| p.1) {
                "no size dependence: the named rate does not grow with the size".to_string()
            } else {
                format!("never named, up to {} x typical", sig(hi, 3))
            }),
        ),
    };
    let above_limit = limit.map(|m| {
        let above: Vec<bool> = points.iter().filter(|p| p.0 >= m).map(|p| p.1).collect();
        Rate::of(above.iter().filter(|&&y| y).count(), above.len())
    });
    let bins = if points.is_empty() {
        Vec::new()
    } else {
        let nb = 6;
        let (l, h) = (lo.ln(), hi.ln() * (1.0 + 1e-12) + 1e-12);
        (0..nb)
            .map(|k| {
                let a = (l + (h - l) * k as f64 / nb as f64).exp();
                let b = (l + (h - l) * (k + 1) as f64 / nb as f64).exp();
                let inside: Vec<bool> = points
                    .iter()
                    .filter(|p| p.0 >= a && (p.0 < b || (k == nb - 1 && p.0 <= b)))
                    .map(|p| p.1)
                    .collect();
                Bin {
                    multiples: [a, b],
                    named: Rate::of(inside.iter().filter(|&&y| y).count(), inside.len()),
                }
            })
            .collect()
    };
    Detection {
        effect: effect.to_string(),
        typical,
        unit,
        n: points.len(),
        logistic: fit,
        limit_multiple: limit,
        no_limit,
        above_limit,
        bins,
        points,
        unseen,
    }
}

/// Label of a record's hidden content for the confusion matrix.
fn row_label(r: &Record) -> String {
    match r.class {
        Class::Nothing => "nothing".into(),
        Class::Pair => "pair of catalogued effects".into(),
        _ => r
            .hidden
            .first()
            .map_or("nothing".to_string(), Hidden::label),
    }
}

/// The distinct row labels of `class`'s records, sorted.
fn labels_of(records: &[Record], class: Class) -> Vec<String> {
    let mut v: Vec<String> = records
        .iter()
        .filter(|r| r.class == class)
        .map(row_label)
        .collect();
    v.sort();
    v.dedup();
    v
}

fn verdict_name(v: Option<Verdict>) -> String {
    v.map_or("error".to_string(), |v| v.to_string())
}

fn match_name(m: Match) -> String {
    serde_json::to_value(m)
        .ok()
        .and_then(|v| v.as_str().map(str::to_string))
        .unwrap_or_default()
}

/// The rates of `records`, of a family whose catalogued effects are `scales`.
pub fn rates(records: &[Record], scales: &[EffectScale]) -> Rates {
    let of_class = |c: Class| records.iter().filter(move |r| r.class == c);
    let count = |it: &mut dyn Iterator<Item = &Record>, f: &dyn Fn(&Record) -> bool| {
        let mut k = 0;
        let mut n = 0;
        for r in it {
            n += 1;
            if f(r) {
                k += 1;
            }
        }
        Rate::of(k, n)
    };
    let any_named = |r: &Record| !r.named.is_empty();
    let clean_named = count(&mut of_class(Class::Nothing), &any_named);
    let clean_noise_refitted = count(&mut of_class(Class::Nothing), &|r: &Record| r.noise_named);
    let clean_not_consistent = count(&mut of_class(Class::Nothing), &|r: &Record| {
        r.verdict != Some(Verdict::Consistent)
    });
    let outside_named = count(&mut of_class(Class::Outside), &any_named);
    let mut outside_by_effect = BTreeMap::new();
    for l in labels_of(records, Class::Outside) {
        let rate = count(
            &mut of_class(Class::Outside).filter(|r| row_label(r) == l),
            &any_named,
        );
        outside_by_effect.insert(l, rate);
    }
    let noise_named = count(&mut of_class(Class::MisstatedNoise), &any_named);
    let noise_found = count(&mut of_class(Class::MisstatedNoise), &|r: &Record| {
        r.noise_named
    });
    let single: Vec<&Record> = of_class(Class::Single).collect();
    let single_found = count(&mut single.iter().copied(), &|r: &Record| {
        r.hidden
            .first()
            .and_then(Hidden::effect)
            .is_some_and(|e| r.named.iter().any(|n| n == e))
    });
    let single_extra = count(&mut single.iter().copied(), &|r: &Record| {
        let e = r.hidden.first().and_then(Hidden::effect).unwrap_or("");
        r.named.iter().any(|n| n != e)
    });
    let catalogue: Vec<&str> = scales.iter().map(|s| s.name.as_str()).collect();
    let detection: Vec<Detection> = scales
        .iter()
        .map(|s| detection(s, &single))
        .filter(|d| d.n > 0)
        .collect();
    let limit = |e: &str| {
        detection
            .iter()
            .find(|d| d.effect == e)
            .and_then(|d| d.limit_multiple)
    };
    let pairs: Vec<&Record> = of_class(Class::Pair).collect();
    let both = |r: &Record| {
        r.hidden
            .iter()
            .filter_map(Hidden::effect)
            .all(|e| r.named.iter().any(|n| n == e))
    };
    let pairs_both = count(&mut pairs.iter().copied(), &both);
    let seen = |h: &Hidden| {
        let scale = scales.iter().find(|s| Some(s.name.as_str()) == h.effect());
        scale.map_or(h.multiple(), |s| s.seen(h))
    };
    let pairs_both_above = count(
        &mut pairs.iter().copied().filter(|r| {
            r.hidden
                .iter()
                .all(|h| h.effect().and_then(limit).is_some_and(|m| seen(h) >= m))
        }),
        &both,
    );
    // Confusion matrix, rows in a fixed order.
    let mut rows: BTreeMap<(usize, String), ConfusionRow> = BTreeMap::new();
    for r in records {
        let label = row_label(r);
        let order = match r.class {
            Class::Nothing => 0,
            Class::Single => 1 + catalogue.iter().position(|c| *c == label).unwrap_or(0),
            Class::Pair => 20,
            Class::Outside => 21,
            Class::MisstatedNoise => 30,
            Class::MemsNoise => 31,
            Class::Misaligned => 32,
            Class::WrongUnits => 33,
        };
        let row = rows.entry((order, label.clone())).or_insert(ConfusionRow {
            hidden: label,
            n: 0,
            matches: BTreeMap::new(),
            verdicts: BTreeMap::new(),
            named: BTreeMap::new(),
            noise_refitted: 0,
        });
        row.n += 1;
        *row.matches.entry(match_name(matching(r))).or_insert(0) += 1;
        *row.verdicts.entry(verdict_name(r.verdict)).or_insert(0) += 1;
        for n in &r.named {
            *row.named.entry(n.clone()).or_insert(0) += 1;
        }
        if r.noise_named {
            row.noise_refitted += 1;
        }
    }
    let mut effect_matrix: BTreeMap<String, BTreeMap<String, usize>> = BTreeMap::new();
    for r in &single {
        let e = r.hidden.first().map(Hidden::label).unwrap_or_default();
        let row = effect_matrix.entry(e).or_default();
        if r.named.is_empty() {
            *row.entry("nothing".to_string()).or_insert(0) += 1;
        }
        for n in &r.named {
            *row.entry(n.clone()).or_insert(0) += 1;
        }
    }
    // A target whose class the study does not hold is not measured, not missed.
    let mut targets = Vec::new();
    if clean_named.n > 0 {
        targets.push(Target {
            what: "clean data: an effect named".into(),
            target: "at most 2 %".into(),
            measured: clean_named.to_string(),
            met: clean_named.rate <= 0.02,
        });
    }
    if outside_named.n > 0 {
        targets.push(Target {
            what: "outside the catalogue: a catalogued effect named".into(),
            // Issue "No confident wrong answer": as on clean data.
            target: "at most 2 %".into(),
            measured: outside_named.to_string(),
            met: outside_named.rate <= 0.02,
        });
    }
    for d in &detection {
        targets.push(Target {
            what: format!("`{}` named above its detection limit", d.effect),
            target: "at least 90 %".into(),
            measured: match (&d.above_limit, &d.no_limit, d.limit_multiple) {
                (Some(r), _, Some(m)) => format!(
                    "{r} above {} x typical ({:.3e} {})",
                    sig(m, 3),
                    m * d.typical,
                    d.unit
                ),
                (_, Some(why), _) => format!("no limit: {why}"),
                _ => "-".into(),
            } + &d.unseen.as_ref().map_or(String::new(), |u| {
                format!(
                    ", sizes being of the part a test can see ({} datasets that hid only what \
                     none sees left out)",
                    u.named.n
                )
            }),
            met: d.above_limit.is_some_and(|r| r.rate >= 0.9),
        });
    }
    if !pairs.is_empty() {
        targets.push(Target {
            what: "pairs above both limits: both named in one command".into(),
            target: "at least 90 %".into(),
            measured: pairs_both_above.to_string(),
            met: pairs_both_above.n > 0 && pairs_both_above.rate >= 0.9,
        });
    }
    // Data of another kind than the model's.
    let mut other_kind_named = BTreeMap::new();
    let mut wrong_units_warned = BTreeMap::new();
    for class in [Class::MemsNoise, Class::Misaligned, Class::WrongUnits] {
        for l in labels_of(records, class) {
            let named = count(
                &mut of_class(class).filter(|r| row_label(r) == l),
                &any_named,
            );
            targets.push(Target {
                what: format!("{l}: an effect named"),
                target: "at most 2 %".into(),
                measured: named.to_string(),
                met: named.rate <= 0.02,
            });
            other_kind_named.insert(l.clone(), named);
            if class == Class::WrongUnits {
                let warned = count(
                    &mut of_class(class).filter(|r| row_label(r) == l),
                    &|r: &Record| {
                        r.hidden.iter().any(|h| match h {
                            Hidden::WrongUnit { unit } => {
                                unit.doubts().iter().any(|d| r.warnings.contains(d))
                            }
                            _ => false,
                        })
                    },
                );
                targets.push(Target {
                    what: format!("{l}: its warning given"),
                    target: "every time".into(),
                    measured: warned.to_string(),
                    met: warned.n > 0 && warned.k == warned.n,
                });
                wrong_units_warned.insert(l, warned);
            }
        }
    }
    let mems: Vec<Vec<Option<f64>>> = of_class(Class::MemsNoise)
        .filter(|r| r.error.is_none())
        .map(mems_level_errors)
        .collect();
    let within = |e: &Option<f64>| e.is_some_and(|q| (q - 1.0).abs() <= 0.2);
    let mut mems_levels_within_20 = BTreeMap::new();
    for (j, label) in SOURCE_LABELS.iter().enumerate() {
        let column: Vec<&Option<f64>> = mems.iter().filter_map(|v| v.get(j)).collect();
        if !column.is_empty() {
            let k = column.iter().filter(|e| within(e)).count();
            mems_levels_within_20.insert(label.to_string(), Rate::of(k, column.len()));
        }
    }
    let pooled: Vec<&Option<f64>> = mems.iter().flatten().collect();
    let (mems_levels_pooled, mems_levels_unresolved) = if pooled.is_empty() {
        (None, None)
    } else {
        let k = pooled.iter().filter(|e| within(e)).count();
        let unresolved = Rate::of(pooled.iter().filter(|e| e.is_none()).count(), pooled.len());
        let rate = Rate::of(k, pooled.len());
        targets.push(Target {
            what: format!("{MEMS_NOISE_LABEL}: fitted levels within 20 % of the truth"),
            target: "at least 95 %".into(),
            measured: format!("{rate}; unresolved (and said so): {unresolved}"),
            met: rate.rate >= 0.95,
        });
        (Some(rate), Some(unresolved))
    };
    // The intervals: which levels the report calls fixed, and whether they hold the truth.
    let (mut levels, mut fixed, mut fixed_within, mut covered) = (0, 0, 0, 0);
    for r in of_class(Class::MemsNoise).filter(|r| r.error.is_none()) {
        let errors = mems_level_errors(r);
        for (j, &interval) in r.noise_intervals.iter().enumerate() {
            let truth = mems_truth(r, j);
            levels += 1;
            covered += usize::from(interval[0] <= truth && truth <= interval[1]);
            if let Some(&Some(ratio)) = r.noise_ratios.get(j) {
                if crate::noise::levels::is_fixed(ratio, interval) {
                    fixed += 1;
                    fixed_within += usize::from(errors.get(j).is_some_and(within));
                }
            }
        }
    }
    let (mems_levels_fixed, mems_fixed_within_20, mems_intervals_cover) = if levels == 0 {
        (None, None, None)
    } else {
        let called = Rate::of(fixed, levels);
        let right = Rate::of(fixed_within, fixed);
        targets.push(Target {
            what: format!(
                "{MEMS_NOISE_LABEL}: levels the report calls fixed (95 % interval within 20 %) \
                 within 20 % of the truth"
            ),
            target: "at least 95 %".into(),
            measured: format!("{right}; called fixed: {called}; the rest said to be coarse"),
            met: right.rate >= 0.95,
        });
        (Some(called), Some(right), Some(Rate::of(covered, levels)))
    };
    let z: Vec<f64> = records
        .iter()
        .flat_map(|r| r.estimate_errors.values().copied())
        .collect();
    let estimates_within_3_sigma = Rate::of(z.iter().filter(|v| v.abs() < 3.0).count(), z.len());
    let estimate_error_rms = (z.iter().map(|v| v * v).sum::<f64>() / z.len().max(1) as f64).sqrt();
    Rates {
        estimates_within_3_sigma,
        estimate_error_rms,
        datasets: records.len(),
        errors: records.iter().filter(|r| r.error.is_some()).count(),
        clean_named,
        clean_noise_refitted,
        clean_not_consistent,
        outside_named,
        outside_by_effect,
        noise_named,
        noise_found,
        single_found,
        single_extra,
        detection,
        pairs_both_above,
        pairs_both,
        confusion: rows.into_values().collect(),
        effect_matrix,
        targets,
        other_kind_named,
        mems_levels_within_20,
        mems_levels_pooled,
        mems_levels_unresolved,
        mems_levels_fixed,
        mems_fixed_within_20,
        mems_intervals_cover,
        wrong_units_warned,
    }
}

#[cfg(test)]
mod tests;
