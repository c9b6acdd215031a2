//! Diagnosis: compare a model with a dataset, see where it fails, and learn which catalogued
//! effects are missing, on data whose noise and effect sizes nobody chose to suit it.
//!
//! 1. **Priors** ([`priors`]): flags over `dataset.toml`'s `[prior]` over the defaults of
//!    [`navkf_dynamics::prior`]. A coefficient the data pull beyond its prior gets a wider
//!    one, kept if the marginal likelihood says so, so that a prior does not cap what can be
//!    found.
//! 2. **Fit** ([`fit`]) the model under test (base plus `--with` effects) with a filter (the
//!    EKF by default), keeping every innovation, its covariance, the NIS, the log-likelihood
//!    and each coefficient's path. Models are compared on the likelihood at their estimates,
//!    which does not depend on how wide a prior was ([`fit::Fit::profile_loglik`]).
//! 3. **Rounds** of forward selection ([`candidates`]). Each round weighs, against the model
//!    as it stands: every catalogued effect not yet in it (refitted with it, in parallel);
//!    the noise-only terms with their density fitted; and the noise levels themselves
//!    ([`noise`]: does the stated noise fit? a scale per source, fitted by maximum likelihood
//!    where the score test says it is off). The evidence is the BIC gain on the maximised
//!    innovation likelihood; the decisive candidate that explains most is named, and the next
//!    round re-ranks the rest with it in the model. Noise competes with structure rather than
//!    going first, because a missing effect inflates the fitted noise: the right structural
//!    model has the larger likelihood, and a noise explanation must beat the best structured
//!    one decisively to be named ([`rivals`] adds the accelerometer-walk check for noise
//!    terms). The search stops when nothing is decisive, not when the model first looks
//!    consistent: a likelihood-ratio test sees effects that NIS and whiteness tests cannot.
//! 4. **Constancy**: a named structured effect whose coefficients differ between the two
//!    halves of the record is withdrawn: it stood in for something the catalogue lacks
//!    ([`candidates::constancy`]); a noise term whose density differs likewise.
//! 5. **Where it fails** ([`consistency`]): NIS overall, in sliding windows and per motion
//!    phase; whiteness of each channel, over seconds and over minutes.
//!
//! The verdict is `consistent` (nothing named, and the model is consistent with the data, at
//! fitted noise levels if the stated ones were off), `explained` (the named effects make it
//! consistent), `partly explained` (they help decisively, but a misfit remains that nothing
//! in the catalogue explains) or `unexplained`; `implausible data` when the dataset fails the
//! checks of [`plausible`] (nothing is fitted or named then). Whatever the verdict, a
//! candidate whose fitted values are no real sensor's is not named.

pub mod candidates;
pub mod consistency;
pub mod diagnosis_study;
pub mod error;
pub mod fit;
pub mod noise;
pub mod plausible;
pub mod plots;
pub mod priors;
pub mod report;
pub mod rivals;

use candidates::{
    constancy, evaluate_all, select, Candidate, CandidateKind, Constancy, Model, Outcome,
};
use consistency::{nis_windows, whiteness, NisStat, NisWindow, Whiteness};
pub use error::DiagnoseError;
pub use fit::{Fit, FitSetup};
use navkf_dynamics::dataset::Dataset;
use navkf_dynamics::state::*;
use navkf_dynamics::trajectory::Phase;
use navkf_dynamics::{NoiseConfig, PlatformPrior, Registry};
use navkf_filters::FilterSpec;
use noise::NoiseFit;
use priors::{fit_adaptive, PriorEntry, Widening};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Family-wise level of the whiteness tests over all channels (Bonferroni-divided).
pub const WHITENESS_ALPHA: f64 = 0.01;

/// Settings of a diagnosis.
#[derive(Debug, Clone)]
pub struct Options {
    /// Effects switched on in the model under test (a manual round).
    pub with: Vec<String>,
    /// Width of the sliding NIS windows, s.
    pub window_s: f64,
    /// Lags of the whiteness test.
    pub lags: usize,
    /// Priors stated on the command line (over `dataset.toml`'s `[prior]`).
    pub prior: PlatformPrior,
    /// Whether to check the stated noise and fit it where it is off (otherwise the stated
    /// noise is taken as it is).
    pub fit_noise: bool,
    /// The filter the fits run.
    pub filter: FilterSpec,
    /// Most automatic rounds.
    pub max_rounds: usize,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            with: Vec::new(),
            window_s: 300.0,
            lags: 20,
            prior: PlatformPrior::default(),
            fit_noise: true,
            filter: FilterSpec::default(),
            max_rounds: 6,
        }
    }
}

/// Consistency of one fit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FitSummary {
    /// Effects in the model.
    pub effects: Vec<String>,
    /// Total log-likelihood of the innovations.
    pub loglik: f64,
    /// NIS over all updates.
    pub nis: NisStat,
    /// NIS per motion phase.
    pub nis_by_phase: BTreeMap<String, NisStat>,
    /// NIS in sliding windows.
    pub nis_windows: Vec<NisWindow>,
    /// Whiteness of each channel.
    pub whiteness: Vec<Whiteness>,
    /// Whether NIS is inside its bounds and every channel is white.
    pub consistent: bool,
    /// Sum over updates of `NIS - dim` (the misfit a missing effect leaves).
    pub excess_nis: f64,
    /// Final coefficient estimates with their sigmas.
    pub coefficients: Vec<Coefficient>,
    /// Filter failure, if any: its cause and where.
    pub failure: Option<navkf_filters::RunFailure>,
    /// The noise the filter assumed.
    pub noise: NoiseConfig,
}

/// A coefficient estimate.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Coefficient {
    /// Name.
    pub name: String,
    /// Final estimate.
    pub estimate: f64,
    /// Final one-sigma.
    pub sigma: f64,
    /// The prior one-sigma it was tested with (after any widening).
    pub prior_sigma: f64,
    /// True value, when the dataset has `truth.csv`.
    pub truth: Option<f64>,
}

/// Summarises a fit.
pub fn summarize_fit(ds: &Dataset, fit: &Fit, opts: &Options) -> FitSummary {
    let nis = NisStat::of(&fit.nis, &fit.dims);
    let mut by_phase: BTreeMap<String, (Vec<f64>, Vec<usize>)> = BTreeMap::new();
    for ((p, v), d) in fit.phases.iter().zip(&fit.nis).zip(&fit.dims) {
        let e = by_phase.entry(phase_name(*p).to_string()).or_default();
        e.0.push(*v);
        e.1.push(*d);
    }
    let nis_by_phase = by_phase
        .into_iter()
        .map(|(k, (v, d))| (k, NisStat::of(&v, &d)))
        .collect();
    let dt = if fit.t.len() > 1 {
        (fit.t[fit.t.len() - 1] - fit.t[0]) / (fit.t.len() - 1) as f64
    } else {
        1.0
    };
    let width = ((opts.window_s / dt).round() as usize).max(10);
    let windows = nis_windows(&fit.t, &fit.nis, &fit.dims, width);
    let whites: Vec<Whiteness> = MEASUREMENT_NAMES
        .iter()
        .enumerate()
        .map(|(c, name)| {
            let e: Vec<f64> = fit
                .z
                .iter()
                .zip(&fit.z_hat)
                .zip(&fit.s_sigma)
                .filter(|((z, _), _)| z[c].is_finite())
                .map(|((z, zh), s)| (z[c] - zh[c]) / s[c])
                .collect();
            whiteness(
                name,
                &e,
                opts.lags,
                WHITENESS_ALPHA / (consistency::TESTS_PER_CHANNEL * MEAS_DIM) as f64,
            )
        })
        .collect();
    // The verdict uses the 99 % NIS band (the 95 % one is shown); with the whiteness tests
    // at a family-wise 1 %, a consistent model is called inconsistent about 2 % of the time.
    let consistent = fit.failure.is_none()
        && nis.within(navkf_report::stats::Band::Percent99)
        && whites.iter().filter(|w| w.count > 0).all(|w| w.white);
    let excess = fit
        .nis
        .iter()
        .zip(&fit.dims)
        .map(|(v, d)| v - *d as f64)
        .sum();
    let n = fit.names.len();
    let truth_last = ds
        .truth
        .as_ref()
        .and_then(|t| t.states.last().map(|s| (t, s)));
    let coefficients = (NAV_DIM..n)
        .map(|i| Coefficient {
            name: fit.names[i].clone(),
            estimate: fit.x[i],
            sigma: fit.sigma(i),
            prior_sigma: fit.prior_sigma[i],
            truth: truth_last.and_then(|(t, s)| {
                t.names
                    .iter()
                    .position(|x| *x == fit.names[i])
                    .map(|j| s[j])
            }),
        })
        .collect();
    FitSummary {
        effects: fit.effects.clone(),
        loglik: fit.loglik,
        nis,
        nis_by_phase,
        nis_windows: windows,
        whiteness: whites,
        consistent,
        excess_nis: excess,
        coefficients,
        failure: fit.failure.clone(),
        noise: fit.setup.noise,
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

/// The verdict of a diagnosis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Verdict {
    /// Nothing named, and the model under test is consistent with the data.
    #[serde(rename = "consistent")]
    Consistent,
    /// The named effects make the model consistent.
    #[serde(rename = "explained")]
    Explained,
    /// The named effects help decisively, but a misfit remains that nothing in the catalogue
    /// explains.
    #[serde(rename = "partly explained")]
    PartlyExplained,
    /// The model is inconsistent and nothing in the catalogue explains it.
    #[serde(rename = "unexplained")]
    Unexplained,
    /// The data cannot be what they claim ([`Diagnosis::implausible`]): nothing is named.
    #[serde(rename = "implausible data")]
    ImplausibleData,
}

impl std::fmt::Display for Verdict {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Verdict::Consistent => "consistent",
            Verdict::Explained => "explained",
            Verdict::PartlyExplained => "partly explained",
            Verdict::Unexplained => "unexplained",
            Verdict::ImplausibleData => "implausible data",
        })
    }
}

/// Whether a round was asked for (`--with`) or chosen by the evidence.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum RoundKind {
    /// `--with`: the effects were added as given.
    Manual,
    /// Forward selection.
    Automatic,
}

/// One round of the forward selection.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Round {
    /// Manual or automatic.
    pub kind: RoundKind,
    /// Effects of the model the candidates were added to.
    pub model: Vec<String>,
    /// That model's NIS.
    pub nis: NisStat,
    /// Whether that model is consistent.
    pub consistent: bool,
    /// The candidates, best first (for a manual round, the `--with` effects together).
    pub candidates: Vec<Candidate>,
    /// Effects named in this round.
    pub named: Vec<String>,
    /// Remarks (competing explanations).
    pub notes: Vec<String>,
}

impl Round {
    /// Whether this round named the refitted noise levels (a candidate of kind
    /// [`CandidateKind::NoiseLevels`]), whatever its label.
    pub fn named_noise_levels(&self) -> bool {
        self.candidates
            .iter()
            .any(|c| c.kind == CandidateKind::NoiseLevels && self.named.contains(&c.effect))
    }
}

/// How the noise-levels candidate is labelled among effects in rounds and reports.
pub const NOISE_LEVELS_LABEL: &str = "noise levels";

/// A named effect withdrawn because its coefficients are not constant.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Withdrawn {
    /// The effect.
    pub effect: String,
    /// Its constancy test in the final model.
    pub constancy: Constancy,
}

/// Fewest measurement rows a diagnosis judges: two blocks of the drift test.
pub const MIN_UPDATES: usize = 2 * consistency::BLOCK;

/// The whole diagnosis (`diagnosis.json`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Diagnosis {
    /// Dataset name.
    pub dataset: String,
    /// The attitude equations of every fit's model.
    #[serde(default)]
    pub attitude: navkf_dynamics::Attitude,
    /// The verdict.
    pub verdict: Verdict,
    /// The first named effect; null when none.
    pub best: Option<String>,
    /// The named effects, in the order named (the `--with` ones are not repeated here).
    pub effects: Vec<String>,
    /// The final model: the model under test plus the named effects.
    pub model: FitSummary,
    /// The base model, when the final model has effects (before/after).
    pub before: Option<FitSummary>,
    /// The rounds, with their full rankings.
    pub rounds: Vec<Round>,
    /// The last noise check (stated and fitted levels); null with `--noise stated`.
    pub noise: Option<NoiseFit>,
    /// Every noise check made, in order.
    pub noise_checks: Vec<NoiseFit>,
    /// The priors the diagnosis started from, with their source.
    pub priors: Vec<PriorEntry>,
    /// Priors widened in the final model's fit.
    pub widened: Vec<Widening>,
    /// Named effects withdrawn by the constancy test.
    pub withdrawn: Vec<Withdrawn>,
    /// Constancy of each named structured effect in the final model.
    pub constancy: Vec<(String, Option<Constancy>)>,
    /// Plain-language findings.
    pub findings: Vec<String>,
    /// The dataset's values that look written in the wrong unit
    /// ([`navkf_dynamics::dataset::Dataset::warnings`]): the verdict stands on data that may
    /// be wrong, and the report says so first.
    #[serde(default)]
    pub data_warnings: Vec<navkf_dynamics::dataset::DataWarning>,
    /// What the data cannot be ([`navkf_dynamics::dataset::Dataset::implausibilities`]); when
    /// any, the verdict is [`Verdict::ImplausibleData`] and nothing is fitted beyond one pass
    /// ([`plausible`]).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub implausible: Vec<navkf_dynamics::dataset::Implausibility>,
    /// Whether the dataset states its noise (a `[noise]` table in dataset.toml); without it
    /// the "stated" noise is navkf's default, and the findings say so first.
    #[serde(default = "stated_by_default")]
    pub noise_stated: bool,
}

/// Diagnoses written before `noise_stated` existed read datasets that stated their noise.
fn stated_by_default() -> bool {
    true
}

/// The filter passes behind a diagnosis, kept for its figures.
#[derive(Debug, Clone)]
pub struct Fits {
    /// The final model.
    pub model: Fit,
    /// The base model, when the final model has effects.
    pub before: Option<Fit>,
}

/// Runs the whole diagnosis (module documentation). Returns the diagnosis and the fits of
/// the final model and, when it has effects, of the base model (for the figures).
pub fn diagnose(
    ds: &Dataset,
    registry: &Registry,
    opts: &Options,
) -> Result<(Diagnosis, Fits), DiagnoseError> {
    let updates = ds.measurements.len();
    if updates < MIN_UPDATES {
        return Err(DiagnoseError::Data(format!(
            "{}: {updates} measurement row(s); a diagnosis needs at least {MIN_UPDATES} \
             updates to judge (its drift test compares blocks of {} updates, and its NIS \
             and whiteness tests have no power on fewer)",
            navkf_dynamics::dataset::MEASUREMENTS_FILE,
            consistency::BLOCK
        )));
    }
    if opts.max_rounds == 0 {
        return Err(DiagnoseError::Data(
            "max_rounds = 0: expected at least 1 (with no automatic round nothing is tested)"
                .into(),
        ));
    }
    let (_, _, start) = fit::first_full_measurement(ds)?;
    let implausible = ds.implausibilities();
    if !implausible.is_empty() {
        return plausible::implausible_diagnosis(ds, registry, opts, implausible);
    }
    let (start_priors, prior_entries) = priors::resolve(ds, &opts.prior, start[0]);
    let base = FitSetup {
        effects: Vec::new(),
        parameters: BTreeMap::new(),
        noise: ds.noise,
        priors: start_priors.clone(),
    };
    let mut under_test = FitSetup {
        effects: opts.with.clone(),
        ..base.clone()
    };
    for e in &opts.with {
        let effect = registry.build(e)?;
        under_test
            .priors
            .open
            .extend(effect.coefficient_names().iter().map(|c| c.to_string()));
    }
    let (current, _) = fit_adaptive(ds, &under_test, registry, &opts.filter)?;
    let (mut current, tilt_widened) = priors::widen_tilt(ds, current, registry, &opts.filter)?;
    let mut rounds = Vec::new();
    let base = FitSetup {
        priors: priors::Priors {
            coefficients: base.priors.coefficients.clone(),
            ..current.setup.priors.clone()
        },
        ..base
    };
    if !opts.with.is_empty() {
        let (b, _) = fit_adaptive(ds, &base, registry, &opts.filter)?;
        rounds.push(manual_round(ds, &b, &current, opts));
    }
    // Forward selection; each round also checks the noise of the model as it stands.
    let mut named: Vec<String> = Vec::new();
    let mut noise_theta = [0.0; 4];
    let mut noise_checks: Vec<NoiseFit> = Vec::new();
    // Effects the trajectory cannot tell from the base model's coefficients stay so in later
    // rounds: a noise term named meanwhile (a walk of the drifts) makes the base coefficients
    // wander, which hides the confusion without removing it.
    let mut confounded: Vec<(String, Vec<candidates::Confusion>)> = Vec::new();
    for _ in 0..opts.max_rounds {
        let (round, chosen, check) =
            run_round(ds, &current, noise_theta, &confounded, registry, opts)?;
        for c in &round.candidates {
            let inseparable = !c.confused_with.is_empty()
                && !c
                    .separable_bic
                    .is_some_and(|b| b > candidates::DECISIVE_BIC);
            if inseparable && !confounded.iter().any(|k| k.0 == c.effect) {
                confounded.push((c.effect.clone(), c.confused_with.clone()));
            }
        }
        rounds.push(round);
        noise_checks.extend(check);
        let Some(chosen) = chosen else { break };
        if chosen.candidate.kind == CandidateKind::NoiseLevels {
            if let Some(n) = &chosen.candidate.noise {
                noise_theta = n.used_theta;
            }
        } else {
            named.push(chosen.candidate.effect.clone());
        }
        current = chosen.fit;
        // Back to the starting priors: a prior the data pulled wide only because the effect
        // was missing (or the noise mis-stated) must not stay wide in the model that now has
        // it.
        if current.setup.priors != current.setup.priors.restarted() {
            let mut setup = current.setup.clone();
            setup.priors = setup.priors.restarted();
            current = fit_adaptive(ds, &setup, registry, &opts.filter)?.0;
        }
    }
    // Constancy of the named structured effects in the final model; withdraw those that fail.
    let mut withdrawn = Vec::new();
    let mut constancies = Vec::new();
    for e in &named {
        let coefs: Vec<String> = registry
            .build(e)?
            .coefficient_names()
            .iter()
            .map(|s| s.to_string())
            .collect();
        let c = if coefs.is_empty() {
            candidates::density_constancy(ds, &current.setup, e, registry, &opts.filter)?
        } else {
            constancy(ds, &current.setup, &coefs, registry, &opts.filter)?
        };
        if let Some(c) = c.as_ref().filter(|c| !c.constant) {
            withdrawn.push(Withdrawn {
                effect: e.clone(),
                constancy: c.clone(),
            });
        }
        constancies.push((e.clone(), c));
    }
    if !withdrawn.is_empty() {
        named.retain(|e| !withdrawn.iter().any(|w| &w.effect == e));
        let mut setup = current.setup.clone();
        setup
            .effects
            .retain(|e| !withdrawn.iter().any(|w| &w.effect == e));
        current = fit_adaptive(ds, &setup, registry, &opts.filter)?.0;
    }
    let mut widened = tilt_widened;
    widened.extend(widened_priors(&start_priors, &current));
    let model = summarize_fit(ds, &current, opts);
    let before_fit = if current.effects.is_empty() {
        None
    } else {
        let setup = FitSetup {
            noise: current.setup.noise,
            ..base.clone()
        };
        Some(fit_adaptive(ds, &setup, registry, &opts.filter)?.0)
    };
    let before = before_fit.as_ref().map(|f| summarize_fit(ds, f, opts));
    let verdict = match (named.is_empty(), model.consistent) {
        (true, true) => Verdict::Consistent,
        (true, false) => Verdict::Unexplained,
        (false, true) => Verdict::Explained,
        (false, false) => Verdict::PartlyExplained,
    };
    let mut d = Diagnosis {
        dataset: ds.name.clone(),
        attitude: opts.filter.attitude,
        verdict,
        best: named.first().cloned(),
        effects: named,
        model,
        before,
        rounds,
        noise: noise_checks.last().cloned(),
        noise_checks,
        priors: prior_entries,
        widened,
        withdrawn,
        constancy: constancies,
        findings: Vec::new(),
        data_warnings: ds.warnings(),
        implausible: Vec::new(),
        noise_stated: ds.noise_stated,
    };
    d.findings = report::findings(&d);
    Ok((
        d,
        Fits {
            model: current,
            before: before_fit,
        },
    ))
}

/// One round of the forward selection on the model `current` (whose noise levels are the
/// stated ones scaled by `noise_theta`): every candidate weighed (those found `confounded` in
/// an earlier round stay so), the noise checked, the choice made. Returns the round, the named candidate with its fit (the next model), and
/// the noise check.
fn run_round(
    ds: &Dataset,
    current: &Fit,
    noise_theta: [f64; 4],
    confounded: &[(String, Vec<candidates::Confusion>)],
    registry: &Registry,
    opts: &Options,
) -> Result<(Round, Option<candidates::Evaluated>, Option<NoiseFit>), DiagnoseError> {
    let summary = summarize_fit(ds, current, opts);
    let model = Model {
        fit: current,
        summary: &summary,
    };
    let mut evaluated = evaluate_all(ds, &model, registry, opts)?;
    for e in &mut evaluated {
        if let Some((_, confusion)) = confounded.iter().find(|k| k.0 == e.candidate.effect) {
            if e.candidate.confused_with.is_empty() {
                e.candidate.confused_with = confusion.clone();
                e.candidate.separable_bic = Some(f64::NEG_INFINITY);
            }
        }
    }
    let mut check = None;
    if opts.fit_noise {
        let c = noise::check(
            ds,
            &current.setup,
            current.loglik,
            &ds.noise,
            noise_theta,
            registry,
            &opts.filter,
        )?;
        if c.refitted && c.used != current.setup.noise {
            evaluated.push(noise_candidate(ds, &model, &c, registry, opts)?);
        }
        check = Some(c);
    }
    let mut cands: Vec<Candidate> = evaluated.iter().map(|e| e.candidate.clone()).collect();
    // A noise-only choice must beat its rival outside the catalogue ([`rivals`]); if it does
    // not, it is set aside and the choice made again.
    let mut not_specific = Vec::new();
    let mut rival_notes = Vec::new();
    let (choice, mut notes) = loop {
        let (choice, notes) = select(&mut cands, &not_specific);
        if let Some(i) = choice.filter(|&i| cands[i].kind == CandidateKind::NoiseOnly) {
            if let Some(note) = rival_note(ds, current, &evaluated[i], registry, opts)? {
                not_specific.push(i);
                rival_notes.push(note);
                continue;
            }
        }
        break (choice, notes);
    };
    notes.extend(rival_notes);
    let named = choice
        .map(|i| vec![cands[i].effect.clone()])
        .unwrap_or_default();
    cands.sort_by(|a, b| b.bic_gain.total_cmp(&a.bic_gain));
    let round = Round {
        kind: RoundKind::Automatic,
        model: current.effects.clone(),
        nis: summary.nis.clone(),
        consistent: summary.consistent,
        candidates: cands,
        named,
        notes,
    };
    Ok((round, choice.map(|i| evaluated.swap_remove(i)), check))
}

/// Whether a random walk of the accelerometer biases ([`rivals::AccelBiasWalk`], outside the
/// catalogue) fits the model as well as the noise-only candidate `chosen`; if so, the note
/// that says why `chosen` is not named.
fn rival_note(
    ds: &Dataset,
    model: &Fit,
    chosen: &candidates::Evaluated,
    registry: &Registry,
    opts: &Options,
) -> Result<Option<String>, DiagnoseError> {
    let mut with_rival = registry.clone();
    with_rival.register(|| Box::new(rivals::AccelBiasWalk::default()));
    let candidates::DensityFit {
        fit: rival,
        density: q,
        ..
    } = candidates::fit_density(
        ds,
        model,
        rivals::AccelBiasWalk::NAME,
        rivals::AccelBiasWalk::DEFAULT_PSD,
        &with_rival,
        &opts.filter,
    )?;
    // Same priors, one density each: the marginal likelihoods compare directly.
    let gain = 2.0 * (chosen.fit.loglik - rival.loglik);
    if rival.failure.is_none() && gain < candidates::DECISIVE_BIC {
        Ok(Some(format!(
            "`{}` would make the model consistent, but a random walk of the accelerometer \
             biases (density {q:.1e} (m/s^2)^2/s, not in the catalogue) fits as well (twice \
             the log-likelihood difference {gain:.1}, below {}): a slow drift is there, but the \
             data cannot say that the gyros carry it. It is not named. A drag, a warming-up \
             sensor or a walk of either sensor would all look like this; a gyro walk shows in \
             the heading too, so a longer test with turns tells them apart.",
            chosen.candidate.effect,
            candidates::DECISIVE_BIC
        )))
    } else {
        Ok(None)
    }
}

/// The candidate "noise levels": the model refitted with the levels `check` found, weighed
/// like an effect with one parameter per source it changed.
fn noise_candidate(
    ds: &Dataset,
    model: &Model<'_>,
    check: &NoiseFit,
    registry: &Registry,
    opts: &Options,
) -> Result<candidates::Evaluated, DiagnoseError> {
    let mut setup = model.fit.setup.clone();
    setup.noise = check.used;
    setup.priors = setup.priors.restarted();
    let (fit, widened) = fit_adaptive(ds, &setup, registry, &opts.filter)?;
    let s = summarize_fit(ds, &fit, opts);
    let keep: Vec<String> = fit
        .names
        .iter()
        .enumerate()
        .filter(|(i, _)| fit.noisy[*i])
        .map(|(_, n)| n.clone())
        .collect();
    let dll = fit.profile_loglik(&keep) - model.fit.profile_loglik(&keep);
    let old = noise::SOURCES.map(|src| src.values(&model.fit.setup.noise));
    let changed = noise::SOURCES
        .iter()
        .enumerate()
        .filter(|(j, src)| src.values(&check.used) != old[*j])
        .count()
        .max(1);
    let ln_n = (model.fit.measurement_count().max(1) as f64).ln();
    let excess = model.summary.excess_nis;
    let candidate = Candidate {
        effect: NOISE_LEVELS_LABEL.into(),
        kind: CandidateKind::NoiseLevels,
        delta_loglik: dll,
        parameters: changed,
        bic_gain: 2.0 * dll - changed as f64 * ln_n,
        excess_removed: if excess > 0.0 {
            1.0 - s.excess_nis.max(0.0) / excess
        } else {
            0.0
        },
        nis: s.nis.clone(),
        consistent: s.consistent,
        coefficients: Vec::new(),
        density: None,
        noise: Some(check.clone()),
        widened,
        confused_with: Vec::new(),
        separable_bic: None,
        beyond_bounds: plausible::noise_beyond(&check.used),
        outcome: Outcome::NotDecisive,
        failure: fit.failure.clone(),
    };
    Ok(candidates::Evaluated { candidate, fit })
}

/// The coefficient priors of `fit` wider than the ones the diagnosis started from; the
/// `implied_estimate` is the final estimate.
fn widened_priors(start: &priors::Priors, fit: &Fit) -> Vec<Widening> {
    (NAV_DIM..fit.names.len())
        .filter_map(|i| {
            let name = &fit.names[i];
            let from = start
                .coefficients
                .get(name)
                .copied()
                .unwrap_or(fit.typical_sigma[i]);
            let cap = priors::widest_sigma(&fit.setup.priors, name, from, fit.typical_sigma[i]);
            (fit.prior_sigma[i] > from).then(|| Widening {
                name: name.clone(),
                from,
                to: fit.prior_sigma[i],
                implied_estimate: fit.x[i],
                at_cap: fit.prior_sigma[i] >= cap * (1.0 - 1e-12),
            })
        })
        .collect()
}

/// The `--with` round: the effects added together to the base model `before`, giving `after`.
fn manual_round(ds: &Dataset, before: &Fit, after: &Fit, opts: &Options) -> Round {
    let b = summarize_fit(ds, before, opts);
    let a = summarize_fit(ds, after, opts);
    let keep: Vec<String> = after
        .names
        .iter()
        .enumerate()
        .filter(|(i, _)| after.noisy[*i])
        .map(|(_, n)| n.clone())
        .collect();
    let dll = after.profile_loglik(&keep) - before.profile_loglik(&keep);
    let k = (after.names.len() - before.names.len()).max(opts.with.len());
    let ln_n = (before.measurement_count().max(1) as f64).ln();
    let removed = if b.excess_nis > 0.0 {
        1.0 - a.excess_nis.max(0.0) / b.excess_nis
    } else {
        0.0
    };
    Round {
        kind: RoundKind::Manual,
        model: Vec::new(),
        nis: b.nis.clone(),
        consistent: b.consistent,
        candidates: vec![Candidate {
            effect: opts.with.join(","),
            kind: candidates::CandidateKind::Structured,
            delta_loglik: dll,
            parameters: k,
            bic_gain: 2.0 * dll - k as f64 * ln_n,
            excess_removed: removed,
            nis: a.nis.clone(),
            consistent: a.consistent,
            coefficients: a
                .coefficients
                .iter()
                .filter(|c| !before.names.contains(&c.name))
                .cloned()
                .collect(),
            density: None,
            noise: None,
            widened: Vec::new(),
            confused_with: Vec::new(),
            separable_bic: None,
            beyond_bounds: Vec::new(),
            outcome: Outcome::Manual,
            failure: after.failure.clone(),
        }],
        named: opts.with.clone(),
        notes: Vec::new(),
    }
}
