//! One catalogued effect weighed as a candidate: the model refitted with it (a structured
//! effect with its coefficients' priors open to widening, a noise-only term at its
//! maximum-likelihood density), its evidence over the model, and whether the trajectory can
//! tell its coefficients from the model's own.

use super::evidence::INDISTINGUISHABLE;
use super::evidence::{Candidate, CandidateKind, Confusion, Evaluated, Model, Named, Outcome};
use crate::catalogue::Catalogue;
use crate::error::DiagnoseError;
use crate::fit::density::fit_density;
use crate::fit::pass::{marginal_states, Fit};
use crate::fit::widening::fit_adaptive;
use crate::options::Options;
use crate::summary::{summarize_fit, Coefficient};
use navkf_dynamics::dataset::Dataset;

/// Evaluates one effect; `None` for an effect with neither coefficients nor noise (nothing
/// to fit).
pub fn evaluate(
    ds: &Dataset,
    model: &Model<'_>,
    name: &str,
    catalogue: &dyn Catalogue,
    opts: &Options,
) -> Result<Option<Evaluated>, DiagnoseError> {
    let effect = catalogue.effect(name)?;
    let k_coef = effect.coefficients.len();
    let (fit, widened, density, kind) = if k_coef > 0 {
        // From the starting priors: a base coefficient the model had to widen to soak up the
        // misfit this candidate explains must not keep the candidate from explaining it.
        let mut setup = model.fit.setup.with_effect(name, None);
        setup.priors = setup.priors.restarted();
        setup
            .priors
            .open
            .extend(effect.coefficients.iter().cloned());
        let (f, w) = fit_adaptive(ds, &setup, catalogue, &opts.filter)?;
        (f, w, None, CandidateKind::Structured)
    } else if let Some(typical) = effect.noise_density {
        let d = fit_density(ds, model.fit, name, typical, catalogue, &opts.filter)?;
        (d.fit, Vec::new(), Some(d.density), CandidateKind::NoiseOnly)
    } else {
        return Ok(None);
    };
    let s = summarize_fit(ds, &fit, opts);
    let keep = marginal_states(model.fit, &fit);
    let dll = fit.profile_loglik(&keep) - model.fit.profile_loglik(&keep);
    // A coefficient the family holds at zero ([`Catalogue::pinned`]) is no parameter: no fit
    // moves it, so the BIC does not charge for it.
    let pinned = catalogue.pinned();
    let k = effect
        .coefficients
        .iter()
        .filter(|c| !pinned.contains(&c.as_str()))
        .count()
        .max(1);
    let ln_n = (model.fit.measurement_count().max(1) as f64).ln();
    let bic = 2.0 * dll - k as f64 * ln_n;
    let excess = model.summary.excess_nis;
    let removed = if excess > 0.0 {
        1.0 - s.excess_nis.max(0.0) / excess
    } else {
        0.0
    };
    let ours = own_states(&fit, &model.fit.names);
    let confused = confusion(&fit, &model.fit.names, &ours);
    let own: Vec<Coefficient> = s
        .coefficients
        .iter()
        .filter(|c| ours.iter().any(|&i| fit.names[i] == c.name))
        .cloned()
        .collect();
    let beyond = crate::physical::coefficients_beyond(&effect, &own);
    let candidate = Candidate {
        effect: name.to_string(),
        kind,
        delta_loglik: dll,
        parameters: k,
        bic_gain: bic,
        excess_removed: removed,
        nis: s.nis.clone(),
        consistent: s.consistent,
        coefficients: own,
        density,
        noise: None,
        widened,
        separable_bic: separable_evidence(&fit, &ours, &confused, ln_n),
        confused_with: confused,
        beside_refitted_noise: None,
        beyond_bounds: beyond,
        outcome: Outcome::NotDecisive,
        failure: fit.failure.clone(),
    };
    let names = match kind {
        CandidateKind::NoiseOnly => Named::NoiseTerm(name.to_string()),
        _ => Named::Effect(name.to_string()),
    };
    Ok(Some(Evaluated {
        candidate,
        fit,
        names,
    }))
}

/// The candidate's own coefficients in its fit `f`: the states the model (`model_names`) does
/// not hold, but for those the family holds at zero ([`Fit::pinned`]: nothing to estimate, separate
/// or bound) and those driven by noise. A strapdown bias instability's departures from
/// the turn-on biases (docs/model.md eq. (69)) are such states: at any instant the data see
/// only their sum with the biases, and what tells the candidate apart is its noise, which the
/// likelihood weighs, not a constant to be separated.
fn own_states(f: &Fit, model_names: &[String]) -> Vec<usize> {
    (f.nav_dim..f.names.len())
        .filter(|&i| !f.noisy[i] && !f.pinned[i] && !model_names.contains(&f.names[i]))
        .collect()
}

/// Coefficients of the candidate (`ours`, from [`own_states`]) that cannot be told apart from
/// one of the model's: correlated beyond [`INDISTINGUISHABLE`] in the
/// posterior the data would give from the priors the diagnosis started from.
///
/// Not the fit's own posterior: after widening, two coefficients the data see only as a sum
/// (`Kg13z fz` and `Kg0z` on a level vehicle) can carry priors a hundred times apart, and
/// their posterior correlation is then near zero although nothing but the priors separates
/// them. Nor the data alone: a drag and the g-sensitive drifts are nearly collinear on the
/// paper's test, and only the platform's priors (a drift of 500 times its typical size is not
/// this platform's) tell them apart. So the data's information `F = P_c^-1 - P0^-1` is put
/// back on the starting priors and the correlation read from `(F + P_start^-1)^-1`.
fn confusion(f: &Fit, model_names: &[String], ours: &[usize]) -> Vec<Confusion> {
    let n = f.names.len();
    // States driven by noise (the drifts under `gyro-bias-walk`) stay in, with their
    // posterior as it is: a walking drift still cannot be told from a constant g-sensitive one.
    let idx: Vec<usize> = (f.nav_dim..n).collect();
    let m = idx.len();
    let p = nalgebra::DMatrix::from_fn(m, m, |a, b| f.p[idx[a] + idx[b] * n]);
    let Some(p_inv) = p.clone().cholesky().map(|c| c.inverse()) else {
        return Vec::new();
    };
    let mut precision = p_inv;
    // A coefficient held at zero keeps its pinned prior: put back on a starting prior, it
    // would be free, and every coefficient the data see only beside it would read as confused
    // with a state that no fit moves.
    for (a, &i) in idx
        .iter()
        .enumerate()
        .filter(|(_, &i)| !f.noisy[i] && !f.pinned[i])
    {
        let start = f
            .setup
            .priors
            .starting_sigma(&f.names[i], f.typical_sigma[i]);
        precision[(a, a)] += 1.0 / (start * start) - 1.0 / (f.prior_sigma[i] * f.prior_sigma[i]);
    }
    let Some(c) = precision.cholesky().map(|c| c.inverse()) else {
        return Vec::new();
    };
    let mut out = Vec::new();
    for (u, &i) in idx.iter().enumerate() {
        if !ours.contains(&i) {
            continue;
        }
        for (v, &j) in idx.iter().enumerate() {
            if f.pinned[j] || !model_names.contains(&f.names[j]) {
                continue;
            }
            let corr = c[(u, v)] / (c[(u, u)] * c[(v, v)]).sqrt();
            if corr.abs() > INDISTINGUISHABLE {
                out.push(Confusion {
                    coefficient: f.names[i].clone(),
                    with: f.names[j].clone(),
                    correlation: corr,
                });
            }
        }
    }
    out
}

/// The Wald evidence of the candidate's coefficients (`ours`) that are not in `confused`, as
/// a BIC gain; `None` when none is confused.
fn separable_evidence(f: &Fit, ours: &[usize], confused: &[Confusion], ln_n: f64) -> Option<f64> {
    if confused.is_empty() {
        return None;
    }
    let n = f.names.len();
    let free: Vec<usize> = ours
        .iter()
        .copied()
        .filter(|&i| !confused.iter().any(|c| c.coefficient == f.names[i]))
        .collect();
    let m = free.len();
    if m == 0 {
        return Some(f64::NEG_INFINITY);
    }
    let mut block = vec![0.0; m * m];
    for (a, &i) in free.iter().enumerate() {
        for (b, &j) in free.iter().enumerate() {
            block[a + b * m] = f.p[i + j * n];
        }
    }
    if navkf_filters::linalg::cholesky_in_place(&mut block, m).is_err() {
        return Some(f64::NEG_INFINITY);
    }
    let mut c: Vec<f64> = free.iter().map(|&i| f.x[i]).collect();
    navkf_filters::linalg::forward_substitute(&block, m, &mut c);
    let wald: f64 = c.iter().map(|v| v * v).sum();
    Some(wald - m as f64 * ln_n)
}
