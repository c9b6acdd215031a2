//! What is known of the platform before a record starts: the `[prior]` table of
//! `dataset.toml` (data-format.md), and the project's defaults with their reasons.
//!
//! A filter started on a dataset needs a one-sigma for the initial tilt and for every
//! coefficient. The user states what they know; what they leave out takes a default that
//! describes the platform class of the project's study files, a navigation-grade platform
//! (gyro drift 0.02 deg/h, accelerometer bias 50 micro-g; see
//! [`base_coefficient_sigma`]) aligned at rest before the test:
//!
//! - **Level**: levelling nulls the horizontal specific force, so it leaves the platform
//!   tilted by the accelerometer bias over gravity (`v_x' = Ka0x - g phi_y = 0`,
//!   docs/model.md eq. (9) at rest):
//!   `sigma_level = sigma_Ka0 / g` = 5.0e-5 rad (10.3 arcsec).
//! - **Azimuth**: gyrocompassing nulls the East gyro's apparent drift
//!   (`phi_x' = wie sinL phi_y - wie cosL phi_z + eps_x = 0`, docs/model.md eq. (8) at rest),
//!   so it leaves the azimuth off by `phi_z = eps_x / (wie cosL) + tanL Ka0x / g`:
//!   `sigma_az = hypot(sigma_Kg0 / (wie cosL), tanL sigma_Ka0 / g)`, which is 1.9e-3 rad
//!   (6.6 arcmin) at the paper's latitude 45.78 deg. It grows towards the poles, where
//!   gyrocompassing fails; it is capped at [`MAX_DEFAULT_AZIMUTH_RAD`].
//! - **Coefficients**: the typical size of each one (the base table, or the effect's
//!   [`crate::Effect::coefficient_sigma`]).
//!
//! A default is where a diagnosis *starts*: it widens any coefficient prior the data pull
//! beyond (`navkf_diagnose`), so a wrong default costs time, not a wrong answer.

use crate::earth::WIE;
use crate::state::*;
use crate::PlatformModel;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Typical one-sigma sizes of the 13 base coefficients for a navigation-grade platform:
/// gyro drift 0.02 deg/h, acceleration-sensitive drift 0.02 deg/h per g, accelerometer bias
/// 50 micro-g, accelerometer scale factor 50 ppm. The paper gives none; these are stated in
/// the study files and docs/diagnosis.md (its priors table).
pub fn base_coefficient_sigma(index: usize) -> f64 {
    const DEG_PER_H: f64 = std::f64::consts::PI / 180.0 / 3600.0;
    const G: f64 = crate::earth::STANDARD_GRAVITY;
    match index {
        KG0X | KG0Y | KG0Z => 0.02 * DEG_PER_H,
        KA0X | KA0Y => 50e-6 * G,
        KA1X | KA1Y => 50e-6,
        i if (KG0X..KA0X).contains(&i) => 0.02 * DEG_PER_H / G,
        _ => 0.0,
    }
}

/// Largest default azimuth sigma, rad (0.1 rad, 5.7 deg): beyond it the small-angle model
/// itself no longer holds, and near the poles a platform is not gyrocompassed.
pub const MAX_DEFAULT_AZIMUTH_RAD: f64 = 0.1;

/// The `[prior]` table of `dataset.toml`: one-sigma values the user states; `None` or an
/// absent coefficient takes the default.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlatformPrior {
    /// Initial level error (about East and North), rad.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub level_rad: Option<f64>,
    /// Initial azimuth error, rad (a strapdown dataset may call it `heading_rad`).
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        alias = "heading_rad"
    )]
    pub azimuth_rad: Option<f64>,
    /// One-sigma of coefficients by name (base or effect, as in `docs/model.md`), in the
    /// coefficient's unit.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub coefficients: BTreeMap<String, f64>,
}

/// Where a prior value came from, for reports.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum PriorSource {
    /// The project's default (this module's documentation gives the reason).
    Default,
    /// `dataset.toml`'s `[prior]` table.
    Dataset,
    /// A command-line flag.
    Flag,
    /// Found in the data: a strapdown dataset without `[initial]` is aligned from its own
    /// readings, and the alignment's sigmas are the tilt priors
    /// (`crate::dataset::alignment`).
    Aligned,
}

impl PlatformPrior {
    /// Whether nothing is stated.
    pub fn is_empty(&self) -> bool {
        self.level_rad.is_none() && self.azimuth_rad.is_none() && self.coefficients.is_empty()
    }

    /// Checks every value (finite, > 0) and every coefficient name against `known`; the error
    /// names the key as `prior.<key>` or `prior.coefficients.<name>`. `heading_key` is the
    /// family's key of the heading's sigma (`azimuth_rad`, `heading_rad`) and `navigation`
    /// its navigation states, which no coefficient may be (the dataset's `FamilyFiles`).
    pub fn validate(
        &self,
        known: &[String],
        heading_key: &str,
        navigation: &[&str],
    ) -> Result<(), (String, String)> {
        for (key, v) in [
            ("level_rad", self.level_rad),
            (heading_key, self.azimuth_rad),
        ] {
            if let Some(v) = v {
                if !(v.is_finite() && v > 0.0) {
                    return Err((
                        format!("prior.{key}"),
                        format!("{v}: expected a one-sigma in rad, finite and > 0"),
                    ));
                }
            }
        }
        for (name, v) in &self.coefficients {
            let key = format!("prior.coefficients.{name}");
            if !known.iter().any(|k| k == name) {
                let hint = if navigation.contains(&name.as_str()) {
                    format!(
                        " (a navigation state: its prior is level_rad / {heading_key} or comes \
                         from the first measurement)"
                    )
                } else {
                    String::new()
                };
                return Err((
                    key,
                    format!(
                        "unknown coefficient `{name}`{hint}; expected one of {}",
                        known.join(", ")
                    ),
                ));
            }
            // Its variance enters the filter's covariance: a square that overflows would stop
            // the first step ("initial state or covariance is not finite").
            if !(v.is_finite() && *v > 0.0 && (v * v).is_finite()) {
                return Err((
                    key,
                    format!(
                        "{v:e}: expected a one-sigma, > 0, whose square is finite (below 1e154)"
                    ),
                ));
            }
        }
        Ok(())
    }

    /// `self` with every value `over` states replacing this one's (flags over the file).
    pub fn overridden_by(&self, over: &PlatformPrior) -> PlatformPrior {
        let mut out = self.clone();
        out.level_rad = over.level_rad.or(self.level_rad);
        out.azimuth_rad = over.azimuth_rad.or(self.azimuth_rad);
        for (k, v) in &over.coefficients {
            out.coefficients.insert(k.clone(), *v);
        }
        out
    }
}

/// Default level sigma, rad: the accelerometer bias over gravity (module documentation).
///
/// ```
/// let s = navkf_dynamics::prior::default_level_rad();
/// assert!((s - 5.0e-5).abs() < 1e-7);
/// ```
pub fn default_level_rad() -> f64 {
    // Standard gravity: the bias's typical size is stated in micro-g of it.
    base_coefficient_sigma(KA0X) / crate::earth::STANDARD_GRAVITY
}

/// Default azimuth sigma at latitude `lat` (rad): what gyrocompassing leaves
/// (module documentation), capped at [`MAX_DEFAULT_AZIMUTH_RAD`].
///
/// ```
/// let s = navkf_dynamics::prior::default_azimuth_rad(45.78f64.to_radians());
/// assert!((s - 1.906e-3).abs() < 2e-6, "{s}"); // 6.6 arcmin
/// ```
pub fn default_azimuth_rad(lat: f64) -> f64 {
    let gyro = base_coefficient_sigma(KG0X) / (WIE * lat.cos().abs());
    let accel = lat.tan().abs() * default_level_rad();
    let s = gyro.hypot(accel);
    if s.is_finite() {
        s.min(MAX_DEFAULT_AZIMUTH_RAD)
    } else {
        MAX_DEFAULT_AZIMUTH_RAD
    }
}

/// The typical one-sigma of state `i` of `model`: the base table
/// ([`base_coefficient_sigma`]) or the effect's own ([`crate::Effect::coefficient_sigma`]);
/// zero for a state that is not a coefficient. Monte Carlo draws truths at this size where a
/// study states none, and a diagnosis starts its priors from it.
pub fn typical_sigma(model: &PlatformModel, i: usize) -> f64 {
    if i < BASE_DIM {
        return base_coefficient_sigma(i);
    }
    model
        .effect_coefficient_sigmas()
        .into_iter()
        .find(|(j, _)| *j == i)
        .map_or(0.0, |(_, s)| s)
}
