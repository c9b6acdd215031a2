//! How a caller names its settings in messages: the command line's `--azimuth-sigma`, the
//! Python package's `azimuth_sigma`. Code that checks settings shared by both (simulate,
//! diagnose) names them through this, so each caller's user reads their own spelling.

/// How the caller names its settings in messages: `--azimuth-sigma` on the command line,
/// `azimuth_sigma` in Python.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SettingNames {
    /// `--kebab-case` flags.
    CommandLine,
    /// `snake_case` keyword arguments.
    Keywords,
}

impl SettingNames {
    /// The setting `snake` (snake_case) as the caller names it.
    pub fn of(self, snake: &str) -> String {
        match self {
            SettingNames::CommandLine => format!("--{}", snake.replace('_', "-")),
            SettingNames::Keywords => snake.to_string(),
        }
    }
}
