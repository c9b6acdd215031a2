//! The attitude a strapdown diagnosis starts from, and where it came from: `dataset.toml`'s
//! `[initial]`, or, without one, the alignment from the data
//! (`navkf_dynamics::dataset::alignment`: level from the first standstill, heading from the
//! first straight GPS track). The report states it beside the priors: a user whose recording
//! has no `[initial]` must be able to see what the filters were told, and from which seconds
//! of the record, before trusting a verdict that rests on it.

use crate::error::DiagnoseError;
use navkf_dynamics::dataset::Dataset;
use serde::{Deserialize, Serialize};

/// The start attitude of a strapdown diagnosis (`diagnosis.json`'s `start_attitude`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct StartAttitude {
    /// Roll at the first IMU reading, deg.
    pub roll_deg: f64,
    /// Pitch at the first IMU reading, deg.
    pub pitch_deg: f64,
    /// Heading at the first IMU reading, deg.
    pub heading_deg: f64,
    /// Where it came from.
    pub source: AttitudeSource,
}

/// Where a [`StartAttitude`] came from.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum AttitudeSource {
    /// `dataset.toml`'s `[initial]`.
    Stated,
    /// Aligned from the data, `dataset.toml` stating no `[initial]`.
    Aligned {
        /// The standstill the level came from, s.
        level_from_s: [f64; 2],
        /// One-sigma of roll and pitch the alignment gives, rad.
        level_sigma_rad: f64,
        /// Whether that sigma is the dataset's `[prior] level_rad` (otherwise a MEMS unit's
        /// accelerometer bias over g).
        level_sigma_stated: bool,
        /// The GPS track the heading came from, s.
        heading_from_s: [f64; 2],
        /// One-sigma of the heading the alignment gives, rad.
        heading_sigma_rad: f64,
    },
}

impl StartAttitude {
    /// The start attitude of `ds`: its `[initial]`, or its alignment from the data; `None`
    /// when it has neither (the diagnosis then stops with the alignment's reason).
    pub fn of(ds: &Dataset) -> Option<StartAttitude> {
        Self::try_of(ds).ok()
    }

    /// [`StartAttitude::of`], with the reason when `ds` has neither.
    pub fn try_of(ds: &Dataset) -> Result<StartAttitude, DiagnoseError> {
        if let Some(a) = ds.initial {
            return Ok(StartAttitude {
                roll_deg: a.roll_deg,
                pitch_deg: a.pitch_deg,
                heading_deg: a.heading_deg,
                source: AttitudeSource::Stated,
            });
        }
        let al = ds.align_from_data().map_err(|e| {
            DiagnoseError::Data(format!(
                "{}: dataset.toml has no [initial] attitude and the data give none: {e}",
                ds.name
            ))
        })?;
        Ok(StartAttitude {
            roll_deg: al.attitude.roll_deg,
            pitch_deg: al.attitude.pitch_deg,
            heading_deg: al.attitude.heading_deg,
            source: AttitudeSource::Aligned {
                level_from_s: al.level_from,
                level_sigma_rad: al.level_sigma,
                level_sigma_stated: ds.prior.level_rad.is_some(),
                heading_from_s: al.heading_from,
                heading_sigma_rad: al.heading_sigma,
            },
        })
    }

    /// Roll, pitch and heading, rad.
    pub fn angles_rad(&self) -> [f64; 3] {
        [
            self.roll_deg.to_radians(),
            self.pitch_deg.to_radians(),
            self.heading_deg.to_radians(),
        ]
    }

    /// Whether it was aligned from the data.
    pub fn is_aligned(&self) -> bool {
        matches!(self.source, AttitudeSource::Aligned { .. })
    }

    /// The report's sentence.
    ///
    /// ```
    /// use navkf_diagnose::start_attitude::{AttitudeSource, StartAttitude};
    /// let a = StartAttitude {
    ///     roll_deg: 0.25,
    ///     pitch_deg: -0.5,
    ///     heading_deg: 30.0,
    ///     source: AttitudeSource::Aligned {
    ///         level_from_s: [0.0, 60.0],
    ///         level_sigma_rad: 0.005,
    ///         level_sigma_stated: false,
    ///         heading_from_s: [75.0, 82.0],
    ///         heading_sigma_rad: 0.01,
    ///     },
    /// };
    /// let s = a.sentence();
    /// assert!(s.contains("aligned from the data"), "{s}");
    /// assert!(s.contains("standstill 0-60 s"), "{s}");
    /// assert!(s.contains("GPS track 75-82 s"), "{s}");
    /// ```
    pub fn sentence(&self) -> String {
        match self.source {
            AttitudeSource::Stated => format!(
                "Start attitude, from dataset.toml's [initial]: roll {:.3} deg, pitch {:.3} \
                 deg, heading {:.3} deg, with the level and heading priors above.",
                self.roll_deg, self.pitch_deg, self.heading_deg
            ),
            AttitudeSource::Aligned {
                level_from_s,
                level_sigma_rad,
                level_sigma_stated,
                heading_from_s,
                heading_sigma_rad,
            } => format!(
                "Start attitude, aligned from the data (dataset.toml has no [initial]): roll \
                 {:.3} deg and pitch {:.3} deg from the mean specific force over the \
                 standstill {:.0}-{:.0} s (one-sigma {:.3} deg: {}), heading {:.3} deg from \
                 the GPS track {:.0}-{:.0} s (one-sigma {:.3} deg), turned back to the first \
                 reading by the gyro. The level and heading priors \
                 above are these sigmas unless a flag or [prior] states others. State \
                 [initial] in dataset.toml to start from an attitude of your own.",
                self.roll_deg,
                self.pitch_deg,
                level_from_s[0],
                level_from_s[1],
                level_sigma_rad.to_degrees(),
                if level_sigma_stated {
                    "dataset.toml's [prior] level_rad"
                } else {
                    "a MEMS unit's accelerometer bias over g, as none is stated"
                },
                self.heading_deg,
                heading_from_s[0],
                heading_from_s[1],
                heading_sigma_rad.to_degrees()
            ),
        }
    }
}
