//! Which goes first, the refitted noise levels or an effect? The noise levels compete with
//! each effect alone ([`super::noise_levels`]), at levels the noise check fitted without that
//! effect. When two effects are missing, neither alone may beat the noise levels, which soak
//! up a share of both; once the inflated levels are in, the effects' signatures are buried
//! under them, and coefficients they would have fixed drift into the model's own (an odometer
//! pitched by 47 mrad was taken up by an x accelerometer bias widened 30 times, beside a gyro
//! noise put at 11 times its true level; docs/strapdown.md, "Pairs").
//!
//! So before the noise levels are named, the best effect that could be named is weighed
//! against them on equal terms: the noise check is run again with the effect in the model,
//! the model is refitted with the effect at the levels that check finds, and the gain of that
//! fit over the noise levels' is the effect's evidence beside refitted noise, charged for the
//! effect's coefficients and for the difference in noise sources changed (the levels' fit is
//! charged for its own). The second check may find better levels than the first whatever the
//! effect (its search starts elsewhere): so the evidence is also taken over the model without
//! the effect at the second check's levels, and the smaller of the two gains counts. Without
//! that, dataset 836 of the strapdown study (noise mis-stated, nothing hidden) named
//! `accel-scale`: 313 over the levels, -25 at the same levels. If the gain is decisive, the
//! effect adds to any noise explanation and goes first ([`crate::naming`]); the next round's
//! noise check sees the model with it. If not, the noise levels explain what the effect would,
//! and they are named as before. They are named too when the effect could not be: another
//! explains the misfit as well, or a look-alike outside the catalogue does.

use super::evidence::Evaluated;
use crate::catalogue::Catalogue;
use crate::error::DiagnoseError;
use crate::fit::pass::{marginal_states, Fit};
use crate::fit::widening::fit_adaptive;
use crate::noise::{CheckMemo, Theta};
use crate::options::Options;
use navkf_dynamics::dataset::Dataset;

/// The BIC gain of the structured candidate `effect` over the noise-levels candidate
/// `noise_levels`, with the noise refitted beside the effect: the noise check run on the
/// effect's fit from the model's levels `theta` (answered from `checks_run` when it was run
/// before), and the effect refitted at the levels it finds. Charged for the effect's
/// coefficients and the noise sources the joint fit changes, less the sources the noise
/// levels changed; and no more than its gain over the model without it at the joint fit's
/// levels. `-inf` when the joint fit fails.
#[allow(clippy::too_many_arguments)]
pub fn gain_beside_refitted_noise(
    ds: &Dataset,
    model: &Fit,
    effect: &Evaluated,
    noise_levels: &Evaluated,
    theta: Theta,
    checks_run: &mut CheckMemo,
    catalogue: &dyn Catalogue,
    opts: &Options,
) -> Result<f64, DiagnoseError> {
    let check = checks_run.check(ds, &effect.fit, theta, catalogue, &opts.filter)?;
    let refitted;
    let (joint, noise_changed) = if check.refitted && check.used != effect.fit.setup.noise {
        let setup = effect.fit.setup.at_noise(check.used);
        refitted = fit_adaptive(ds, &setup, catalogue, &opts.filter)?.0;
        (&refitted, check.changed_sources(&model.setup.noise))
    } else {
        (&effect.fit, 0)
    };
    if joint.failure.is_some() {
        return Ok(f64::NEG_INFINITY);
    }
    let keep = marginal_states(&noise_levels.fit, joint);
    let dll = joint.profile_loglik(&keep) - noise_levels.fit.profile_loglik(&keep);
    let k = (effect.candidate.parameters + noise_changed) as f64
        - noise_levels.candidate.parameters as f64;
    let ln_n = (model.measurement_count().max(1) as f64).ln();
    let over_levels = 2.0 * dll - k * ln_n;
    if noise_changed == 0 {
        return Ok(over_levels);
    }
    let without = fit_adaptive(
        ds,
        &model.setup.at_noise(check.used),
        catalogue,
        &opts.filter,
    )?
    .0;
    if without.failure.is_some() {
        return Ok(over_levels);
    }
    let keep = marginal_states(&without, joint);
    let at_same_levels = 2.0 * (joint.profile_loglik(&keep) - without.profile_loglik(&keep))
        - effect.candidate.parameters as f64 * ln_n;
    Ok(over_levels.min(at_same_levels))
}
