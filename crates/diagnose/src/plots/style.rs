//! What the diagnosis figures share: the channels as drawn, the colours of a model before and
//! after, the local metric frame that shows positions in metres, and the thinning of long
//! series.

use crate::catalogue::ChannelKind;
use crate::diagnosis::Diagnosis;
use crate::fit::pass::Fit;
use navkf_dynamics::earth::{meridian_radius, prime_vertical_radius};
use plotters::prelude::*;

/// Points drawn per curve at most (longer series are thinned evenly).
pub const MAX_POINTS: usize = 4000;

/// A measured channel.
pub const MEASURED: RGBColor = RGBColor(120, 120, 120);
/// The model diagnosed (after the named effects).
pub const AFTER: RGBColor = RGBColor(31, 119, 180);
/// The base model, before them (and a filter failure).
pub const BEFORE: RGBColor = RGBColor(214, 39, 40);
/// Bounds and bands of a consistent model.
pub const BOUNDS: RGBColor = RGBColor(150, 150, 150);

/// How a legend names the model with `effects`.
pub fn model_label(effects: &[String]) -> String {
    if effects.is_empty() {
        "base model".into()
    } else {
        format!("with {}", effects.join(", "))
    }
}

/// How an axis names what channel `kind` measures, in words with its display unit.
pub fn quantity(kind: ChannelKind) -> &'static str {
    match kind {
        ChannelKind::Velocity | ChannelKind::Constraint => "velocity (m/s)",
        ChannelKind::Latitude => "north of the first fix (m)",
        ChannelKind::Longitude => "east of the first fix (m)",
    }
}

/// How a legend or caption names the base model of `d` (the model before any effect was
/// named), saying when it is fitted at noise levels the diagnosis refitted.
pub fn base_label(d: &Diagnosis) -> String {
    if d.rounds.iter().any(|r| r.named_noise_levels()) {
        "base model (no effects), at the refitted noise levels".into()
    } else {
        "base model (no effects)".into()
    }
}

/// Local metric frame at the first GPS fix: channel values to display units.
pub struct Geo {
    kinds: Vec<ChannelKind>,
    lat0: f64,
    lon0: f64,
    north_per_rad: f64,
    east_per_rad: f64,
}

impl Geo {
    pub fn of(fit: &Fit) -> Self {
        let (la, lo) = position_channels(fit);
        let first = fit
            .z
            .iter()
            .find(|z| z[la].is_finite() && z[lo].is_finite());
        let (lat0, lon0) = first.map_or((0.0, 0.0), |z| (z[la], z[lo]));
        let s = lat0.sin();
        Geo {
            kinds: fit.channels.iter().map(|c| c.kind).collect(),
            lat0,
            lon0,
            north_per_rad: meridian_radius(s),
            east_per_rad: prime_vertical_radius(s) * lat0.cos(),
        }
    }

    /// Factor from channel `c`'s units to display units.
    pub fn scale(&self, c: usize) -> f64 {
        match self.kinds.get(c) {
            Some(ChannelKind::Latitude) => self.north_per_rad,
            Some(ChannelKind::Longitude) => self.east_per_rad,
            _ => 1.0,
        }
    }

    /// A measured or predicted value of channel `c` in display units.
    pub fn show(&self, c: usize, v: f64) -> f64 {
        match self.kinds.get(c) {
            Some(ChannelKind::Latitude) => (v - self.lat0) * self.north_per_rad,
            Some(ChannelKind::Longitude) => (v - self.lon0) * self.east_per_rad,
            _ => v,
        }
    }
}

/// The indices of the latitude and longitude channels of `fit`.
pub fn position_channels(fit: &Fit) -> (usize, usize) {
    let find = |k: ChannelKind| fit.channels.iter().position(|c| c.kind == k);
    (
        find(ChannelKind::Latitude).unwrap_or(0),
        find(ChannelKind::Longitude).unwrap_or(0),
    )
}

/// Every `stride`-th index of a series of `n`, so that at most [`MAX_POINTS`] are drawn.
pub fn stride(n: usize) -> usize {
    n.div_ceil(MAX_POINTS).max(1)
}
