//! What a caller asks a diagnosis for, checked against the dataset before anything is
//! fitted: the `navkf diagnose` command and the Python package's `navkf.diagnose` both build
//! a [`DiagnoseRequest`] and get back the family's catalogue and the [`Options`].
//!
//! Refused, naming the setting as the caller spells it ([`SettingNames`]): an effect given
//! twice or unknown to the dataset's family, a window that is not a duration, no automatic
//! round, a prior for a coefficient the family lacks or not a one-sigma, a tilt sigma beyond
//! what the attitude equations hold (the dataset's own `[prior]` included), the
//! platform's attitude choice on a strapdown dataset, an effects file of the other family or
//! declaring a dataset's effect otherwise (naming the file), and `with` effects that no model
//! can hold together (two in one strapdown place).

use crate::catalogue::{coefficient_names, with_declared, Catalogue};
use crate::error::DiagnoseError;
use crate::options::Options;
use navkf_dynamics::dataset::{Dataset, CONFIG_FILE};
use navkf_dynamics::declared::DeclaredFile;
use navkf_dynamics::{Attitude, PlatformPrior};
use navkf_filters::{FilterKind, FilterSpec};
use navkf_report::SettingNames;
use std::collections::BTreeMap;

/// A diagnosis as a caller asks for it; `Default` is the command line's defaults.
#[derive(Debug, Clone)]
pub struct DiagnoseRequest {
    /// Effects switched on in the model under test (a manual first round).
    pub with: Vec<String>,
    /// Width of the sliding NIS windows, s.
    pub window_s: f64,
    /// Initial level error, one sigma, rad (over the dataset's `[prior]`).
    pub level_sigma: Option<f64>,
    /// Initial azimuth (heading) error, one sigma, rad (over the dataset's `[prior]`).
    pub azimuth_sigma: Option<f64>,
    /// Coefficient priors, one sigma each, by name (over `[prior.coefficients]`).
    pub priors: BTreeMap<String, f64>,
    /// Check the stated noise and fit the levels that are off (`false`: take it as stated).
    pub fit_noise: bool,
    /// The filter of every fit.
    pub filter: FilterKind,
    /// The attitude equations of the fits' model (the platform's choice; small-angle when
    /// `None`).
    pub attitude: Option<Attitude>,
    /// An effects file: effects declared without Rust beside the dataset's own (refused when
    /// of the other family or clashing with the dataset's, naming the file).
    pub declared: Option<DeclaredFile>,
    /// Most automatic rounds.
    pub max_rounds: usize,
}

impl Default for DiagnoseRequest {
    fn default() -> Self {
        let o = Options::default();
        DiagnoseRequest {
            with: Vec::new(),
            window_s: o.window_s,
            level_sigma: None,
            azimuth_sigma: None,
            priors: BTreeMap::new(),
            fit_noise: o.fit_noise,
            filter: o.filter.kind,
            attitude: None,
            declared: None,
            max_rounds: o.max_rounds,
        }
    }
}

impl DiagnoseRequest {
    /// Checks the request against `ds` (module documentation) and returns the catalogue of
    /// its family and the diagnosis options.
    pub fn check(
        &self,
        ds: &Dataset,
        names: SettingNames,
    ) -> Result<(Box<dyn Catalogue>, Options), DiagnoseError> {
        let bad = |m: String| Err(DiagnoseError::Data(m));
        for (i, w) in self.with.iter().enumerate() {
            if self.with[..i].contains(w) {
                return bad(format!("{}: `{w}` is given twice", names.of("with")));
            }
        }
        if !(self.window_s.is_finite() && self.window_s > 0.0) {
            return bad(format!(
                "{} {}: expected a duration > 0 s",
                names.of("window"),
                self.window_s
            ));
        }
        if self.max_rounds == 0 {
            return bad(format!(
                "{} 0: expected at least 1 (with no automatic round nothing is tested)",
                names.of("max_rounds")
            ));
        }
        let catalogue = with_declared(ds, self.declared.as_ref())?;
        let effects = catalogue.effect_names();
        for w in &self.with {
            if !effects.contains(w) {
                return bad(format!(
                    "{}: unknown {} effect `{w}`; known effects: {}",
                    names.of("with"),
                    ds.model.name(),
                    effects.join(", ")
                ));
            }
        }
        let prior = PlatformPrior {
            level_rad: self.level_sigma,
            azimuth_rad: self.azimuth_sigma,
            coefficients: self.priors.clone(),
        };
        let known = coefficient_names(&*catalogue);
        let files = navkf_dynamics::dataset::files_of(ds.model);
        let heading_key = files.heading_prior_key();
        prior
            .validate(&known, &heading_key, files.navigation_names())
            .map_err(|(key, message)| {
                let setting = match key.as_str() {
                    "prior.level_rad" => names.of("level_sigma"),
                    k if k == format!("prior.{heading_key}") => names.of("azimuth_sigma"),
                    k => format!(
                        "{} {}",
                        names.of("prior"),
                        k.trim_start_matches("prior.coefficients.")
                    ),
                };
                DiagnoseError::Data(format!("{setting}: {message}"))
            })?;
        let strapdown = !ds.model.is_platform();
        let attitude = self.attitude.unwrap_or(Attitude::SmallAngle);
        if strapdown && attitude != Attitude::SmallAngle {
            return bad(format!(
                "{}: the platform's choice; the strapdown family's attitude equations are \
                 exact Euler angles, expected no {0}",
                names.of("attitude")
            ));
        }
        // Effects that cannot share one model (two coefficients in one place of the strapdown
        // sensor model) are refused now, not when the first fit is built.
        if !self.with.is_empty() {
            catalogue
                .model(&self.with, &BTreeMap::new(), &ds.noise, attitude)
                .map_err(|e| DiagnoseError::Data(format!("{}: {e}", names.of("with"))))?;
        }
        // The tilt priors, the request's first, then the dataset's own where the request
        // does not override them: the platform's within what its attitude equations hold, a
        // strapdown heading up to half a turn.
        let check_tilt = |what: &str, v: f64| -> Result<(), DiagnoseError> {
            if strapdown {
                if v.is_finite() && v > 0.0 && v <= std::f64::consts::PI {
                    Ok(())
                } else {
                    Err(DiagnoseError::Data(format!(
                        "{what} {v}: expected a one-sigma in (0, pi] rad"
                    )))
                }
            } else {
                attitude
                    .check_tilt_sigma(what, v)
                    .map_err(DiagnoseError::Data)
            }
        };
        for (key, v) in [
            ("level_sigma", self.level_sigma),
            ("azimuth_sigma", self.azimuth_sigma),
        ] {
            if let Some(v) = v {
                check_tilt(&names.of(key), v)?;
            }
        }
        for (key, stated, given) in [
            ("level_rad", ds.prior.level_rad, self.level_sigma),
            (
                heading_key.as_str(),
                ds.prior.azimuth_rad,
                self.azimuth_sigma,
            ),
        ] {
            if let (Some(v), None) = (stated, given) {
                check_tilt(&format!("{CONFIG_FILE} [prior] {key} ="), v)?;
            }
        }
        let options = Options {
            with: self.with.clone(),
            window_s: self.window_s,
            prior,
            fit_noise: self.fit_noise,
            filter: FilterSpec {
                attitude,
                ..FilterSpec::new(self.filter)
            },
            max_rounds: self.max_rounds,
            ..Default::default()
        };
        Ok((catalogue, options))
    }
}
