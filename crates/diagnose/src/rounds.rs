//! The diagnosis, as its algorithm: compare a model with a dataset, see where it fails, and
//! learn which catalogued effects are missing, on data whose noise and effect sizes nobody
//! chose to suit it. [`diagnose`] runs it. Each step is a function of its own module that
//! takes what it needs and returns a typed result; none calls back into the loop.
//!
//! 0. **Can the data be judged?** Too few updates is an error. Data that cannot be what they
//!    claim get the verdict `implausible data` and nothing is fitted beyond one pass
//!    ([`crate::implausible_data`]): any effect named on them would stand in for the defect.
//! 1. **The model under test** ([`crate::under_test`]): the base model plus the `--with`
//!    effects, fitted with a filter (the EKF by default) from the priors of the flags over
//!    `dataset.toml`'s `[prior]` over the defaults ([`crate::priors`]). Every fit keeps each
//!    innovation, its covariance, the NIS and the log-likelihood (docs/model.md eq. (18)). A
//!    coefficient the data pull beyond its prior gets a wider one, kept if the marginal
//!    likelihood says so ([`crate::fit::widening`]), so that a prior does not cap what can be
//!    found; models are then compared on the likelihood at their estimates, which does not
//!    depend on how wide a prior was ([`crate::fit::Fit::profile_loglik`]).
//! 2. **Rounds** of forward selection, each against the model as it stands:
//!    1. *noise check* ([`crate::noise`]): does the stated noise fit? A scale per source,
//!       fitted by maximum likelihood where the score test says it is off.
//!    2. *rank candidates* ([`crate::candidates`]): every catalogued effect not yet in the
//!       model, refitted with it (in parallel; a noise-only term with its density fitted),
//!       and the noise levels the check found. The evidence is the BIC gain on the maximised
//!       innovation likelihood.
//!    3. *name* ([`crate::naming`]): the decisive candidate that explains most, if it can be
//!       told apart from the model's own coefficients and its values are a real sensor's
//!       ([`crate::physical`]). Noise competes with structure rather than going first,
//!       because a missing effect inflates the fitted noise: the right structural model has
//!       the larger likelihood, and a noise explanation must beat the best structured one
//!       decisively to be named; even then the best effect that could be named goes first
//!       if it still adds decisively to the noise refitted beside it
//!       ([`crate::candidates::beside_noise`]). [`crate::rivals`] adds explanations outside
//!       the catalogue that a choice must beat: a walk of the other sensor for noise terms, a
//!       GPS antenna away from the platform for `gps-latency`.
//!
//!    The named effect joins the model (named noise levels replace the stated ones), which is
//!    refitted from the starting priors, and the next round ranks the rest against it. The
//!    search stops when nothing is named, not when the model first looks consistent: a
//!    likelihood-ratio test sees effects that NIS and whiteness tests cannot.
//! 3. **Check for stand-ins** ([`crate::stand_ins`]): a named effect whose coefficients
//!    differ between the two halves of the record is withdrawn, because a catalogued effect's
//!    coefficients are constants (docs/model.md eq. (11)) and one that is not stood in for
//!    something the catalogue lacks; a noise term whose density differs likewise.
//! 4. **Verdict** ([`crate::verdict`]): from what survived and from where the final model
//!    fails ([`crate::summary`]: NIS overall, in sliding windows and per motion phase;
//!    whiteness of each channel, over seconds and over minutes): `consistent` (nothing named,
//!    and the model is consistent with the data, at fitted noise levels if the stated ones
//!    were off), `explained` (the named effects make it consistent), `partly explained` (they
//!    help decisively, but a misfit remains that nothing in the catalogue explains),
//!    `unexplained`, or `does not follow the model` (it still fails grossly: the data are of
//!    another kind than the model, and the diagnosis says where, [`crate::misfit`]).
//!
//! The findings in words ([`crate::report::findings()`]) are made from the typed result last.

use crate::candidates::evidence::{Model, Named, Outcome};
use crate::candidates::rank::{rank, Confounded};
use crate::catalogue::first_full_measurement;
use crate::catalogue::Catalogue;
use crate::consistency::BLOCK;
use crate::diagnosis::{Diagnosis, Fits, Round, RoundKind};
use crate::error::DiagnoseError;
use crate::fit::setup::FitSetup;
use crate::fit::widening::{fit_adaptive, refit_from_starting_priors, widened_since};
use crate::implausible_data::implausible_diagnosis;
use crate::misfit::{is_gross, Misfit, SUGGEST_SHARE};
use crate::naming::name;
use crate::noise;
use crate::options::Options;
use crate::priors::beyond_small_angle;
use crate::report::findings::findings;
use crate::stand_ins::withdraw_stand_ins;
use crate::summary::{summarize_fit, window_width};
use crate::under_test::fit_under_test;
use crate::verdict::{judge, Verdict};
use navkf_dynamics::dataset::{Dataset, MEASUREMENTS_FILE};

/// Fewest measurement rows a diagnosis judges: two blocks of the drift test.
pub const MIN_UPDATES: usize = 2 * BLOCK;

/// Runs the whole diagnosis (module documentation). Returns the diagnosis and the fits of
/// the final model and, when it has effects, of the base model (for the figures).
pub fn diagnose(
    ds: &Dataset,
    catalogue: &dyn Catalogue,
    opts: &Options,
) -> Result<(Diagnosis, Fits), DiagnoseError> {
    // 0. Can the data be judged?
    judgeable(ds, catalogue, opts)?;
    let (_, start) = first_full_measurement(ds)?;
    let implausible = ds.implausibilities();
    if !implausible.is_empty() {
        return implausible_diagnosis(ds, catalogue, opts, implausible);
    }
    // 1. The model under test.
    let under_test = fit_under_test(ds, catalogue, opts, start[0])?;
    let mut model = under_test.fit;
    let mut rounds: Vec<Round> = under_test.manual_round.into_iter().collect();
    // 2. Rounds.
    let mut named: Vec<Named> = Vec::new();
    let mut noise_theta: crate::noise::Theta = [0.0; crate::noise::MAX_SOURCES];
    let mut noise_checks = Vec::new();
    let mut checks_run = noise::CheckMemo::default();
    let mut confounded = Confounded::default();
    let beyond_small_angle = !beyond_small_angle(
        &under_test.prior_entries,
        opts.filter.attitude,
        catalogue.kind(),
    )
    .is_empty();
    let mut untried: Vec<String> = Vec::new();
    for _ in 0..opts.max_rounds {
        crate::error::stop_if_requested()?;
        let summary = summarize_fit(ds, &model, opts);
        // 2.1 Noise check.
        let check = if opts.fit_noise {
            Some(checks_run.check(ds, &model, noise_theta, catalogue, &opts.filter)?)
        } else {
            None
        };
        // 2.2 Rank candidates.
        let as_it_stands = Model {
            fit: &model,
            summary: &summary,
        };
        let ranked = rank(
            ds,
            &as_it_stands,
            check.as_ref(),
            &confounded,
            catalogue,
            opts,
        )?;
        // 2.3 Name.
        let naming = name(
            ds,
            &as_it_stands,
            ranked,
            noise_theta,
            &mut checks_run,
            catalogue,
            opts,
            beyond_small_angle,
        )?;
        confounded.remember(&naming.candidates);
        let mut notes = naming.notes;
        for (effect, note) in not_tried(catalogue, &model.effects) {
            // Said once, in the first round that could not try it.
            if !untried.contains(&effect) {
                untried.push(effect);
                notes.push(note);
            }
        }
        rounds.push(Round {
            kind: RoundKind::Automatic,
            model: model.effects.clone(),
            nis: summary.nis,
            consistent: summary.consistent,
            candidates: naming.candidates,
            named: naming.named.iter().map(|(n, _)| n.to_string()).collect(),
            notes,
        });
        noise_checks.extend(check);
        let Some((what, with_it)) = naming.named else {
            break;
        };
        match what {
            Named::NoiseLevels { theta } => noise_theta = theta,
            effect => named.push(effect),
        }
        // Back to the starting priors: a prior the data pulled wide only because the effect
        // was missing (or the noise mis-stated) must not stay wide in the model that now has
        // it.
        model = refit_from_starting_priors(ds, with_it, catalogue, &opts.filter)?;
    }
    // 3. Check for stand-ins.
    crate::error::stop_if_requested()?;
    let stand_ins = withdraw_stand_ins(ds, model, named, catalogue, &opts.filter)?;
    let model = stand_ins.model;
    // 4. Verdict.
    let summary = summarize_fit(ds, &model, opts);
    let gross = !summary.consistent && is_gross(&summary.nis, summary.failure.is_some());
    let verdict = judge(!stand_ins.kept.is_empty(), summary.consistent, gross);
    let misfit = (!summary.consistent).then(|| Misfit::of(&model, window_width(&model, opts)));
    // For the report: the priors widened, and the base model at the final noise levels.
    let mut widened = under_test.tilt_widened;
    widened.extend(widened_since(&under_test.start, &model));
    let before = if model.effects.is_empty() {
        None
    } else {
        let setup = FitSetup {
            noise: model.setup.noise,
            ..under_test.base
        };
        Some(fit_adaptive(ds, &setup, catalogue, &opts.filter)?.0)
    };
    let kept: Vec<String> = stand_ins.kept.iter().map(Named::to_string).collect();
    // An effect that leaves the model inconsistent is suggested, not named (crate::verdict).
    // Beside a gross misfit, a named effect is suggested only if it removed most of its
    // round's excess; the rest stood in for a part of it (crate::misfit).
    let removed_most = |e: &String| {
        rounds
            .iter()
            .flat_map(|r| &r.candidates)
            .filter(|c| &c.effect == e)
            .any(|c| c.excess_removed >= SUGGEST_SHARE)
    };
    let (effects, mut suggested) = match verdict {
        Verdict::PartlyExplained => (Vec::new(), kept),
        Verdict::DoesNotFollowModel => {
            (Vec::new(), kept.into_iter().filter(removed_most).collect())
        }
        _ => (kept, Vec::new()),
    };
    // Explanations the data could not tell apart from each other or from something outside
    // the catalogue (crate::naming) are suggested too.
    for c in rounds.iter().flat_map(|r| &r.candidates) {
        let undecided = matches!(
            c.outcome,
            Outcome::Indistinguishable | Outcome::LooksLikeOutside | Outcome::BeyondSmallAngle
        );
        if undecided && !suggested.contains(&c.effect) {
            suggested.push(c.effect.clone());
        }
    }
    let mut d = Diagnosis {
        dataset: ds.name.clone(),
        family: catalogue.kind(),
        pinned: catalogue.pinned().iter().map(|p| p.to_string()).collect(),
        start_attitude: catalogue.start_attitude(ds),
        attitude: opts.filter.attitude,
        verdict,
        best: effects.first().cloned(),
        effects,
        suggested,
        model: summary,
        misfit,
        before: before.as_ref().map(|f| summarize_fit(ds, f, opts)),
        rounds,
        noise: noise_checks.last().cloned(),
        noise_checks,
        priors: under_test.prior_entries,
        widened,
        withdrawn: stand_ins.withdrawn,
        constancy: stand_ins.constancy,
        findings: Vec::new(),
        data_warnings: ds.warnings(),
        implausible: Vec::new(),
        noise_stated: ds.noise_stated,
    };
    d.findings = findings(&d);
    Ok((d, Fits { model, before }))
}

/// Each catalogue effect a round could not try beside `effects`
/// ([`Catalogue::cannot_join`]), with its note.
fn not_tried(catalogue: &dyn Catalogue, effects: &[String]) -> Vec<(String, String)> {
    catalogue
        .effect_names()
        .into_iter()
        .filter(|e| !effects.contains(e))
        .filter_map(|e| {
            catalogue.cannot_join(effects, &e).map(|why| {
                let note = format!("`{e}` not tried: it cannot join this model ({why})");
                (e, note)
            })
        })
        .collect()
}

/// Refuses a dataset too short to judge, and options under which nothing is tested.
fn judgeable(ds: &Dataset, catalogue: &dyn Catalogue, opts: &Options) -> Result<(), DiagnoseError> {
    if ds.model != catalogue.kind() {
        return Err(DiagnoseError::Data(format!(
            "{}: a {} dataset judged with the {} family's catalogue; expected the catalogue of \
             its own family (crate::catalogue::of)",
            ds.name,
            ds.model.name(),
            catalogue.kind().name()
        )));
    }
    let effects = catalogue.effect_names();
    if let Some(missing) = ds.effects.iter().find(|d| !effects.contains(&d.name)) {
        return Err(DiagnoseError::Data(format!(
            "{}: dataset.toml declares the effect `{}`, which the catalogue given does not \
             hold; expected the dataset's own catalogue (crate::catalogue::of)",
            ds.name, missing.name
        )));
    }
    let updates = ds.measurements.len();
    if updates < MIN_UPDATES {
        return Err(DiagnoseError::Data(format!(
            "{MEASUREMENTS_FILE}: {updates} measurement row(s); a diagnosis needs at least \
             {MIN_UPDATES} updates to judge (its drift test compares blocks of {BLOCK} updates, \
             and its NIS and whiteness tests have no power on fewer)"
        )));
    }
    if opts.max_rounds == 0 {
        return Err(DiagnoseError::Data(
            "max_rounds = 0: expected at least 1 (with no automatic round nothing is tested)"
                .into(),
        ));
    }
    Ok(())
}
