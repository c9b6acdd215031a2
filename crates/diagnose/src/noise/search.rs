//! The search of a noise check ([`super`]): the log-likelihood over the sources' log-scales,
//! its score at the start, Newton's method over the sources that are off, the probes of the
//! process-noise densities, and the resolution at the optimum.

use super::levels::{
    scaled, NoiseFit, NoiseSource, NoiseVerdict, SourceFit, Theta, WhyUnresolved, FEW_UPDATES,
    MAX_SOURCES, RESOLVED_SIGMA_FACTOR, SOURCES, TRADE_OFF, Z_FLAG,
};
use super::likelihood_interval;
use crate::catalogue::Catalogue;
use crate::error::DiagnoseError;
use crate::fit::pass::{fit, Fit};
use crate::fit::setup::FitSetup;
use navkf_dynamics::dataset::Dataset;
use navkf_dynamics::NoiseConfig;
use navkf_filters::FilterSpec;
use rayon::prelude::*;

/// Largest Newton step per source, in log-variance (a factor 3.5 in sigma).
pub const MAX_STEP: f64 = 2.5;
/// Upward probes of the process-noise densities, in log-variance (x10 and x100 in sigma).
const PROBES: [f64; 2] = [4.605_170_185_988_092, 9.210_340_371_976_184];
/// Log-likelihood gain of a probe that counts as significant (`Z_FLAG^2 / 2`).
const PROBE_GAIN: f64 = 0.5 * Z_FLAG * Z_FLAG;
/// Sources whose score at the stated levels is at least this join the Newton iterations.
pub const Z_ACTIVE: f64 = Z_FLAG;
/// Finite-difference step in log-variance.
const H: f64 = 0.3;
/// Newton stops when no log-scale moves by more than this (a 2.5 % change of a sigma).
const CONVERGED: f64 = 0.05;
/// Filter passes after which Newton stops where it is: the levels are then resolved to within
/// the steps taken, which is all a competing candidate needs (a slow structured misfit can
/// leak into flat process-noise directions and keep Newton walking them).
const PASS_BUDGET: usize = 80;
/// Most Newton iterations.
const MAX_ITERATIONS: usize = 6;
/// Curvature floor: a log-scale the data do not inform gets a standard error of at most 5.
const MIN_CURVATURE: f64 = 1.0 / 25.0;

/// Log-likelihood surface access: one filter pass per point, in parallel.
struct Surface<'a> {
    ds: &'a Dataset,
    setup: &'a FitSetup,
    stated: NoiseConfig,
    catalogue: &'a dyn Catalogue,
    filter: &'a FilterSpec,
    passes: std::sync::atomic::AtomicUsize,
    /// Filter passes after which Newton stops where it is ([`PASS_BUDGET`], raised by the
    /// restarts of the process-noise grid).
    budget: std::sync::atomic::AtomicUsize,
    /// The family's sources: the first this many of [`SOURCES`].
    sources: usize,
}

impl Surface<'_> {
    /// Filter passes made so far.
    fn spent(&self) -> usize {
        self.passes.load(std::sync::atomic::Ordering::Relaxed)
    }

    /// Whether Newton has used up its passes.
    fn exhausted(&self) -> bool {
        self.spent() >= self.budget.load(std::sync::atomic::Ordering::Relaxed)
    }

    /// Allows `more` passes beyond those spent so far.
    fn allow(&self, more: usize) {
        self.budget
            .store(self.spent() + more, std::sync::atomic::Ordering::Relaxed);
    }

    fn at(&self, thetas: &[Theta]) -> Result<Vec<f64>, DiagnoseError> {
        self.passes
            .fetch_add(thetas.len(), std::sync::atomic::Ordering::Relaxed);
        thetas
            .par_iter()
            .map(|th| {
                let mut s = self.setup.clone();
                s.noise = scaled(&self.stated, *th);
                let f = fit(self.ds, &s, self.catalogue, self.filter)?;
                Ok(if f.failure.is_some() || !f.loglik.is_finite() {
                    f64::NEG_INFINITY
                } else {
                    f.loglik
                })
            })
            .collect()
    }

    /// Gradient and Hessian at `theta` (whose value is `f0`) along `axes`, by finite
    /// differences: central along each axis; forward for the cross terms when `cross`. Other
    /// entries are left at zero.
    fn derivatives(
        &self,
        theta: Theta,
        f0: f64,
        axes: &[usize],
        cross: bool,
    ) -> Result<(Theta, [[f64; MAX_SOURCES]; MAX_SOURCES]), DiagnoseError> {
        let mut pts = Vec::new();
        for &j in axes {
            for s in [H, -H] {
                let mut t = theta;
                t[j] += s;
                pts.push(t);
            }
        }
        let pairs: Vec<(usize, usize)> = if cross {
            axes.iter()
                .enumerate()
                .flat_map(|(a, &i)| axes[a + 1..].iter().map(move |&j| (i, j)))
                .collect()
        } else {
            Vec::new()
        };
        for &(i, j) in &pairs {
            let mut t = theta;
            t[i] += H;
            t[j] += H;
            pts.push(t);
        }
        let v = self.at(&pts)?;
        let mut g = [0.0; MAX_SOURCES];
        let mut hess = [[0.0; MAX_SOURCES]; MAX_SOURCES];
        let mut plus = [0.0; MAX_SOURCES];
        for (a, &j) in axes.iter().enumerate() {
            let (fp, fm) = (v[2 * a], v[2 * a + 1]);
            plus[j] = fp;
            g[j] = (fp - fm) / (2.0 * H);
            hess[j][j] = (fp - 2.0 * f0 + fm) / (H * H);
        }
        let base = 2 * axes.len();
        for (k, &(i, j)) in pairs.iter().enumerate() {
            let h = (v[base + k] - plus[i] - plus[j] + f0) / (H * H);
            hess[i][j] = h;
            hess[j][i] = h;
        }
        Ok((g, hess))
    }
}

impl super::grid::Landscape for Surface<'_> {
    fn values(&self, points: &[Theta]) -> Result<Vec<f64>, DiagnoseError> {
        self.at(points)
    }
    fn climb(
        &self,
        start: Theta,
        value: f64,
        active: &mut Vec<usize>,
        g: &mut Theta,
        hess: &mut super::grid::Hessian,
    ) -> Result<(Theta, f64), DiagnoseError> {
        self.allow(PASS_BUDGET);
        optimise(self, start, value, active, g, hess)
    }
}

/// The score statistic `g / sqrt(-H)` of each axis; 0 where the curvature is not negative
/// (no information).
fn scores(g: &Theta, hess: &[[f64; MAX_SOURCES]; MAX_SOURCES]) -> Theta {
    std::array::from_fn(|j| {
        let curv = -hess[j][j];
        if curv > 0.0 && g[j].is_finite() {
            g[j] / curv.sqrt()
        } else {
            0.0
        }
    })
}

/// A first step for the active sources from the axis values at the stated levels, fitting
/// each axis with the shape a pure noise scale gives the log-likelihood,
/// `f(theta) = a - b (theta + r exp(-theta))`, whose maximum is at `ln r` (exact when the
/// innovations of that source are its own noise, as for GPS and odometer). Kept only if the
/// log-likelihood rises.
fn model_jump(
    surface: &Surface<'_>,
    start: Theta,
    f0: f64,
    g: &Theta,
    hess: &[[f64; MAX_SOURCES]; MAX_SOURCES],
    active: &[usize],
) -> Result<(Theta, f64), DiagnoseError> {
    let mut theta = start;
    for &j in active {
        // Back from the derivatives to the differences of the three axis values.
        let d1 = 2.0 * H * g[j];
        let d2 = H * H * hess[j][j];
        let denom = d1 * (2.0 * H.cosh() - 2.0) + 2.0 * d2 * H.sinh();
        let r = 2.0 * H * d2 / denom;
        if r.is_finite() && r > 0.0 {
            theta[j] += r.ln().clamp(-4.0 * MAX_STEP, 4.0 * MAX_STEP);
        }
    }
    if theta == start {
        return Ok((theta, f0));
    }
    let v = surface.at(&[theta])?[0];
    Ok(if v > f0 { (theta, v) } else { (start, f0) })
}

/// Newton's method over `active` from `theta` (value `f`), then the scores of the other
/// sources at the optimum; any significant one joins and Newton runs again (at most two
/// times). Leaves in `g` and `hess` the last derivatives along every axis it took.
fn optimise(
    surface: &Surface<'_>,
    mut theta: Theta,
    mut f: f64,
    active: &mut Vec<usize>,
    g: &mut Theta,
    hess: &mut [[f64; MAX_SOURCES]; MAX_SOURCES],
) -> Result<(Theta, f64), DiagnoseError> {
    for _ in 0..2 {
        let end = newton(surface, theta, f, active)?;
        theta = end.theta;
        f = end.value;
        *hess = end.hessian;
        let inactive: Vec<usize> = (0..surface.sources)
            .filter(|j| !active.contains(j))
            .collect();
        if inactive.is_empty() {
            break;
        }
        let (gi, hi) = surface.derivatives(theta, f, &inactive, false)?;
        for &j in &inactive {
            g[j] = gi[j];
            hess[j][j] = hi[j][j];
        }
        let z = scores(&gi, &hi);
        let joining: Vec<usize> = inactive
            .into_iter()
            .filter(|&j| z[j].abs() >= Z_FLAG)
            .collect();
        if joining.is_empty() {
            break;
        }
        active.extend(joining);
        active.sort_unstable();
    }
    Ok((theta, f))
}

/// What probing some axes wider found: the axes whose probe gained more than `PROBE_GAIN`
/// over the point probed from (in the order probed), and the best of that point and the
/// probes with its value.
struct Probe {
    gained: Vec<usize>,
    best: Theta,
    value: f64,
}

/// Each of `axes` raised by each of `PROBES` from `from` (value `value`), evaluated in one
/// batch: a level stated far too small leaves the likelihood flat around it, so only a
/// probe well away can see it.
fn probe_wider(
    surface: &Surface<'_>,
    from: Theta,
    value: f64,
    axes: &[usize],
) -> Result<Probe, DiagnoseError> {
    let probes: Vec<(usize, Theta)> = axes
        .iter()
        .flat_map(|&j| {
            PROBES.iter().map(move |&p| {
                let mut t = from;
                t[j] += p;
                (j, t)
            })
        })
        .collect();
    let values = surface.at(&probes.iter().map(|p| p.1).collect::<Vec<_>>())?;
    let mut found = Probe {
        gained: Vec::new(),
        best: from,
        value,
    };
    for ((j, t), &v) in probes.iter().zip(&values) {
        if v - value > PROBE_GAIN {
            if !found.gained.contains(j) {
                found.gained.push(*j);
            }
            if v > found.value {
                (found.best, found.value) = (*t, v);
            }
        }
    }
    Ok(found)
}

/// Where Newton's method stopped: the log-scales, the log-likelihood there and its Hessian.
struct NewtonEnd {
    theta: Theta,
    value: f64,
    hessian: [[f64; MAX_SOURCES]; MAX_SOURCES],
}

/// Newton's method on the log-scales of `active` (the others fixed), from `theta` with value
/// `f`; returns the optimum, its value and the Hessian there (over `active`).
fn newton(
    surface: &Surface<'_>,
    mut theta: Theta,
    mut f: f64,
    active: &[usize],
) -> Result<NewtonEnd, DiagnoseError> {
    for _ in 0..MAX_ITERATIONS {
        if surface.exhausted() {
            break;
        }
        let (g, hess) = surface.derivatives(theta, f, active, true)?;
        if active.iter().any(|&j| !g[j].is_finite()) {
            return Ok(NewtonEnd {
                theta,
                value: f,
                hessian: hess,
            });
        }
        let m = active.len();
        let info = information(&hess, active);
        let Some(inv) = info.clone().try_inverse() else {
            return Ok(NewtonEnd {
                theta,
                value: f,
                hessian: hess,
            });
        };
        let gv = nalgebra::DVector::from_iterator(m, active.iter().map(|&j| g[j]));
        let step = inv * gv;
        let step: Vec<f64> = step.iter().map(|s| s.clamp(-MAX_STEP, MAX_STEP)).collect();
        if step.iter().all(|s| s.abs() < CONVERGED) {
            break;
        }
        let mut t = 1.0;
        let mut moved = false;
        for _ in 0..4 {
            let mut cand = theta;
            for (a, &j) in active.iter().enumerate() {
                cand[j] += t * step[a];
            }
            let v = surface.at(&[cand])?[0];
            if v > f {
                theta = cand;
                f = v;
                moved = true;
                break;
            }
            t *= 0.5;
        }
        let size = step.iter().fold(0.0f64, |m, s| m.max(s.abs())) * t;
        if !moved || size < CONVERGED {
            break;
        }
    }
    let (_, hess) = surface.derivatives(theta, f, active, true)?;
    Ok(NewtonEnd {
        theta,
        value: f,
        hessian: hess,
    })
}

/// `-H` over `active`, made positive definite (eigenvalues at least [`MIN_CURVATURE`]);
/// non-finite entries count as no information.
fn information(
    hess: &[[f64; MAX_SOURCES]; MAX_SOURCES],
    active: &[usize],
) -> nalgebra::DMatrix<f64> {
    let m = active.len();
    let raw = nalgebra::DMatrix::from_fn(m, m, |a, b| {
        let v = -hess[active[a]][active[b]];
        if v.is_finite() {
            v
        } else if a == b {
            MIN_CURVATURE
        } else {
            0.0
        }
    });
    let sym = 0.5 * (&raw + raw.transpose());
    let mut e = sym.symmetric_eigen();
    for l in e.eigenvalues.iter_mut() {
        *l = l.max(MIN_CURVATURE);
    }
    e.recompose()
}

/// Checks the noise of the model `model` fits on `ds` (the stated levels scaled by
/// `theta_start`): the module documentation of [`super`].
///
/// Newton's method runs only over the sources whose score is at least [`Z_ACTIVE`] at the
/// start levels, and those fitted earlier (the others' log-likelihood is typically flat, and
/// letting them wander costs passes and changes nothing); at the optimum the other sources'
/// scores are taken again, and any that became significant joins.
pub fn check(
    ds: &Dataset,
    model: &Fit,
    theta_start: Theta,
    catalogue: &dyn Catalogue,
    filter: &FilterSpec,
) -> Result<NoiseFit, DiagnoseError> {
    let k = catalogue.noise_sources();
    let stated = &own_standstill(&ds.noise, k);
    let (setup, loglik_start) = (&model.setup, model.loglik);
    let surface = Surface {
        ds,
        setup,
        stated: *stated,
        catalogue,
        filter,
        passes: Default::default(),
        budget: PASS_BUDGET.into(),
        sources: k,
    };
    let all: Vec<usize> = (0..k).collect();
    let (mut theta, mut f) = (theta_start, loglik_start);
    let mut failed_start = false;
    if !f.is_finite() {
        // The filter failed at the start levels: start from the best of a few common scales
        // (variance x 7 to x 22000).
        failed_start = true;
        let starts: Vec<Theta> = (1..=5)
            .map(|m| std::array::from_fn(|j| if j < k { 2.0 * m as f64 } else { 0.0 }))
            .collect();
        let v = surface.at(&starts)?;
        if let Some((k, &best)) = v
            .iter()
            .enumerate()
            .filter(|(_, v)| v.is_finite())
            .max_by(|a, b| a.1.total_cmp(b.1))
        {
            theta = starts[k];
            f = best;
        }
    }
    // The axes at the start: scores and curvatures.
    let (mut g, mut hess) = if f.is_finite() {
        surface.derivatives(theta, f, &all, false)?
    } else {
        (
            [f64::NAN; MAX_SOURCES],
            [[f64::NAN; MAX_SOURCES]; MAX_SOURCES],
        )
    };
    let joined = |z: Theta, active: &mut Vec<usize>, threshold: f64| {
        let mut any = false;
        for j in 0..k {
            if !active.contains(&j) && z[j].abs() >= threshold {
                active.push(j);
                any = true;
            }
        }
        active.sort_unstable();
        any
    };
    let z0 = scores(&g, &hess);
    let mut active: Vec<usize> = if failed_start {
        all.to_vec()
    } else {
        all.iter().copied().filter(|&j| theta[j] != 0.0).collect()
    };
    let mut refitted = failed_start || z0.iter().any(|z| z.abs() >= Z_FLAG);
    if f.is_finite() && refitted {
        joined(z0, &mut active, Z_ACTIVE);
        if !failed_start && theta == theta_start {
            let jump = model_jump(&surface, theta, f, &g, &hess, &active)?;
            theta = jump.0;
            f = jump.1;
        }
        (theta, f) = optimise(&surface, theta, f, &mut active, &mut g, &mut hess)?;
    }
    // Process noise stated far too small leaves the log-likelihood flat around the stated
    // level (the filter ignores it either way), so the local score cannot see it: probe the
    // gyro and accelerometer densities 10 and 100 times larger in sigma, from the optimum of
    // the local search (probing first would let a process noise stand in for a measurement
    // noise the local search finds at once).
    if f.is_finite() && !failed_start {
        let unfitted: Vec<usize> = [0usize, 1]
            .into_iter()
            .filter(|j| !active.contains(j))
            .collect();
        let probe = probe_wider(&surface, theta, f, &unfitted)?;
        let probed = !probe.gained.is_empty();
        if probed {
            refitted = true;
            active.extend(probe.gained);
            active.sort_unstable();
            (theta, f) = optimise(
                &surface,
                probe.best,
                probe.value,
                &mut active,
                &mut g,
                &mut hess,
            )?;
        }
        // Noise stated far off leaves local optima along the ridge where one process noise
        // stands in for the other: a gyro density raised 10^4 times in sigma explains the
        // velocity misfit of an accelerometer noise 500 times the stated one, and from there
        // the accelerometer's own level is flat (MEMS data diagnosed with the defaults,
        // `examples/noise_from_afar.rs`). So when anything was refitted, the pair is also
        // tried on a grid of absolute levels, 1 to 10^4 times the stated sigma each, at the
        // measurement levels found; a decisively better point restarts the search.
        if refitted && (probed || active.contains(&0) || active.contains(&1)) {
            (theta, f) = super::grid::restart(
                &surface,
                PROBE_GAIN,
                theta,
                f,
                theta_start,
                &mut active,
                &mut g,
                &mut hess,
            )?;
        }
        // A tolerance stated far too tight is absorbed by a process noise: between updates the
        // filter's velocity variance grows with the accelerometer's density, and a density
        // raised enough covers the standstill's misfit, after which the tolerance's own
        // likelihood is flat (a standstill stated 10x tight was fitted as accelerometer noise
        // 6x, the verdict `unexplained`). Stated tighter still, the tolerance is flat at the
        // start too (the filter's own velocity variance swamps it), so its score cannot see
        // it, as a process noise stated far too small cannot be seen. So when a process noise
        // was refitted, each tolerance is also probed 10 and 100 times larger in sigma from
        // the start's levels, and the search starts over from the best of the start and the
        // probes, with the process noises held and the tolerances and measurement sources
        // that were off free; the better optimum is kept.
        let tolerances: Vec<usize> = (2..k).filter(|&j| SOURCES[j].is_tolerance()).collect();
        if !tolerances.is_empty() && (active.contains(&0) || active.contains(&1)) {
            let mut free: Vec<usize> = (2..k).filter(|&j| z0[j].abs() >= Z_ACTIVE).collect();
            let probe = probe_wider(&surface, theta_start, loglik_start, &tolerances)?;
            for j in probe.gained {
                if !free.contains(&j) {
                    free.push(j);
                }
            }
            if free.iter().any(|&j| SOURCES[j].is_tolerance()) {
                free.sort_unstable();
                // (The gradient is not read after the search: the resolution takes it again.)
                let (mut other_g, mut other_hess) = (g, hess);
                surface.allow(PASS_BUDGET);
                let (t, v) = optimise(
                    &surface,
                    probe.best,
                    probe.value,
                    &mut free,
                    &mut other_g,
                    &mut other_hess,
                )?;
                if v > f {
                    (theta, f, active, hess) = (t, v, free, other_hess);
                }
            }
        }
    }
    // Standard errors: the inverse information over the active sources; the axis curvature
    // for the others.
    let mut se = [0.0; MAX_SOURCES];
    let mut correlation = [[0.0; MAX_SOURCES]; MAX_SOURCES];
    if !active.is_empty() {
        let info = information(&hess, &active);
        let cov = info.try_inverse().unwrap_or_else(|| {
            nalgebra::DMatrix::identity(active.len(), active.len()) / MIN_CURVATURE
        });
        for (a, &j) in active.iter().enumerate() {
            se[j] = cov[(a, a)].max(0.0).sqrt();
        }
        for (a, &i) in active.iter().enumerate() {
            for (b, &j) in active.iter().enumerate() {
                let d = (cov[(a, a)] * cov[(b, b)]).sqrt();
                correlation[i][j] = if d > 0.0 { cov[(a, b)] / d } else { 0.0 };
            }
        }
    }
    for j in all.iter().copied().filter(|j| !active.contains(j)) {
        let curv = -hess[j][j];
        se[j] = if curv.is_finite() {
            1.0 / curv.max(MIN_CURVATURE).sqrt()
        } else {
            1.0 / MIN_CURVATURE.sqrt()
        };
    }
    // A fitted level's interval: the likelihood ratio's (super::likelihood_interval).
    let mut interval: [[f64; 2]; MAX_SOURCES] = std::array::from_fn(|j| {
        [
            (0.5 * (theta[j] - 1.96 * se[j])).exp(),
            (0.5 * (theta[j] + 1.96 * se[j])).exp(),
        ]
    });
    if f.is_finite() {
        for j in (0..k).filter(|&j| (theta[j] / se[j]).abs() > Z_FLAG) {
            // The ridge: each other active source's best move per unit of this one's.
            let ridge: Theta = std::array::from_fn(|i| {
                if i == j {
                    1.0
                } else if active.contains(&i) && active.contains(&j) && se[j] > 0.0 {
                    correlation[i][j] * se[i] / se[j]
                } else {
                    0.0
                }
            });
            let [lo, hi] = likelihood_interval::bounds(&surface, theta, f, j, ridge, se[j])?;
            interval[j] = [
                lo.map_or(0.0, |t| (0.5 * t).exp()),
                (0.5 * hi.unwrap_or(theta[j] + likelihood_interval::FARTHEST)).exp(),
            ];
        }
    }
    // A tolerance's likelihood goes flat towards zero when the vehicle holds its constraint
    // more closely than any level resolves (a standing car that is exactly still): the optimum
    // then sits on a plateau whose curvature says nothing, and the score statistic cannot flag
    // a level the data put far below the stated one. There the likelihood ratio against the
    // stated level decides, at the same level (`Z_FLAG^2 / 2`).
    let plateau: Vec<usize> = (0..k)
        .filter(|&j| {
            SOURCES[j].is_tolerance() && theta[j] != 0.0 && (theta[j] / se[j]).abs() <= Z_FLAG
        })
        .collect();
    let at_stated: Vec<Theta> = plateau
        .iter()
        .map(|&j| {
            let mut t = theta;
            t[j] = 0.0;
            t
        })
        .collect();
    let mut ratio_flags = [false; MAX_SOURCES];
    if f.is_finite() && !at_stated.is_empty() {
        for (&j, v) in plateau.iter().zip(surface.at(&at_stated)?) {
            ratio_flags[j] = f - v >= PROBE_GAIN;
        }
    }
    let mut used_theta = [0.0; MAX_SOURCES];
    let ml = scaled(stated, theta);
    let updates = channel_updates(ds);
    let why = |j: usize| -> WhyUnresolved {
        if let Some(&n) = updates.get(j).filter(|&&n| n < FEW_UPDATES) {
            return WhyUnresolved::FewUpdates { updates: n };
        }
        let partner = (0..k)
            .filter(|&i| i != j)
            .max_by(|&a, &b| correlation[j][a].abs().total_cmp(&correlation[j][b].abs()));
        if let Some(i) = partner.filter(|&i| correlation[j][i].abs() >= TRADE_OFF) {
            return WhyUnresolved::TradesOff {
                with: SOURCES[i],
                correlation: correlation[j][i],
            };
        }
        if se[j] >= 0.99 / MIN_CURVATURE.sqrt() {
            WhyUnresolved::Flat
        } else {
            WhyUnresolved::Weak
        }
    };
    let sources = SOURCES[..k]
        .iter()
        .enumerate()
        .map(|(j, &source)| {
            let z = theta[j] / se[j];
            let verdict = if z.abs() > Z_FLAG || ratio_flags[j] {
                used_theta[j] = theta[j];
                if theta[j] > 0.0 {
                    NoiseVerdict::UnderStated
                } else {
                    NoiseVerdict::OverStated
                }
            } else if (0.5 * 1.96 * se[j]).exp() > RESOLVED_SIGMA_FACTOR {
                NoiseVerdict::Unresolved
            } else {
                NoiseVerdict::Fits
            };
            let mut fit = SourceFit {
                source,
                verdict,
                sigma_ratio: (0.5 * theta[j]).exp(),
                sigma_ratio_interval: interval[j],
                stated: source.values(stated),
                fitted: source.values(&ml),
                unresolved_because: None,
            };
            let coarse = verdict != NoiseVerdict::Fits && !fit.fixed();
            fit.unresolved_because =
                (verdict == NoiseVerdict::Unresolved || coarse).then(|| why(j));
            fit
        })
        .collect();
    Ok(NoiseFit {
        model: setup.effects.clone(),
        stated: *stated,
        start: scaled(stated, theta_start),
        refitted,
        used: scaled(stated, used_theta),
        used_theta: used_theta[..k].to_vec(),
        theta: theta[..k].to_vec(),
        theta_se: se[..k].to_vec(),
        sources,
        loglik_gain: f - loglik_start,
        passes: surface.passes.into_inner(),
    })
}

/// `stated` with the zero-velocity update's tolerance written out when the family fits it as
/// a source of its own ([`NoiseSource::Standstill`]) and `dataset.toml` leaves it to default to
/// the odometer's floor: the odometer's refitted level then leaves it where it was stated,
/// as the source's own level does the odometer.
fn own_standstill(stated: &NoiseConfig, sources: usize) -> NoiseConfig {
    let has_standstill = SOURCES[..sources].contains(&NoiseSource::Standstill);
    NoiseConfig {
        zupt_m_s: stated
            .zupt_m_s
            .or(has_standstill.then_some(stated.odometer_floor)),
        ..*stated
    }
}

/// Updates of each source's channel, in the order of [`SOURCES`]: `usize::MAX` for the
/// process noises, which have no channel of their own.
fn channel_updates(ds: &Dataset) -> [usize; MAX_SOURCES] {
    let count = |f: &dyn Fn(&navkf_dynamics::dataset::Measurement) -> bool| {
        ds.measurements.iter().filter(|m| f(m)).count()
    };
    [
        usize::MAX,
        usize::MAX,
        count(&|m| m.velocity.is_some() || m.speed.is_some()),
        count(&|m| m.position_deg.is_some()),
        // The constraint reads while moving when `nhc_m_s` is given, the zero-velocity update
        // at every standstill (navkf_dynamics::strapdown::sensors), whether or not the file
        // holds their zeros.
        count(&|m| m.speed.is_some_and(|v| v != 0.0) && ds.noise.nhc_m_s.is_some()),
        count(&|m| m.speed == Some(0.0)),
    ]
}
