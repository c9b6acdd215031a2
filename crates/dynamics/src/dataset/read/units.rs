//! Plausible-looking nonsense caught before a verdict: positions in radians where degrees
//! are expected, judged by the odometer's travel against the fixes'.

use super::*;

/// Odometer travel (m) below which it cannot tell degrees from radians.
pub(super) const MIN_TRAVEL_M: f64 = 100.0;
/// If the GPS track read as degrees is shorter than this fraction of the odometer's, the
/// positions are radians (a radian track read as degrees is 180/pi = 57 times too short).
pub(super) const TRAVEL_RATIO: f64 = 0.1;
/// Without odometer travel: distance from (0, 0) beyond which a small-valued track is radians.
pub(super) const ORIGIN_RADIUS: f64 = 0.1;

/// Whether the GPS columns hold radians; if so, the line of the first fix and the evidence.
///
/// The heuristic, in order:
/// 1. Radians are bounded: if any fix has `|lat| >= 1.6` (a little over pi/2) or
///    `|lon| > 2*pi`, the values are degrees. Otherwise every fix lies, read as degrees,
///    within 180 km of the equator and 700 km of Greenwich: the open Gulf of Guinea. Real
///    degree tracks land there only when synthetic (a simulation placed at (0, 0)), so we
///    need more evidence than the box.
/// 2. With the odometer: between consecutive GPS fixes, compare the GPS chord (read as
///    degrees, in metres) with the odometer's displacement over the same interval (its
///    velocity integrated by trapezoids). Summed over the track, once the odometer has
///    covered at least [`MIN_TRAVEL_M`], degrees give a GPS length about equal to the
///    odometer's or longer (GPS noise adds length), radians read as degrees give 1/57 of it.
///    Below [`TRAVEL_RATIO`] of it, the column is radians. Chords between consecutive fixes
///    (rather than whole-track lengths) make GPS outages and closed loops harmless.
/// 3. Without odometer travel (standing still, or no odometer): radians if some fix is more
///    than [`ORIGIN_RADIUS`] from (0, 0) -- as degrees that is more than 11 km out at sea,
///    where no vehicle drives and a synthetic run placed at the origin does not start.
///    A radian track in the few hundred km next to (0, 0) with no odometer travel is
///    missed; such data are rare.
pub(super) fn looks_like_radians(
    measurements: &[Measurement],
    lines: &[usize],
) -> Option<(usize, String)> {
    let fixes: Vec<(f64, [f64; 2], usize)> = measurements
        .iter()
        .zip(lines)
        .filter_map(|(m, &l)| m.position_deg.map(|p| (m.t, p, l)))
        .collect();
    let first_line = fixes.first()?.2;
    if fixes
        .iter()
        .any(|(_, [lat, lon], _)| lat.abs() >= 1.6 || lon.abs() > std::f64::consts::TAU)
    {
        return None;
    }
    let odometer: Vec<(f64, [f64; 2])> = measurements
        .iter()
        .filter_map(|m| m.velocity.map(|v| (m.t, v)))
        .collect();
    let (mut gps_m, mut odo_m) = (0.0, 0.0);
    for w in fixes.windows(2) {
        let ((ta, a, _), (tb, b, _)) = (w[0], w[1]);
        let Some(d) = odometer_displacement(&odometer, ta, tb) else {
            continue;
        };
        odo_m += d;
        gps_m += chord_m(a, b);
    }
    if odo_m >= MIN_TRAVEL_M {
        return (gps_m < TRAVEL_RATIO * odo_m).then(|| {
            (
                first_line,
                format!(
                    "read as degrees the GPS track moves {gps_m:.1} m while the odometer \
                     moves {odo_m:.1} m"
                ),
            )
        });
    }
    fixes
        .iter()
        .find(|(_, [lat, lon], _)| lat.abs().max(lon.abs()) > ORIGIN_RADIUS)
        .map(|(_, _, line)| {
            (
                first_line,
                format!(
                    "read as degrees, the fix on line {line} would lie at sea more than \
                     {ORIGIN_RADIUS} deg off (0, 0), and no odometer travel tells otherwise"
                ),
            )
        })
}

/// The length (m) of the odometer's displacement over `[ta, tb]`, from its samples inside
/// the interval; `None` with fewer than two.
pub(in crate::dataset) fn odometer_displacement(
    odometer: &[(f64, [f64; 2])],
    ta: f64,
    tb: f64,
) -> Option<f64> {
    odometer_east_north(odometer, ta, tb).map(|d| d[0].hypot(d[1]))
}

/// The odometer's East and North displacement (m) over `[ta, tb]` (its velocity integrated
/// by trapezoids over its samples inside the interval); `None` with fewer than two.
pub(in crate::dataset) fn odometer_east_north(
    odometer: &[(f64, [f64; 2])],
    ta: f64,
    tb: f64,
) -> Option<[f64; 2]> {
    let start = odometer.partition_point(|(t, _)| *t < ta);
    let end = odometer.partition_point(|(t, _)| *t <= tb);
    let inside = odometer.get(start..end)?;
    if inside.len() < 2 {
        return None;
    }
    let mut d = [0.0, 0.0];
    for w in inside.windows(2) {
        let ((t0, v0), (t1, v1)) = (w[0], w[1]);
        let dt = t1 - t0;
        d[0] += 0.5 * (v0[0] + v1[0]) * dt;
        d[1] += 0.5 * (v0[1] + v1[1]) * dt;
    }
    Some(d)
}

/// Distance (m) between two positions in degrees, on the local tangent plane.
pub(in crate::dataset) fn chord_m(a: [f64; 2], b: [f64; 2]) -> f64 {
    let lat = (0.5 * (a[0] + b[0])).to_radians();
    let s = lat.sin();
    let north = (b[0] - a[0]).to_radians() * meridian_radius(s);
    let east = (b[1] - a[1]).to_radians() * prime_vertical_radius(s) * lat.cos();
    north.hypot(east)
}
