//! What a caller sets for a diagnosis: the model under test, the noise check, the filter,
//! the consistency tests' windows and lags, and how many rounds.

use navkf_dynamics::PlatformPrior;
use navkf_filters::FilterSpec;

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
